#!/usr/bin/env bash
# Fails if any C++ source under include/, src/, tests/, bench/ or fuzz/ differs from what
# clang-format makes of it with the tree's .clang-format (ctest Formatting).
# Usage: check_format.sh SOURCE_DIR. Fix with:
#   find include src tests bench -name '*.cpp' -o -name '*.hpp' | xargs clang-format -i
# Set CLANG_FORMAT to use another binary. The .clang-format is written for clang-format 14
# (scripts/install-deps.sh installs it); a missing clang-format fails the check.
set -euo pipefail
source_dir=${1:?usage: check_format.sh SOURCE_DIR}
clang_format=${CLANG_FORMAT:-clang-format}
if ! command -v "$clang_format" >/dev/null 2>&1; then
  echo "check_format: $clang_format not found (scripts/install-deps.sh installs it)" >&2
  exit 1
fi
cd "$source_dir"
if [ ! -f .clang-format ]; then
  echo "check_format: no .clang-format in $source_dir" >&2
  exit 1
fi
folders=()
for d in include src tests bench fuzz; do
  [ -d "$d" ] && folders+=("$d")
done
mapfile -d '' files < <(find "${folders[@]}" -type f \( -name '*.cpp' -o -name '*.hpp' \) -print0 | sort -z)
if [ ${#files[@]} -eq 0 ]; then
  echo "check_format: no sources found under $source_dir" >&2
  exit 1
fi
if ! "$clang_format" --style=file --dry-run --Werror "${files[@]}"; then
  echo "check_format: the files above are not formatted; run clang-format -i on them" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted ($("$clang_format" --version))"
