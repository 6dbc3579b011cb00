#!/usr/bin/env bash
# Installs what is missing, builds Release and runs the main job:
#   scripts/run.sh                 the GUI on the half-sphere sample
#   scripts/run.sh FILE            the GUI on FILE (.igs/.iges or .json)
#   scripts/run.sh --batch [CASE]  headless: runs a case (default samples/bwb_deform.json: deform + mesh)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
if [ "${1:-}" = "--batch" ]; then
  exec build/release/app/aeroform --batch "${2:-samples/bwb_deform.json}"
fi
if [ -z "${DISPLAY:-}" ]; then
  echo "[run] no DISPLAY: starting the GUI under xvfb-run (use --batch FILE for headless work)" >&2
  exec xvfb-run -a -s "-screen 0 1280x800x24" build/release/app/aeroform "${1:-samples/half_sphere.igs}"
fi
exec build/release/app/aeroform "${1:-samples/half_sphere.igs}"
