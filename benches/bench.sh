#!/usr/bin/env bash
# enginedyn against the Python yardsticks of ../shared/bench (see bench.py).
# usage: benches/bench.sh [FILES] [CYCLES] [ROUNDS]   (defaults 40 files, 50 cycles, 9 rounds)
set -euo pipefail
cd "$(dirname "$0")/.."
exec python3 benches/bench.py --files "${1:-40}" --cycles "${2:-50}" --rounds "${3:-9}" ${RESULTS:+--results "$RESULTS"}
