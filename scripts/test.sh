#!/usr/bin/env bash
# Checks the sources (no .cpp over 600 lines, clang-format), builds emrm three times and runs
# every test in a normal GCC build (preset dev) and every test once under AddressSanitizer +
# UndefinedBehaviorSanitizer: a third in clang (preset clang), the other two thirds in GCC (preset
# asan) (docs/testing.md); then clang-tidy over the clang build's unity batches (and the MPI and
# Python sources through the dev build), and a short smoke run of each libFuzzer target
# (docs/fuzzing.md). Each stage prints its time; a stage over its budget (below, for CI's two
# cores from a clean clone) fails the run once every stage has run.
# Run scripts/install-deps.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."

# Seconds each stage may take on CI's machine (2 cores, a clean clone, nothing cached): about 1.5
# times what it took there (docs/testing.md, "Stage times"). A stage over budget names itself.
declare -A budget=(
  [lint]=60
  [dev-build]=1200 [dev-test]=420
  [clang-build]=900 [clang-test]=330
  [asan-build]=750 [asan-test]=520
  [tidy]=360 [fuzz]=200
)
order=()
declare -A took=()

stage() {
  local name="$1" start=$SECONDS
  shift
  echo "== stage $name"
  "$@"
  took[$name]=$((SECONDS - start))
  order+=("$name")
  printf '== stage %s: %d s (budget %d s)\n' "$name" "${took[$name]}" "${budget[$name]}"
}

# The tests of a build that the clang run did not take: by name, so that the two sanitized runs
# together run every test once whatever their indices (ctest -I with the indices listed).
not_in_clang_run() {
  local -A in_clang=()
  local name
  while IFS= read -r name; do in_clang[$name]=1; done < <(ctest --preset clang -N | sed -n 's/^ *Test *#[0-9]*: //p')
  local -a rest=()
  local index
  while read -r index name; do
    [[ -n ${in_clang[$name]:-} ]] || rest+=("$index")
  done < <(ctest --preset "$1" -N | sed -n 's/^ *Test *#\([0-9]*\): /\1 /p')
  local IFS=,
  echo "0,0,0,${rest[*]}"
}

asan_test() { ctest --preset asan -I "$(not_in_clang_run asan)"; }

stage lint ./scripts/lint.sh sources
stage dev-build bash -c 'cmake --preset dev >/dev/null && cmake --build --preset dev'
stage dev-test ctest --preset dev
stage clang-build bash -c 'cmake --preset clang >/dev/null && cmake --build --preset clang'
stage clang-test ctest --preset clang
stage asan-build bash -c 'cmake --preset asan >/dev/null && cmake --build --preset asan'
stage asan-test asan_test
stage tidy ./scripts/lint.sh tidy
stage fuzz ./scripts/fuzz.sh --seconds 10

echo "== stage times (s)"
over=()
total=0
for name in "${order[@]}"; do
  printf '  %-12s %5d  (budget %d)\n' "$name" "${took[$name]}" "${budget[$name]}"
  total=$((total + took[$name]))
  if ((took[$name] > budget[$name])); then over+=("$name"); fi
done
printf '  %-12s %5d\n' total "$total"
if ((${#over[@]})); then
  echo "test.sh: over budget: ${over[*]} (budgets at the top of scripts/test.sh, docs/testing.md)" >&2
  exit 1
fi
