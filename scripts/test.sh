#!/usr/bin/env bash
# Checks the sources (no .cpp over 600 lines, clang-format), builds emrm and runs every test three
# times: a normal GCC build (preset dev), GCC under
# AddressSanitizer + UndefinedBehaviorSanitizer (preset asan), and clang under both sanitizers
# (preset clang), whose libFuzzer targets then each run a short smoke run (docs/fuzzing.md,
# docs/testing.md).
# Run scripts/install-deps.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/lint.sh sources
cmake --workflow --preset dev
cmake --workflow --preset asan
cmake --workflow --preset clang
./scripts/fuzz.sh --seconds 10
