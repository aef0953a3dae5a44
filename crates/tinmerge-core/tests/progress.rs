//! Progress of long builds (`tinmerge_core::progress`): what a build
//! reports through `progress::step` to the sink its caller set, checked
//! against the result it returns (its own levels' triangle counts, the
//! number of tiles of the raster): each finer level's refinement counts its
//! parents, the previous level's triangles, from 0 to all of them, never
//! down, then assembly and the build's own check count its levels; a
//! tiled build counts its tiles.
use crate::common;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;
use tinmerge_core::progress::scoped;
use tinmerge_core::tin::build::{BuildOptions, build_lattice, default_tolerances};

type Steps = Rc<RefCell<Vec<(String, &'static str, u64, u64)>>>;

fn collect<R>(work: impl FnOnce() -> R) -> (R, Vec<(String, &'static str, u64, u64)>) {
    let steps: Steps = Rc::default();
    let s = steps.clone();
    let r = scoped(
        Box::new(move |p, u, d, t| s.borrow_mut().push((p.to_string(), u, d, t))),
        work,
    );
    let v = steps.borrow().clone();
    (r, v)
}

/// The steps by phase, in order: within a pass of a phase, done never goes
/// down and never past its total; a phase starts again from the beginning
/// (parents refined again, round after round) only after a pass that
/// reached its total. Each phase's last (done, total) and its steps.
fn phases(steps: &[(String, &'static str, u64, u64)]) -> BTreeMap<String, (u64, u64, usize)> {
    let mut by: BTreeMap<String, (u64, u64, usize)> = BTreeMap::new();
    for (p, _, d, t) in steps {
        let e = by.entry(p.clone()).or_insert((0, *t, 0));
        assert!(*d <= *t, "{p}: done {d} past total {t}");
        if *d < e.0 || *t != e.1 {
            assert_eq!(
                e.0, e.1,
                "{p}: a new pass began before the last reached its total"
            );
        }
        *e = (*d, *t, e.2 + 1);
    }
    by
}

#[test]
fn a_raster_build_counts_each_levels_parents() {
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let tols = default_tolerances(2.0, 5).unwrap();
    let opts = BuildOptions {
        keep_border: false,
        between_samples: true,
    };
    // the valid pixels at their (column, row), as tin_from_raster builds them
    let mut samples = Vec::new();
    for r in 0..dem.height {
        for c in 0..dem.width {
            let v = dem.values[r * dem.width + c];
            if !v.is_nan() && Some(v) != dem.nodata {
                samples.push([c as f64, r as f64, v]);
            }
        }
    }
    let build = || {
        build_lattice(
            samples.clone(),
            &dem.lattice(),
            &tols,
            32616,
            opts,
            &mut || Ok(()),
        )
    };
    let (tin, all) = collect(|| build().unwrap());
    // after the refinement, assembly and the build's own check count the
    // levels
    let n = tin.levels.len() as u64;
    for phase in ["assembling the levels", "checking the levels"] {
        let done: Vec<u64> = all
            .iter()
            .filter(|s| s.0 == phase)
            .map(|s| {
                assert_eq!((s.1, s.3), ("levels", n), "{phase}");
                s.2
            })
            .collect();
        assert_eq!(done, (0..=n).collect::<Vec<_>>(), "{phase}");
    }
    let steps: Vec<_> = all.into_iter().filter(|s| s.1 != "levels").collect();
    assert!(steps.iter().all(|s| s.1 == "triangles"));
    let by = phases(&steps);
    // one phase per finer level (and one for the parents it refines again,
    // if any), its total the parent level's triangles
    let first = by.keys().filter(|p| !p.ends_with("refined again")).count();
    assert_eq!(first, tin.levels.len() - 1, "phases: {:?}", by.keys());
    for k in 1..tin.levels.len() {
        let name = format!(
            "refining a level parent by parent ({k} of {})",
            tin.levels.len() - 1
        );
        let &(done, total, n) = by.get(&name).unwrap_or_else(|| panic!("no phase {name:?}"));
        let parents = tin.levels[k - 1].tris.len() as u64;
        assert!(n >= 2, "{name}: {n} steps");
        assert_eq!(
            total,
            parents,
            "{name}: total {total}, level {} has {parents} triangles",
            k - 1
        );
        // (redone parents report again, from 0: the last step of the
        // first pass is all of them)
        assert!(
            steps.iter().any(|s| s.0 == name && s.2 == parents),
            "{name}: never reached all {parents} parents (last {done}, {n} steps)"
        );
    }
    // without a sink nothing is reported, and the build is the same
    let again = build().unwrap();
    assert_eq!(again.levels.len(), tin.levels.len());
    for (a, b) in again.levels.iter().zip(&tin.levels) {
        assert_eq!(a.tris, b.tris);
    }
}

#[test]
fn a_tiled_build_counts_its_tiles() {
    let dem = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let tols = default_tolerances(4.0, 3).unwrap();
    let n = 100;
    let ((tiles, _), steps) = collect(|| common::tiles_and_seams_of(&dem, n, &tols, 32616));
    let by = phases(&steps);
    let (done, total, _) = by["building tiles"];
    let expect = (dem.width.div_ceil(n) * dem.height.div_ceil(n)) as u64;
    assert_eq!(
        total, expect,
        "{} x {} pixels in tiles of {n}",
        dem.width, dem.height
    );
    assert_eq!(done, total, "the last step is of every tile");
    assert!(tiles.len() as u64 <= total);
    for p in by.keys() {
        assert!(p.starts_with("building tiles"), "phase {p}");
    }
}
