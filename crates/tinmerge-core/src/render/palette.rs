//! Colours for pictures: a hypsometric ramp for heights, a perceptually
//! ordered ramp for other values, and distinct colours for classes.

/// An sRGB colour.
pub type Rgb = [u8; 3];

/// Stops of the height ramp (green lowlands, yellow, brown, grey-white
/// tops), as in common hypsometric tints.
const TERRAIN: [Rgb; 6] = [
    [38, 115, 77],
    [104, 168, 82],
    [224, 214, 122],
    [191, 143, 84],
    [140, 104, 84],
    [242, 242, 242],
];

/// Stops of the value ramp (viridis, sampled at 7 points).
const VIRIDIS: [Rgb; 7] = [
    [68, 1, 84],
    [68, 57, 131],
    [49, 104, 142],
    [33, 145, 140],
    [53, 183, 121],
    [144, 215, 67],
    [253, 231, 37],
];

/// Distinct colours for classes (Tableau 10).
pub const CLASSES: [Rgb; 10] = [
    [78, 121, 167],
    [242, 142, 43],
    [225, 87, 89],
    [118, 183, 178],
    [89, 161, 79],
    [237, 201, 72],
    [176, 122, 161],
    [255, 157, 167],
    [156, 117, 95],
    [186, 176, 172],
];

/// Which ramp to map values through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ramp {
    /// Heights: hypsometric tints.
    Terrain,
    /// Any other value: viridis.
    Viridis,
}

impl Ramp {
    fn stops(self) -> &'static [Rgb] {
        match self {
            Ramp::Terrain => &TERRAIN,
            Ramp::Viridis => &VIRIDIS,
        }
    }

    /// Colour of `v` on the ramp from `lo` to `hi` (clamped; the middle of
    /// the ramp when `lo == hi` or `v` is not finite).
    ///
    /// ```
    /// use tinmerge_core::render::palette::Ramp;
    /// assert_eq!(Ramp::Viridis.colour(0.0, 0.0, 1.0), [68, 1, 84]);
    /// assert_eq!(Ramp::Viridis.colour(1.0, 0.0, 1.0), [253, 231, 37]);
    /// ```
    pub fn colour(self, v: f64, lo: f64, hi: f64) -> Rgb {
        let t = if hi > lo && v.is_finite() {
            ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let stops = self.stops();
        let f = t * (stops.len() - 1) as f64;
        let i = (f.floor() as usize).min(stops.len() - 2);
        let w = f - i as f64;
        let (a, b) = (stops[i], stops[i + 1]);
        let mix = |k: usize| (a[k] as f64 + (b[k] as f64 - a[k] as f64) * w).round() as u8;
        [mix(0), mix(1), mix(2)]
    }
}

/// `#rrggbb`.
pub fn hex(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}
