#!/usr/bin/env bash
# Runs the C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer:
#   scripts/asan.sh [ctest arguments, e.g. -R GraphRun]
# (from scratch about 40 minutes on 2 cores, the tests about 17 more; not part of ./dev.sh test)
# It builds the library, mereo-run and the GoogleTest executables with -DMEREO_SANITIZE=address
# (build/asan; the benchmarks are not built and their *_quick tests not run) and runs the ctest
# suite. Any report fails the run:
# - ASan stops at its first error (its default) and LeakSanitizer reports leaks at exit; both exit
#   non-zero, so the test fails.
# - UBSan (GCC's -fsanitize=undefined, recoverable) would only print and go on: halt_on_error=1
#   makes it exit non-zero too. A runtime option rather than -fno-sanitize-recover=undefined: no
#   rebuild to change it, and the suppressions apply as usual.
# The suppressions are for third-party code only, each with its reason: tests/lsan.supp (leaks
# in third-party globals; none needed so far) and tests/ubsan.supp (oneTBB's flow graph trips
# the vptr check in its own header; a suppression of that header only, not -fno-sanitize=vptr).
# Tests that measure memory growth widen their bound when built with ASan (MEREO_TEST_ASAN in
# their source).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD=build/asan
NICE="nice -n 10"
GENERATOR=()
if command -v ninja >/dev/null; then GENERATOR=(-G Ninja); fi
$NICE cmake -S . -B "$BUILD" "${GENERATOR[@]}" -DMEREO_BUILD_TESTS=ON -DMEREO_SANITIZE=address \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_POLICY_VERSION_MINIMUM=3.5 >/dev/null
# One executable per tests/cpp/test_*.cpp (test_graph included), and mereo-run for its tests.
targets=(mereo-run)
for f in tests/cpp/test_*.cpp; do targets+=("$(basename "$f" .cpp)"); done
$NICE cmake --build "$BUILD" --target "${targets[@]}" -j2

export ASAN_OPTIONS="detect_leaks=1:check_initialization_order=1:strict_string_checks=1"
export LSAN_OPTIONS="suppressions=$ROOT/tests/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$ROOT/tests/ubsan.supp"
$NICE ctest --test-dir "$BUILD" --output-on-failure -j2 -E '_quick$' "$@"
