#!/usr/bin/env bash
# Checks that every C++ file follows .clang-format (Google-based, 120 columns), with Debian's clang-format-14.
#   bash scripts/check_format.sh          check; lists the files that differ and exits 1
#   bash scripts/check_format.sh --fix    reformat them in place
set -euo pipefail
cd "$(dirname "$0")/.."
clang_format=$(command -v clang-format-14 || true)
if [ -z "$clang_format" ]; then
  echo "check_format: clang-format-14 is missing (bash scripts/setup.sh --tests installs it)" >&2
  exit 2
fi
mapfile -t files < <(git ls-files '*.h' '*.cc' '*.cpp')
if [ "${1:-}" = "--fix" ]; then
  "$clang_format" -i "${files[@]}"
  echo "check_format: formatted ${#files[@]} files"
  exit 0
elif [ -n "${1:-}" ]; then
  echo "usage: $0 [--fix]" >&2
  exit 2
fi
differ=()
for file in "${files[@]}"; do
  "$clang_format" --dry-run --Werror "$file" >/dev/null 2>&1 || differ+=("$file")
done
if ((${#differ[@]} > 0)); then
  printf 'check_format: not formatted: %s\n' "${differ[@]}" >&2
  echo "check_format: ${#differ[@]} of ${#files[@]} files differ from .clang-format (bash scripts/check_format.sh --fix)" >&2
  exit 1
fi
echo "check_format: all ${#files[@]} C++ files follow .clang-format"
