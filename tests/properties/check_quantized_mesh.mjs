// Quantized-mesh tiles from SQL read back by an independent decoder
// (loaders.gl's @loaders.gl/terrain, from npm) and checked against PostGIS
// on the same triangles, for the UTM and the geographic tin of the
// regress database (PG* environment variables):
//  - the tiles of a zoom add up, tile by tile, to the level's triangles
//    (tin_triangles through ST_Transform) intersected with the tile by
//    PostGIS, within what quantizing the hull can move;
//  - heights at the decoded vertices equal tin_height at those positions
//    within the quantization (the height step, plus the change of the
//    surface over half a position step, measured around the point);
//  - neighbouring tiles have the same vertices on their shared side;
//  - the level is the one the documented rule gives; off-terrain tiles are
//    NULL, and with fill every tile of zoom 0 is a full tile;
//  - the water mask extension (loaders.gl's decoding) against PostGIS's
//    ST_Intersects at every mask cell's centre, for lakes with an island
//    (one overlapping another) in the tin's UTM SRID; the metadata
//    extension (walked by its own lengths) against layer.json's available
//    tiles cut to the tile.
import { createRequire } from 'node:module';
const require = createRequire(new URL('../../web/package.json', import.meta.url));
const pg = require('pg');
const { default: decode } = await import(new URL('../../web/node_modules/@loaders.gl/terrain/dist/lib/decode-quantized-mesh.js', import.meta.url));

const client = new pg.Client();
await client.connect();
const q = async (sql, params) => (await client.query(sql, params)).rows;
await q(`CREATE TABLE IF NOT EXISTS qm_geo AS SELECT tin_from_raster(rast, 2.0, 4) AS t FROM dem_geo`);
// a terrain stored as tiles (tin_tiles: tins sharing their seams), served as one
await q(`CREATE TABLE IF NOT EXISTS qm_tiles AS SELECT tx, ty, t FROM dem_window, tin_tiles(rast, 100, 2.0, 3)`);

const fail = [];
const check = (ok, msg) => { if (!ok) fail.push(msg); };
const LEVEL0 = 6378137 * 2 * Math.PI * 0.25 / (65 * 2);

function tileBounds(z, x, y) {
  const s = 180 / 2 ** z;
  return [-180 + x * s, -90 + y * s, -180 + (x + 1) * s, -90 + (y + 1) * s];
}

function decodeTile(buf, b) {
  const ab = buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength);
  const d = decode(ab);
  const n = d.vertexData.length / 3;
  const { minHeight, maxHeight } = d.header;
  const pos = [];
  for (let i = 0; i < n; i++) {
    const u = d.vertexData[i], v = d.vertexData[i + n], h = d.vertexData[i + 2 * n];
    pos.push([b[0] + u / 32767 * (b[2] - b[0]), b[1] + v / 32767 * (b[3] - b[1]), minHeight + h / 32767 * (maxHeight - minHeight), u, v]);
  }
  let area = 0;
  const t = d.triangleIndices;
  for (let i = 0; i < t.length; i += 3) {
    const [a, bb, c] = [pos[t[i]], pos[t[i + 1]], pos[t[i + 2]]];
    area += 0.5 * ((bb[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (bb[1] - a[1]));
  }
  return { d, pos, area, hstep: (maxHeight - minHeight) / 32767, n };
}

// One zoom's tiles xs x ys of the terrain `table` (a FROM item giving the
// array ts; `stored` the same tins as rows) cut from `level`: areas against
// PostGIS, heights against tin_height, shared sides; the tiles decoded.
async function checkZoom(name, table, stored, srid, z, level, xs, ys) {
  // the tiles, and PostGIS's area of the level's triangles in each
  const rows = await q(`
    WITH tiles AS (
      SELECT x, y, ST_MakeEnvelope(-180 + x * s, -90 + y * s, -180 + (x + 1) * s, -90 + (y + 1) * s, 4326) AS e
      FROM generate_series($2::int, $3::int) x, generate_series($4::int, $5::int) y, (SELECT 180 / 2.0 ^ $1::int AS s) k),
    tris AS (SELECT ST_Transform(ST_Segmentize(geom, 50), 4326) AS g FROM ${table}, unnest(ts) t, tin_triangles(t, $6)),
    hull AS (SELECT ST_Boundary(ST_ConvexHull(ST_Collect(g))) AS h FROM tris)
    SELECT x, y, tin_quantized_mesh(ts, $1::int, x, y) AS b,
           (SELECT coalesce(sum(ST_Area(ST_Intersection(g, e))), 0) FROM tris WHERE g && e) AS oracle,
           (SELECT ST_Length(ST_Intersection(h, e)) FROM hull) AS hull_len,
           ST_Area(e) AS full
    FROM tiles, ${table}`, [z, xs[0], xs[1], ys[0], ys[1], level]);
  const tiles = new Map();
  let total = 0, oracleTotal = 0, tol = 0;
  for (const row of rows) {
    const b = tileBounds(z, row.x, row.y);
    const ustep = (b[2] - b[0]) / 32767;
    if (row.b === null) { check(row.oracle < 1e-14, `${name} z${z} ${row.x}/${row.y}: NULL but ${row.oracle} deg² of terrain`); continue; }
    const t = decodeTile(row.b, b);
    const tt = ustep * (2 * row.hull_len + 4 * ustep) + 1e-12 * row.full;
    check(Math.abs(t.area - row.oracle) <= tt, `${name} z${z} ${row.x}/${row.y}: decoded area ${t.area}, PostGIS ${row.oracle}, tolerance ${tt}`);
    total += t.area; oracleTotal += row.oracle; tol += tt;
    tiles.set(`${row.x},${row.y}`, { b, t });
  }
  check(Math.abs(total - oracleTotal) <= tol, `${name} z${z}: tiles add up to ${total}, PostGIS ${oracleTotal}`);
  // the zoom's tiles over the terrain were decoded: not a pass by having none
  check(tiles.size > 0 && oracleTotal > 0, `${name} z${z}: ${tiles.size} tiles decoded, PostGIS has ${oracleTotal} deg² of terrain there`);
  // heights: up to 25 vertices a tile, with the surface around each
  const pts = [];
  for (const { b, t } of tiles.values()) {
    const step = [(b[2] - b[0]) / 32767 / 2, (b[3] - b[1]) / 32767 / 2];
    for (let i = 0; i < t.n; i += Math.max(1, Math.floor(t.n / 25))) pts.push([...t.pos[i], step[0], step[1], t.hstep]);
  }
  const hs = await q(`
    WITH p AS (SELECT * FROM unnest($1::float8[], $2::float8[], $3::float8[], $4::float8[]) WITH ORDINALITY AS p(lon, lat, du, dv, i))
    SELECT i,
      (SELECT array_agg(h ORDER BY k)
       FROM (VALUES (1, 0, 0), (2, 1, 0), (3, -1, 0), (4, 0, 1), (5, 0, -1)) o(k, a, c),
            LATERAL (SELECT ST_Transform(ST_SetSRID(ST_MakePoint(lon + a * du, lat + c * dv), 4326), $5::int) AS pt) m,
            -- the height of a terrain made of tins: any tin whose extent holds the point
            LATERAL (SELECT (SELECT z FROM (SELECT tin_height(r.t, pt, $6::int) AS z FROM ${stored} r WHERE tin_envelope(r.t) && pt) y
                             ORDER BY z IS NULL LIMIT 1) AS h) v) AS h
    FROM p ORDER BY 1`,
    [pts.map((p) => p[0]), pts.map((p) => p[1]), pts.map((p) => p[5]), pts.map((p) => p[6]), srid, level]);
  let worst = 0, off = 0, kinked = 0;
  const edge = [];
  for (const { i, h } of hs) {
    const p = pts[i - 1];
    if (h[0] === null) { off++; continue; }
    // at the edge of the domain (a point around it off the terrain) the
    // surface over the position step is not measured by its neighbours:
    // checked below against the triangles there
    if (h.slice(1).some((v) => v === null)) { edge.push(p); continue; }
    const around = (k) => (h[k] === null ? 0 : Math.abs(h[k] - h[0]));
    const tolh = p[7] + Math.max(around(1), around(2)) + Math.max(around(3), around(4)) + 1e-6;
    const err = Math.abs(p[2] - h[0]);
    // the bound above holds where the surface is linear over the position
    // step; where the step spans a kink (at the coarsest zooms a step is
    // hundreds of metres) the vertex is checked as one on the edge is
    if (err > tolh) { kinked++; edge.push(p); continue; }
    worst = Math.max(worst, err / tolh);
  }
  check(pts.length > 0, `${name} z${z}: no decoded vertex to check`);
  // a vertex at the edge of the domain, or whose position step spans a
  // kink: its true place is within the position step, so its height is
  // within the heights of the level's triangles within that step of it
  // (PostGIS), to the height step
  if (edge.length > 0) {
    const range = await q(`
      WITH p AS (SELECT * FROM unnest($1::float8[], $2::float8[], $3::float8[]) WITH ORDINALITY AS p(lon, lat, d, i))
      SELECT i, (SELECT array[min(ST_ZMin(tr.geom)), max(ST_ZMax(tr.geom))] FROM ${table}, unnest(ts) t, tin_triangles(t, $4) tr
                 WHERE ST_DWithin(ST_Transform(tr.geom, 4326), ST_SetSRID(ST_MakePoint(lon, lat), 4326), d)) AS r
      FROM p ORDER BY i`,
      [edge.map((p) => p[0]), edge.map((p) => p[1]), edge.map((p) => 2 * Math.hypot(p[5], p[6])), level]);
    for (const { i, r } of range) {
      const p = edge[i - 1];
      check(r[0] !== null && p[2] >= r[0] - p[7] - 1e-6 && p[2] <= r[1] + p[7] + 1e-6,
            `${name} z${z}: vertex at ${p[0]}, ${p[1]} (on the domain's edge or a kink within its step) has height ${p[2]}, the triangles within a step of it ${r}`);
    }
  }
  // a vertex off the terrain is one quantizing moved off its edge: PostGIS
  // finds a triangle of the level within one position step (the diagonal
  // of the step) of it, every one of them
  if (off > 0) {
    const offPts = hs.filter(({ h }) => h[0] === null).map(({ i }) => pts[i - 1]);
    const near = await q(`
      WITH p AS (SELECT * FROM unnest($1::float8[], $2::float8[], $3::float8[]) WITH ORDINALITY AS p(lon, lat, d, i))
      SELECT count(*) FILTER (WHERE EXISTS (
               SELECT FROM ${table}, unnest(ts) t, tin_triangles(t, $4) tr
               WHERE ST_DWithin(ST_Transform(tr.geom, 4326), ST_SetSRID(ST_MakePoint(lon, lat), 4326), d))) AS near
      FROM p`,
      [offPts.map((p) => p[0]), offPts.map((p) => p[1]), offPts.map((p) => 2 * Math.hypot(p[5], p[6])), level]);
    check(Number(near[0].near) === off, `${name} z${z}: ${off - Number(near[0].near)} of ${off} vertices off the terrain are further than a position step from it`);
  }
  // shared sides
  let shared = 0;
  for (const [k, { t }] of tiles) {
    const [x, y] = k.split(',').map(Number);
    for (const [dx, dy, mine, theirs, along] of [[1, 0, 'eastIndices', 'westIndices', 4], [0, 1, 'northIndices', 'southIndices', 3]]) {
      const o = tiles.get(`${x + dx},${y + dy}`);
      if (!o) continue;
      const a = [...new Set(Array.from(t.d[mine], (i) => t.pos[i][along]))].sort((p, q2) => p - q2);
      const b = [...new Set(Array.from(o.t.d[theirs], (i) => o.t.pos[i][along]))].sort((p, q2) => p - q2);
      check(a.join() === b.join(), `${name} z${z}: side between ${x},${y} and ${x + dx},${y + dy}: ${a.length} against ${b.length} vertices`);
      shared += a.length;
    }
  }
  console.log(`  ${name} z${z} (level ${level}): ${tiles.size} tiles, areas within ${tol.toExponential(1)} deg², ${pts.length} heights (worst ${(100 * worst).toFixed(0)} % of tolerance, ${edge.length - kinked} on the domain's edge, ${kinked} over a kink, ${off} off the terrain), ${shared} shared side vertices`);
  return tiles;
}

// every terrain as an array of tins (one for a single tin): the array form
// of tin_quantized_mesh; pg_regress serve checks it gives the single form's
// bytes for one tin
// (`stored` is the same terrain as table rows: heights read the stored
// values, which the extension's cache keeps, not a copy inside an array)
for (const [name, table, stored] of [['utm', '(SELECT ARRAY[t] AS ts FROM terrain) s', 'terrain'], ['geographic', '(SELECT ARRAY[t] AS ts FROM qm_geo) s', 'qm_geo'],
                             ['utm tiled', '(SELECT array_agg(t ORDER BY ty, tx) AS ts FROM qm_tiles) s', 'qm_tiles']]) {
  const [{ errors, layer, srid }] = await q(`SELECT tin_quantized_mesh_layer(ts) AS layer, tin_srid(ts[1]) AS srid,
      (SELECT array_agg(m ORDER BY lv) FROM (SELECT (l->>'level')::int AS lv, max(greatest((l->>'tolerance')::float8, (l->>'max_error')::float8)) AS m
         FROM unnest(ts) t, jsonb_array_elements(tin_info(t)->'levels') l GROUP BY 1) x) AS errors FROM ${table}`);
  const levelFor = (z) => { const e = LEVEL0 / 2 ** z; const i = errors.findIndex((m) => m <= e); return i < 0 ? errors.length - 1 : i; };
  const top = layer.maxzoom;
  check(levelFor(top) === errors.length - 1 && levelFor(top - 1) !== errors.length - 1, `${name}: maxzoom ${top} is not the first zoom of the finest level`);
  // zooms: where the terrain spans a few tiles, dozens, hundreds, and a block at maxzoom
  for (const z of [10, 12, top]) {
    const r = layer.available[z][0];
    let xs = [r.startX, r.endX], ys = [r.startY, r.endY];
    if (z === top) { const cx = (xs[0] + xs[1]) >> 1, cy = (ys[0] + ys[1]) >> 1; xs = [cx - 2, cx + 2]; ys = [cy - 2, cy + 2]; }
    await checkZoom(name, table, stored, srid, z, levelFor(z), xs, ys);
  }
  // off the terrain: NULL; with fill a whole tile
  const [{ b0, f0, fw }] = await q(`SELECT tin_quantized_mesh(ts, 0, 1, 0) AS b0, tin_quantized_mesh(ts, 0, 1, 0, fill => 0) AS f0,
      tin_quantized_mesh(ts, 0, 0, 0, fill => 0) AS fw FROM ${table}`);
  check(b0 === null, `${name}: the eastern root tile is not NULL`);
  const f = decodeTile(f0, tileBounds(0, 1, 0));
  check(Math.abs(f.area - 180 * 180) < 1e-6 && f.d.triangleIndices.length === 6, `${name}: the filled eastern root tile covers ${f.area} deg² in ${f.d.triangleIndices.length / 3} triangles`);
  // the western one holds the terrain and the fill around it
  const w = decodeTile(fw, tileBounds(0, 0, 0));
  check(Math.abs(w.area - 180 * 180) < 1e-6, `${name}: the filled western root tile covers ${w.area} deg²`);
}

// One terrain from zoom 0 to the finest (tin_overviews): a table of 128-px
// raster tiles (ST_Tile) and its PostGIS overviews (ST_CreateOverview,
// factors 2 and 4), for the UTM DEM (nodata along its rotated border) and
// the geographic one. At every zoom an overview serves and the tiles'
// first two, one layer serves; a tile from the rows the documented indexed query finds
// is at most 4 tins and the same bytes as from the whole layer; and the
// zoom's tiles pass checkZoom (areas, heights against tin_height of the
// level served, shared sides), all of them where a zoom has 16 or fewer,
// else a block of 3 x 3. Each zoom's tiles cover at least the base layer's
// area (printed; an overview reaches past the data's edge by up to about
// two of its pixels, and quantized vertices move the edge by up to half a
// quantum); pg_regress overviews checks with PostGIS that every layer's
// domain holds the base layer's.
for (const [name, base, rast, seg] of [['utm pyramid', 'qm_pyr_utm', 'dem', 100], ['geographic pyramid', 'qm_pyr_geo', 'dem_geo', 0.001]]) {
  await q(`DROP TABLE IF EXISTS ${base}, o_2_${base}, o_4_${base}, ${base}_t`);
  await q(`CREATE TABLE ${base} AS SELECT ST_Tile(rast, 128, 128) AS rast FROM ${rast}`);
  await q(`SELECT AddRasterConstraints('${base}'::name, 'rast'::name)`);
  await q(`SELECT ST_CreateOverview('${base}'::regclass, 'rast', 2), ST_CreateOverview('${base}'::regclass, 'rast', 4)`);
  await q(`CREATE TABLE ${base}_t AS SELECT * FROM tin_overviews('${base}', 2.0, 3)`);
  const env = `ST_Transform(ST_Segmentize(tin_envelope(t), ${seg}), 4326)`;
  await q(`CREATE INDEX ON ${base}_t USING gist ((${env}))`);
  const layers = await q(`SELECT factor, minzoom, maxzoom, count(*)::int AS n FROM ${base}_t GROUP BY 1, 2, 3 ORDER BY 1`);
  check(layers.length === 3 && layers[2].minzoom === 0 && layers[0].maxzoom === 24 &&
        layers.every((l, i) => i === 0 || l.maxzoom === layers[i - 1].minzoom - 1), `${name}: layers ${JSON.stringify(layers)}`);
  const [{ layer, srid }] = await q(`SELECT tin_quantized_mesh_layer(array_agg(t)) AS layer, min(tin_srid(t)) AS srid FROM ${base}_t WHERE factor = 1`);
  const [{ basearea }] = await q(`SELECT sum(ST_Area(ST_Transform(geom, 4326))) AS basearea FROM ${base}_t, tin_triangles(t) WHERE factor = 1`);
  let most = 0, zooms = 0, coverage = Infinity;
  // every zoom an overview serves and the tiles' first two (deeper, the
  // tiles are a tiled terrain like qm_tiles above)
  const last = Math.min(layer.maxzoom, layers[0].minzoom + 1);
  for (let z = 0; z <= last; z++) {
    const at = `(SELECT factor, t, tx, ty FROM ${base}_t WHERE ${z} BETWEEN minzoom AND maxzoom)`;
    const [{ factors, errors }] = await q(`SELECT array_agg(DISTINCT factor) AS factors,
        (SELECT array_agg(m ORDER BY lv) FROM (SELECT (l->>'level')::int AS lv, max(greatest((l->>'tolerance')::float8, (l->>'max_error')::float8)) AS m
           FROM ${at} r, jsonb_array_elements(tin_info(r.t)->'levels') l GROUP BY 1) x) AS errors FROM ${at} r`);
    check(factors.length === 1, `${name} z${z}: served by layers ${factors}`);
    const e = LEVEL0 / 2 ** z;
    let level = errors.findIndex((m) => m <= e);
    if (level < 0) level = errors.length - 1;
    const r = layer.available[z][0];
    let xs = [r.startX, r.endX], ys = [r.startY, r.endY];
    const all = (xs[1] - xs[0] + 1) * (ys[1] - ys[0] + 1) <= 16;
    if (!all) { const cx = (xs[0] + xs[1]) >> 1, cy = (ys[0] + ys[1]) >> 1; xs = [cx - 1, cx + 1]; ys = [cy - 1, cy + 1]; }
    const tiles = await checkZoom(`${name} (factor ${factors[0]})`, `(SELECT array_agg(t ORDER BY ty, tx) AS ts FROM ${at} r) s`, at, srid, z, level, xs, ys);
    // the indexed query's rows: at most 4, and the same tile
    const idx = await q(`
      SELECT x, y, (SELECT count(*) FROM ${base}_t WHERE $1 BETWEEN minzoom AND maxzoom AND ${env} && e)::int AS n,
             (SELECT tin_quantized_mesh(array_agg(t ORDER BY ty, tx), $1, x, y) FROM ${base}_t WHERE $1 BETWEEN minzoom AND maxzoom AND ${env} && e)
               IS NOT DISTINCT FROM (SELECT tin_quantized_mesh(array_agg(t ORDER BY ty, tx), $1, x, y) FROM ${base}_t WHERE $1 BETWEEN minzoom AND maxzoom) AS same
      FROM generate_series($2::int, $3::int) x, generate_series($4::int, $5::int) y,
           LATERAL (SELECT ST_MakeEnvelope(-180 + x * s, -90 + y * s, -180 + (x + 1) * s, -90 + (y + 1) * s, 4326) AS e FROM (SELECT 180 / 2.0 ^ $1::int AS s) k) k`,
      [z, xs[0], xs[1], ys[0], ys[1]]);
    for (const t of idx) {
      most = Math.max(most, t.n);
      check(t.n <= 4, `${name} z${z} ${t.x}/${t.y}: the index finds ${t.n} tins`);
      check(t.same, `${name} z${z} ${t.x}/${t.y}: the tile from the index's tins differs from the whole layer's`);
    }
    if (all) {
      let area = 0;
      for (const { t } of tiles.values()) area += t.area;
      coverage = Math.min(coverage, area / basearea);
    }
    zooms++;
  }
  check(zooms > 10 && layers[0].minzoom > 2 && coverage > 0.999, `${name}: ${zooms} zooms, coverage of the base domain ${coverage}`);
  console.log(`  ${name}: layers ${layers.map((l) => `x${l.factor} z${l.minzoom}..${l.maxzoom} (${l.n} tins)`).join(', ')}; zooms 0..${last}: at most ${most} tins a tile, each zoom covering at least ${(100 * coverage).toFixed(2)} % of the base layer's area`);
}

// water and metadata, on the UTM tin (one tin) and the same lakes over the tiled terrain
await q(`DROP TABLE IF EXISTS qm_lakes`);
await q(`CREATE TABLE qm_lakes AS
  SELECT ST_Difference(ST_Buffer(c, 2500, 64), ST_Buffer(ST_Translate(c, 300, 200), 500, 16)) AS geom FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) s
  UNION ALL SELECT ST_Buffer(ST_Translate(c, 2200, -1000), 450, 8) FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) s`);
const [{ lw, ls, le, ln }] = await q(`SELECT ST_XMin(e) AS lw, ST_YMin(e) AS ls, ST_XMax(e) AS le, ST_YMax(e) AS ln
  FROM (SELECT ST_Extent(ST_Transform(geom, 4326))::geometry AS e FROM qm_lakes) s`);
for (const [name, table] of [['utm', '(SELECT ARRAY[t] AS ts FROM terrain) s'], ['utm tiled', '(SELECT array_agg(t ORDER BY ty, tx) AS ts FROM qm_tiles) s']]) {
  const [{ layer }] = await q(`SELECT tin_quantized_mesh_layer(ts, water => true, metadata => true) AS layer FROM ${table}`);
  check(['watermask', 'metadata'].every((e) => layer.extensions.includes(e)), `${name}: layer.json extensions ${layer.extensions}`);
  let cells = 0, wrong = 0, grazing = 0, full = 0, single = [0, 0], metas = 0;
  for (const [z, block] of [[13, null], [15, 4]]) {
    const s = 180 / 2 ** z;
    let [x0, x1] = [Math.floor((lw + 180) / s), Math.floor((le + 180) / s)];
    let [y0, y1] = [Math.floor((ls + 90) / s), Math.floor((ln + 90) / s)];
    if (block) { const cx = (x0 + x1) >> 1, cy = (y0 + y1) >> 1; [x0, x1, y0, y1] = [cx - block, cx - 1, cy - block, cy - 1]; }
    for (let x = x0; x <= x1; x++) {
      for (let y = y0; y <= y1; y++) {
        const [{ plain, tile }] = await q(`SELECT tin_quantized_mesh(ts, $1::int, $2::int, $3::int) AS plain,
            tin_quantized_mesh(ts, $1::int, $2::int, $3::int, water => (SELECT ST_Collect(geom) FROM qm_lakes), metadata => true) AS tile FROM ${table}`, [z, x, y]);
        if (tile === null) { check(plain === null, `${name} ${z}/${x}/${y}: NULL with water, not without`); continue; }
        const b = tileBounds(z, x, y);
        const mask = new Uint8Array(decodeTile(tile, b).d.extensions.waterMask || new ArrayBuffer(0));
        check(mask.length === 1 || mask.length === 65536, `${name} ${z}/${x}/${y}: a water mask of ${mask.length} bytes`);
        // PostGIS: every cell centre in any lake (each lake on its own, so the overlap is plainly water)
        const [{ bits, near }] = await q(`
          WITH l AS (SELECT ST_Transform(geom, 4326) AS g FROM qm_lakes),
               b AS (SELECT $1::float8 AS w, $2::float8 AS s, $3::float8 AS e, $4::float8 AS n),
               c AS (SELECT i, j, ST_SetSRID(ST_MakePoint(w + (j + 0.5) * (e - w) / 256, n - (i + 0.5) * (n - s) / 256), 4326) AS p
                     FROM b, generate_series(0, 255) i, generate_series(0, 255) j)
          SELECT string_agg(CASE WHEN EXISTS (SELECT FROM l WHERE ST_Intersects(l.g, p)) THEN '1' ELSE '0' END, '' ORDER BY i, j) AS bits,
                 array_agg(i * 256 + j) FILTER (WHERE EXISTS (SELECT FROM l WHERE ST_DWithin(ST_Boundary(l.g), p, 1e-9))) AS near
          FROM c`, b);
        const nearSet = new Set(near || []);
        for (let k = 0; k < 65536; k++) {
          const got = mask.length === 1 ? mask[0] : mask[k];
          const want = bits[k] === '1' ? 255 : 0;
          cells++;
          if (got !== want) { if (nearSet.has(k)) grazing++; else { wrong++; if (wrong <= 5) check(false, `${name} ${z}/${x}/${y}: cell ${k >> 8}, ${k & 255} is ${got}, PostGIS says ${want}`); } }
        }
        if (mask.length === 1) single[mask[0] ? 1 : 0]++; else full++;
        // the extensions after the plain tile: water (2), then metadata (4) by their lengths
        const ext = tile.subarray(plain.length);
        const dv = new DataView(ext.buffer, ext.byteOffset, ext.byteLength);
        let pos = 0, meta = null;
        while (pos < ext.length) {
          const id = dv.getUint8(pos), len = dv.getUint32(pos + 1, true);
          if (id === 4) meta = JSON.parse(Buffer.from(ext.subarray(pos + 9, pos + 9 + dv.getUint32(pos + 5, true))).toString());
          pos += 5 + len;
        }
        check(pos === ext.length, `${name} ${z}/${x}/${y}: the extensions' lengths overrun the tile`);
        // what layer.json says of the 10 zooms below, cut to this tile
        const want = [];
        for (let k = 1; k <= 10 && z + k <= layer.maxzoom; k++) {
          const r = layer.available[z + k][0];
          const c = { startX: Math.max(r.startX, x * 2 ** k), startY: Math.max(r.startY, y * 2 ** k),
                      endX: Math.min(r.endX, (x + 1) * 2 ** k - 1), endY: Math.min(r.endY, (y + 1) * 2 ** k - 1) };
          want.push(c.startX <= c.endX && c.startY <= c.endY ? [c] : []);
        }
        check(meta && JSON.stringify(meta.available.map((l) => l.map((r) => [r.startX, r.startY, r.endX, r.endY])))
                      === JSON.stringify(want.map((l) => l.map((r) => [r.startX, r.startY, r.endX, r.endY]))),
              `${name} ${z}/${x}/${y}: metadata ${JSON.stringify(meta)}, layer.json cut to the tile ${JSON.stringify(want)}`);
        metas++;
      }
    }
  }
  check(full > 0 && single[0] + single[1] > 0, `${name}: ${full} mixed masks, ${single[0]} all land, ${single[1]} all water: not every form seen`);
  check(wrong === 0, `${name}: ${wrong} of ${cells} water mask cells differ from PostGIS away from a lake's edge`);
  console.log(`  ${name} water: ${cells} mask cells in ${full} mixed tiles and ${single[0]} + ${single[1]} one-byte (land + water): ${wrong} differ from PostGIS, ${grazing} on an edge; metadata of ${metas} tiles = layer.json`);
}
await client.end();
if (fail.length) {
  console.error(`quantized-mesh check failed (${fail.length}):\n  ` + fail.slice(0, 20).join('\n  '));
  process.exit(1);
}
console.log('quantized-mesh tiles: decoded by loaders.gl, areas, heights and shared sides agree with PostGIS');
