#!/usr/bin/env bash
# The README's two commands:
#   ./dev.sh demo   install what is missing, build, and run mereo on the built-in default scene
#   ./dev.sh test   install what is missing, build, and run every test (ctest, pytest, a bounded fuzz run)
set -euo pipefail
cd "$(dirname "$0")"
BUILD=build/dev

build() {  # $1: ON to build the C++ tests too
  scripts/setup.sh
  export PATH="$PWD/.venv/bin:$PATH"
  echo "build: compiling mereo (incremental, in $BUILD)"
  .venv/bin/pip install -q --disable-pip-version-check --no-build-isolation --no-deps \
    -Cbuild-dir="$BUILD" -Ccmake.define.MEREO_BUILD_TESTS="$1" .
}

case "${1:-}" in
  demo)
    build OFF
    shift
    .venv/bin/mereo demo "$@"
    ;;
  test)
    build ON
    export PATH="$PWD/.venv/bin:$PATH"
    ctest --test-dir "$BUILD" --output-on-failure -j2
    .venv/bin/python -m pytest -q -n 2  # two worker processes (pytest-xdist): a quarter less time on 2 cores
    # the readers fuzzed for a bounded time (a minute per target; MEREO_FUZZ_SECONDS to change)
    scripts/fuzz.sh --seconds "${MEREO_FUZZ_SECONDS:-60}"
    ;;
  *)
    echo "usage: ./dev.sh demo | test" >&2
    exit 2
    ;;
esac
