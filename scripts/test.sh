#!/usr/bin/env bash
# Checks the sources (no .cpp over 600 lines, clang-format), builds emrm three times and runs
# every test in a normal GCC build (preset dev) and in GCC under AddressSanitizer +
# UndefinedBehaviorSanitizer (preset asan), and every third test in clang under both sanitizers
# (preset clang, docs/testing.md); then clang-tidy over the clang build's unity batches (and the MPI and Python
# sources through the dev build), and a short smoke run of each libFuzzer target (docs/fuzzing.md,
# docs/testing.md).
# Run scripts/install-deps.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/lint.sh sources
cmake --workflow --preset dev
cmake --workflow --preset asan
cmake --workflow --preset clang
./scripts/lint.sh tidy
./scripts/fuzz.sh --seconds 10
