#!/usr/bin/env bash
# The project's Python: target/venv (made by scripts/setup.sh from Debian's
# python3, with the test libraries), whatever python3 comes first on PATH.
exec "$(cd "$(dirname "$0")/.." && pwd)/target/venv/bin/python3" "$@"
