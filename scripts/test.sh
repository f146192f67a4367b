#!/usr/bin/env bash
# Builds emrm and runs every test twice: a normal build (preset dev), then one under
# AddressSanitizer + UndefinedBehaviorSanitizer (preset asan). Run scripts/install-deps.sh first.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --workflow --preset dev
cmake --workflow --preset asan
