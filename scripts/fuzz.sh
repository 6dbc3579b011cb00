#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) into build/fuzz with clang, AddressSanitizer and UBSan,
# and runs each for SECONDS (default 60) from its seeds in tests/fuzz/corpus. Exits non-zero when
# a target finds a crash, a leak, a sanitizer report or an exception other than aero::Error;
# the input that caused it is kept as build/fuzz/findings/<target>/crash-* (or leak-, timeout-,
# oom-). Usage: scripts/fuzz.sh [seconds] [target...]   (targets: see `targets` below)
# Environment: JOBS (compile jobs, default 1), RSS_MB (default 2048).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
build=build/fuzz
# target -> its seed directory under tests/fuzz/corpus
declare -A seeds=(
  [fuzz_iges_text]=iges [fuzz_iges]=iges [fuzz_step]=step [fuzz_patchset_json]=patchset_json
  [fuzz_case_file]=case_file [fuzz_plot3d]=plot3d [fuzz_restart]=restart
  [fuzz_wall_pressure]=wall_pressure [fuzz_history]=history [fuzz_warm_state]=warm_state
)
targets=(fuzz_iges_text fuzz_iges fuzz_step fuzz_patchset_json fuzz_case_file fuzz_plot3d fuzz_restart
         fuzz_wall_pressure fuzz_history fuzz_warm_state)
if [ $# -gt 0 ]; then targets=("$@"); fi
for t in "${targets[@]}"; do
  [ -n "${seeds[$t]:-}" ] || { echo "[fuzz] unknown target '$t'" >&2; exit 2; }
done

if ! command -v "${CXX:-clang++-14}" >/dev/null || ! dpkg-query -W libfuzzer-14-dev >/dev/null 2>&1; then
  echo "[fuzz] needs clang and libFuzzer: apt-get install clang libfuzzer-14-dev" >&2
  exit 2
fi
CC="${CC:-clang-14}" CXX="${CXX:-clang++-14}" cmake -S . -B "$build" -G Ninja -DAEROFORM_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" \
  -DAEROFORM_BUILD_GUI=OFF -DAEROFORM_BUILD_BENCH=OFF >/dev/null
ninja -C "$build" -j"${JOBS:-1}" "${targets[@]}"

# OCCT and OpenMP keep memory on purpose until exit; only the readers' own leaks matter, and
# those show up as growing RSS (rss_limit_mb) rather than through LeakSanitizer at exit.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export OMP_NUM_THREADS=1
status=0
printf '%-20s %8s %10s %8s %s\n' target seconds exec/s corpus result
for t in "${targets[@]}"; do
  work="$build/corpus/$t"      # new inputs go here; the checked-in seeds stay untouched
  found="$build/findings/$t"
  mkdir -p "$work" "$found"
  log="$build/fuzz-$t.log"
  set +e
  "$build/tests/fuzz/$t" "$work" "tests/fuzz/corpus/${seeds[$t]}" -max_total_time="$seconds" \
    -rss_limit_mb="${RSS_MB:-2048}" -timeout=10 -print_final_stats=1 -artifact_prefix="$found/" \
    >"$log" 2>&1
  rc=$?
  set -e
  execs=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  units=$(find "$work" -type f | wc -l)
  if [ $rc -eq 0 ]; then result=ok; else result="FOUND (exit $rc, see $log)"; status=1; fi
  printf '%-20s %8s %10s %8s %s\n' "$t" "$seconds" "${execs:-?}" "$units" "$result"
done
exit $status
