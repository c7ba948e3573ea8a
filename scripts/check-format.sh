#!/usr/bin/env bash
# Check that every tracked C++ file is as .clang-format (Google, 100 columns) writes it, with
# Debian's clang-format; exit 1 listing the files that differ. `make format` rewrites them.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format > /dev/null || {
  echo "check-format: clang-format not found (make deps installs it)" >&2
  exit 2
}
mapfile -t files < <(git ls-files '*.cpp' '*.h')
# one clang-format for every file; its messages start "file:line:col: error:"
rc=0
out=$(clang-format --dry-run -Werror "${files[@]}" 2>&1) || rc=$?
mapfile -t bad < <(printf '%s\n' "$out" | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error:.*/\1/p' | sort -u)
if [ $rc -ne 0 ] && [ ${#bad[@]} -eq 0 ]; then
  printf '%s\n' "$out" | tail -5 >&2
  echo "check-format: clang-format failed (exit $rc)" >&2
  exit 1
fi
if [ ${#bad[@]} -ne 0 ]; then
  echo "check-format: ${#bad[@]} of ${#files[@]} C++ files differ from .clang-format:" >&2
  printf '  %s\n' "${bad[@]}" >&2
  echo "check-format: run 'make format' (clang-format -i) and commit" >&2
  exit 1
fi
echo "check-format: ${#files[@]} C++ files as .clang-format writes them"
