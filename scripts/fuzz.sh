#!/usr/bin/env bash
# Runs emrm's libFuzzer targets (docs/fuzzing.md) from the clang build, each for SECONDS, two at a
# time, and prints one line per target: executions, coverage, corpus. Exit 1 when any target found
# a crash, a leak, an input slower than 10 s or one using more than 2 GB; its input is then in
# BUILD/fuzz-artifacts/TARGET/ (save it under tests/fuzz-regressions/TARGET/ once fixed).
#
#   scripts/fuzz.sh [--seconds S] [--runs R] [--build DIR] [--jobs N] [--seed K] [TARGET...]
#
# A target stops after S seconds or R executions, whichever comes first.
# Defaults: 30 s, no execution limit (-1), build/clang, 2 jobs, seed 1 (libFuzzer's -seed: the same mutations on every
# machine, so CI's smoke run is reproducible; 0 picks a random one), every target. The working corpus grows in
# BUILD/fuzz-corpus/TARGET/, seeded from fuzz/seeds/TARGET/ (kept between runs: a long campaign
# is the same command with more seconds, or several in a row).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=30
runs=-1
build=build/clang
jobs=2
seed=1
targets=()
while (($#)); do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --build) build="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
    -*) echo "fuzz.sh: unknown option '$1'" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
if ((${#targets[@]} == 0)); then
  for seeds in fuzz/seeds/*/; do targets+=("$(basename "$seeds")"); done
fi
for t in "${targets[@]}"; do
  [[ -x "$build/fuzz/fuzz_$t" ]] || { echo "fuzz.sh: no $build/fuzz/fuzz_$t (cmake --workflow --preset clang builds it)" >&2; exit 2; }
done

run_one() {
  local t="$1" corpus="$build/fuzz-corpus/$1" artifacts="$build/fuzz-artifacts/$1" log="$build/fuzz-logs/$1.log"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  cp -L fuzz/seeds/"$t"/* "$corpus"/ 2>/dev/null || true
  local status=0 start=$SECONDS
  ASAN_OPTIONS="detect_leaks=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -runs="$runs" -seed="$seed" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -close_fd_mask=1 -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" >"$log" 2>&1 || status=$?
  local execs cov corpus_size rss elapsed=$((SECONDS - start))
  rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log" | tail -1)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  corpus_size=$(find "$corpus" -type f | wc -l)
  if ((status == 0)); then
    printf '%-18s ok      %10s execs  cov %6s  corpus %5s  rss %5s MB  %6s s\n' "$t" "${execs:-?}" "${cov:-?}" "$corpus_size" "${rss:-?}" "$elapsed"
  else
    printf '%-18s FAILED  %10s execs  cov %6s  corpus %5s  (see %s)\n' "$t" "${execs:-?}" "${cov:-?}" "$corpus_size" "$log"
    grep -m3 -E 'ERROR|SUMMARY|timeout|out-of-memory|deadly' "$log" | sed 's/^/    /'
    return 1
  fi
}
export -f run_one
export build seconds runs seed
printf '%s\n' "${targets[@]}" | xargs -P "$jobs" -I{} bash -c 'run_one "$@"' _ {} || exit 1
