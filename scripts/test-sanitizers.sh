#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer build (the `asan` preset) of the geometry layers
# -- NURBS, patch sets, both FFD levels' lattices, grids, elasticity, Plot3D -- and their tests,
# with the fuzz corpora of the readers of outside files they build on replayed (tests/fuzz:
# replay_plot3d, and replay_iges, replay_iges_text and replay_step over the CAD readers' own
# pre-checks, about 1.5 minutes of building for the OpenCASCADE layer);
# scripts/test.sh runs it after the release tests. Every test of these executables runs; an ASan
# or UBSan report fails the test (abort_on_error, halt_on_error in the preset). The rest of the
# suite (flow, adjoint, study, CLI, GUI) under ASan is `ctest --preset asan` on a full asan
# build: about 6x the release time, longer than CI allows (docs/reliability.md has its record).
# Then ThreadSanitizer (the `tsan` preset: clang, OpenMP through libomp, followed by the Archer
# tool) on the code that runs threads: the OpenMP linear algebra (test_threads: block CG, block
# ILU in parts, block-sparse products, GMRES) on 2 threads, and the GUI's job runner
# (test_job_runner: worker threads, progress, cancellation). Any race report fails the test.
set -euo pipefail
cd "$(dirname "$0")/.."
targets=(test_nurbs test_geometry test_ffd test_mesh replay_plot3d replay_iges replay_iges_text replay_step)
cmake --preset asan > /dev/null
cmake --build --preset asan --target "${targets[@]}" -j"$(nproc)"
ctest --preset asan -L "^(test_(nurbs|geometry|ffd|mesh)|replay_(plot3d|iges|iges_text|step))$" -j2 --timeout 900

tsan_targets=(test_threads test_job_runner)
cmake --preset tsan > /dev/null
cmake --build --preset tsan --target "${tsan_targets[@]}" -j"$(nproc)"
OMP_NUM_THREADS=2 ctest --preset tsan -L "^(test_threads|test_job_runner)$" -j1 --timeout 900
