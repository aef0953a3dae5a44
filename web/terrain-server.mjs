// A small HTTP server for Cesium: the terrain of a tin column served from
// PostgreSQL by tin_quantized_mesh, and the globe page (web/globe.html)
// with CesiumJS from web/node_modules (npm ci --prefix web; nothing is
// fetched from the internet). docs/serving.md explains it.
//
//   node web/terrain-server.mjs [--port 8090] [--table terrain] [--column t]
//                               [--where "name = 'x'"] [--fill 0]
//
// Connection settings come from the usual PG* environment variables.
//   GET /terrain/layer.json         tin_quantized_mesh_layer(t, normals, fill)
//   GET /terrain/{z}/{x}/{y}.terrain tin_quantized_mesh(t, z, x, y, normals, fill)
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

export function start({ port = 8090, table = 'terrain', column = 't', where = 'true', fill = null } = {}) {
  const pool = new pg.Pool({ max: 4 });
  const source = `(SELECT ${pg.escapeIdentifier(column)} AS t FROM ${table.split('.').map(pg.escapeIdentifier).join('.')} WHERE ${where} LIMIT 1) s`;
  const stats = { tiles: 0, empty: 0, ms: 0 };
  const server = http.createServer(async (req, res) => {
    const url = new URL(req.url, 'http://localhost');
    try {
      if (url.pathname === '/terrain/layer.json') {
        const r = await pool.query(`SELECT tin_quantized_mesh_layer(t, normals => true, fill => $1) AS j FROM ${source}`, [fill !== null]);
        if (!r.rows.length) return send(res, 404, 'text/plain', 'no terrain');
        return send(res, 200, 'application/json', JSON.stringify(r.rows[0].j));
      }
      const m = url.pathname.match(/^\/terrain\/(\d+)\/(\d+)\/(\d+)\.terrain$/);
      if (m) {
        // Cesium asks for the normals extension in its Accept header
        const normals = /octvertexnormals/.test(req.headers.accept || '');
        const t0 = performance.now();
        const r = await pool.query(
          `SELECT tin_quantized_mesh(t, $1, $2, $3, normals => $4, fill => $5) AS b FROM ${source}`,
          [+m[1], +m[2], +m[3], normals, fill]);
        stats.ms += performance.now() - t0;
        const b = r.rows.length ? r.rows[0].b : null;
        if (b === null) { stats.empty++; return send(res, 404, 'text/plain', 'no terrain in this tile'); }
        stats.tiles++;
        const ext = normals ? ';extensions=octvertexnormals' : '';
        return send(res, 200, `application/vnd.quantized-mesh${ext}`, b);
      }
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
  const s = await start(opt);
  console.log(`terrain on http://127.0.0.1:${s.port}/ (layer: /terrain/layer.json)`);
}
