#!/usr/bin/env bash
# The source checks of the test command (docs/testing.md).
#   scripts/lint.sh sources   no .cpp over 600 lines (one concept per file, docs/architecture.md);
#                             every C++ file as clang-format (.clang-format) writes it
#   scripts/lint.sh tidy      clang-tidy's short rule set (.clang-tidy) finds nothing in the
#                             library, the CLI and the Python module (needs the compile_commands.json
#                             of build/clang and build/dev: run after their `cmake --workflow`)
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

# clang-tidy reads the clang build's unity batches of the library and the CLI (a batch parses its
# heavy headers once: about half the time of file by file), and file by file from build/dev what
# that build leaves out: the MPI sources and the Python module. A batch includes its .cpp files, so
# findings are shown in src/ and apps/ too, and bugprone-suspicious-include (a .cpp included) is off.
check_tidy() {
  local start=$SECONDS
  local build
  for build in build/clang build/dev; do
    if [[ ! -f $build/compile_commands.json ]]; then
      echo "lint: $build/compile_commands.json is missing: run cmake --workflow --preset ${build#build/} first" >&2
      return 2
    fi
  done
  local -a batches files
  mapfile -t batches < <(find "$PWD/build/clang/CMakeFiles" -path '*/Unity/unity_*_cxx.cxx' | sort)
  mapfile -t files < <(git ls-files 'src/cluster/*.cpp' 'python/src/*.cpp' | grep -v without_mpi.cpp)
  if ((${#batches[@]} == 0)); then
    echo "lint: build/clang has no unity batches (the clang preset sets CMAKE_UNITY_BUILD)" >&2
    return 2
  fi
  local jobs
  jobs=$(nproc)
  local -a tidy=(run-clang-tidy -quiet -j "$jobs" -header-filter="$PWD/(src|apps|include|python)/.*"
    -checks=-bugprone-suspicious-include)
  # Colour codes stripped, so that a finding reads (and greps) as FILE:LINE:COLUMN: warning: ...
  local status=0
  "${tidy[@]}" -p build/clang "${batches[@]}" >/tmp/emrm-clang-tidy.raw 2>&1 || status=1
  "${tidy[@]}" -p build/dev "${files[@]/#/$PWD/}" >>/tmp/emrm-clang-tidy.raw 2>&1 || status=1
  sed 's/\x1b\[[0-9;]*m//g' /tmp/emrm-clang-tidy.raw >/tmp/emrm-clang-tidy.log
  if ((status != 0)) || grep -qE 'warning:|error:' /tmp/emrm-clang-tidy.log; then
    grep -E 'warning:|error:' /tmp/emrm-clang-tidy.log | sort -u >&2 || cat /tmp/emrm-clang-tidy.log >&2
    echo "lint: clang-tidy found the above (.clang-tidy lists the checks)" >&2
    return 1
  fi
  printf 'lint: clang-tidy on %d unity batches and %d files in %d s\n' "${#batches[@]}" "${#files[@]}" \
    $((SECONDS - start))
}

case "${1:-all}" in
  sources) check_sources ;;
  tidy) check_tidy ;;
  all) check_sources && check_tidy ;;
  *) echo "usage: scripts/lint.sh [sources|tidy]" >&2; exit 2 ;;
esac
