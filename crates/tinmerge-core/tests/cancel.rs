//! Cancellation: every long loop of the builds and merges calls the
//! caller's interrupt check (in PostgreSQL: `check_for_interrupts!`, which
//! is how a cancel or `statement_timeout` stops a query). For each long
//! operation on the real DEM:
//! - an interrupt check that fails at its k-th call stops the operation
//!   with `Interrupted` (for several k: early, middle and late stops all
//!   return cleanly, no panic, no partial result);
//! - the largest gap between two checks over a full run is printed (not
//!   asserted: shared machines are noisy): that gap bounds how long a cancel
//!   waits. docs/reliability.md quotes it.
use crate::common;

use std::time::Instant;
use tinmerge_core::interrupt::Interrupt;
use tinmerge_core::merge::area::polygon::Area;
use tinmerge_core::merge::area::{Method, sweep};
use tinmerge_core::merge::line::{Part, TriangleSink, walk_parts};
use tinmerge_core::merge::overlay::{overlay, overlay_constrained};
use tinmerge_core::merge::raster::PixelGrid;
use tinmerge_core::merge::raster::patch::TinLevel;
use tinmerge_core::merge::raster::stats::{weighted_stats, zonal_stats};
use tinmerge_core::tin::build::{build, default_tolerances};
use tinmerge_core::tin::{Tin, TinError};

type Op<'a> = Box<dyn Fn(&mut Interrupt<'_>) -> Result<(), TinError> + 'a>;

/// Full run: number of checks and the largest gap between two (ms).
fn gaps(op: &Op) -> (usize, f64, f64) {
    let t0 = Instant::now();
    let mut last = t0;
    let (mut n, mut max) = (0usize, 0.0f64);
    op(&mut || {
        let now = Instant::now();
        max = max.max((now - last).as_secs_f64());
        last = now;
        n += 1;
        Ok(())
    })
    .unwrap();
    let end = Instant::now();
    max = max.max((end - last).as_secs_f64());
    (n, max * 1e3, (end - t0).as_secs_f64() * 1e3)
}

fn check(name: &str, op: Op) {
    let (n, max_gap, total) = gaps(&op);
    eprintln!("| {name} | {total:.0} | {n} | {max_gap:.2} |");
    assert!(n >= 2, "{name}: only {n} interrupt checks in a full run");
    for k in [1, n / 2, n] {
        let mut calls = 0usize;
        let r = op(&mut || {
            calls += 1;
            if calls >= k.max(1) {
                Err(TinError::Interrupted)
            } else {
                Ok(())
            }
        });
        assert!(
            matches!(r, Err(TinError::Interrupted)),
            "{name}: stop at check {k} of {n} gave {r:?}"
        );
        assert_eq!(calls, k.max(1), "{name}: went on checking after the stop");
    }
}

/// A closed ring around the domain's centre with many vertices (a wavy
/// circle) and the same as a line.
fn wavy(t: &Tin, n: usize) -> Vec<[f64; 2]> {
    let b = &t.bbox;
    let (cx, cy) = ((b.min_x + b.max_x) / 2.0, (b.min_y + b.max_y) / 2.0);
    let r = (b.max_x - b.min_x).min(b.max_y - b.min_y) * 0.4;
    let mut pts: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = i as f64 / n as f64 * std::f64::consts::TAU;
            let rr = r * (1.0 + 0.05 * (a * 40.0).sin());
            [cx + rr * a.cos(), cy + rr * a.sin()]
        })
        .collect();
    pts.push(pts[0]);
    pts
}

#[test]
fn long_operations_stop_at_the_interrupt_check() {
    let d = common::read_dem("jacksboro_fault_dem_utm16n.tif");
    let samples = d.samples();
    let a = common::dem_tin();
    let b = build(
        d.samples(),
        &default_tolerances(1.5, 5).unwrap(),
        32616,
        &mut || Ok(()),
    )
    .unwrap();
    let fine = a.levels.len() - 1;
    let (gt4, w4, h4, v4) = d.upsampled(4);
    let g4 = PixelGrid::new(&gt4, w4, h4).unwrap();
    let ring = wavy(&a, 200_000);
    let area = Area::new(vec![vec![ring.clone()]]);
    let parts = vec![Part::new(ring.clone())];
    eprintln!("| operation | full run ms | interrupt checks | largest gap between checks ms |");
    eprintln!("|---|---:|---:|---:|");
    check(
        "build, DEM 2 m, 5 levels",
        Box::new(|i| {
            build(
                samples.clone(),
                &default_tolerances(2.0, 5).unwrap(),
                32616,
                i,
            )
            .map(|_| ())
        }),
    );
    let stored = tinmerge_core::tin::layout::encode(&a);
    check(
        "decode + validate the stored DEM tin (15.7 MB)",
        Box::new(|i| tinmerge_core::tin::layout::decode_checked(&stored, i).map(|_| ())),
    );
    check(
        "raster zonal stats, DEM x4 (1.9M px), finest level",
        Box::new(|i| {
            zonal_stats(
                &TinLevel::new(&a, fine).unwrap(),
                &g4,
                &v4,
                Some(-9999.0),
                true,
                i,
            )
            .map(|_| ())
        }),
    );
    check(
        "raster weighted stats, DEM x4, level 0",
        Box::new(|i| {
            weighted_stats(
                &TinLevel::new(&a, 0).unwrap(),
                &gt4,
                w4,
                h4,
                &v4,
                Some(-9999.0),
                false,
                i,
            )
            .map(|_| ())
        }),
    );
    check(
        "area sweep, 200k-vertex polygon, finest level",
        Box::new(|i| sweep(&a, fine, &area, Method::Hierarchy, i).map(|_| ())),
    );
    check(
        "line walk, 200k-vertex line, finest level",
        Box::new(|i| {
            let mut sink = TriangleSink::default();
            walk_parts(&a, fine, &parts, &mut sink, &mut |_, _| {}, i)
        }),
    );
    check(
        "overlay (faces), DEM vs 1.5 m, finest levels",
        Box::new(|i| overlay(&a, fine, &b, fine, i).map(|_| ())),
    );
    check(
        "overlay (constrained), DEM vs 1.5 m, level 3",
        Box::new(|i| overlay_constrained(&a, 3, &b, 3, i).map(|_| ())),
    );
}
