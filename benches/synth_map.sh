#!/bin/sh
# Synthesis for design (issue 35): a 20 × 10 speed × load map on one core
# (target: at most 3 s), and the engine file it runs on (the petrol
# template with [combustion]). `cargo build --release` first.
# Usage: sh benches/synth_map.sh [ROUNDS]
set -eu
BIN=${BIN:-target/release/enginedyn}
ROUNDS=${1:-5}
DIR=$(mktemp -d)
trap 'rm -rf "$DIR"' EXIT
"$BIN" template --combustion petrol > "$DIR/petrol.toml"
echo "20 speeds (1000:6700:300) x 10 loads (2:20:2 bar) at 0.1°, one core:"
for r in $(seq "$ROUNDS"); do
    start=$(date +%s.%N)
    RAYON_NUM_THREADS=1 taskset -c 0 "$BIN" sweep --engine "$DIR/petrol.toml" \
        --rpm 1000:6700:300 --imep 2:20:2 --out "$DIR/map" 2>/dev/null
    end=$(date +%s.%N)
    echo "  round $r: $(echo "$end - $start" | bc) s"
done
echo "one synthesised point at 0.1° (synth, process start included), one core:"
for r in $(seq "$ROUNDS"); do
    start=$(date +%s.%N)
    taskset -c 0 "$BIN" synth --engine "$DIR/petrol.toml" --imep 9 --out "$DIR/p.csv" > /dev/null
    end=$(date +%s.%N)
    echo "  round $r: $(echo "$end - $start" | bc) s"
done
