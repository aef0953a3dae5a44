#!/usr/bin/env bash
# Writes the demo page into target/demo/ (or $1): one SVG per level of the
# bundled DEM's tin, one per merge (a contour drape, a polygon merge, raster
# statistics, an overlay), two glTF meshes (height colours; a hillshade
# painted on the surface), and index.html showing them with an offline 3D
# viewer. Needs the running cluster with database tinmerge_demo and its
# table terrain (scripts/demo.sh makes both); $TINMERGE_DEMO_DB overrides.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/demo}
db=${TINMERGE_DEMO_DB:-tinmerge_demo}
mkdir -p "$out"
q() { scripts/cluster.sh psql -qAtX -v ON_ERROR_STOP=1 -d "$db" "$@"; }

# fixtures of the merge pictures: a second terrain for the overlay (the DEM
# shifted by 1.3 km east and 0.9 km south, one level at 24 m), the slope of the DEM
q <<'SQL'
SET client_min_messages = warning;
DROP TABLE IF EXISTS demo_shifted, demo_slope;
CREATE TABLE demo_shifted AS
  SELECT tin_from_raster(ST_SetUpperLeft(rast, ST_UpperLeftX(rast) + 1300, ST_UpperLeftY(rast) - 900), 24.0, 1) AS t FROM dem;
CREATE TABLE demo_slope AS SELECT ST_Slope(rast, 1, '32BF', 'DEGREES') AS rast FROM dem;
SQL

pictures="$out/pictures.js"
echo "const PICTURES = [" > "$pictures"
# pic FILE GROUP CAPTION SQL: run SQL (one text value), write FILE, list it
pic() {
  local file=$1 group=$2 caption=$3 sql=$4
  q -c "$sql" > "$out/$file"
  [ -s "$out/$file" ] || { echo "demo-pictures: $file is empty" >&2; exit 1; }
  scripts/python.sh - "$file" "$group" "$caption" "$sql" >> "$pictures" <<'PY'
import json, sys
f, g, c, s = sys.argv[1:]
print(json.dumps({"file": f, "group": g, "caption": c, "sql": " ".join(s.split())}) + ",")
PY
  echo "  $out/$file ($(wc -c < "$out/$file") bytes)"
}

echo "== pictures of the levels"
levels=$(q -c "SELECT tin_num_levels(t) FROM terrain")
for ((l = 0; l < levels; l++)); do
  caption=$(q -c "SELECT format('Level %s: %s triangles, within %s m of every pixel', $l, tin_num_triangles(t, $l), tin_tolerance(t, $l)) FROM terrain")
  pic "level-$l.svg" levels "$caption" "SELECT tin_as_svg(t, $l, width => 800) FROM terrain"
done

echo "== the levels close up: one level-0 triangle and what each level makes of it"
# At 800 px the whole terrain's triangles are smaller than a pixel at the
# finer levels, and the level pictures look alike. Each close-up shows the
# triangles of one level in a window three times the size of the level-0
# triangle at the terrain's centre (grey by height), that triangle's edges
# in red on top: the coarse edges persisting, split, into every finer level.
# the SQL of a close-up, @LEVEL@ standing for the level
read -r -d '' zoom_sql <<'SQL' || true
WITH c AS (SELECT t, (SELECT geom FROM tin_triangles(t, 0)
                      WHERE id = tin_locate(t, ST_Centroid(tin_envelope(t)), 0)) AS g0 FROM terrain),
     w AS (SELECT t, g0, ST_Expand(ST_Envelope(g0), greatest(ST_XMax(g0) - ST_XMin(g0), ST_YMax(g0) - ST_YMin(g0))) AS win FROM c),
     z AS (SELECT min(ST_Z(ST_PointN(ST_ExteriorRing(geom), 1))) AS lo, max(ST_Z(ST_PointN(ST_ExteriorRing(geom), 1))) AS hi
           FROM w, tin_triangles(w.t, @LEVEL@) tr WHERE tr.geom && w.win)
SELECT format('<svg xmlns="http://www.w3.org/2000/svg" width="800" height="%s" viewBox="%s %s %s %s">',
              round(800 * (ST_YMax(win) - ST_YMin(win)) / (ST_XMax(win) - ST_XMin(win))),
              ST_XMin(win), -ST_YMax(win), ST_XMax(win) - ST_XMin(win), ST_YMax(win) - ST_YMin(win))
    || string_agg(format('<path d="%s" fill="rgb(%s,%s,%s)" stroke="#333" stroke-width="%s"/>',
                         ST_AsSVG(k.piece, 0, 2), g, g, g, (ST_XMax(win) - ST_XMin(win)) / 800),
                  '')
    || format('<path d="%s" fill="none" stroke="#d00" stroke-width="%s"/></svg>',
              ST_AsSVG(g0, 0, 2), 4 * (ST_XMax(win) - ST_XMin(win)) / 800)
FROM w, z, tin_triangles(w.t, @LEVEL@) tr,
     LATERAL (SELECT (90 + 150 * (ST_Z(ST_PointN(ST_ExteriorRing(tr.geom), 1)) - z.lo) / greatest(z.hi - z.lo, 1e-9))::int AS g,
                     ST_CollectionExtract(ST_Intersection(tr.geom, w.win), 3) AS piece) k
WHERE tr.geom && w.win AND NOT ST_IsEmpty(k.piece)
GROUP BY w.win, w.g0
SQL
for ((l = 0; l < levels; l++)); do
  caption="Level $l close up: the triangles in a window around one level-0 triangle (red)"
  pic "zoom-level-$l.svg" closeups "$caption" "${zoom_sql//@LEVEL@/$l}"
done

echo "== pictures of the merges"
pic drape.svg merges "Line merge: the triangles of level 2 the two longest 50 m contours pass through (tin_line_triangles), contours on top" \
"WITH c AS (SELECT ST_Collect(geom) AS g FROM (SELECT geom FROM contours ORDER BY ST_Length(geom) DESC LIMIT 2) s),
      tr AS (SELECT array_agg(DISTINCT x.triangle) AS ids FROM terrain, c, ST_Dump(c.g) d, tin_line_triangles(t, d.geom, 2) x)
 SELECT tin_as_svg(t, 2, triangles => tr.ids, features => c.g, legend => 'triangles crossed') FROM terrain, c, tr"

pic area.svg merges "Area merge: level 2 triangles inside and on the boundary of a contour band (tin_area_triangles), the band on top" \
"WITH b AS (SELECT geom AS g FROM contour_bands ORDER BY ST_Area(geom) DESC OFFSET 2 LIMIT 1),
      a AS (SELECT array_agg(x.triangle) AS ids, array_agg(x.relation) AS rel FROM terrain, b, tin_area_triangles(t, b.g, 2) x)
 SELECT tin_as_svg(t, 2, triangles => a.ids, classes => a.rel, features => b.g, legend => 'relation to the band') FROM terrain, b, a"

pic raster-stats.svg merges "Raster merge: mean slope of the DEM pixels in each level 1 triangle (tin_raster_stats over ST_Slope of the DEM)" \
"SELECT tin_as_svg(t, 1, triangles => s.ids, vals => s.means, legend => 'mean slope (degrees)')
 FROM terrain, LATERAL (SELECT array_agg(x.triangle) AS ids, array_agg(x.mean) AS means
                        FROM demo_slope d, tin_raster_stats(terrain.t, d.rast, 1) x) s"

pic overlay.svg merges "TIN/TIN overlay: the overlay of level 0 with a shifted, coarser terrain (tin_overlay_tin), coloured by height; the second terrain's triangles on top" \
"SELECT tin_as_svg(tin_overlay_tin(a.t, b.t, 0, 0), 0,
                   features => (SELECT ST_Collect(ST_Boundary(geom)) FROM tin_triangles(b.t, 0)), legend => 'height (m)')
 FROM terrain a, demo_shifted b"
echo "];" >> "$pictures"

echo "== 3D meshes"
q -c "SELECT encode(tin_as_gltf(t, 3, z_factor => 3), 'base64') FROM terrain" | tr -d '\n' > "$out/surface.b64"
q -c "SELECT encode(tin_as_gltf(t, 2, ST_HillShade(d.rast), 3), 'base64') FROM terrain, dem d" | tr -d '\n' > "$out/surface-textured.b64"
base64 -d "$out/surface.b64" > "$out/surface.glb"
base64 -d "$out/surface-textured.b64" > "$out/surface-textured.glb"
{
  printf 'const MESHES = {\n  "view-height": "'
  cat "$out/surface.b64"
  printf '",\n  "view-texture": "'
  cat "$out/surface-textured.b64"
  printf '",\n};\n'
} > "$out/meshes.js"
rm -f "$out/surface.b64" "$out/surface-textured.b64"
echo "  $out/surface.glb ($(wc -c < "$out/surface.glb") bytes), $out/surface-textured.glb ($(wc -c < "$out/surface-textured.glb") bytes)"
cp web/index.html web/viewer.js "$out/"
cp docs/img/globe.jpg "$out/"
q -c "DROP TABLE demo_shifted, demo_slope"
echo "== open $out/index.html in a browser"
