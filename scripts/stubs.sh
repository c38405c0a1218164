#!/usr/bin/env bash
# Regenerates the type stubs of the extension (python/mereo/_mereo/*.pyi) from the installed
# package, after bindings change: scripts/stubs.sh (tests/python/test_stubs.py checks them).
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp -d)
.venv/bin/pybind11-stubgen mereo._mereo -o "$out" --numpy-array-use-type-var --ignore-all-errors >/dev/null
rm -rf python/mereo/_mereo
cp -r "$out/mereo/_mereo" python/mereo/_mereo
rm -rf "$out"
echo "stubs written to python/mereo/_mereo/"
