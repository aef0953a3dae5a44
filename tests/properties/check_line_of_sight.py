#!/usr/bin/env python3
"""tin_line_of_sight against an oracle written from tin_triangles alone.

For both bundled DEMs (UTM 16N with a nodata border; EPSG:4326), a tin of
5 levels (tolerance 2 m), 10,000 random pairs, each at every level: 50,000
sight lines a DEM. The oracle reads every triangle of the level from
tin_triangles (PostGIS geometries, corners with their heights) and, with
numpy only, clips the sight line's ground track to each triangle it meets
(the three half-planes of a counter-clockwise triangle), puts the sight
line's height minus the triangle's plane at both ends of each piece (linear
between them), and so finds:
 - the clearance: the least of those strictly between observer and target;
 - the verdict: blocked when some piece goes below -1e-9 of the heights
   (the function's promise: touching the sight line is seeing);
 - the obstruction: on the first blocking piece along the line, where the
   sight line first goes below the plane.
Checked: the same verdict for every pair not grazing (|clearance| >= 1e-6 m;
the grazing ones are counted and listed), the obstruction's distance within
1e-6 of the pair's length and its point within 1e-6 relative, the
clearance within 1e-6 m. Triangles are looked up through a bucket grid the
test builds itself (every triangle in each cell its box meets; the cells a
segment's box meets).
"""
import csv
import io
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
HOST = os.path.join(ROOT, "target", "pg")
PORT = os.environ.get("TINMERGE_PORT", "28815")
DB = os.environ.get("TINMERGE_DB", "tinmerge_regress")
PAIRS, LEVELS = 10000, 5


def psql(args, stdin=None):
    return subprocess.run(["psql", "-h", HOST, "-p", PORT, "-U", "postgres", "-d", DB, "-v", "ON_ERROR_STOP=1",
                           "-qAt"] + args, input=stdin, check=True, capture_output=True, text=True).stdout


def rows(query):
    return np.array(list(csv.reader(io.StringIO(psql(["-c", f"COPY ({query}) TO STDOUT WITH CSV"])))), dtype=object)


class Level:
    """The triangles of a level as numpy arrays, with a bucket grid."""

    def __init__(self, tris):
        self.a, self.b, self.c = tris[:, 0:3], tris[:, 3:6], tris[:, 6:9]
        xy = tris.reshape(-1, 3, 3)[:, :, :2]
        area2 = (self.b[:, 0] - self.a[:, 0]) * (self.c[:, 1] - self.a[:, 1]) - \
                (self.c[:, 0] - self.a[:, 0]) * (self.b[:, 1] - self.a[:, 1])
        assert (area2 > 0).all(), "tin_triangles gave a triangle that is not counter-clockwise"
        # plane z = px x + py y + pc
        u, v = self.b - self.a, self.c - self.a
        n = np.cross(u, v)
        self.px, self.py = -n[:, 0] / n[:, 2], -n[:, 1] / n[:, 2]
        self.pc = self.a[:, 2] - self.px * self.a[:, 0] - self.py * self.a[:, 1]
        lo, hi = xy.min(axis=1), xy.max(axis=1)
        self.lo, self.hi = lo, hi
        ext = hi.max(axis=0) - lo.min(axis=0)
        self.origin = lo.min(axis=0)
        self.cell = float(np.sqrt(ext[0] * ext[1] / len(tris)) * 2.0)
        self.nx = int(ext[0] / self.cell) + 1
        self.ny = int(ext[1] / self.cell) + 1
        c0 = np.floor((lo - self.origin) / self.cell).astype(int)
        c1 = np.floor((hi - self.origin) / self.cell).astype(int)
        ids, owners = [], []
        for dx in range(int((c1[:, 0] - c0[:, 0]).max()) + 1):
            for dy in range(int((c1[:, 1] - c0[:, 1]).max()) + 1):
                ok = (c0[:, 0] + dx <= c1[:, 0]) & (c0[:, 1] + dy <= c1[:, 1])
                ids.append((c0[ok, 0] + dx) * self.ny + c0[ok, 1] + dy)
                owners.append(np.nonzero(ok)[0])
        ids, owners = np.concatenate(ids), np.concatenate(owners)
        order = np.argsort(ids, kind="stable")
        self.ids, self.owners = ids[order], owners[order]

    def near(self, p, q):
        """Triangles whose box meets the segment's box (a superset)."""
        lo, hi = np.minimum(p, q), np.maximum(p, q)
        c0 = np.clip(np.floor((lo - self.origin) / self.cell).astype(int), 0, [self.nx - 1, self.ny - 1])
        c1 = np.clip(np.floor((hi - self.origin) / self.cell).astype(int), 0, [self.nx - 1, self.ny - 1])
        cx, cy = np.meshgrid(np.arange(c0[0], c1[0] + 1), np.arange(c0[1], c1[1] + 1))
        want = (cx * self.ny + cy).ravel()
        s, e = np.searchsorted(self.ids, want, "left"), np.searchsorted(self.ids, want, "right")
        cand = np.unique(np.concatenate([self.owners[i:j] for i, j in zip(s, e)] or [np.zeros(0, int)]))
        keep = (self.lo[cand, 0] <= hi[0]) & (self.hi[cand, 0] >= lo[0]) & \
               (self.lo[cand, 1] <= hi[1]) & (self.hi[cand, 1] >= lo[1])
        return cand[keep]


def oracle(lv, o, g, zo, zt):
    """(visible, clearance or None, obstruction distance, obstruction xyz)."""
    d = g - o
    total = float(np.hypot(*d))
    cand = lv.near(o, g)
    t0, t1 = np.zeros(len(cand)), np.ones(len(cand))
    empty = np.zeros(len(cand), bool)
    for a, b in ((lv.a, lv.b), (lv.b, lv.c), (lv.c, lv.a)):
        e = b[cand, :2] - a[cand, :2]
        num = e[:, 0] * (o[1] - a[cand, 1]) - e[:, 1] * (o[0] - a[cand, 0])
        den = e[:, 0] * d[1] - e[:, 1] * d[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = -num / den
        t0 = np.where(den > 0, np.maximum(t0, t), t0)
        t1 = np.where(den < 0, np.minimum(t1, t), t1)
        empty |= (den == 0) & (num < 0)
    ok = ~empty & (t1 > t0)
    cand, t0, t1 = cand[ok], t0[ok], t1[ok]
    order = np.argsort(t0)
    cand, t0, t1 = cand[order], t0[order], t1[order]

    def gap(t):
        x, y = o[0] + t * d[0], o[1] + t * d[1]
        return zo + (zt - zo) * t - (lv.px[cand] * x + lv.py[cand] * y + lv.pc[cand])
    g0, g1 = gap(t0), gap(t1)
    inner = np.concatenate([g0[(t0 > 1e-12) & (t0 < 1 - 1e-12)], g1[(t1 > 1e-12) & (t1 < 1 - 1e-12)]])
    clearance = float(inner.min()) if len(inner) else None
    tol = 1e-9 * max(abs(zo), abs(zt), 1.0)
    below = np.nonzero(np.minimum(g0, g1) < -tol)[0]
    if len(below) == 0:
        return True, clearance, None, None
    k = below[0]
    t = t0[k] if g0[k] <= 0 else t0[k] + (t1[k] - t0[k]) * g0[k] / (g0[k] - g1[k])
    x, y = o[0] + t * d[0], o[1] + t * d[1]
    z = lv.px[cand[k]] * x + lv.py[cand[k]] * y + lv.pc[cand[k]]
    return False, clearance, t * total, np.array([x, y, z])


def check(name, source):
    psql(["-c", f"DROP TABLE IF EXISTS los_prop_tin; CREATE TABLE los_prop_tin AS SELECT tin_from_raster(rast, 2.0, {LEVELS}) AS t FROM {source}"])
    srid, x0, y0, x1, y1 = (float(v) for v in rows(
        "SELECT tin_srid(t), ST_XMin(e), ST_YMin(e), ST_XMax(e), ST_YMax(e) FROM los_prop_tin, tin_envelope(t) e")[0])
    rng = np.random.default_rng(49)
    # observers in the middle of the extent, targets up to a third of its
    # width away in any direction; eyes 0-30 m up, targets on the ground
    # (every other one: it touches the sight line) or up to 10 m up
    w = min(x1 - x0, y1 - y0)
    ox = x0 + (0.15 + 0.7 * rng.random(PAIRS)) * (x1 - x0)
    oy = y0 + (0.15 + 0.7 * rng.random(PAIRS)) * (y1 - y0)
    ang, dist = rng.random(PAIRS) * 2 * np.pi, rng.random(PAIRS) * w / 3
    gx, gy = ox + dist * np.cos(ang), oy + dist * np.sin(ang)
    oh = 30 * rng.random(PAIRS)
    th = np.where(np.arange(PAIRS) % 2 == 0, 0.0, 10 * rng.random(PAIRS))
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack([np.arange(PAIRS), ox, oy, gx, gy, oh, th]), fmt="%.17g", delimiter=",")
    psql(["-c", "DROP TABLE IF EXISTS los_prop_pairs; CREATE TABLE los_prop_pairs (i int, ox float8, oy float8, gx float8, gy float8, oh float8, th float8)"])
    psql(["-c", "COPY los_prop_pairs FROM STDIN WITH CSV"], stdin=buf.getvalue())
    summary = []
    for level in range(LEVELS):
        tris = rows(f"""SELECT ST_X(a), ST_Y(a), ST_Z(a), ST_X(b), ST_Y(b), ST_Z(b), ST_X(c), ST_Y(c), ST_Z(c)
                        FROM los_prop_tin, tin_triangles(t, {level}) tr,
                             LATERAL (SELECT ST_PointN(ST_ExteriorRing(tr.geom), 1) a, ST_PointN(ST_ExteriorRing(tr.geom), 2) b,
                                             ST_PointN(ST_ExteriorRing(tr.geom), 3) c) p""").astype(float)
        lv = Level(tris)
        got = rows(f"""SELECT i, zo, zt, s.visible, ST_X(s.obstruction), ST_Y(s.obstruction), ST_Z(s.obstruction), s.distance, s.clearance
            FROM los_prop_tin, los_prop_pairs p,
                 LATERAL (SELECT ST_SetSRID(ST_MakePoint(ox, oy), {int(srid)}) AS o, ST_SetSRID(ST_MakePoint(gx, gy), {int(srid)}) AS g) q,
                 LATERAL (SELECT tin_height(t, o, {level}) + oh AS zo, tin_height(t, g, {level}) + th AS zt) z,
                 tin_line_of_sight(t, o, g, oh, th, {level}) s
            WHERE zo IS NOT NULL AND zt IS NOT NULL ORDER BY i""")
        n = blocked = grazing = differ = far = clear_off = 0
        listed = []
        for r in got:
            i, zo, zt = int(r[0]), float(r[1]), float(r[2])
            vis = r[3] == "t"
            o, g = np.array([ox[i], oy[i]]), np.array([gx[i], gy[i]])
            total = float(np.hypot(*(g - o)))
            ovis, oclear, odist, opt = oracle(lv, o, g, zo, zt)
            n += 1
            blocked += not ovis
            if oclear is not None and abs(oclear) < 1e-6:
                grazing += 1
                listed.append(f"pair {i}: clearance {oclear:.3g} m, {'seen' if vis else 'hidden'} (oracle {'seen' if ovis else 'hidden'})")
                continue
            if vis != ovis:
                differ += 1
                if differ <= 5:
                    print(f"  {name} level {level} pair {i}: tin_line_of_sight says {'seen' if vis else 'hidden'}, the oracle "
                          f"{'seen' if ovis else 'hidden'} (clearance {oclear})", file=sys.stderr)
                continue
            if (r[8] == "") != (oclear is None) or (oclear is not None and abs(float(r[8]) - oclear) > 1e-6):
                clear_off += 1
                if clear_off <= 5:
                    print(f"  {name} level {level} pair {i}: clearance {r[8]!r}, oracle {oclear}", file=sys.stderr)
            if not vis:
                pt = np.array([float(r[4]), float(r[5]), float(r[6])])
                scale = max(float(np.abs(opt).max()), 1.0)
                if abs(float(r[7]) - odist) > 1e-6 * total or np.abs(pt - opt).max() > 1e-6 * scale:
                    far += 1
                    if far <= 5:
                        print(f"  {name} level {level} pair {i}: obstruction {pt} at {r[7]}, oracle {opt} at {odist}", file=sys.stderr)
        summary.append((level, len(tris), n, blocked, grazing, differ, clear_off, far, listed))
        print(f"  {name} level {level} ({len(tris)} triangles): {n} pairs on the surface, {blocked} blocked; "
              f"{grazing} grazing, {differ} verdicts differ, {clear_off} clearances differ, {far} obstructions off")
        for line in listed[:10]:
            print(f"    grazing: {line}")
    psql(["-c", "DROP TABLE los_prop_tin, los_prop_pairs"])
    return summary


def main():
    bad = []
    for name, source in (("UTM", "dem"), ("geographic", "dem_geo")):
        for level, _, n, blocked, grazing, differ, clear_off, far, _ in check(name, source):
            if n < 0.5 * PAIRS or blocked < 0.05 * n or blocked > 0.95 * n:
                bad.append(f"{name} level {level}: {n} pairs, {blocked} blocked: not a test of both verdicts")
            if differ or clear_off or far:
                bad.append(f"{name} level {level}: {differ} verdicts, {clear_off} clearances, {far} obstructions differ")
            if grazing > 0.001 * n:
                bad.append(f"{name} level {level}: {grazing} grazing pairs of {n}")
    if bad:
        print("line of sight check failed:\n  " + "\n  ".join(bad), file=sys.stderr)
        sys.exit(1)
    print(f"line of sight: 2 DEMs x {LEVELS} levels x {PAIRS} pairs against the oracle from tin_triangles: same verdicts, "
          "obstructions and clearances")


if __name__ == "__main__":
    main()
