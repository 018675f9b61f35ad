#!/usr/bin/env bash
# Checks the C++ sources against .clang-format with clang-format 14 (dry run, nothing is changed):
#   scripts/check_format.sh [PATH...]   the tracked *.cpp/*.hpp files under PATH (default: host/,
#                                       python/src/, tests/, bench/, fuzz/)
# Prints how many places are off the style, in how many files, and the first of them (clang-format's
# own messages; BRDFBAKE_FORMAT_SHOW=N shows N places, default 20). Exit 0 when every file is
# formatted, 1 when some place is off, 2 when clang-format 14 is missing or a PATH has no C++ file.
# To fix a file: clang-format-14 -i FILE (the whole tree is formatted in one commit, not piecemeal).
# Only tracked files are read (git ls-files), so build trees and generated sources never count;
# kernels/ (OpenCL C) is not checked.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

clang_format=""
for candidate in clang-format-14 clang-format; do
  if command -v "$candidate" > /dev/null && "$candidate" --version | grep -q 'version 14\.'; then
    clang_format=$candidate
    break
  fi
done
if [[ -z $clang_format ]]; then
  echo "scripts/check_format.sh: clang-format 14 not found (apt install clang-format-14; other versions" \
       "format differently)" >&2
  exit 2
fi

paths=("$@")
if ((${#paths[@]} == 0)); then paths=(host python/src tests bench fuzz); fi
patterns=()
for p in "${paths[@]}"; do
  p=${p%/}
  if [[ $p == *.cpp || $p == *.hpp ]]; then patterns+=("$p"); else patterns+=("$p/*.cpp" "$p/*.hpp"); fi
done
mapfile -d '' files < <(git ls-files -z -- "${patterns[@]}")
if ((${#files[@]} == 0)); then
  echo "scripts/check_format.sh: no tracked C++ file under ${paths[*]}" >&2
  exit 2
fi

# --Werror makes clang-format exit non-zero on a file that is off; the messages (one per place:
# FILE:LINE:COL: error: code should be clang-formatted, then the line and a caret) are counted.
report=$(printf '%s\0' "${files[@]}" | xargs -0 "$clang_format" --dry-run --Werror --ferror-limit=0 2>&1) || true
marker='error: code should be clang-formatted'
places=$(grep -c -- "$marker" <<< "$report" || true)
if ((places == 0)); then
  if [[ -n $report ]]; then  # clang-format failed for another reason (a file it cannot read or parse)
    echo "$report" >&2
    exit 2
  fi
  echo "clang-format: ${#files[@]} files, all formatted"
  exit 0
fi
off_files=$(grep -- "$marker" <<< "$report" | cut -d: -f1 | sort -u | wc -l)
show=${BRDFBAKE_FORMAT_SHOW:-20}
echo "clang-format: $places places off the style in $off_files of ${#files[@]} files; the first $show:"
awk -v marker="$marker" -v show="$show" 'index($0, marker) { n++ } n > show { exit } n > 0 { print }' <<< "$report"
echo "Fix a file with: $clang_format -i FILE"
exit 1
