#!/usr/bin/env bash
# Installs what mereo needs on Debian 12 and is missing, idempotently:
#  - the Debian packages of the C++ dependencies (skipped when already installed);
#  - a virtual environment .venv with the pinned build and test tools from PyPI.
# Used by both README commands (dev.sh) and by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential pkg-config python3-venv python3-dev
  libeigen3-dev libtbb-dev libopencv-dev libopencv-contrib-dev libpcl-dev
  libgtest-dev libbenchmark-dev nlohmann-json3-dev libyaml-cpp-dev graphviz
  libcgal-dev toulbar2
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  # python3-venv/python3-dev only matter for Debian's own python3; skip them where python3 is
  # another build (pyenv) that has venv already.
  if python3 -c 'import venv, sysconfig, os; assert os.path.exists(sysconfig.get_paths()["include"] + "/Python.h")' 2>/dev/null; then
    keep=(); for p in "${missing[@]}"; do case "$p" in python3-venv|python3-dev) ;; *) keep+=("$p");; esac; done
    missing=("${keep[@]+"${keep[@]}"}")
  fi
fi
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv"
  python3 -m venv .venv
fi
# Build tools pinned in pyproject.toml's [dev] extra (with [test], [dask] and [open3d] for the tests), installed so that builds reuse one build
# folder (no build isolation) and stay incremental.
.venv/bin/python - <<'PY'
import re, subprocess, sys, tomllib
from importlib import metadata
spec = tomllib.load(open("pyproject.toml", "rb"))["project"]
extras = spec["optional-dependencies"]
wanted = extras["dev"] + extras["test"] + extras["dask"] + extras["open3d"] + spec["dependencies"]
need = []
for req in wanted:
    m = re.match(r"([A-Za-z0-9_.\-]+)\s*(==|>=)?\s*(.*)", req)
    name, op, version = m.group(1), m.group(2), m.group(3)
    try:
        have = metadata.version(name)
        if op == "==" and have != version:
            need.append(req)
    except metadata.PackageNotFoundError:
        need.append(req)
if need:
    print("setup: pip installing", " ".join(need), flush=True)
    subprocess.check_call([sys.executable, "-m", "pip", "install", "-q", "--disable-pip-version-check", *need])
PY
