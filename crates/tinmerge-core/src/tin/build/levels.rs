//! A build's levels: level 0 (greedy, or seeded and finished parent by
//! parent), the void triangles outside a boundary, the finer levels.

use super::assemble::*;
use super::builder::*;
use super::common::*;
use super::finer::{ByParents, refine_by_parents};
use super::lines::*;
use super::parents::*;
use crate::interrupt::Interrupt;
use crate::polygon::{Area, Where};
use crate::tin::breaklines::{Breakline, Network};
use crate::tin::dense::Dense;
use crate::tin::samples::{SampleGrid, Samples};
use crate::tin::sides::choose_border;
use crate::tin::surface::{GridReference, Reference};
use crate::tin::{Tin, TinError};

/// What a build makes from its samples: the tolerances and SRID, the
/// options, and what constrains it (none by default: [`Spec::new`]).
pub(super) struct Spec<'a> {
    pub(super) tolerances: &'a [f64],
    pub(super) srid: i32,
    pub(super) opts: BuildOptions,
    /// breaklines held as edges of every level
    pub(super) lines: &'a [Breakline],
    /// the domain's boundaries (none: the samples' hull)
    pub(super) boundaries: &'a [&'a Area],
    /// the samples are pixel centres of a lattice (in its own frame)
    pub(super) on_lattice: bool,
    /// the surface the tolerance holds on between samples (none: at the
    /// samples only, or the lattice's own when `opts.between_samples`)
    pub(super) reference: Option<&'a dyn Reference>,
    /// the seam samples each level keeps
    pub(super) border: &'a Border,
    /// a tile over its data only: the boundary's segments on its seams
    pub(super) seams: Option<&'a SeamLines<'a>>,
}

impl<'a> Spec<'a> {
    /// Scattered samples, no constraint, no border.
    pub(super) fn new(tolerances: &'a [f64], srid: i32, opts: BuildOptions) -> Self {
        const NO_BORDER: &Border = &Border { levels: Vec::new() };
        Spec {
            tolerances,
            srid,
            opts,
            lines: &[],
            boundaries: &[],
            on_lattice: false,
            reference: None,
            border: NO_BORDER,
            seams: None,
        }
    }
}

/// The build. Lattice samples (`on_lattice`) that fill most of their
/// window of the lattice are built in place there ([`build_dense`]);
/// scattered samples, and lattice samples too sparse for that, are
/// bucketed ([`SampleGrid`]) and built the same way on them
/// ([`build_levels`]).
pub(super) fn build_inner(
    samples: Vec<[f64; 3]>,
    spec: &Spec<'_>,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let Spec {
        tolerances,
        srid,
        opts,
        lines,
        boundaries,
        on_lattice,
        reference,
        border,
        seams,
    } = *spec;
    check_tolerances(tolerances)?;
    let constrained = !lines.is_empty() || !boundaries.is_empty();
    if constrained && (on_lattice || (opts.keep_border && seams.is_none())) {
        return Err(TinError::InvalidParameter(
            "internal: breaklines are built on scattered samples without keep_border".into(),
        ));
    }
    if on_lattice && samples.len() <= MAX_SAMPLES {
        if let Some(p) = samples.iter().find(|p| !p[2].is_finite()) {
            return Err(TinError::InvalidParameter(format!(
                "sample coordinates must be finite, got ({}, {}, {})",
                p[0], p[1], p[2]
            )));
        }
        if let Some(d) = dense_of(&samples) {
            drop(samples);
            return build_dense(d, tolerances, srid, opts, border, interrupt);
        }
    }
    let mut pts = prepare_samples(samples)?;
    let mut net = Network::default();
    let mut profiles = Vec::new();
    if constrained && pts.len() >= 3 {
        let tol = *tolerances.last().unwrap_or(&0.0);
        (pts, net, profiles) =
            with_breaklines(pts, lines, boundaries, tol, reference, seams, interrupt)?;
    }
    if !boundaries.is_empty() && net.segs.is_empty() && pts.len() < 3 {
        return Err(no_domain());
    }
    if pts.len() < 3 {
        return Err(TinError::Degenerate(format!(
            "need at least 3 samples with distinct x,y to build a tin, got {}",
            pts.len()
        )));
    }
    // the hull on the (x, y)-sorted samples, found again once bucketed
    let hull_xy: Vec<[f64; 3]> = convex_hull(&pts).into_iter().map(|k| pts[k]).collect();
    let grid = SampleGrid::new(pts, 1.0);
    let hull = hull_xy
        .iter()
        .map(|p| grid.find(p[0], p[1]))
        .collect::<Option<Vec<usize>>>()
        .ok_or_else(|| TinError::Degenerate("internal: a hull sample was lost".into()))?;
    drop(hull_xy);
    let sides = if opts.keep_border {
        hull_sides(&grid.pts, &hull, interrupt)?
    } else {
        Vec::new()
    };
    let (verts, raw_levels) = if net.segs.is_empty() {
        let b: Builder<'_, _, Dt> = start(&grid, &hull, opts.keep_border, reference)?;
        let seam = vec![true; sides.len()];
        build_levels(b, &grid, &sides, &seam, spec, interrupt)?
    } else {
        let segment_sides = segment_sides(&net, &profiles, &grid, seams)?;
        drop(profiles);
        let mut b: Builder<'_, _, Cdt> = start(&grid, &hull, true, reference)?;
        let kept = if seams.is_some() { border.at(0) } else { &[] };
        // a tile's seams, planned at the seam tolerance
        let on_seam: Vec<bool> = net
            .segs
            .iter()
            .map(|s| {
                let (a, b) = (&net.verts[s[0] as usize], &net.verts[s[1] as usize]);
                reference.is_some() && seams.is_some_and(|sl| sl.holds(a, b))
            })
            .collect();
        add_network(
            &mut b,
            &net,
            &segment_sides,
            &on_seam,
            tolerances[0],
            kept,
            &|x, y| grid.find(x, y),
        )?;
        let (sides, seam): (Vec<Vec<usize>>, Vec<bool>) = segment_sides
            .into_iter()
            .zip(on_seam)
            .filter(|s| !s.0.is_empty())
            .unzip();
        // a tile's seams keep what the tiles agreed on; other lines no
        // border
        let no_border = Border::default();
        let segments = Spec {
            border: if seams.is_some() { border } else { &no_border },
            ..*spec
        };
        build_levels(b, &grid, &sides, &seam, &segments, interrupt)?
    };
    drop(grid);
    // on a lattice the grid indexes are built once, by `Lattice::to_world`
    assemble_verified(verts, raw_levels, srid, !on_lattice, interrupt)
}

/// Each soft segment's samples from end to end (a hard one: none), chosen
/// level by level as a tile's seam is; reserved from the greedy
/// refinement of level 0. A seam's samples come in the order the tile
/// beside it takes them (a lattice side's).
fn segment_sides(
    net: &Network,
    profiles: &[Vec<[f64; 3]>],
    grid: &SampleGrid,
    seams: Option<&SeamLines>,
) -> Result<Vec<Vec<usize>>, TinError> {
    let find = |p: &[f64; 3]| grid.find(p[0], p[1]);
    net.segs
        .iter()
        .zip(profiles)
        .map(|(s, prof)| {
            if prof.is_empty() {
                return Some(Vec::new());
            }
            let (a, b) = (&net.verts[s[0] as usize], &net.verts[s[1] as usize]);
            let mut side = vec![find(a)?];
            for p in prof {
                side.push(find(p)?);
            }
            side.push(find(b)?);
            if seams.is_some_and(|sl| sl.holds(a, b)) && (b[0], b[1]) < (a[0], a[1]) {
                side.reverse();
            }
            Some(side)
        })
        .collect::<Option<Vec<Vec<usize>>>>()
        .ok_or_else(|| TinError::Degenerate("internal: a profile sample was lost".into()))
}

/// The error of a boundary that leaves nothing of the samples' extent.
pub(super) fn no_domain() -> TinError {
    TinError::InvalidParameter(
        "the boundary does not overlap the samples' extent: the tin would have no domain".into(),
    )
}

/// Level 0's void triangles (or the seed's, [`build_levels`]): those whose
/// centroid is outside any of the `boundaries`. Their rings within the hull
/// are edges of level 0, so no triangle has parts on both sides; the finer
/// levels inherit ([`refine_by_parents`], [`assemble`]).
pub(super) fn mark_void(
    verts: &[[f64; 3]],
    level0: &mut RawLevel,
    boundaries: &[&Area],
    interrupt: &mut Interrupt<'_>,
) -> Result<(), TinError> {
    let mut void = Vec::with_capacity(level0.tris.len());
    for (k, t) in level0.tris.iter().enumerate() {
        if k % 65536 == 0 {
            interrupt()?;
        }
        let [a, b, c] = t.map(|v| verts[v as usize]);
        let g = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
        void.push(boundaries.iter().any(|a| a.locate(g) == Where::Outside));
    }
    if void.iter().all(|&v| v) {
        return Err(no_domain());
    }
    level0.void = void;
    Ok(())
}

/// Every level: level 0 refined in `b` (the whole domain, its hull
/// inserted; the hull's `sides` under keep_border, or the soft lines',
/// those on a tile's `seam` planned at
/// [`seam_tolerance`]), the finer ones parent by
/// parent on `src`, void outside the spec's `boundaries` (none: the whole
/// hull), to its `tolerances`, keeping its `border`, between samples on its
/// `reference`. The vertices and the levels, for [`assemble`].
pub(super) fn build_levels<S: Samples, T: Tri, P: ParentSamples>(
    mut b: Builder<'_, S, T>,
    src: &P,
    sides: &[Vec<usize>],
    seam: &[bool],
    spec: &Spec<'_>,
    interrupt: &mut Interrupt<'_>,
) -> Result<(Vec<[f64; 3]>, Vec<RawLevel>), TinError> {
    let Spec {
        reference,
        boundaries,
        tolerances,
        opts,
        border,
        ..
    } = *spec;
    // (seams are tighter only where their strips are measured: between
    // samples, as the finer levels' hull sides are)
    let seam: Vec<bool> = seam.iter().map(|&s| s && reference.is_some()).collect();
    let mut level0 = refine_level0(
        &mut b,
        sides,
        &seam,
        tolerances[0],
        SEED_VERTICES,
        border.at(0),
        interrupt,
    )?;
    let (mut verts, vsample) = b.finish();
    if !boundaries.is_empty() {
        mark_void(&verts, &mut level0, boundaries, interrupt)?;
    }
    // a level 0 of more than SEED_VERTICES vertices is refined parent by
    // parent too, over the triangles the whole-domain refinement had when
    // it stopped (the seed, then dropped)
    let seeded = level0.max_error > tolerances[0];
    let mut raw_levels = vec![level0];
    let spec = ByParents {
        src,
        reference,
        tolerances: &tolerances[usize::from(!seeded)..],
        keep_border: opts.keep_border,
        border: border.levels.get(usize::from(!seeded)..).unwrap_or(&[]),
    };
    refine_by_parents(&spec, &mut verts, vsample, &mut raw_levels, interrupt)?;
    if seeded {
        raw_levels.remove(0);
        raw_levels[0].parents = Vec::new();
    }
    Ok((verts, raw_levels))
}

/// Vertices level 0 gets in one triangulation of the whole domain; a level
/// 0 needing more is refined on from there parent by parent (the
/// triangulation of a vertex costs about 150 bytes; a parent's, only while
/// it is refined).
pub(super) const SEED_VERTICES: usize = 65536;

/// A builder of the whole domain on `grid`, its convex `hull` (sample
/// indices) inserted; `keep_border`: flags for the hull sides' samples.
pub(super) fn start<'g, S: Samples, T: Tri>(
    grid: &'g S,
    hull: &[usize],
    keep_border: bool,
    reference: Option<&'g dyn Reference>,
) -> Result<Builder<'g, S, T>, TinError> {
    if hull.len() < 3 {
        return Err(TinError::Degenerate(
            "all samples are collinear: a tin needs at least 3 non-collinear samples".into(),
        ));
    }
    let mut b = Scratch::default().builder(grid, grid.len(), keep_border);
    b.reference = reference;
    for &i in hull {
        b.insert_sample(i, None)?;
    }
    Ok(b)
}

/// Level 0: refine `b` (its hull inserted) to `tol`, the vertices of the
/// hull's `sides` (keep_border) chosen first, from each side's samples
/// alone (a seam's two tiles agree on them; a `seam` side's at
/// [`seam_tolerance`]), those at `forced`
/// positions (the seam's samples both tiles were told to keep,
/// [`Border`]) among them from the start.
pub(super) fn refine_level0<S: Samples, T: Tri>(
    b: &mut Builder<'_, S, T>,
    sides: &[Vec<usize>],
    seam: &[bool],
    tol: f64,
    max_vertices: usize,
    forced: &[[f64; 2]],
    interrupt: &mut Interrupt<'_>,
) -> Result<RawLevel, TinError> {
    let forced: rustc_hash::FxHashSet<(u64, u64)> = forced
        .iter()
        .map(|p| (p[0].to_bits(), p[1].to_bits()))
        .collect();
    for &i in sides.iter().flatten() {
        b.reserved[i] = true;
    }
    let mut border_error = 0.0f64;
    let mut new = Vec::new();
    for (k, side) in sides.iter().enumerate() {
        interrupt()?;
        let grid = b.grid;
        let mut chosen: Vec<bool> = (0..side.len())
            .map(|k| {
                let p = grid.point(side[k]);
                k == 0 || k + 1 == side.len() || forced.contains(&(p[0].to_bits(), p[1].to_bits()))
            })
            .collect();
        for k in 1..side.len().saturating_sub(1) {
            if chosen[k] {
                new.push(side[k]);
            }
        }
        border_error = border_error.max(choose_border(
            &|i| grid.point(i),
            side,
            &mut chosen,
            super::common::seam_split(tol, seam.get(k).copied().unwrap_or(false)),
            &mut new,
        ));
    }
    for i in new {
        if !b.inserted[i] {
            b.insert_sample(i, None)?;
        }
    }
    let max_error = b.refine(tol, max_vertices, interrupt)?.max(border_error);
    Ok(RawLevel {
        tolerance: tol,
        max_error,
        num_vertices: b.dt.num_vertices() as u32,
        tris: b.snapshot(),
        parents: Vec::new(),
        void: Vec::new(),
    })
}

/// The convex hull of the valid samples of `d` (indices into it,
/// counter-clockwise), from each row's first and last sample with data.
pub(crate) fn dense_hull(d: &Dense) -> Vec<usize> {
    lattice_hull(d.width, d.height, &|i| d.valid(i))
}

/// Largest lattice window, in pixels per sample, read in place
/// ([`build_dense`]); sparser samples are bucketed.
pub(super) const DENSE_PIXELS_PER_SAMPLE: usize = 8;

/// The samples of a lattice build in place on their window of the lattice,
/// when it is not much larger than they are and no pixel is given twice.
pub(crate) fn dense_of(samples: &[[f64; 3]]) -> Option<Dense> {
    let (mut c0, mut r0, mut c1, mut r1) = (i64::MAX, i64::MAX, i64::MIN, i64::MIN);
    for p in samples {
        let (c, r) = (p[0] as i64, p[1] as i64);
        (c0, r0, c1, r1) = (c0.min(c), r0.min(r), c1.max(c), r1.max(r));
    }
    if samples.is_empty() {
        return None;
    }
    let (w, h) = ((c1 - c0 + 1) as usize, (r1 - r0 + 1) as usize);
    if w.checked_mul(h)? > DENSE_PIXELS_PER_SAMPLE * samples.len() + (1 << 20) {
        return None;
    }
    let mut d = Dense {
        c0,
        r0,
        width: w,
        height: h,
        z: vec![f64::NAN; w * h],
    };
    for p in samples {
        let i = d.index(p[0] as i64, p[1] as i64);
        if !d.z[i].is_nan() {
            return None;
        }
        d.z[i] = p[2];
    }
    Some(d)
}

/// A lattice build on the samples in place ([`Dense`]): the hull from each
/// row's first and last pixel with data, its sides' samples by gcd steps,
/// level 0 refined in one triangulation and the finer levels parent by
/// parent on windows of the lattice.
pub(super) fn build_dense(
    d: Dense,
    tolerances: &[f64],
    srid: i32,
    opts: BuildOptions,
    border: &Border,
    interrupt: &mut Interrupt<'_>,
) -> Result<Tin, TinError> {
    let count = d.z.iter().filter(|z| !z.is_nan()).count();
    if count < 3 {
        return Err(TinError::Degenerate(format!(
            "need at least 3 samples with distinct x,y to build a tin, got {count}"
        )));
    }
    if opts.keep_border && opts.between_samples {
        // build engine 2 (issue 74)
        return crate::tin::construct::build_dense_kept(&d, tolerances, srid, border, interrupt);
    }
    let hull = dense_hull(&d);
    let whole = d.window(d.c0, d.r0, d.width, d.height);
    let grid_reference = GridReference::on_lattice(&d);
    let reference = opts
        .between_samples
        .then_some(&grid_reference as &dyn Reference);
    let b: Builder<'_, _, Dt> = start(&whole, &hull, opts.keep_border, reference)?;
    let sides: Vec<Vec<usize>> = if opts.keep_border {
        (0..hull.len())
            .map(|k| d.side(hull[k], hull[(k + 1) % hull.len()]))
            .collect()
    } else {
        Vec::new()
    };
    let spec = Spec {
        reference,
        border,
        ..Spec::new(tolerances, srid, opts)
    };
    let seam = vec![true; sides.len()];
    let (verts, raw_levels) = build_levels(b, &d, &sides, &seam, &spec, interrupt)?;
    drop(d);
    assemble_verified(verts, raw_levels, srid, false, interrupt)
}
