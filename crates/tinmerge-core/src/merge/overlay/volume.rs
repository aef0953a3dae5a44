//! Cut and fill between two surfaces inside a polygon (`tin_volume(a, b,
//! polygon)`): two epochs of a survey, or a design against the ground, as
//! ArcGIS's Surface Difference and Cut Fill report them.
//!
//! Over each triangle of the overlay ([`super::overlay`]) both surfaces are
//! linear, so their difference A - B is too: the overlay's triangles with
//! the height A - B at every vertex are one more linear surface, and the
//! volume merge of the area merge ([`crate::merge::area::surface`]) clips it
//! to the polygon exactly and integrates its parts above and below 0. The
//! triangles over which A and B are one plane ([`Overlay::same`], or equal
//! at their corners) are left out of that surface and measured on their
//! own: the unchanged area.
//!
//! ```
//! use tinmerge_core::tin::build::build;
//! use tinmerge_core::merge::overlay::{mark_same, overlay, volume::volumes_in};
//! use tinmerge_core::polygon::Area;
//! use tinmerge_core::geom::Units;
//! // A: the plane z = x over [0, 4]^2; B: the flat plane z = 2
//! let grid = |f: &dyn Fn(f64, f64) -> f64| {
//!     let mut pts = Vec::new();
//!     for i in 0..5 { for j in 0..5 { pts.push([i as f64, j as f64, f(i as f64, j as f64)]); } }
//!     build(pts, &[0.0], 0, &mut || Ok(())).unwrap()
//! };
//! let (a, b) = (grid(&|x, _| x), grid(&|_, _| 2.0));
//! let mut o = overlay(&a, 0, &b, 0, &mut || Ok(())).unwrap();
//! mark_same(&mut o, &a, 0, &b, 0);
//! // the square [1, 3] x [0, 1]: A - B runs from -1 to 1 across it
//! let sq = Area::new(vec![vec![vec![[1.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.0, 1.0]]]]);
//! let v = volumes_in(&o, &sq, 0, Units::Planar, &mut || Ok(())).unwrap();
//! assert!((v.cut - 0.5).abs() < 1e-12 && (v.fill - 0.5).abs() < 1e-12);
//! assert!((v.area_cut - 1.0).abs() < 1e-12 && (v.area_fill - 1.0).abs() < 1e-12);
//! assert_eq!(v.area_unchanged, 0.0);
//! ```

use super::Overlay;
use crate::geom::Units;
use crate::interrupt::Interrupt;
use crate::merge::area::surface::volume_parts_with;
use crate::merge::area::{Method, sweep};
use crate::polygon::Area;
use crate::tin::TinError;
use crate::tin::build::from_triangles_void;

/// What [`volumes_in`] measures inside the polygon.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Volumes {
    /// Volume where A is above B.
    pub cut: f64,
    /// Volume where A is below B.
    pub fill: f64,
    /// Planar area where A is above B.
    pub area_cut: f64,
    /// Planar area where A is below B.
    pub area_fill: f64,
    /// Planar area where A and B are one surface.
    pub area_unchanged: f64,
}

/// Cut, fill and their areas between the two surfaces of an overlay inside
/// `area` (the common domain's part of it; [`super::mark_same`] first, so
/// that where the surfaces are one plane counts as unchanged), measured in
/// `units` (metres on the spheroid for a geographic overlay). `srid` is
/// carried by the intermediate surfaces only.
pub fn volumes_in(
    o: &Overlay,
    area: &Area,
    srid: i32,
    units: Units,
    interrupt: &mut Interrupt<'_>,
) -> Result<Volumes, TinError> {
    let mut out = Volumes::default();
    let n = o.tris.len();
    let unchanged: Vec<bool> = (0..n)
        .map(|t| {
            o.same.get(t).copied().unwrap_or(false)
                || o.tris[t]
                    .iter()
                    .all(|&v| o.za[v as usize] == o.zb[v as usize])
        })
        .collect();
    let verts: Vec<[f64; 3]> = (0..o.pts.len())
        .map(|v| [o.pts[v][0], o.pts[v][1], o.za[v] - o.zb[v]])
        .collect();
    // the changed triangles as a surface of A - B; the rest void
    let changed_void: Vec<bool> = (0..n).map(|t| o.is_void(t) || unchanged[t]).collect();
    if changed_void.iter().any(|&v| !v) {
        let d = from_triangles_void(verts.clone(), o.tris.clone(), changed_void, srid, interrupt)?;
        let s = sweep(&d, 0, area, Method::Flat, interrupt)?;
        let v = volume_parts_with(&d, area, &s, 0.0, None, units, interrupt)?;
        out.cut = v.cut;
        out.fill = v.fill;
        out.area_cut = v.area_above;
        out.area_fill = v.area_below;
    }
    // the unchanged triangles: their area inside the polygon (every part
    // of them is "below" a base above all heights)
    let same_void: Vec<bool> = (0..n).map(|t| o.is_void(t) || !unchanged[t]).collect();
    if same_void.iter().any(|&v| !v) {
        let flat: Vec<[f64; 3]> = verts.iter().map(|v| [v[0], v[1], 0.0]).collect();
        let d = from_triangles_void(flat, o.tris.clone(), same_void, srid, interrupt)?;
        let s = sweep(&d, 0, area, Method::Flat, interrupt)?;
        out.area_unchanged =
            volume_parts_with(&d, area, &s, 1.0, None, units, interrupt)?.area_below;
    }
    Ok(out)
}
