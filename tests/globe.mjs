// CesiumJS draws the terrain served from the database: web/terrain-server.mjs
// (tin_quantized_mesh, tin_quantized_mesh_layer) on the regress database's
// UTM terrain, the globe page in Debian's headless Chromium (WebGL through
// SwiftShader, driven by puppeteer-core). Checks:
//  - the view drew the globe: pixels that are not background, in many
//    shades (the lit relief), and a screenshot in target/globe-test/;
//  - Cesium's sampleTerrainMostDetailed at 100 points inside the terrain
//    agrees with tin_height (the level Cesium's deepest tiles are cut
//    from: the finest) within the quantization alone (height step, and
//    the steepest nearby gradient times a position step);
//  - the server answered every tile Cesium asked for;
//  - the same for the DEM window stored as 16 tin_tiles, served as one
//    terrain (the array form, tins picked by their extent in degrees);
//  - the picture: the camera frames the terrain obliquely, draped with its
//    hillshade; at least half of the frame is terrain (hillshade pixels);
//  - water: two lakes (one with an island) served as the tiles' water
//    mask; Cesium's water effect (the frame with it against the same frame
//    without) changes the pixels whose ground (globe.pick) PostGIS puts
//    inside a lake and not those outside, away from the shores, over the
//    terrain's extent (beyond it Cesium draws its own fill, and a seam of
//    that fill near the horizon changed with the effect in some runs);
//    and every served tile drawn there has its own mask (else Cesium
//    borrows an ancestor's coarse one).
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const require = createRequire(path.join(root, 'web', 'package.json'));
const pg = require('pg');
const puppeteer = require('puppeteer-core');
const { start } = await import(path.join(root, 'web', 'terrain-server.mjs'));

const out = path.join(root, 'target', 'globe-test');
fs.mkdirSync(out, { recursive: true });
const db = new pg.Client();
await db.connect();
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-dev-shm-usage', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--ignore-gpu-blocklist', '--window-size=1200,800'],
});
const fail = [];

// One terrain on the globe: `tins` is SQL giving its tins (one row each),
// `tiled` serves them with the array form.
async function run(label, table, tiled, shot, water) {
  const tins = `SELECT t FROM ${table}`;
  const [{ zmin, tol }] = (await db.query(`SELECT min((tin_info(t)->'z_range'->>0)::float8) AS zmin,
      max((tin_info(t)->'levels'->-1->>'tolerance')::float8) AS tol FROM (${tins}) s`)).rows;
  const fill = Number.isFinite(zmin) ? Math.floor(zmin) : 0;
  const server = await start({ port: 0, table, fill, tiled, water });
  const page = await browser.newPage();
  try {
    await page.setViewport({ width: 1200, height: 800 });
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
    await page.goto(`http://127.0.0.1:${server.port}/`, { waitUntil: 'load', timeout: 120000 });
    await page.evaluate(() => window.globe.then(() => true));
    const view = await page.evaluate(() => window.settled());
    await page.screenshot({ path: path.join(out, shot) });
    console.log(`  ${label}: view ${view.width} x ${view.height}: ${view.drawn} pixels drawn in ${view.shades} shades; ${server.stats.tiles} tiles served (${server.stats.empty} empty), ${(server.stats.ms / Math.max(1, server.stats.tiles)).toFixed(1)} ms each`);
    if (!view.settled) fail.push(`${label}: the view never settled (tiles still loading after a minute)`);
    if (view.drawn < 0.25 * view.width * view.height) fail.push(`${label}: only ${view.drawn} pixels drawn`);
    if (view.shades < 30) fail.push(`${label}: only ${view.shades} shades: the relief is not lit`);
    const share = await page.evaluate(() => window.terrainShare());
    console.log(`  ${label}: ${(100 * share).toFixed(1)} % of the frame is terrain (hillshade)`);
    if (share < 0.5) fail.push(`${label}: only ${(100 * share).toFixed(1)} % of the frame is terrain`);
    const layer = await (await fetch(`http://127.0.0.1:${server.port}/terrain/layer.json`)).json();
    if (water) {
      const px = await page.evaluate(() => window.waterPixels(8));
      // PostGIS: inside a lake or not, and how far from its shore (metres)
      const rows = (await db.query(`
        WITH p AS (SELECT * FROM unnest($1::float8[], $2::float8[]) WITH ORDINALITY AS p(lon, lat, i))
        SELECT i, EXISTS (SELECT FROM ${water} l WHERE ST_Intersects(l.geom, ST_Transform(ST_SetSRID(ST_MakePoint(lon, lat), 4326), ST_SRID(l.geom)))) AS inside,
               (SELECT min(ST_Distance(ST_Boundary(l.geom), ST_Transform(ST_SetSRID(ST_MakePoint(lon, lat), 4326), ST_SRID(l.geom)))) FROM ${water} l) AS shore,
               EXISTS (SELECT FROM (${tins}) s WHERE ST_Intersects(tin_envelope(t), ST_Transform(ST_SetSRID(ST_MakePoint(lon, lat), 4326), ST_SRID(tin_envelope(t))))) AS served
        FROM p ORDER BY i`, [px.map((p) => p[2]), px.map((p) => p[3])])).rows;
      const margin = 60;
      let [wet, wetDrawn, dry, dryDrawn, away, awayDrawn] = [0, 0, 0, 0, 0, 0];
      const wrong = new Map(); // the tiles drawn at land pixels with water
      const borrowed = new Set(); // served tiles drawn without their own mask
      let seen = 0; // pixels whose tile was found
      rows.forEach((r, k) => {
        const t = px[k][5];
        if (t) seen++;
        if (r.served && t && t.served && !t.ownMask) borrowed.add(t.tile);
        // ground the terrain does not reach (toward the horizon, up to
        // thousands of km away) is Cesium's own fill of the coarse tiles
        // around the terrain: not what the water mask is checked on
        if (!r.served) { away++; if (px[k][4]) awayDrawn++; return; }
        if (r.shore < margin) return;
        if (r.inside) { wet++; if (px[k][4]) wetDrawn++; } else {
          dry++;
          if (px[k][4]) { dryDrawn++; const key = t ? `${t.tile} (mask ${t.mask})` : '?'; wrong.set(key, (wrong.get(key) || 0) + 1); }
        }
      });
      console.log(`  ${label}: water drawn at ${wetDrawn} of ${wet} sampled pixels over the lakes, ${dryDrawn} of ${dry} over land (${margin} m from a shore or more); ${away} pixels beyond the terrain left out (${awayDrawn} changed)`);
      if (wet < 50) fail.push(`${label}: only ${wet} sampled pixels over the lakes: the lakes are not in view`);
      if (wetDrawn < 0.95 * wet) fail.push(`${label}: water drawn at only ${wetDrawn} of ${wet} pixels over the lakes`);
      if (dryDrawn > 0.01 * dry) fail.push(`${label}: water drawn at ${dryDrawn} of ${dry} pixels over land`);
      if (wrong.size) console.log(`  ${label}: the land pixels with water, by the tile drawn there: ${[...wrong].map(([t, n]) => `${t}: ${n}`).join(', ')}`);
      // every tile the server answers carries its mask (one byte when all
      // land): without it Cesium borrows an ancestor's coarse mask, which
      // drew water over whole land tiles in some runs (CI, 2026-12-02)
      if (seen < 0.5 * rows.length) fail.push(`${label}: the tile drawn was found at ${seen} of ${rows.length} pixels (Cesium's internals changed? web/globe.html drawnTile)`);
      if (borrowed.size) fail.push(`${label}: tiles drawn without their own water mask: ${[...borrowed].slice(0, 5).join(', ')}`);
      if (server.stats.water === 0) fail.push(`${label}: Cesium asked for no water mask`);
    }
    // 100 points inside the terrain, their heights from tin_height (of any
    // tin holding the point: on a seam all give the same)
    const pts = (await db.query(`
      WITH h AS (SELECT ST_ConvexHull(ST_Collect(geom)) AS g FROM (${tins}) s, tin_triangles(t, 0)),
           p AS (SELECT (ST_Dump(ST_GeneratePoints(ST_Buffer(g, -200), 100, 27))).geom AS p FROM h)
      SELECT ST_X(ST_Transform(p, 4326)) AS lon, ST_Y(ST_Transform(p, 4326)) AS lat,
             (SELECT tin_height(t, p) FROM (${tins}) s WHERE tin_envelope(t) && p LIMIT 1) AS h FROM p`)).rows;
    const got = await page.evaluate((p) => window.sample(p), pts.map((r) => [r.lon, r.lat]));
    // Cesium's deepest tiles are cut from the finest level, the surface
    // tin_height answers on: the two differ by the quantization alone.
    // Heights: one step of the tile's range (at most the terrain's, over
    // 32767). Positions: a vertex moves at most half a step of a maxzoom
    // tile (in metres: a degree of latitude is at most 111.7 km), which
    // tilts the triangles around by at most their gradient times that, both
    // ends: twice the steepest gradient (|grad z|, PostGIS's corners of the
    // finest triangles within a step of the point) times the step diagonal.
    const tileDeg = 180 / 2 ** layer.maxzoom;
    const stepM = (tileDeg * 111700) / 32767 * Math.SQRT2;
    const [{ range }] = (await db.query(`SELECT max((tin_info(t)->'z_range'->>1)::float8 - (tin_info(t)->'z_range'->>0)::float8) AS range FROM (${tins}) s`)).rows;
    await db.query(`DROP TABLE IF EXISTS globe_tris`);
    await db.query(`
      CREATE TEMP TABLE globe_tris AS
      SELECT tr.geom,
             (SELECT sqrt((uy * vz - uz * vy) ^ 2 + (uz * vx - ux * vz) ^ 2) / abs(ux * vy - uy * vx)
              FROM (SELECT ST_X(b) - ST_X(a) ux, ST_Y(b) - ST_Y(a) uy, ST_Z(b) - ST_Z(a) uz,
                           ST_X(c) - ST_X(a) vx, ST_Y(c) - ST_Y(a) vy, ST_Z(c) - ST_Z(a) vz
                    FROM (SELECT ST_PointN(ST_ExteriorRing(tr.geom), 1) a, ST_PointN(ST_ExteriorRing(tr.geom), 2) b,
                                 ST_PointN(ST_ExteriorRing(tr.geom), 3) c) v) w) AS grad
      FROM (${tins}) s, tin_triangles(t) tr`);
    await db.query(`CREATE INDEX ON globe_tris USING gist (geom); ANALYZE globe_tris`);
    const grads = (await db.query(`
      SELECT i, (SELECT max(grad) FROM globe_tris tr
                 WHERE ST_DWithin(tr.geom, ST_Transform(ST_SetSRID(ST_MakePoint(lon, lat), 4326), ST_SRID(tr.geom)), $3)) AS g
      FROM unnest($1::float8[], $2::float8[]) WITH ORDINALITY AS p(lon, lat, i) ORDER BY i`,
      [pts.map((r) => r.lon), pts.map((r) => r.lat), stepM])).rows;
    let worst = 0, worstRatio = 0;
    got.forEach((h, i) => {
      const d = Math.abs(h - pts[i].h);
      const allowed = range / 32767 + 2 * (grads[i].g ?? 0) * stepM + 1e-6;
      worst = Math.max(worst, d);
      worstRatio = Math.max(worstRatio, d / allowed);
      if (!(d <= allowed)) fail.push(`${label}: point ${pts[i].lon}, ${pts[i].lat}: Cesium ${h}, tin_height ${pts[i].h} (quantization allows ${allowed.toFixed(3)} m)`);
    });
    console.log(`  ${label}: sampleTerrainMostDetailed at ${got.length} points: worst difference from tin_height ${worst.toFixed(3)} m, ${(100 * worstRatio).toFixed(0)} % of what quantization allows there (level tolerance ${tol} m not used)`);
    if (got.length !== 100) fail.push(`${label}: ${got.length} samples`);
    if (errors.length) fail.push(...errors.slice(0, 5).map((e) => `${label}: ${e}`));
  } finally {
    await page.close();
    await server.close();
  }
}

try {
  // two lakes at the terrain's centre, in its UTM SRID: one with an island
  await db.query(`DROP TABLE IF EXISTS globe_lakes`);
  await db.query(`CREATE TABLE globe_lakes AS
    SELECT ST_Difference(ST_Buffer(c, 2500, 64), ST_Buffer(ST_Translate(c, 300, 200), 600, 16)) AS geom FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) s
    UNION ALL SELECT ST_Buffer(ST_Translate(c, -3500, 4000), 1200, 32) FROM (SELECT ST_Centroid(tin_envelope(t)) AS c FROM terrain) s`);
  await run('one tin', 'terrain', false, 'globe.png', 'globe_lakes');
  // the DEM window as 16 tin_tiles (made by check_quantized_mesh.mjs)
  await run('16 tiles', 'qm_tiles', true, 'globe-tiled.png', null);
} finally {
  await browser.close();
  await db.end();
}
if (fail.length) {
  console.error('globe test failed:\n  ' + fail.slice(0, 20).join('\n  '));
  process.exit(1);
}
console.log(`globe test: CesiumJS drew the served terrain, one tin and tiles (screenshots in ${out})`);
