#!/usr/bin/env bash
# The source checks of the test command (docs/testing.md).
#   scripts/lint.sh sources   no .cpp over 600 lines (one concept per file, docs/architecture.md);
#                             every C++ file as clang-format (.clang-format) writes it
#   scripts/lint.sh tidy      clang-tidy's short rule set (.clang-tidy) finds nothing in the
#                             library, the CLI and the Python module (needs build/dev's
#                             compile_commands.json: run after `cmake --workflow --preset dev`)
# With no argument, both. Exit 1 with the findings listed when a check fails.
set -euo pipefail
cd "$(dirname "$0")/.."

readonly max_cpp_lines=600

check_sources() {
  local failed=0 start=$SECONDS
  local -a long=()
  while IFS= read -r file; do
    local n
    n=$(wc -l <"$file")
    if ((n > max_cpp_lines)); then long+=("$file: $n lines"); fi
  done < <(git ls-files '*.cpp')
  if ((${#long[@]})); then
    printf 'lint: a .cpp file holds at most %d lines (split it by concept):\n' "$max_cpp_lines" >&2
    printf '  %s\n' "${long[@]}" >&2
    failed=1
  fi
  # clang-format's own check mode; a file it would change is named with the first lines it would change.
  if ! git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run --Werror 2>/tmp/emrm-clang-format.log; then
    printf 'lint: clang-format would change these files (run: git ls-files "*.cpp" "*.hpp" | xargs clang-format -i):\n' >&2
    grep -E '^[^ ].*: error:' /tmp/emrm-clang-format.log | cut -d: -f1 | sort -u | sed 's/^/  /' >&2
    failed=1
  fi
  printf 'lint: sources checked in %d s\n' $((SECONDS - start))
  return "$failed"
}

check_tidy() {
  local start=$SECONDS
  if [[ ! -f build/dev/compile_commands.json ]]; then
    echo "lint: build/dev/compile_commands.json is missing: run cmake --workflow --preset dev first" >&2
    return 2
  fi
  local -a files
  mapfile -t files < <(git ls-files 'src/*.cpp' 'apps/*.cpp' 'python/src/*.cpp')
  local jobs
  jobs=$(nproc)
  # Colour codes stripped, so that a finding reads (and greps) as FILE:LINE:COLUMN: warning: ...
  if ! run-clang-tidy -quiet -j "$jobs" -p build/dev "${files[@]/#/$PWD/}" 2>&1 |
    sed 's/\x1b\[[0-9;]*m//g' >/tmp/emrm-clang-tidy.log; then
    grep -E 'warning:|error:' /tmp/emrm-clang-tidy.log | sort -u >&2 || cat /tmp/emrm-clang-tidy.log >&2
    echo "lint: clang-tidy found the above (.clang-tidy lists the checks)" >&2
    return 1
  fi
  if grep -qE 'warning:|error:' /tmp/emrm-clang-tidy.log; then
    grep -E 'warning:|error:' /tmp/emrm-clang-tidy.log | sort -u >&2
    echo "lint: clang-tidy found the above (.clang-tidy lists the checks)" >&2
    return 1
  fi
  printf 'lint: clang-tidy on %d files in %d s\n' "${#files[@]}" $((SECONDS - start))
}

case "${1:-all}" in
  sources) check_sources ;;
  tidy) check_tidy ;;
  all) check_sources && check_tidy ;;
  *) echo "usage: scripts/lint.sh [sources|tidy]" >&2; exit 2 ;;
esac
