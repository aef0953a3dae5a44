//! Line of sight over the surface of a level (`tin_line_of_sight`).
//!
//! The sight line runs straight from the observer's eye to the target. The
//! line merge cuts its ground track at every triangle edge
//! ([`crate::merge::line::pieces`]); inside each piece the surface is linear
//! along the track, so the sight line's height above it, `g(d)` at distance
//! `d` from the observer, is linear too, or, with the earth's curvature, a
//! quadratic: the ground at distance `d` looks lower by
//! `(1 - k) d² / (2 R)` (R = 6,371,000 m, k the refraction coefficient),
//! the textbook correction of `gdal_viewshed` and `r.viewshed`. The target
//! is blocked where `g` goes below 0 (by more than 1e-9 of the heights: a
//! target on the ground touches the sight line): the first such point,
//! the *obstruction*, is found piece by piece in closed form, exact up to
//! the rounding of the surface's heights. Where the track leaves the domain
//! (off the hull, over a hole) nothing blocks.
//!
//! ```
//! use tinmerge_core::analysis::visibility::{line_of_sight, Curvature};
//! use tinmerge_core::tin::build::build;
//! // a ridge 10 m high along x = 5 across flat ground at 0
//! let pts = vec![[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0], [0.0, 10.0, 0.0],
//!                [5.0, 0.0, 10.0], [5.0, 10.0, 10.0]];
//! let tin = build(pts, &[0.0], 0, &mut || Ok(())).unwrap();
//! // eyes 2 m above the ground at x = 1 and x = 9: the ridge is in between
//! let s = line_of_sight(&tin, 0, [1.0, 5.0, 2.0], [9.0, 5.0, 2.0], Curvature::None, &mut || Ok(())).unwrap();
//! assert!(!s.visible);
//! let o = s.obstruction.unwrap();
//! // the sight line at 2 m meets the ridge's flank, rising 2 m a metre, at x = 1
//! assert!((o[0] - 1.0).abs() < 1e-9 && (o[2] - 2.0).abs() < 1e-9);
//! // from 20 m up, it clears the ridge by 10 m
//! let s = line_of_sight(&tin, 0, [1.0, 5.0, 20.0], [9.0, 5.0, 20.0], Curvature::None, &mut || Ok(())).unwrap();
//! assert!(s.visible && (s.clearance.unwrap() - 10.0).abs() < 1e-9);
//! ```

use crate::error::TinError;
use crate::interrupt::Interrupt;
use crate::merge::line::{Part, pieces_in};
use crate::tin::Tin;

/// The earth's mean radius, metres.
pub const EARTH_RADIUS: f64 = 6_371_000.0;

/// Whether and how the earth's curvature lowers distant ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Curvature {
    /// A flat earth (projected coordinates over short distances).
    None,
    /// Ground at distance `d` (metres) looks lower by
    /// `(1 - refraction) d² / (2 R)`; `metres_per_unit` turns the tin's
    /// horizontal units into metres along the sight line (1 for a
    /// projected SRID in metres).
    Earth {
        refraction: f64,
        metres_per_unit: f64,
    },
}

impl Curvature {
    /// The drop per squared horizontal unit.
    fn c(&self) -> f64 {
        match *self {
            Curvature::None => 0.0,
            Curvature::Earth {
                refraction,
                metres_per_unit,
            } => (1.0 - refraction) * metres_per_unit * metres_per_unit / (2.0 * EARTH_RADIUS),
        }
    }
}

/// What a line of sight finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sight {
    /// No point of the surface between the two is above the sight line
    /// (by more than 1e-9 of the heights: touching it, as a target on the
    /// ground does, is seeing).
    pub visible: bool,
    /// Where the sight line first goes below the surface (x, y, z on the
    /// surface), and its horizontal distance from the observer.
    pub obstruction: Option<[f64; 3]>,
    pub distance: Option<f64>,
    /// The least height of the sight line above the (curvature-lowered)
    /// surface strictly between observer and target: at the edges it
    /// crosses, and where the curved clearance is least inside a triangle;
    /// negative when blocked. None when the track crosses no edge of the
    /// domain between the two.
    pub clearance: Option<f64>,
}

/// The line of sight from `eye` to `target` (x, y and absolute heights) over
/// `level`. The caller places the eye and the target (on the surface plus
/// a height, or at a given height).
pub fn line_of_sight(
    tin: &Tin,
    level: usize,
    eye: [f64; 3],
    target: [f64; 3],
    curvature: Curvature,
    interrupt: &mut Interrupt<'_>,
) -> Result<Sight, TinError> {
    if level >= tin.levels.len() {
        return Err(TinError::LevelOutOfRange {
            level: level as i64,
            num_levels: tin.levels.len(),
        });
    }
    if !eye.iter().chain(target.iter()).all(|v| v.is_finite()) {
        return Err(TinError::InvalidParameter(
            "line of sight: observer and target must be finite".into(),
        ));
    }
    let c = curvature.c();
    let total = (target[0] - eye[0]).hypot(target[1] - eye[1]);
    // the sight line aims at where the target looks to be
    let z_target = target[2] - c * total * total;
    let sight = |d: f64| {
        if total > 0.0 {
            eye[2] + (z_target - eye[2]) * (d / total)
        } else {
            eye[2]
        }
    };
    let mut out = Sight {
        visible: true,
        obstruction: None,
        distance: None,
        clearance: None,
    };
    if total == 0.0 {
        return Ok(out);
    }
    let part = Part::new(vec![[eye[0], eye[1]], [target[0], target[1]]]);
    let pieces = pieces_in(tin, level, &[part], interrupt)?;
    let at = |d: f64| {
        let t = d / total;
        [
            eye[0] + t * (target[0] - eye[0]),
            eye[1] + t * (target[1] - eye[1]),
        ]
    };
    let mut clear = f64::INFINITY;
    let inside = |d: f64| d > 0.0 && d < total;
    // below the sight line by less than this is touching it: the heights
    // of the eye, of the target and of the surface under them come from
    // interpolations that differ in their last bits (a target on the
    // ground, target_height 0, touches the sight line at its end)
    let tol = 1e-9 * eye[2].abs().max(target[2].abs()).max(1.0);
    for p in &pieces {
        for k in 0..p.points.len().saturating_sub(1) {
            let (d0, d1) = (p.along[k], p.along[k + 1]);
            if d1.partial_cmp(&d0) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            let (z0, z1) = (p.points[k][2], p.points[k + 1][2]);
            // g(d) = sight(d) - surface(d) + c d², surface linear on [d0, d1]
            let g = |d: f64| {
                let s = (d - d0) / (d1 - d0);
                sight(d) - (z0 + s * (z1 - z0)) + c * d * d
            };
            let (g0, g1) = (g(d0), g(d1));
            for (d, gv) in [(d0, g0), (d1, g1)] {
                if inside(d) {
                    clear = clear.min(gv);
                }
            }
            // g = c d² + b d + e on the piece (c the curvature's drop); its least value inside
            let b = (z_target - eye[2]) / total - (z1 - z0) / (d1 - d0);
            if c > 0.0 {
                let dm = -b / (2.0 * c);
                if dm > d0 && dm < d1 {
                    clear = clear.min(g(dm));
                }
            }
            if out.obstruction.is_some() {
                continue;
            }
            // the first d in [d0, d1] where g < 0, on a piece where g goes
            // below -tol
            let first = if c == 0.0 {
                (g0.min(g1) < -tol).then(|| {
                    if g0 <= 0.0 {
                        d0
                    } else {
                        d0 + (d1 - d0) * (g0 / (g0 - g1))
                    }
                })
            } else {
                // g is convex here: below -tol somewhere iff at its least
                let dm = (-b / (2.0 * c)).clamp(d0, d1);
                (g(dm) < -tol).then(|| {
                    if g0 <= 0.0 {
                        return d0;
                    }
                    // the smaller root of c d² + b d + e in [d0, dm], by
                    // the cancellation-free formula
                    let e = g0 - c * d0 * d0 - b * d0;
                    let disc = (b * b - 4.0 * c * e).max(0.0);
                    let q = -0.5 * (b + b.signum() * disc.sqrt());
                    let roots = [q / c, if q != 0.0 { e / q } else { f64::NAN }];
                    roots
                        .into_iter()
                        .filter(|r| r.is_finite() && *r >= d0 && *r <= dm)
                        .fold(dm, f64::min)
                })
            };
            if let Some(d) = first {
                let s = (d - d0) / (d1 - d0);
                let xy = at(d);
                out.visible = false;
                out.obstruction = Some([xy[0], xy[1], z0 + s * (z1 - z0)]);
                out.distance = Some(d);
            }
        }
    }
    out.clearance = clear.is_finite().then_some(clear);
    Ok(out)
}
