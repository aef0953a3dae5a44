#!/usr/bin/env bash
# The algorithms (src/tin, src/io, src/merge, ...) must never use pgrx: only
# the SQL layer (src/pg/) and the crate root may.
set -euo pipefail
cd "$(dirname "$0")/.."
bad=$(grep -rlE '(^|[^a-z_])pgrx(::|_)|extern crate pgrx|use pgrx' src --include='*.rs' | grep -vE '^src/(pg/|lib\.rs$)' || true)
if [ -n "$bad" ]; then
  echo "pgrx used outside the SQL layer (src/pg/): $bad" >&2
  exit 1
fi
echo "module boundary ok: pgrx only in src/pg/ and src/lib.rs"
