#!/usr/bin/env bash
# Runs the dataflow engine's tests under ThreadSanitizer:
#   scripts/tsan.sh            (about 10-20 minutes on 2 cores; not part of ./dev.sh test)
# TSan only sees the synchronisation of code it instruments, and Debian's libtbb is not
# instrumented: every hand-over between oneTBB tasks would be reported as a race. So this script
# builds oneTBB itself from Debian's source package with -fsanitize=thread (once, cached in
# build/tsan-tbb), builds the engine's tests with -DMEREO_SANITIZE=thread (build/tsan) and runs
# them against that libtbb. The only suppression (tests/tsan.supp) is for a third-party library;
# any report fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
TBB_DIR=$ROOT/build/tsan-tbb
if [ ! -f "$TBB_DIR/lib/libtbb.so.12" ]; then
  mkdir -p "$TBB_DIR/src"
  if ! ls "$TBB_DIR"/src/onetbb_*.orig.tar.* >/dev/null 2>&1; then
    if ! grep -rqs "deb-src" /etc/apt/sources.list /etc/apt/sources.list.d/; then
      SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
      printf 'Types: deb-src\nURIs: http://deb.debian.org/debian\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
        $SUDO tee /etc/apt/sources.list.d/mereo-deb-src.sources >/dev/null
      $SUDO apt-get update -qq
    fi
    (cd "$TBB_DIR/src" && apt-get source -qq --download-only onetbb)
  fi
  tar -C "$TBB_DIR/src" -xf "$TBB_DIR"/src/onetbb_*.orig.tar.*
  src=$(ls -d "$TBB_DIR"/src/oneTBB-*/ | head -1)
  cmake -S "$src" -B "$TBB_DIR/build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTBB_TEST=OFF \
    -DTBB_STRICT=OFF -DTBB_SANITIZE=thread -DTBBMALLOC_BUILD=OFF -DCMAKE_POLICY_VERSION_MINIMUM=3.5 >/dev/null
  cmake --build "$TBB_DIR/build" -j2 >/dev/null
  mkdir -p "$TBB_DIR/lib"
  cp -a "$TBB_DIR"/build/*_relwithdebinfo/libtbb.so* "$TBB_DIR/lib/"
fi
cmake -S . -B build/tsan -G Ninja -DMEREO_BUILD_TESTS=ON -DMEREO_SANITIZE=thread \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_POLICY_VERSION_MINIMUM=3.5 >/dev/null
cmake --build build/tsan --target test_graph -j2
LD_LIBRARY_PATH=$TBB_DIR/lib TSAN_OPTIONS="suppressions=$ROOT/tests/tsan.supp halt_on_error=1 exitcode=66" \
  ./build/tsan/tests/test_graph
