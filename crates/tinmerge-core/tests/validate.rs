//! `tin_validate`'s problems, each produced by a hand-made value: a sliver
//! (a zero-area triangle whose corner lies on the edge with the edge's
//! height), a crack (the same corner at another height: a wall) and a hole
//! (two vertices a few ulps apart where the triangles around should share
//! one). The oracle is the construction: the triangle made degenerate, the
//! vertex split. The values are written to `tests/data/problems/` (the
//! current format), which pg_regress `validate_problems.sql` reads through
//! `tin_validate` and checks with PostGIS; this test fails when those files
//! are not these values.
use crate::common;

use tinmerge_core::tin::build::from_triangles;
use tinmerge_core::tin::check::problems;
use tinmerge_core::tin::{Tin, layout};

/// A 2 x 2 square fanned around vertex 4 in the middle of its south side
/// (1e-20 inside it: a stored triangle has a positive area, exactly), with
/// the triangle (0, 1, 4) of zero area up to rounding along that side: the fan's two
/// triangles at vertex 4 meet the sliver, not each other. `z4`: vertex 4's
/// height (0: on the side's line, a sliver; else a crack).
fn sliver(z4: f64) -> Tin {
    let verts = vec![
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [0.0, 2.0, 0.0],
        [1.0, 1e-20, z4],
    ];
    from_triangles(
        verts,
        vec![[1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 1, 4]],
        32616,
        &mut || Ok(()),
    )
    .unwrap()
}

/// A square cut into four triangles around its centre, where one triangle
/// uses a second centre vertex 3 ulps from the first.
fn hole() -> Tin {
    let c = 0.5f64;
    let c2 = f64::from_bits(c.to_bits() + 3);
    let verts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [c, c, 1.0],
        [c2, c, 1.0],
    ];
    from_triangles(
        verts,
        vec![[0, 1, 4], [1, 2, 4], [2, 3, 5], [3, 0, 4]],
        32616,
        &mut || Ok(()),
    )
    .unwrap()
}

fn cases() -> Vec<(&'static str, Tin, &'static str)> {
    vec![
        ("sliver", sliver(0.0), "sliver"),
        ("crack", sliver(1.0), "crack"),
        ("hole", hole(), "hole"),
    ]
}

#[test]
fn each_problem_is_found_on_the_value_made_to_have_it() {
    for (name, tin, kind) in cases() {
        let p = problems(&tin, &mut || Ok(())).unwrap();
        assert!(!p.is_empty(), "{name}: no problem found");
        assert!(p.iter().all(|p| p.kind == kind), "{name}: {p:?}");
        // the triangle made degenerate is the one named (by its corners'
        // positions: the build numbers vertices its own way)
        let corners = |t: u32| {
            let mut c: Vec<(u64, u64)> = tin
                .corners(0, t)
                .iter()
                .map(|p| (p[0].to_bits(), p[1].to_bits()))
                .collect();
            c.sort_unstable();
            c
        };
        if kind != "hole" {
            assert_eq!(p.len(), 1, "{name}: {p:?}");
            let mut want: Vec<(u64, u64)> = [[0.0f64, 0.0], [2.0, 0.0], [1.0, 1e-20]]
                .iter()
                .map(|p| (p[0].to_bits(), p[1].to_bits()))
                .collect();
            want.sort_unstable();
            assert_eq!(corners(p[0].triangle), want, "{name}: {p:?}");
        } else {
            // among them the triangle with the second centre vertex
            let c2 = f64::from_bits(0.5f64.to_bits() + 3);
            assert!(
                p.iter()
                    .any(|p| corners(p.triangle).contains(&(c2.to_bits(), 0.5f64.to_bits()))),
                "{p:?}"
            );
        }
    }
    // the same squares made soundly: no problem
    let sound = from_triangles(
        vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
            [1.0, 0.0, 0.0],
        ],
        vec![[1, 2, 4], [2, 3, 4], [3, 0, 4]],
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    assert!(problems(&sound, &mut || Ok(())).unwrap().is_empty());
}

/// The fixtures pg_regress reads are these values (written when missing:
/// `cargo test --release --test core validate:: -- --ignored`).
#[test]
fn the_regress_fixtures_are_these_values() {
    for (name, tin, _) in cases() {
        let path = common::data_path(&format!("problems/{name}.tin"));
        let stored = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        assert_eq!(layout::decode(&stored).unwrap(), tin, "{path}");
    }
}

#[test]
#[ignore]
fn write_fixtures() {
    for (name, tin, _) in cases() {
        let path = common::data_path(&format!("problems/{name}.tin"));
        if !std::path::Path::new(&path).exists() {
            std::fs::write(path, layout::encode(&tin)).unwrap();
        }
    }
}
