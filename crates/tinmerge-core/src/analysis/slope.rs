//! Slope and aspect of each triangle of a level: the surface is a plane on
//! each triangle, so both are exact per triangle.
//!
//! Slope is the angle of the plane with the horizontal, in degrees (0 flat,
//! towards 90 vertical). Aspect is the compass direction the plane faces
//! (its steepest descent), in degrees clockwise from north (grid north of
//! the tin's SRID), in `[0, 360)`; `None` for a flat triangle. Both take x,
//! y and z in the same unit (a projected SRID in metres with heights in
//! metres); [`slope_aspect_in`] takes a tin in degrees too, its triangle
//! laid out in local metres around its centroid (north is then true
//! north).
//!
//! ```
//! use tinmerge_core::analysis::slope::slope_aspect;
//! // a plane rising 1 m per metre towards the north: it faces south
//! let (s, a) = slope_aspect(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 1.0]]);
//! assert!((s - 45.0).abs() < 1e-12);
//! assert_eq!(a, Some(180.0));
//! ```

/// Slope (degrees) and aspect (degrees clockwise from north, None when
/// flat) of the plane through three points, counter-clockwise or not.
pub fn slope_aspect(c: &[[f64; 3]; 3]) -> (f64, Option<f64>) {
    let u = [c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]];
    let v = [c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]];
    // normal, turned upwards
    let mut n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    if n[2] < 0.0 {
        n = [-n[0], -n[1], -n[2]];
    }
    let h = n[0].hypot(n[1]);
    let slope = h.atan2(n[2]).to_degrees();
    if h == 0.0 {
        return (slope, None);
    }
    // the upward normal leans the way the plane faces (downhill): east
    // component n[0], north component n[1]
    let mut a = n[0].atan2(n[1]).to_degrees();
    if a < 0.0 {
        a += 360.0;
    }
    if a >= 360.0 {
        a -= 360.0;
    }
    (slope, Some(a))
}

/// [`slope_aspect`] in `units`: a triangle in degrees is first laid out in
/// metres around its centroid, its corners on the spheroid seen in the
/// centroid's tangent plane (east, north) with their heights as up.
///
/// ```
/// use tinmerge_core::analysis::slope::slope_aspect_in;
/// use tinmerge_core::geom::{Spheroid, Units};
/// // at the equator, a rise of 1,105.74 m over 0.01 degree of latitude
/// let (s, a) = slope_aspect_in(
///     &[[0.0, -0.005, 0.0], [0.01, -0.005, 0.0], [0.0, 0.005, 1105.7427582]],
///     Units::Degrees(Spheroid::WGS84),
/// );
/// assert!((s - 45.0).abs() < 1e-3, "{s}");
/// assert!((a.unwrap() - 180.0).abs() < 1e-6, "{a:?}");
/// ```
pub fn slope_aspect_in(c: &[[f64; 3]; 3], units: crate::geom::Units) -> (f64, Option<f64>) {
    match units {
        crate::geom::Units::Planar => slope_aspect(c),
        crate::geom::Units::Degrees(sph) => {
            let (cx, cy) = (
                (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                (c[0][1] + c[1][1] + c[2][1]) / 3.0,
            );
            // the corners on the spheroid in earth-centred metres, seen in
            // the east and north of the centroid's tangent plane, their
            // heights as up: the plane through them in local metres
            let (lon0, lat0) = (cx.to_radians(), cy.to_radians());
            let east = [-lon0.sin(), lon0.cos(), 0.0];
            let north = [
                -lat0.sin() * lon0.cos(),
                -lat0.sin() * lon0.sin(),
                lat0.cos(),
            ];
            let o = sph.ecef(cx, cy);
            slope_aspect(&c.map(|v| {
                let p = sph.ecef(v[0], v[1]);
                let d = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
                let dot = |u: [f64; 3]| d[0] * u[0] + d[1] * u[1] + d[2] * u[2];
                [dot(east), dot(north), v[2]]
            }))
        }
    }
}
