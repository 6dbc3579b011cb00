#!/usr/bin/env bash
# Installs what is missing, builds Release and runs every test (GUI tests under Xvfb), then the
# geometry layers' tests under AddressSanitizer + UBSan and the threaded kernels and job runner under
# ThreadSanitizer (scripts/test-sanitizers.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
xvfb-run -a -s "-screen 0 1280x800x24" ctest --preset release -j2 --timeout 600
bash scripts/test-sanitizers.sh
