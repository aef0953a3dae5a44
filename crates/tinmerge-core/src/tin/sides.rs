//! A parent's sides at the next level of a build: the vertices each is
//! split at, chosen from the side's own profile alone, so the two triangles
//! sharing it choose the same ones without knowing of each other.
//!
//! The profile is the side's samples (exactly on it on a lattice, up to
//! rounding for scattered samples) and, in a build between samples
//! ([`super::build::BuildOptions::between_samples`]), its crossings with the
//! reference surface's grid segments ([`super::surface`]); a
//! Douglas-Peucker split ([`choose_border`]) picks the vertices
//! ([`plan_side`]); points forced onto a side ([`Forced`]) are taken first.
//! [`close_chains`] closes the triangles of a parent whose side skips chosen
//! vertices a rounding outside it.

use super::surface::{Crossing, Reference};

/// How a side is split ([`choose_border`]): at what tolerance, and
/// whether a gap of a power of two steps is halved (a tile's seam).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Split {
    pub(crate) tol: f64,
    pub(crate) halve: bool,
}

impl Split {
    /// A side that no other tile shares: each gap at its worst sample.
    pub(crate) fn at(tol: f64) -> Split {
        Split { tol, halve: false }
    }
}

/// One level's choice of border vertices on a hull side (`keep_border`): a
/// Douglas-Peucker split of the side's height profile, from the positions
/// already `chosen` (at first its two corners), until every sample of the
/// side is within `split.tol` of the straight line between the chosen
/// samples on either side of it. Each gap is split at its first worst
/// sample; with `split.halve` (a tile's seam) a gap of a power of two
/// steps at its middle instead: a whole tile side (2^k pixels) is then
/// split only where a lattice-aligned triangulation bisects it, and a
/// kept build stays along the lattice inside ([`crate::tin::construct`]).
/// Every build plans a seam so, whichever engine, so two tiles agree. The
/// error is measured from coordinate differences only, so tiles whose
/// lattices differ by whole pixels choose the same samples of a shared
/// seam. Marks the new choices in `chosen`, pushes their sample indices to
/// `new` (a gap's middle before its halves') and returns the worst error
/// left.
pub(crate) fn choose_border(
    point: &dyn Fn(usize) -> [f64; 3],
    side: &[usize],
    chosen: &mut [bool],
    split: Split,
    new: &mut Vec<usize>,
) -> f64 {
    let err = |i: usize, j: usize, k: usize| -> f64 {
        let (p, q, s) = (point(side[i]), point(side[j]), point(side[k]));
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let t = if dx.abs() >= dy.abs() {
            (s[0] - p[0]) / dx
        } else {
            (s[1] - p[1]) / dy
        };
        (s[2] - (p[2] + t * (q[2] - p[2]))).abs()
    };
    let marks: Vec<usize> = (0..side.len()).filter(|&k| chosen[k]).collect();
    let mut gaps: Vec<(usize, usize)> = marks.windows(2).map(|w| (w[0], w[1])).collect();
    let mut worst = 0.0f64;
    while let Some((i, j)) = gaps.pop() {
        let mut best = (0.0f64, usize::MAX);
        for k in i + 1..j {
            let e = err(i, j, k);
            if e > best.0 {
                best = (e, k);
            }
        }
        if best.0 > split.tol {
            let at = if split.halve && (j - i).is_power_of_two() {
                (i + j) / 2
            } else {
                best.1
            };
            chosen[at] = true;
            new.push(side[at]);
            gaps.push((i, at));
            gaps.push((at, j));
        } else {
            worst = worst.max(best.0);
        }
    }
    worst
}

/// A vertex a parent's side is split at: one of the builder's samples, or a
/// point of the side that is no sample (a grid-line crossing, with the
/// reference's height there).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Pt {
    Sample(usize),
    At([f64; 3]),
}

/// One fixed side of a parent at the level being built: the samples on it
/// that stay no vertex (reserved from the greedy refinement), the chain of
/// vertices it is split at from its canonical end to the other (both ends
/// included), and the worst error left along it (samples and crossings).
pub(crate) struct SidePlan {
    pub(crate) reserve: Vec<usize>,
    pub(crate) chosen: Vec<Pt>,
    /// the chosen vertices between the ends in the order the split picked
    /// them (the order they are inserted in: spade breaks ties between
    /// cocircular points by insertion order)
    pub(crate) order: Vec<Pt>,
    pub(crate) err: f64,
}

/// A parent's side by its two ends in canonical order (the smaller in
/// (x, y) first), as bits: the same in both parents sharing it.
pub(crate) type SideKey = [u64; 4];
/// A grid segment by its two pixel centres, or a sample by its position
/// twice, as bits.
pub(crate) type SegKey = [u64; 4];
/// Crossings each side must be split at (besides what its profile picks).
pub(crate) type Forced = rustc_hash::FxHashMap<SideKey, Vec<SegKey>>;

pub(crate) fn side_key(a: &[f64; 3], b: &[f64; 3]) -> SideKey {
    let (p, q) = if (b[0], b[1]) < (a[0], a[1]) {
        (b, a)
    } else {
        (a, b)
    };
    [
        p[0].to_bits(),
        p[1].to_bits(),
        q[0].to_bits(),
        q[1].to_bits(),
    ]
}

/// The key of a sample at `p` among a side's forced points.
pub(crate) fn sample_key(p: &[f64; 3]) -> SegKey {
    [
        p[0].to_bits(),
        p[1].to_bits(),
        p[0].to_bits(),
        p[1].to_bits(),
    ]
}

pub(crate) fn seg_key(c: &Crossing) -> SegKey {
    let [p, q] = c.seg;
    [
        p[0].to_bits(),
        p[1].to_bits(),
        q[0].to_bits(),
        q[1].to_bits(),
    ]
}

/// A crossing on a side: its parameter along the side, the point, whether
/// it is forced, and the crossed grid segment's two pixels.
type SideCrossing = (f64, [f64; 3], bool, [[f64; 3]; 2]);

/// Plan a side from its own profile: its ends `ends` (canonical order,
/// positions `a`, `b`), the samples strictly between them in order along it
/// (`on`: sample, position) and, with a `reference`, its crossings with the
/// grid segments between valid pixels, at their reference heights. A
/// Douglas-Peucker split ([`choose_border`]) of that profile by `split` picks
/// the chain: the two parents sharing the side compute the same profile
/// bit for bit and so the same chain, and a coarse edge becomes, level by
/// level, a profile of the surface along it.
pub(crate) fn plan_side(
    ends: [Pt; 2],
    a: &[f64; 3],
    b: &[f64; 3],
    on: &[(usize, [f64; 3])],
    reference: Option<&dyn Reference>,
    forced: &Forced,
    split: Split,
) -> SidePlan {
    let must: &[SegKey] = forced
        .get(&side_key(a, b))
        .map(|v| v.as_slice())
        .unwrap_or(&[]);
    let ax = if (b[0] - a[0]).abs() >= (b[1] - a[1]).abs() {
        0
    } else {
        1
    };
    let along = |p: &[f64; 3]| (p[ax] - a[ax]) / (b[ax] - a[ax]);
    let mut prof: Vec<(f64, [f64; 3], Pt)> = Vec::with_capacity(on.len() + 2);
    prof.push((0.0, *a, ends[0]));
    let mut crossings: Vec<SideCrossing> = Vec::new();
    if let Some(r) = reference {
        r.for_each_crossing(a, b, &mut |c| {
            crossings.push((c.t, c.p, must.contains(&seg_key(c)), c.seg))
        });
    }
    // a crossing that is one of the side's samples (a soft line's profile
    // point at a grid-line crossing, [`super::build`]'s `with_crossings`,
    // found again here up to rounding) is that sample, forced with it
    let on_t: Vec<f64> = on.iter().map(|s| along(&s.1)).collect();
    let mut on_must = vec![false; on.len()];
    // a crossing with a grid segment that ends at a sample on the side, or
    // at one of its ends, is that sample: were the side exact it would
    // pass through the sample and meet the segment there only, so the
    // crossing is the sample moved by rounding (4.4e-9 pixel on a 1/9"
    // grid, issue 73: kept as a vertex of its own beside the sample, both
    // parents dropped the slivers between them and left a gap)
    let key = |p: &[f64; 3]| (p[0].to_bits(), p[1].to_bits());
    let on_at: std::collections::HashMap<(u64, u64), usize> =
        on.iter().enumerate().map(|(i, s)| (key(&s.1), i)).collect();
    let end_at = |p: &[f64; 3]| {
        ends.iter()
            .zip([a, b])
            .any(|(e, q)| matches!(e, Pt::Sample(_)) && key(q) == key(p))
    };
    crossings.retain(|c| !end_at(&c.3[0]) && !end_at(&c.3[1]));
    crossings.retain(|c| {
        let hit = c.3.iter().find_map(|p| on_at.get(&key(p)).copied());
        if let Some(i) = hit {
            on_must[i] |= c.2;
        }
        hit.is_none()
    });
    crossings.retain(|c| {
        let k = on_t.partition_point(|&t| t < c.0);
        let same = [k.checked_sub(1), Some(k)]
            .into_iter()
            .flatten()
            .find(|&i| on_t.get(i).is_some_and(|&t| (t - c.0).abs() <= 1e-9));
        if let Some(i) = same {
            on_must[i] |= c.2;
        }
        same.is_none()
    });
    let mut prof_must = vec![false];
    let (mut i, mut j) = (0, 0);
    while i < on.len() || j < crossings.len() {
        let ts = on.get(i).map(|s| along(&s.1));
        let tc = crossings.get(j).map(|c| c.0);
        if tc.is_none() || ts.is_some_and(|t| tc.is_some_and(|u| t <= u)) {
            let (s, p) = on[i];
            prof.push((ts.unwrap_or(0.0), p, Pt::Sample(s)));
            prof_must.push(on_must[i] || must.contains(&sample_key(&p)));
            i += 1;
        } else {
            let (t, p, m, _) = crossings[j];
            prof.push((t, p, Pt::At(p)));
            prof_must.push(m);
            j += 1;
        }
    }
    prof.push((1.0, *b, ends[1]));
    prof_must.push(false);
    let idx: Vec<usize> = (0..prof.len()).collect();
    let mut chosen: Vec<bool> = (0..prof.len())
        .map(|k| k == 0 || k + 1 == prof.len() || prof_must[k])
        .collect();
    let mut new = Vec::new();
    let err = choose_border(&|k| prof[k].1, &idx, &mut chosen, split, &mut new);
    let mut plan = SidePlan {
        reserve: Vec::new(),
        chosen: Vec::new(),
        // forced points first (in order along the side), then the split's
        order: (0..prof.len())
            .filter(|&k| prof_must[k])
            .chain(new.iter().copied())
            .map(|k| prof[k].2)
            .collect(),
        err,
    };
    for (e, &ch) in prof.iter().zip(&chosen) {
        if ch {
            plan.chosen.push(e.2);
        } else if let Pt::Sample(s) = e.2 {
            plan.reserve.push(s);
        }
    }
    plan
}

/// Split every triangle whose side runs between two vertices of a chain
/// (the vertices chosen on one edge of the parent, in order along it, by
/// local sample) that are not next to each other in it: the vertices
/// between lie a rounding outside that side (the sliver between was
/// dropped), and the neighbour across the edge meets them. The triangle
/// becomes a fan from its third corner through them. `vsample`: the local
/// sample of each vertex; `vert`: a vertex's position.
pub(crate) fn close_chains(
    tris: Vec<[u32; 3]>,
    chains: &[Vec<usize>],
    vsample: &[u32],
    vert: &dyn Fn(usize) -> [f64; 3],
) -> Vec<[u32; 3]> {
    // chain vertices by vertex: (chain, position in it)
    let mut at: std::collections::HashMap<u32, Vec<(usize, usize)>> =
        std::collections::HashMap::new();
    let mut vertex_of: std::collections::HashMap<usize, u32> = std::collections::HashMap::new();
    for (v, &l) in vsample.iter().enumerate() {
        vertex_of.insert(l as usize, v as u32);
    }
    // (two samples at one place are one vertex: once in its chain)
    let chains: Vec<Vec<u32>> = chains
        .iter()
        .map(|ch| {
            let mut c: Vec<u32> = ch
                .iter()
                .filter_map(|l| vertex_of.get(l).copied())
                .collect();
            c.dedup();
            c
        })
        .collect();
    for (k, ch) in chains.iter().enumerate() {
        for (p, &v) in ch.iter().enumerate() {
            at.entry(v).or_default().push((k, p));
        }
    }
    let mut out = Vec::with_capacity(tris.len());
    // every split makes triangles with fewer chain vertices skipped, so
    // this ends; a budget all the same, so that no input can keep a
    // backend here (whatever is left is kept as it is)
    let mut budget = 64 * (tris.len() + chains.iter().map(Vec::len).sum::<usize>()) + 1024;
    let mut work = tris;
    while let Some(t) = work.pop() {
        if budget == 0 {
            out.push(t);
            continue;
        }
        budget -= 1;
        let mut split = None;
        'edges: for j in 0..3 {
            let (u, v) = (t[j], t[(j + 1) % 3]);
            let (Some(au), Some(av)) = (at.get(&u), at.get(&v)) else {
                continue;
            };
            for &(ku, pu) in au {
                for &(kv, pv) in av {
                    if ku == kv && pu.abs_diff(pv) > 1 {
                        split = Some((j, ku, pu, pv));
                        break 'edges;
                    }
                }
            }
        }
        let Some((j, k, pu, pv)) = split else {
            out.push(t);
            continue;
        };
        let x = t[(j + 2) % 3];
        let path: Vec<u32> = if pu < pv {
            chains[k][pu..=pv].to_vec()
        } else {
            chains[k][pv..=pu].iter().rev().copied().collect()
        };
        for w in path.windows(2) {
            let f = [w[0], w[1], x];
            let p = f.map(|v| vert(v as usize));
            if crate::geom::orient(&p[0], &p[1], &p[2]) > 0.0 {
                work.push(f);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{Split, choose_border};

    /// A seeded rough profile along a row: (x, 0, z).
    fn profile(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut s = seed;
        let mut z = 100.0;
        (0..n)
            .map(|i| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                z += (s % 2001) as f64 / 1000.0 - 1.0 + 0.3 * ((i as f64) / 9.0).sin();
                [i as f64, 0.0, z]
            })
            .collect()
    }

    /// The largest error of the samples strictly between `i` and `j`
    /// against the line between them.
    fn gap_error(p: &[[f64; 3]], i: usize, j: usize) -> f64 {
        (i + 1..j)
            .map(|k| {
                let t = (p[k][0] - p[i][0]) / (p[j][0] - p[i][0]);
                (p[k][2] - (p[i][2] + t * (p[j][2] - p[i][2]))).abs()
            })
            .fold(0.0, f64::max)
    }

    fn choose(p: &[[f64; 3]], split: Split) -> (Vec<usize>, Vec<usize>, f64) {
        let side: Vec<usize> = (0..p.len()).collect();
        let mut chosen: Vec<bool> = (0..p.len()).map(|k| k == 0 || k + 1 == p.len()).collect();
        let mut new = Vec::new();
        let worst = choose_border(&|k| p[k], &side, &mut chosen, split, &mut new);
        let marks = (0..p.len()).filter(|&k| chosen[k]).collect();
        (marks, new, worst)
    }

    /// A side of 2^8 steps (a whole tile side of 256 pixels) is halved:
    /// every gap left is a dyadic interval, each split only because the
    /// interval it halves was over the tolerance, each middle chosen
    /// before its halves', and every sample within the tolerance of its
    /// gap's line (checked here by its own arithmetic).
    #[test]
    fn a_whole_tile_side_is_halved_where_it_needs() {
        for seed in 1..40u64 {
            let p = profile(257, seed * 7919);
            let tol = [0.5, 2.0, 8.0][seed as usize % 3];
            let (marks, new, worst) = choose(&p, Split { tol, halve: true });
            let mut left = 0.0f64;
            for w in marks.windows(2) {
                let (i, j) = (w[0], w[1]);
                let len = j - i;
                assert!(
                    len.is_power_of_two() && i % len == 0,
                    "seed {seed}: gap {i}..{j}"
                );
                let e = gap_error(&p, i, j);
                assert!(e <= tol, "seed {seed}: gap {i}..{j} off by {e}");
                left = left.max(e);
                if len < 256 {
                    // the interval it halves
                    let (a, b) = (i - i % (2 * len), i - i % (2 * len) + 2 * len);
                    assert!(
                        gap_error(&p, a, b) > tol,
                        "seed {seed}: {a}..{b} split needlessly"
                    );
                }
            }
            assert_eq!(worst, left, "seed {seed}");
            // a middle before its halves
            for (n, &k) in new.iter().enumerate() {
                let step = 1 << k.trailing_zeros();
                if step < 128 {
                    let parent = if (k / step) % 4 == 1 {
                        k + step
                    } else {
                        k - step
                    };
                    let at = new.iter().position(|&q| q == parent);
                    assert!(
                        at.is_some_and(|a| a < n),
                        "seed {seed}: {k} before {parent}"
                    );
                }
            }
        }
    }

    /// Any other gap, and any gap of a side no tile shares, is split at
    /// its worst sample (the first of equals).
    #[test]
    fn other_gaps_split_at_their_worst_sample() {
        for seed in 1..80u64 {
            let (n, halve) = if seed % 2 == 0 {
                (101, true)
            } else {
                (257, false)
            };
            let p = profile(n, seed * 104_729);
            let (_, new, _) = choose(&p, Split { tol: 0.5, halve });
            let m = n - 1;
            let want = (1..m)
                .map(|k| {
                    let t = p[k][0] / m as f64;
                    ((p[k][2] - (p[0][2] + t * (p[m][2] - p[0][2]))).abs(), k)
                })
                .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
            if want.0 > 0.5 {
                assert_eq!(new.first(), Some(&want.1), "seed {seed}");
            }
        }
    }
}
