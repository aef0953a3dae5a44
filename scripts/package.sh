#!/usr/bin/env bash
# make package: a Debian package of tinmerge for PostgreSQL 15,
# target/postgresql-15-tinmerge_<version>_<arch>.deb, holding what
# scripts/stage.sh stages (the library, stripped; the control file; the
# install scripts of this and every earlier release and the upgrade
# scripts between them), the copyright and a changelog. It depends on
# postgresql-15 and postgresql-15-postgis-3 and on the shared libraries the
# library links (dpkg-shlibdeps). Install it with
#   apt-get install ./target/postgresql-15-tinmerge_<version>_<arch>.deb
# and remove it with apt-get remove postgresql-15-tinmerge. lintian (when
# installed) checks the package; an error fails this script.
#
# TINMERGE_PACKAGE_NO_BUILD=1: package what target/package holds without
# building it again (make test, after scripts/install.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
NAME=postgresql-15-tinmerge
VERSION=$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -1)
ARCH=$(dpkg --print-architecture)
STAGED="$PWD/target/package"
[ "${TINMERGE_PACKAGE_NO_BUILD:-}" = 1 ] || scripts/stage.sh
[ -f "$STAGED/usr/lib/postgresql/15/lib/tinmerge.so" ] ||
  { echo "package.sh: nothing staged in $STAGED (run without TINMERGE_PACKAGE_NO_BUILD)" >&2; exit 1; }
ROOT="$PWD/target/deb/$NAME"
rm -rf "$ROOT"
mkdir -p "$ROOT/DEBIAN"
cp -a "$STAGED/usr" "$ROOT/"
# the library without its symbol table and debug sections (its dynamic
# symbols, which PostgreSQL looks up, stay)
strip --strip-unneeded --remove-section=.comment --remove-section=.note \
  "$ROOT/usr/lib/postgresql/15/lib/tinmerge.so"
find "$ROOT/usr" -type d -exec chmod 755 {} +
find "$ROOT/usr" -type f -name '*.so' -exec chmod 644 {} +
find "$ROOT/usr" -type f ! -name '*.so' -exec chmod 644 {} +
doc="$ROOT/usr/share/doc/$NAME"
install -d -m 755 "$doc"
install -m 644 packaging/copyright "$doc/copyright"
# a native package's changelog, dated as the commit it is built from
when=$(git log -1 --format=%aD 2>/dev/null || date -R)
maint="tinmerge developers <tinmerge@users.noreply.github.com>"
{
  echo "$NAME ($VERSION) unstable; urgency=medium"
  echo
  echo "  * tinmerge $VERSION: what this release changes is in docs/upgrading.md"
  echo "    of the source tree."
  echo
  echo " -- $maint  $when"
} | gzip -9n > "$doc/changelog.gz"
chmod 644 "$doc/changelog.gz"
# the shared libraries the library links, as Depends
tmp=$(mktemp -d)
mkdir -p "$tmp/debian"
printf 'Source: tinmerge\n\nPackage: %s\nArchitecture: any\n' "$NAME" > "$tmp/debian/control"
shlibs=$(cd "$tmp" && dpkg-shlibdeps -O "$ROOT/usr/lib/postgresql/15/lib/tinmerge.so" 2>/dev/null |
  sed -n 's/^shlibs:Depends=//p')
rm -rf "$tmp"
[ -n "$shlibs" ] || { echo "package.sh: dpkg-shlibdeps found no dependencies of tinmerge.so" >&2; exit 1; }
size=$(du -sk --apparent-size "$ROOT/usr" | cut -f1)
cat > "$ROOT/DEBIAN/control" <<CONTROL
Package: $NAME
Version: $VERSION
Architecture: $ARCH
Maintainer: $maint
Installed-Size: $size
Depends: postgresql-15, postgresql-15-postgis-3, $shlibs
Section: database
Priority: optional
Description: terrain TINs merged with PostGIS data in PostgreSQL 15
 tinmerge is a PostgreSQL extension: a type tin holding an adaptive
 hierarchical triangulation of a terrain (levels of detail, each within its
 tolerance of the source everywhere), built from PostGIS rasters, points,
 lines and polygons, and merged with them in SQL: heights of points, lines
 draped and cut per triangle, triangles of polygons and zonal statistics,
 rasters handed to triangles, TIN overlay, contours, slope, viewsheds and
 Cesium quantized-mesh tiles.
 .
 After installing: CREATE EXTENSION tinmerge CASCADE;
CONTROL
(cd "$ROOT" && find usr -type f -print0 | sort -z | xargs -0 md5sum) > "$ROOT/DEBIAN/md5sums"
chmod 644 "$ROOT/DEBIAN/control" "$ROOT/DEBIAN/md5sums"
deb="$PWD/target/${NAME}_${VERSION}_${ARCH}.deb"
rm -f "$deb"
dpkg-deb --root-owner-group -Zxz --build "$ROOT" "$deb" >/dev/null
echo "built $deb ($(du -k "$deb" | cut -f1) kB, $(find "$ROOT/usr" -type f | wc -l) files)"
if command -v lintian >/dev/null; then
  # errors fail the package; warnings are shown
  lintian --fail-on error --tag-display-limit 0 "$deb"
  echo "lintian: no error"
else
  echo "package.sh: lintian is not installed (apt-get install lintian), the package was not checked" >&2
fi
