#!/usr/bin/env bash
# Configures and builds the Release preset (GUI, CLI, tests, benchmarks) into build/release.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset release >/dev/null
cmake --build --preset release -j"$(nproc)"
