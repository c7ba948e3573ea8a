#!/usr/bin/env bash
# Install the Debian packages a command needs, only those missing. Uses sudo when not root.
#
#   scripts/install-deps.sh [SET...]            install the sets now (default: all of them)
#   scripts/install-deps.sh --start LOG SET...  install them in the background, output in LOG
#   scripts/install-deps.sh --wait LOG          wait for that install; exit 1 if it failed
#   scripts/install-deps.sh --list SET...       print the sets' packages
#
# The sets (a command installs what it needs; the Makefile says which):
#   build   the compiler, CMake, Ninja and every library the build compiles against
#   run     what the command line's scenes and experiments read at run time: MuJoCo's sample
#           models, matplotlib and Pillow for the figures, three.js for the viewer's pages
#   test    what the tests run besides the build: valgrind, pytest, Dask, Blender and a virtual
#           X server for the add-on, Chromium and its driver for the viewer's page
#   format  clang-format (scripts/check-format.sh)
# `make build-cli` and `make test` install `build` first and the rest in the background while
# the build compiles (--start), then wait for it (--wait) before anything runs: Blender and
# Chromium, most of the download, overlap the compile.
set -euo pipefail

set_packages() {
  case "$1" in
    build)
      echo build-essential cmake ninja-build \
        libeigen3-dev nlohmann-json3-dev libcli11-dev \
        libmujoco-dev libqhull-dev libceres-dev libfcl-dev liborocos-kdl-dev \
        libgtest-dev libbenchmark-dev pybind11-dev python3-dev
      ;;
    run) echo libmujoco-samples python3-matplotlib python3-numpy python3-pil libjs-three ;;
    # valgrind: `make bench-count`'s instruction counts and the bench_count test
    test)
      echo valgrind python3-pytest python3-distributed blender xvfb \
        chromium chromium-driver python3-selenium
      ;;
    format) echo clang-format ;;
    *)
      echo "install-deps: unknown set '$1' (known: build run test format)" >&2
      exit 2
      ;;
  esac
}

missing_of() {
  local p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2> /dev/null | grep -q "install ok installed" || echo "$p"
  done
}

sudo_prefix() {
  [ "$(id -u)" -eq 0 ] || echo sudo
}

# apt-get waits up to 10 minutes for another install's lock (a background one) instead of failing
install_now() {
  local sudo
  sudo=$(sudo_prefix)
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get -o DPkg::Lock::Timeout=600 update -qq &&
    $sudo apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "$@"
}

mode=now
log=""
case "${1:-}" in
  --start | --wait)
    mode=${1#--}
    log=${2:?"install-deps: $1 needs a log file"}
    shift 2
    ;;
  --list)
    mode=list
    shift
    ;;
esac

if [ "$mode" = wait ]; then
  [ -f "$log.pid" ] || exit 0 # nothing was started
  pid=$(cat "$log.pid")
  if kill -0 "$pid" 2> /dev/null; then
    echo "deps: waiting for the background install (log: $log)"
    while kill -0 "$pid" 2> /dev/null; do sleep 2; done
  fi
  rm -f "$log.pid"
  status=$(tail -n 1 "$log")
  if [ "$status" != "deps: done" ]; then
    tail -n 20 "$log" >&2
    echo "deps: the background install failed (log: $log)" >&2
    exit 1
  fi
  echo "deps: background install done"
  exit 0
fi

sets=("$@")
[ ${#sets[@]} -ne 0 ] || sets=(build run test format)
packages=()
for s in "${sets[@]}"; do
  set_packages "$s" > /dev/null # exits 2 on an unknown set
  read -r -a in_set <<< "$(set_packages "$s")"
  packages+=("${in_set[@]}")
done
if [ "$mode" = list ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi
mapfile -t missing < <(missing_of "${packages[@]}")
if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} Debian packages of ${sets[*]} present"
  exit 0
fi

# a background install cannot ask for a sudo password: then it runs now, in the foreground
if [ "$mode" = start ] && [ -n "$(sudo_prefix)" ] && ! sudo -n true 2> /dev/null; then
  echo "deps: sudo needs a password, so ${sets[*]} install now rather than in the background"
  mode=now
fi
if [ "$mode" = now ]; then
  echo "deps: installing ${missing[*]}"
  install_now "${missing[@]}"
  exit 0
fi

mkdir -p "$(dirname "$log")"
echo "deps: installing ${sets[*]} in the background (${#missing[@]} packages; log: $log)"
(
  if install_now "${missing[@]}"; then echo "deps: done"; else echo "deps: failed"; fi
) > "$log" 2>&1 < /dev/null &
echo $! > "$log.pid"
