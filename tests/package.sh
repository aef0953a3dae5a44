#!/usr/bin/env bash
# The Debian package (scripts/package.sh) in the system PostgreSQL 15, in
# place of a development install, with apt-get (as root, otherwise through
# sudo): `tests/package.sh install` removes every tinmerge file no package
# owns (what scripts/install.sh or cargo pgrx put there), installs
# target/postgresql-15-tinmerge_<version>_<arch>.deb with apt-get and checks
# that dpkg lists every file it installed and that each is there;
# `tests/package.sh remove` removes the package with apt-get and checks that
# no tinmerge file is left in PostgreSQL's directories or the package's
# documentation directory. make test installs it before pg_regress (which
# then runs against the package, as an installcheck) and removes it last.
set -euo pipefail
cd "$(dirname "$0")/.."
NAME=postgresql-15-tinmerge
VERSION=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -1)
deb="$PWD/target/${NAME}_${VERSION}_$(dpkg --print-architecture).deb"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
LIB=/usr/lib/postgresql/15/lib
EXT=/usr/share/postgresql/15/extension
ours() { # every tinmerge file in PostgreSQL's directories and the package's docs
  find "$LIB" "$EXT" -maxdepth 1 \( -name 'tinmerge*' -o -name '.tinmerge*' \) 2>/dev/null
  [ -e "/usr/share/doc/$NAME" ] && echo "/usr/share/doc/$NAME"
  true
}
case "${1:-}" in
install)
  [ -f "$deb" ] || { echo "tests/package.sh: no $deb (make package)" >&2; exit 1; }
  n=0
  for f in $(ours); do
    if ! dpkg -S "$f" >/dev/null 2>&1; then
      $SUDO rm -rf "$f"
      n=$((n + 1))
    fi
  done
  echo "removed $n files of a development install"
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --reinstall --no-install-recommends "$deb" 2>&1 |
    grep -v 'couldn.t be accessed by user ._apt.' | tail -3
  [ "$(dpkg-query -W -f '${Status} ${Version}' "$NAME")" = "install ok installed $VERSION" ] ||
    { echo "tests/package.sh: $NAME $VERSION is not installed" >&2; exit 1; }
  listed=0
  while IFS= read -r f; do
    [ -d "$f" ] && continue
    [ -f "$f" ] || { echo "tests/package.sh: dpkg lists $f, which is not there" >&2; exit 1; }
    listed=$((listed + 1))
  done < <(dpkg -L "$NAME")
  [ -f "$LIB/tinmerge.so" ] && [ -f "$EXT/tinmerge.control" ] && [ -f "$EXT/tinmerge--$VERSION.sql" ] ||
    { echo "tests/package.sh: the package lacks the library, the control file or the install script" >&2; exit 1; }
  echo "$NAME $VERSION installed from $(basename "$deb"): $listed files"
  ;;
remove)
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get remove -y -q "$NAME" 2>&1 | tail -2
  if dpkg-query -W -f '${Status}' "$NAME" 2>/dev/null | grep -q 'ok installed'; then
    echo "tests/package.sh: $NAME is still installed" >&2
    exit 1
  fi
  left=$(ours)
  if [ -n "$left" ]; then
    echo "tests/package.sh: apt-get remove left these behind:" >&2
    echo "$left" >&2
    exit 1
  fi
  echo "$NAME removed: no tinmerge file left in $LIB, $EXT or /usr/share/doc"
  ;;
*)
  echo "usage: tests/package.sh install|remove" >&2
  exit 2
  ;;
esac
