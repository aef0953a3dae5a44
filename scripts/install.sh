#!/usr/bin/env bash
# Build (release) and install tinmerge into the system PostgreSQL 15
# (as root directly, otherwise through sudo): the files scripts/stage.sh
# stages in target/package (the library, the control file, the install
# script and those of earlier releases with the upgrade scripts from them).
# TINMERGE_FEATURES=bench adds the benchmark-only SQL entry points
# (`make bench` does; `make install` never). A Debian package of the same
# files: `make package` (scripts/package.sh).
#
# Safe on a live server: every file is written under a temporary name in
# its own directory and renamed over the old one, as dpkg does, so a
# backend that has the old library mapped keeps the old file (a copy in
# place, as `cargo pgrx install` makes, truncates the mapped file and
# kills every session of the cluster with SIGBUS: issue 75). Sessions
# load the new library when they next start; see docs/upgrading.md.
#
# TINMERGE_INSTALL_NO_BUILD=1: install what the last build packaged
# (target/package) without building (tests/live_install.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
OUT="$PWD/target/package"
[ "${TINMERGE_INSTALL_NO_BUILD:-}" = 1 ] || scripts/stage.sh
[ -d "$OUT" ] || { echo "install.sh: nothing packaged in $OUT (run without TINMERGE_INSTALL_NO_BUILD)" >&2; exit 1; }
# put FILE DEST: written as DEST.new-<pid> beside DEST, then renamed over it
put() {
  local src=$1 dest=$2 mode=644 tmp
  [ -x "$src" ] && [ "${src%.so}" != "$src" ] && mode=755
  tmp="$(dirname "$dest")/.$(basename "$dest").new-$$"
  $SUDO install -D -m "$mode" "$src" "$tmp"
  $SUDO mv -f "$tmp" "$dest"
}
n=0
while IFS= read -r -d '' f; do
  put "$f" "/${f#"$OUT"/}"
  n=$((n + 1))
done < <(find "$OUT" -type f -print0)
echo "installed $n files (each renamed into place) from $OUT"
