#!/usr/bin/env bash
# Peak memory of one cycle per column at the column bound (issue 29, item 8;
# INTERFACE.md "Bounds": at most 16,384 columns and 8 bytes a value): a
# header-less file of 16,384 columns (the angle and 16,383 cycles) by 720
# rows, read with --columns crank_deg,pressure_bar... Target: peak RSS
# below 150 MB. Usage: bash benches/wide_columns.sh [ROWS] (default 720).
set -euo pipefail
cd "$(dirname "$0")/.."
rows=${1:-720}
cargo build --release --quiet
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir/wide.csv" "$rows" <<'PY'
import math, sys
path, rows = sys.argv[1], int(sys.argv[2])
with open(path, "w") as f:
    for k in range(rows):
        a = k * 720.0 / rows
        d = (a - 10 + 360) % 720 - 360
        p = 1.0 + 50.0 * math.exp(-((d / 30.0) ** 2))
        f.write(f"{a}" + f",{p:.3f}" * 16383 + "\n")
PY
size=$(stat -c %s "$dir/wide.csv")
/usr/bin/time -f "%M %e" -o "$dir/time" ./target/release/enginedyn run --engine data/single.toml \
  --diagram "$dir/wide.csv" --columns 'crank_deg,pressure_bar...' --json > /dev/null 2> "$dir/err" || {
  cat "$dir/err"; exit 1; }
read -r kb secs < "$dir/time"
values=$((16383 * rows))
echo "16,384 columns x $rows rows ($((size / 1000000)) MB, $values values): peak RSS $((kb / 1024)) MB ($(python3 -c "print(round($kb*1024/$values,1))") bytes a value), $secs s"
if [ "$kb" -ge $((150 * 1024)) ]; then echo "above the 150 MB target"; exit 1; fi
