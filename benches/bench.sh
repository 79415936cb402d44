#!/usr/bin/env bash
# enginedyn against the Python yardsticks of ../shared/bench, on the same
# files, in the same run; prints seconds per file and the ratios.
# usage: benches/bench.sh [FILES] [CYCLES]   (defaults 40 files of 50 cycles at 0.1°)
set -euo pipefail
cd "$(dirname "$0")/.."
files=${1:-40}
cycles=${2:-50}
shared=../shared/bench
python3 -c "import numpy, pandas, pyarrow" 2>/dev/null \
  || python3 -m pip install --quiet numpy pandas pyarrow
cargo build --release --quiet
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 "$shared/make_batch.py" "$dir" --files "$files" --cycles "$cycles" --step 0.1 > /dev/null
echo "machine: $(nproc) cores, $(uname -m); $files files x $cycles cycles at 0.1° ($(du -sh "$dir" | cut -f1))"
slow=$(python3 "$shared/yardstick.py" "$dir/engine.toml" "$dir"/d*.csv)
slow=${slow%% s per file*}
fast=$(python3 "$shared/yardstick_fast.py" "$dir/engine.toml" "$dir"/d*.csv)
fast=${fast%% s per file*}
t0=$(date +%s.%N)
./target/release/enginedyn batch --engine "$dir/engine.toml" "$dir" --out "$dir/out" 2> /dev/null
t1=$(date +%s.%N)
t2=$(date +%s.%N)
./target/release/enginedyn batch --engine "$dir/engine.toml" "$dir" --jobs 1 --out "$dir/out1" 2> /dev/null
t3=$(date +%s.%N)
python3 - "$slow" "$fast" "$t0" "$t1" "$t2" "$t3" "$files" <<'PY'
import sys
slow, fast, t0, t1, t2, t3, n = map(float, sys.argv[1:])
ours = (t1 - t0) / n
ours1 = (t3 - t2) / n
print(f"yardstick.py (pandas)          {slow:.4f} s per file")
print(f"yardstick_fast.py (pyarrow)    {fast:.4f} s per file")
print(f"enginedyn batch, all cores     {ours:.4f} s per file  ({slow/ours:.1f}x pandas, {fast/ours:.2f}x pyarrow)")
print(f"enginedyn batch, --jobs 1      {ours1:.4f} s per file  ({slow/ours1:.1f}x pandas, {fast/ours1:.2f}x pyarrow)")
PY
