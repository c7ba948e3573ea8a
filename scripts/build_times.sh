#!/usr/bin/env bash
# Where the build's time goes (`make build-times`): a clean build in its own folder without ccache,
# every compile and link timed by scripts/time_command.py, then scripts/build_times.py's tables
# (CPU per target, the most expensive translation units, the wall time they imply on an idle
# machine of JOBS cores) and the whole build's CPU and wall time.
#
#   scripts/build_times.sh [TARGET...]      (default: all)
#   BUILD_TIMES_DIR=build-times JOBS=2 CMAKE_ARGS="-DPHYSIK_PYTHON=OFF" scripts/build_times.sh physik_cli
#
# CPU time (user + sys) is what other processes on a shared machine hardly change; the wall time
# is this machine's, as busy as it was. The folder keeps the log (time_log.tsv), one CSV row per
# command (build_times.csv) and the tables (build_times.txt).
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${BUILD_TIMES_DIR:-build-times}
jobs=${JOBS:-2}
python=${PYTHON:-/usr/bin/python3}
generator=${CMAKE_GENERATOR:-}
[ -n "$generator" ] || { command -v ninja > /dev/null && generator=Ninja || generator="Unix Makefiles"; }
targets=("$@")
[ ${#targets[@]} -ne 0 ] || targets=(all)

rm -rf "$dir"
mkdir -p "$dir"
log=$(realpath "$dir")/time_log.tsv
launcher="$python;$(realpath scripts/time_command.py);$log"
export CCACHE_DISABLE=1
echo "build-times: configuring $dir ($generator, no ccache)"
# shellcheck disable=SC2086  # CMAKE_ARGS is a list of options
cmake -S . -B "$dir" -G "$generator" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE="$python" \
  -DPHYSIK_CCACHE=OFF -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" \
  -DCMAKE_CXX_LINKER_LAUNCHER="$launcher" ${CMAKE_ARGS:-} > "$dir/configure.log"
: > "$log"
echo "build-times: building ${targets[*]} with $jobs jobs"
/usr/bin/time -f "%e s wall, %U s user, %S s sys" -o "$dir/whole_build.txt" \
  cmake --build "$dir" -j "$jobs" --target "${targets[@]}" > "$dir/build.log"
{
  echo "the whole build (cmake --build -j $jobs --target ${targets[*]}): $(cat "$dir/whole_build.txt")"
  echo
  "$python" scripts/build_times.py "$log" --jobs "$jobs" --csv "$dir/build_times.csv"
} | tee "$dir/build_times.txt"
