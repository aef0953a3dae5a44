// A small HTTP server for Cesium: the terrain of a tin column served from
// PostgreSQL by tin_quantized_mesh, and the globe page (web/globe.html)
// with CesiumJS from web/node_modules (npm ci --prefix web; nothing is
// fetched from the internet). docs/serving.md explains it.
//
//   node web/terrain-server.mjs [--port 8090] [--table terrain] [--column t]
//                               [--where "name = 'x'"] [--fill 0] [--tiled 1]
//                               [--water lakes]
//
// --tiled: the table holds a terrain stored as tiles (tin_tiles, one tin
// per row sharing seams); each request passes the tins whose extent meets
// the tile (array form of tin_quantized_mesh).
// --water: a table of lake and sea polygons (column geom, one SRID): the
// tiles carry their water mask, and the globe shows water.
//
// Connection settings come from the usual PG* environment variables.
//   GET /terrain/layer.json         tin_quantized_mesh_layer(t, normals, fill, water, metadata)
//   GET /terrain/{z}/{x}/{y}.terrain tin_quantized_mesh(t, z, x, y, normals, fill, water, metadata),
//                                   the extensions Cesium's Accept header asks for
//   GET /imagery.json, /imagery.png the terrain's hillshade (tin_as_raster, ST_HillShade)
//                                   in degrees, the globe's imagery
//   GET /                           the globe page
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import pg from 'pg';

const here = path.dirname(fileURLToPath(import.meta.url));
const cesiumDir = path.join(here, 'node_modules', 'cesium', 'Build', 'Cesium');
const types = {
  '.js': 'text/javascript', '.css': 'text/css', '.html': 'text/html', '.json': 'application/json',
  '.png': 'image/png', '.jpg': 'image/jpeg', '.svg': 'image/svg+xml', '.wasm': 'application/wasm',
  '.xml': 'application/xml', '.glb': 'model/gltf-binary', '.ktx2': 'image/ktx2',
};

export function start({ port = 8090, table = 'terrain', column = 't', where = 'true', fill = null, tiled = false, water = null } = {}) {
  // PNG for the hillshade imagery (PostGIS enables no GDAL driver by default)
  const pool = new pg.Pool({ max: 4, options: '-c postgis.gdal_enabled_drivers=PNG' });
  const rel = table.split('.').map(pg.escapeIdentifier).join('.');
  const col = pg.escapeIdentifier(column);
  // one tin, or the tins of a tiled terrain meeting the tile ($6..$9: its bounds in degrees)
  const source = `(SELECT ${col} AS t FROM ${rel} WHERE ${where} LIMIT 1) s`;
  const layerSource = tiled ? `(SELECT array_agg(${col}) AS t FROM ${rel} WHERE ${where}) s` : source;
  const tileSource = tiled
    ? `(SELECT coalesce(array_agg(${col}), '{}') AS t FROM ${rel} WHERE (${where})
         AND ST_Transform(ST_Segmentize(tin_envelope(${col}), 100), 4326) && ST_MakeEnvelope($6, $7, $8, $9, 4326)) s`
    : source;
  const stats = { tiles: 0, empty: 0, ms: 0, water: 0 };
  // the water polygons meeting a tile ($6..$9 its bounds in degrees), in
  // their own SRID (a tile of zoom 0 is half the earth: compared in degrees,
  // which an index on ST_Transform(geom, 4326) serves). None is an empty
  // polygon, not NULL: a tile must carry its mask (all land, one byte)
  // whenever the layer announces water, or Cesium borrows the coarse mask
  // of an ancestor and draws water over the whole tile
  const lakes = water ? water.split('.').map(pg.escapeIdentifier).join('.') : null;
  const waterSql = lakes
    ? `coalesce((SELECT ST_Collect(geom) FROM ${lakes} WHERE ST_Transform(geom, 4326) && ST_MakeEnvelope($6, $7, $8, $9, 4326)), 'POLYGON EMPTY')`
    : 'NULL::geometry';
  // the hillshade of the finest level as imagery: tin_as_raster at about
  // 600 pixels across, ST_HillShade (z in metres: a degree is 111,120 m),
  // to degrees; made once
  let imagery = null;
  const hillshade = async () => {
    if (imagery) return imagery;
    const r = await pool.query(`
      WITH t AS (SELECT ${col} AS t FROM ${rel} WHERE ${where}),
           e AS (SELECT ST_Extent(tin_envelope(t))::geometry AS e, min(tin_srid(t)) AS srid FROM t),
           k AS (SELECT greatest(ST_XMax(e) - ST_XMin(e), ST_YMax(e) - ST_YMin(e)) / 600 AS px,
                        CASE WHEN (SELECT NOT proj4text LIKE '%+proj=longlat%' FROM spatial_ref_sys WHERE srid = e.srid) THEN 1.0 ELSE 111120.0 END AS scale FROM e),
           r AS (SELECT ST_Union(tin_as_raster(t, px)) AS r FROM t, k),
           h AS (SELECT ST_Transform(ST_HillShade(r, 1, '8BUI', 315, 45, 255, scale), 4326) AS h FROM r, k)
      SELECT ST_AsPNG(ST_SetBandNoDataValue(ST_SetBandNoDataValue(ST_SetBandNoDataValue(ST_SetBandNoDataValue(
               ST_AddBand(ST_Band(h, ARRAY[1, 1, 1]), ST_MapAlgebra(h, 1, '8BUI', '255', 0)), 1, NULL), 2, NULL), 3, NULL), 4, NULL)) AS png,
             ST_XMin(ST_Envelope(h)) AS w, ST_YMin(ST_Envelope(h)) AS s, ST_XMax(ST_Envelope(h)) AS e, ST_YMax(ST_Envelope(h)) AS n,
             (SELECT min((tin_info(t)->'z_range'->>0)::float8) FROM t) AS zmin, (SELECT max((tin_info(t)->'z_range'->>1)::float8) FROM t) AS zmax
      FROM h`);
    imagery = r.rows[0];
    return imagery;
  };
  const server = http.createServer(async (req, res) => {
    const url = new URL(req.url, 'http://localhost');
    try {
      if (url.pathname === '/terrain/layer.json') {
        const r = await pool.query(`SELECT tin_quantized_mesh_layer(t, normals => true, fill => $1, water => $2, metadata => true) AS j FROM ${layerSource}`, [fill !== null, water !== null]);
        if (!r.rows.length) return send(res, 404, 'text/plain', 'no terrain');
        return send(res, 200, 'application/json', JSON.stringify(r.rows[0].j));
      }
      const m = url.pathname.match(/^\/terrain\/(\d+)\/(\d+)\/(\d+)\.terrain$/);
      if (m) {
        // Cesium asks for the extensions in its Accept header
        const accept = req.headers.accept || '';
        const normals = /octvertexnormals/.test(accept);
        const withWater = lakes !== null && /watermask/.test(accept);
        const metadata = /metadata/.test(accept);
        const t0 = performance.now();
        const [z, x, y] = [+m[1], +m[2], +m[3]];
        const size = 180 / 2 ** z;
        const bounds = [-180 + x * size, -90 + y * size, -180 + (x + 1) * size, -90 + (y + 1) * size];
        const r = await pool.query(
          `SELECT tin_quantized_mesh(t, $1::int, $2::int, $3::int, normals => $4, fill => $5,
                                     water => CASE WHEN $10 THEN ${waterSql} END, metadata => $11) AS b
           FROM ${tileSource}, (SELECT $6::float8, $7::float8, $8::float8, $9::float8) bounds`,
          [z, x, y, normals, fill, ...bounds, withWater, metadata]);
        stats.ms += performance.now() - t0;
        const b = r.rows.length ? r.rows[0].b : null;
        if (b === null) { stats.empty++; return send(res, 404, 'text/plain', 'no terrain in this tile'); }
        stats.tiles++;
        if (withWater) stats.water++;
        const ext = [normals && 'octvertexnormals', withWater && 'watermask', metadata && 'metadata'].filter(Boolean).join('-');
        return send(res, 200, `application/vnd.quantized-mesh${ext ? `;extensions=${ext}` : ''}`, b);
      }
      if (url.pathname === '/imagery.json') {
        const { w, s, e, n, zmin, zmax } = await hillshade();
        return send(res, 200, 'application/json', JSON.stringify({ rectangle: [w, s, e, n], z_range: [zmin, zmax] }));
      }
      if (url.pathname === '/imagery.png') return send(res, 200, 'image/png', (await hillshade()).png);
      let file = url.pathname === '/' ? path.join(here, 'globe.html')
        : url.pathname.startsWith('/cesium/') ? path.join(cesiumDir, url.pathname.slice(8)) : null;
      if (file && !path.relative(here, path.resolve(file)).startsWith('..') && fs.existsSync(file) && fs.statSync(file).isFile()) {
        return send(res, 200, types[path.extname(file)] || 'application/octet-stream', fs.readFileSync(file));
      }
      send(res, 404, 'text/plain', 'not found');
    } catch (e) {
      send(res, 500, 'text/plain', String(e.message || e));
    }
  });
  return new Promise((resolve) => server.listen(port, '127.0.0.1', () => resolve({
    server, pool, stats, port: server.address().port,
    close: () => new Promise((r) => server.close(() => pool.end().then(r))),
  })));
}

function send(res, code, type, body) {
  res.writeHead(code, { 'Content-Type': type, 'Access-Control-Allow-Origin': '*', 'Cache-Control': 'no-cache' });
  res.end(body);
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const opt = {};
  const a = process.argv.slice(2);
  for (let i = 0; i < a.length; i += 2) opt[a[i].replace(/^--/, '')] = a[i + 1];
  if (opt.port) opt.port = +opt.port;
  if (opt.fill !== undefined) opt.fill = +opt.fill;
  if (opt.tiled !== undefined) opt.tiled = opt.tiled !== '0';
  const s = await start(opt);
  console.log(`terrain on http://127.0.0.1:${s.port}/ (layer: /terrain/layer.json)`);
}
