//! Per-triangle statistics of a raster band over the sweep ([`super::sweep`]):
//! plain zonal statistics of the pixel centres a triangle owns, exact
//! coverage-weighted statistics of every pixel it overlaps
//! ([`super::coverage`]), and the mean colour of a three-band image.

use super::coverage::{check_grid, coverage_of};
use super::patch::RasterLevel;
use super::{PixelGrid, sweep, sweep_par};
use crate::interrupt::{Interrupt, Ticker};
use crate::io::raster::GeoTransform;
use crate::tin::TinError;

/// Statistics of the valid pixels handed to one triangle (or, weighted,
/// of the valid pixels it overlaps, each counting by its coverage).
#[derive(Clone, Debug, PartialEq)]
pub struct ZoneStats {
    pub triangle: u32,
    /// Pixels handed over (weighted: pixels overlapped).
    pub count: u64,
    /// Sum of the pixels' weights: `count` unweighted, the pixel area of
    /// the triangle's valid cover when weighted.
    pub weight: f64,
    /// Sum of values (weighted: of value times coverage).
    pub sum: f64,
    pub min: f64,
    pub max: f64,
    /// Most frequent value, smallest on ties (when asked for).
    pub mode: Option<f64>,
}

impl ZoneStats {
    pub fn mean(&self) -> f64 {
        self.sum / self.weight
    }

    fn empty(triangle: u32) -> ZoneStats {
        ZoneStats {
            triangle,
            count: 0,
            weight: 0.0,
            sum: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            mode: None,
        }
    }
}

/// Whether a value counts: not NaN, not the nodata value.
#[inline]
pub fn is_data(v: f64, nodata: Option<f64>) -> bool {
    !v.is_nan() && Some(v) != nodata
}

/// Per-triangle statistics of a band (`values` row-major, `width x
/// height` of `g`; NaN and `nodata` values are skipped). Triangles
/// receiving no valid pixel are left out; rows in triangle order, with
/// triangle ids (`lv.id`).
pub fn zonal_stats<L: RasterLevel>(
    lv: &L,
    g: &PixelGrid,
    values: &[f64],
    nodata: Option<f64>,
    want_mode: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<ZoneStats>, TinError> {
    if values.len() != g.width * g.height {
        return Err(TinError::InvalidParameter(format!(
            "raster band has {} values for {} x {} pixels",
            values.len(),
            g.width,
            g.height
        )));
    }
    // by position until the end
    let n = lv.count();
    let mut st: Vec<ZoneStats> = (0..n as u32).map(ZoneStats::empty).collect();
    let mut spans: Vec<(u32, u32, u32, u32)> = Vec::new();
    let w = g.width;
    let nd = nodata.unwrap_or(f64::NAN);
    // each run's count, sum, min and max (on the sweep's threads), added
    // to its triangle in the sweep's order
    let per_span = |t: u32, r: usize, c0: usize, c1: usize| {
        let (mut n, mut sum, mut lo, mut hi) = (0u64, 0.0, f64::INFINITY, f64::NEG_INFINITY);
        for &v in &values[r * w + c0..r * w + c1] {
            if !v.is_nan() && v != nd {
                n += 1;
                sum += v;
                lo = if v < lo { v } else { lo };
                hi = if v > hi { v } else { hi };
            }
        }
        (t, r as u32, c0 as u32, c1 as u32, n, sum, lo, hi)
    };
    sweep_par(lv, g, interrupt, &per_span, &mut |(
        t,
        r,
        c0,
        c1,
        n,
        sum,
        lo,
        hi,
    )| {
        let z = &mut st[t as usize];
        z.count += n;
        z.sum += sum;
        z.min = z.min.min(lo);
        z.max = z.max.max(hi);
        if want_mode {
            spans.push((t, r, c0, c1));
        }
    })?;
    if want_mode {
        // spans grouped by triangle: a stable counting sort (rows stay in
        // order within a triangle), linear and checked between passes
        interrupt()?;
        let mut start = vec![0u32; n + 1];
        for sp in &spans {
            start[sp.0 as usize + 1] += 1;
        }
        for t in 0..n {
            start[t + 1] += start[t];
        }
        interrupt()?;
        let mut grouped = vec![(0u32, 0u32, 0u32, 0u32); spans.len()];
        let mut fill = start.clone();
        for sp in &spans {
            let at = &mut fill[sp.0 as usize];
            grouped[*at as usize] = *sp;
            *at += 1;
        }
        drop(spans);
        // work items: runs of triangles holding about MODE_PIXELS pixels
        const MODE_PIXELS: u64 = 1 << 16;
        let mut items: Vec<(usize, usize)> = Vec::new();
        let (mut t0, mut px) = (0usize, 0u64);
        for (t, z) in st.iter().enumerate() {
            px += z.count;
            if px >= MODE_PIXELS || t + 1 == n {
                items.push((t0, t + 1));
                t0 = t + 1;
                px = 0;
            }
        }
        let modes = |&(ta, tb): &(usize, usize)| {
            let mut buf: Vec<f64> = Vec::new();
            let mut out = Vec::with_capacity(tb - ta);
            for t in ta..tb {
                buf.clear();
                for &(_, r, c0, c1) in &grouped[start[t] as usize..start[t + 1] as usize] {
                    let base = r as usize * w;
                    buf.extend(
                        values[base + c0 as usize..base + c1 as usize]
                            .iter()
                            .copied()
                            .filter(|&v| is_data(v, nodata)),
                    );
                }
                out.push(mode(&mut buf));
            }
            (ta, out)
        };
        crate::par::map_batched(&items, modes, interrupt, &mut |(ta, out)| {
            for (k, m) in out.into_iter().enumerate() {
                st[ta + k].mode = m;
            }
            Ok(())
        })?;
    }
    st.retain(|z| z.count > 0);
    for z in &mut st {
        z.weight = z.count as f64;
        z.triangle = lv.id(z.triangle as usize);
    }
    Ok(st)
}

/// Coverage-weighted per-triangle statistics of a band: every valid pixel
/// a triangle overlaps counts by the exact fraction `f` of its area inside
/// the triangle (as exactextract does for polygons): `weight` = sum of `f`,
/// `sum` = sum of `f * value`, `mean` their ratio, `min`/`max` over the
/// overlapped pixels, `mode` the value of greatest total coverage
/// (smallest on ties). Triangles overlapping no valid pixel are left out;
/// rows in triangle order, with triangle ids (`lv.id`).
#[allow(clippy::too_many_arguments)]
pub fn weighted_stats<L: RasterLevel>(
    lv: &L,
    gt: &GeoTransform,
    width: usize,
    height: usize,
    values: &[f64],
    nodata: Option<f64>,
    want_mode: bool,
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<ZoneStats>, TinError> {
    if values.len() != width * height {
        return Err(TinError::InvalidParameter(format!(
            "raster band has {} values for {width} x {height} pixels",
            values.len()
        )));
    }
    let run = |tris: std::ops::Range<u32>, tk: &mut Ticker| -> Result<Vec<ZoneStats>, TinError> {
        let mut out: Vec<ZoneStats> = Vec::new();
        let mut cur = ZoneStats::empty(u32::MAX);
        let mut pairs: Vec<(f64, f64)> = Vec::new();
        let mut finish = |z: &mut ZoneStats, pairs: &mut Vec<(f64, f64)>| {
            if z.count > 0 {
                if want_mode {
                    z.mode = weighted_mode(pairs);
                }
                let mut z = z.clone();
                z.triangle = lv.id(z.triangle as usize);
                out.push(z);
            }
            pairs.clear();
        };
        coverage_of(lv, gt, width, height, tris, tk, &mut |t, r, c, f| {
            let v = values[r * width + c];
            if !is_data(v, nodata) {
                return;
            }
            if t != cur.triangle {
                finish(&mut cur, &mut pairs);
                cur = ZoneStats::empty(t);
            }
            cur.count += 1;
            cur.weight += f;
            cur.sum += f * v;
            cur.min = cur.min.min(v);
            cur.max = cur.max.max(v);
            if want_mode {
                pairs.push((v, f));
            }
        })?;
        finish(&mut cur, &mut pairs);
        Ok(out)
    };
    let n = lv.count() as u32;
    if crate::par::threads() <= 1 {
        return run(0..n, &mut Ticker::new(interrupt));
    }
    check_grid(gt)?;
    // on threads: runs of triangles covering about ITEM_PIXELS pixels
    // (bounding boxes in pixel units), each triangle wholly in one run, so
    // every triangle's statistics are computed as in the serial loop
    const ITEM_PIXELS: f64 = 65536.0;
    let (sx, sy) = (gt.scale_x.abs(), gt.scale_y.abs());
    let mut items: Vec<std::ops::Range<u32>> = Vec::new();
    let (mut t0, mut px) = (0u32, 0.0f64);
    for t in 0..n {
        let cs = lv.corners(t as usize);
        let bw = cs[0][0].max(cs[1][0]).max(cs[2][0]) - cs[0][0].min(cs[1][0]).min(cs[2][0]);
        let bh = cs[0][1].max(cs[1][1]).max(cs[2][1]) - cs[0][1].min(cs[1][1]).min(cs[2][1]);
        px += (bw / sx + 2.0) * (bh / sy + 2.0);
        if px >= ITEM_PIXELS || t + 1 == n {
            items.push(t0..t + 1);
            t0 = t + 1;
            px = 0.0;
        }
    }
    let mut out: Vec<ZoneStats> = Vec::new();
    crate::par::map_batched(
        &items,
        |r| {
            let mut none = || Ok(());
            run(r.clone(), &mut Ticker::new(&mut none))
        },
        interrupt,
        &mut |part| {
            out.extend(part?);
            Ok(())
        },
    )?;
    Ok(out)
}

/// The value of greatest total weight, smallest on ties.
pub(super) fn weighted_mode(pairs: &mut [(f64, f64)]) -> Option<f64> {
    pairs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let mut best: Option<(f64, f64)> = None;
    let mut i = 0;
    while i < pairs.len() {
        let mut j = i;
        let mut wsum = 0.0;
        while j < pairs.len() && pairs[j].0 == pairs[i].0 {
            wsum += pairs[j].1;
            j += 1;
        }
        if best.is_none_or(|(bw, _)| wsum > bw) {
            best = Some((wsum, pairs[i].0));
        }
        i = j;
    }
    best.map(|(_, v)| v)
}

/// The mean colour of each triangle: every pixel whose centre a triangle
/// owns (the rule of [`sweep`]) and whose three bands are all valid adds
/// its (r, g, b). Returns `(triangle id, pixels, [r, g, b] means)` for the
/// triangles receiving a pixel, in triangle order.
pub fn paint<L: RasterLevel>(
    lv: &L,
    g: &PixelGrid,
    bands: [&[f64]; 3],
    nodata: [Option<f64>; 3],
    interrupt: &mut Interrupt<'_>,
) -> Result<Vec<(u32, u64, [f64; 3])>, TinError> {
    if bands.iter().any(|b| b.len() != g.width * g.height) {
        return Err(TinError::InvalidParameter(format!(
            "raster bands do not hold {} x {} pixels",
            g.width, g.height
        )));
    }
    let mut acc = vec![(0u64, [0.0f64; 3]); lv.count()];
    let w = g.width;
    sweep(lv, g, false, interrupt, &mut |t, r, c0, c1| {
        let a = &mut acc[t as usize];
        let (lo, hi) = (r * w + c0, r * w + c1);
        let (rs, gs, bs) = (&bands[0][lo..hi], &bands[1][lo..hi], &bands[2][lo..hi]);
        for ((&rv, &gv), &bv) in rs.iter().zip(gs).zip(bs) {
            if is_data(rv, nodata[0]) && is_data(gv, nodata[1]) && is_data(bv, nodata[2]) {
                a.0 += 1;
                a.1[0] += rv;
                a.1[1] += gv;
                a.1[2] += bv;
            }
        }
    })?;
    Ok(acc
        .into_iter()
        .enumerate()
        .filter(|(_, a)| a.0 > 0)
        .map(|(k, (cnt, s))| (lv.id(k), cnt, s.map(|v| v / cnt as f64)))
        .collect())
}

/// Most frequent value, smallest on ties.
pub(super) fn mode(buf: &mut [f64]) -> Option<f64> {
    buf.sort_unstable_by(|a, b| a.total_cmp(b));
    let mut best: Option<(usize, f64)> = None;
    let mut i = 0;
    while i < buf.len() {
        let mut j = i + 1;
        while j < buf.len() && buf[j] == buf[i] {
            j += 1;
        }
        if best.is_none_or(|(n, _)| j - i > n) {
            best = Some((j - i, buf[i]));
        }
        i = j;
    }
    best.map(|(_, v)| v)
}
