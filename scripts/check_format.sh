#!/usr/bin/env bash
# Checks that every C++ file is laid out as .clang-format says (clang-format 14, Debian's), and
# names the files that are not. Fix with: clang-format-14 -i FILE...
# Part of the release stage of scripts/run_tests.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/install-deps.sh clang-format-14
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  # Tracked and new (untracked, not ignored) files alike, so that a file is checked before it is
  # added; a tracked file deleted in the work tree is skipped.
  mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp' |
    while read -r f; do [[ -f $f ]] && echo "$f"; done | sort -u)
else
  mapfile -t files < <(find src tests bench -name '*.cpp' -o -name '*.hpp')
fi
# One process for all files; each departure is reported as "FILE:LINE:COLUMN: error: ...".
if ! report=$(clang-format-14 --dry-run --Werror "${files[@]}" 2>&1); then
  unformatted=$(grep -oE '^[^:]+:[0-9]+:[0-9]+: error' <<<"$report" | cut -d: -f1 | sort -u | tr '\n' ' ')
  echo "check_format: not laid out as .clang-format says (clang-format-14 -i to fix): ${unformatted:-$report}" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files laid out as .clang-format says"
