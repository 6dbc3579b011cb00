#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build (the `asan` preset) of the geometry layers
# -- NURBS, patch sets, both FFD levels' lattices, grids, elasticity, Plot3D -- and their tests,
# with the Plot3D reader's fuzz corpus replayed (tests/fuzz: replay_plot3d);
# scripts/test.sh runs it after the release tests. Every test of these executables runs; an ASan
# or UBSan report fails the test (abort_on_error, halt_on_error in the preset). The rest of the
# suite (flow, adjoint, study, CLI, GUI) under ASan is `ctest --preset asan` on a full asan
# build: about 6x the release time, longer than CI allows (docs/reliability.md has its record).
set -euo pipefail
cd "$(dirname "$0")/.."
targets=(test_nurbs test_geometry test_ffd test_mesh replay_plot3d)
cmake --preset asan > /dev/null
cmake --build --preset asan --target "${targets[@]}" -j"$(nproc)"
ctest --preset asan -L "^(test_(nurbs|geometry|ffd|mesh)|replay_plot3d)$" -j2 --timeout 900
