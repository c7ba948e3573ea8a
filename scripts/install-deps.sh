#!/usr/bin/env bash
# Install the Debian packages the testbed needs, only those missing. Uses sudo when not root.
set -euo pipefail
packages=(
  build-essential cmake
  clang-format  # the C++ style check (scripts/check-format.sh): bookworm's clang-format 14
  libeigen3-dev nlohmann-json3-dev libcli11-dev
  libmujoco-dev libqhull-dev libmujoco-samples
  libceres-dev
  libfcl-dev
  libgtest-dev libbenchmark-dev
  valgrind  # `make bench-count`: callgrind's instruction counts (bench/bench_count.py)
  liborocos-kdl-dev
  python3-matplotlib python3-numpy
  pybind11-dev python3-dev python3-pytest python3-distributed
  blender xvfb
  # the viewer: three.js r111 (inlined into every page), the browser its tests drive, and Pillow
  # for the report's animated GIFs
  libjs-three chromium chromium-driver python3-selenium python3-pil
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} Debian packages present"
  exit 0
fi
echo "deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
