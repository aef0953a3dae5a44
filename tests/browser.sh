#!/usr/bin/env bash
# Browser test of the demo page: writes the pictures and meshes with
# scripts/demo-pictures.sh from the regress database (its terrain, dem,
# contours and contour_bands are the demo's), opens index.html in headless
# Chromium (Debian's package; WebGL through SwiftShader), and checks what
# the page reports: every picture decoded with a size and drawn (pixels
# that are not white), both 3D views drew the surface. Saves a screenshot.
# Needs the running test cluster after pg_regress.
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/demo-test
rm -rf "$out"
TINMERGE_DEMO_DB=${TINMERGE_DEMO_DB:-tinmerge_regress} scripts/demo-pictures.sh "$out" >/dev/null
chrome=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chrome" ] || { echo "browser test: chromium is not installed (scripts/setup.sh installs it)"; exit 1; }
flags=(--headless=new --no-sandbox --disable-dev-shm-usage --hide-scrollbars
       --use-angle=swiftshader --enable-unsafe-swiftshader --allow-file-access-from-files
       --virtual-time-budget=60000 --window-size=1300,3600)
page="file://$PWD/$out/index.html"
timeout 300 "$chrome" "${flags[@]}" --dump-dom "$page" 2>/dev/null > "$out/dom.html"
timeout 300 "$chrome" "${flags[@]}" --screenshot="$PWD/$out/screenshot.png" "$page" >/dev/null 2>&1
python3 - "$out" <<'PY'
import json, os, re, sys
out = sys.argv[1]
dom = open(os.path.join(out, "dom.html")).read()
m = re.search(r'<pre id="check">check (\{.*?\})</pre>', dom, re.S)
if not m:
    sys.exit("browser test: the page did not report (no check line in the DOM)")
rep = json.loads(m.group(1).replace("&quot;", '"'))
bad = []
for p in rep["pictures"]:
    if p["width"] <= 0 or p["height"] <= 0:
        bad.append(f'{p["file"]}: not decoded')
    elif p["drawn"] < 0.2 * p["width"] * p["height"] * 0.5:
        bad.append(f'{p["file"]}: only {p["drawn"]} of {p["width"]} x {p["height"]} pixels drawn')
for view, n in rep["views"].items():
    if not isinstance(n, int) or n < 20000:
        bad.append(f"{view}: {n} pixels drawn")
if len(rep["pictures"]) < 9:
    bad.append(f'only {len(rep["pictures"])} pictures on the page')
png = os.path.join(out, "screenshot.png")
if not os.path.exists(png) or os.path.getsize(png) < 10000:
    bad.append("no screenshot")
for p in rep["pictures"]:
    print(f'  {p["file"]}: {p["width"]} x {p["height"]}, {p["drawn"]} pixels drawn')
for view, n in rep["views"].items():
    print(f"  {view}: {n} pixels drawn")
if bad:
    sys.exit("browser test failed:\n  " + "\n  ".join(bad))
print(f"browser test: {len(rep['pictures'])} pictures and {len(rep['views'])} 3D views rendered; screenshot {png}")
PY
