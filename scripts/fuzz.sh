#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz with clang (build/fuzz, MEREO_FUZZ=ON: ASan + UBSan)
# and runs each for N seconds on a fresh copy of its seed corpus (tests/fuzz/corpus/<target>).
#   scripts/fuzz.sh [--seconds N] [target...]     targets: pcd png_pair model graph python (default: all)
# (python: tests/fuzz/fuzz_python.py with atheris, in .venv where mereo is installed)
# Prints the executions per target; exits non-zero when a target crashed, with the path of the
# input that did (build/fuzz/crashes/<target>/). Reproduce: build/fuzz/tests/fuzz/fuzz_<target> FILE
# Needs mereo's own Debian packages (scripts/setup.sh); installs clang 14 when it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=60
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --seconds=*) seconds="${1#*=}"; shift ;;
    pcd|png_pair|model|graph|python) targets+=("$1"); shift ;;
    *) echo "usage: scripts/fuzz.sh [--seconds N] [pcd|png_pair|model|graph|python ...]" >&2; exit 2 ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(pcd png_pair model graph python)
cxx_targets=()
for t in "${targets[@]}"; do [ "$t" = python ] || cxx_targets+=("$t"); done

# the longest input per target: room for a few thousand points or a small image pair, and for
# YAML files larger than the shipped ones
declare -A max_len=([pcd]=65536 [png_pair]=65536 [model]=16384 [graph]=8192 [python]=16384)

missing=()
for p in clang-14 libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "fuzz: installing Debian packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

BUILD=build/fuzz
cmake_bin=cmake
command -v cmake >/dev/null || cmake_bin=.venv/bin/cmake
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
[ -f "$BUILD/CMakeCache.txt" ] && generator=()  # the folder keeps the generator it has
# -O1 with assertions on (no NDEBUG): what fuzzing wants; line tables for the stack traces
start=$(date +%s)
mkdir -p "$BUILD/logs"
CC=clang-14 CXX=clang++-14 nice -n 10 "$cmake_bin" -S . -B "$BUILD" "${generator[@]}" -Wno-dev \
  -DMEREO_FUZZ=ON -DMEREO_BUILD_TESTS=OFF -DMEREO_BUILD_PYTHON=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 \
  >"$BUILD/logs/configure.log" 2>&1 || { cat "$BUILD/logs/configure.log" >&2; exit 1; }
[ ${#cxx_targets[@]} -eq 0 ] || nice -n 10 "$cmake_bin" --build "$BUILD" -j "$(nproc)" --target "${cxx_targets[@]/#/fuzz_}"
echo "fuzz: built in $(( $(date +%s) - start )) s"

# UBSan's reports with their stacks, as ASan's have
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}"
status=0
for t in "${targets[@]}"; do
  corpus="$BUILD/corpus/$t" crashes="$BUILD/crashes/$t" log="$BUILD/logs/$t.log"
  rm -rf "$corpus" && mkdir -p "$corpus" "$crashes"
  cp tests/fuzz/corpus/"$t"/* "$corpus"/
  # every input that once crashed a reader is replayed first (tests/fuzz/regressions/<target>)
  [ -d tests/fuzz/regressions/"$t" ] && cp tests/fuzz/regressions/"$t"/* "$corpus"/
  dict=()
  [ -f tests/fuzz/"$t".dict ] && dict=(-dict=tests/fuzz/"$t".dict)
  echo "fuzz: fuzz_$t for $seconds s (log: $log)"
  rc=0
  exe=("$BUILD/tests/fuzz/fuzz_$t")
  [ "$t" = python ] && exe=(.venv/bin/python tests/fuzz/fuzz_python.py)
  nice -n 10 "${exe[@]}" "$corpus" "${dict[@]}" -max_total_time="$seconds" \
    -max_len="${max_len[$t]}" -rss_limit_mb=2048 -timeout=30 -print_final_stats=1 \
    -artifact_prefix="$crashes/" >"$log" 2>&1 || rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  echo "fuzz: fuzz_$t: ${runs:-?} executions (${speed:-?}/s), corpus $(ls "$corpus" | wc -l) inputs"
  if [ "$rc" -ne 0 ]; then
    status=1
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -1)
    summary=$(grep -m1 -E 'ERROR: (AddressSanitizer|libFuzzer|UndefinedBehaviorSanitizer|LeakSanitizer)|runtime error|terminate called' "$log" || true)
    echo "fuzz: fuzz_$t FOUND A CRASH (exit $rc): ${summary:-see the log}" >&2
    echo "fuzz:   input: ${artifact:-none written}; reproduce: $BUILD/tests/fuzz/fuzz_$t ${artifact:-FILE}" >&2
  fi
done
exit $status
