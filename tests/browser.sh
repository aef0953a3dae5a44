#!/usr/bin/env bash
# Browser test of the demo page: writes the pictures and meshes with
# scripts/demo-pictures.sh from the regress database (its terrain, dem,
# contours and contour_bands are the demo's), opens index.html in headless
# Chromium (Debian's package; WebGL through SwiftShader; tests/browser.mjs
# drives it and waits for the page in real time), and checks what
# the page reports: every picture decoded with a size and drawn (pixels
# that are not white), both 3D views drew the surface. Saves a screenshot.
# Needs the running test cluster after pg_regress.
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/demo-test
rm -rf "$out"
TINMERGE_DEMO_DB=${TINMERGE_DEMO_DB:-tinmerge_regress} scripts/demo-pictures.sh "$out" >/dev/null
[ -d web/node_modules/puppeteer-core ] || { echo "browser test: web/node_modules is missing (scripts/setup.sh runs npm ci --prefix web)"; exit 1; }
chrome=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chrome" ] || { echo "browser test: chromium is not installed (scripts/setup.sh installs it)"; exit 1; }
CHROMIUM="$chrome" timeout 660 node tests/browser.mjs "$out"
