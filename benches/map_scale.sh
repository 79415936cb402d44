#!/bin/sh
# Peak memory (max RSS) and time of a speed × load map and of long sweeps
# (issues 44.8 and 41.11): `sh benches/map_scale.sh [BINARY]`, one core.
# Needs GNU time (/usr/bin/time -v).
set -u
BIN=${1:-target/release/enginedyn}
T=$(mktemp -d)
"$BIN" template --combustion petrol > "$T/petrol.toml"
run() {
    echo "== $*"
    RAYON_NUM_THREADS=1 /usr/bin/time -v taskset -c 0 "$BIN" "$@" >/dev/null 2>"$T/err"
    echo "exit $?"
    grep -E "Maximum resident|Elapsed \(wall" "$T/err"
    grep -cE "^(note|warning):" "$T/err" | sed 's/^/note and warning lines: /'
}
# The design model's maps (RESULTS "Session 17: a map with the design
# model"): 60 × 40 by IMEP (a cycle a load) and in percent of the
# full-load line (a cycle a point).
run sweep --engine "$T/petrol.toml" --rpm 1000:6900:100 --imep 1:14.65:0.35 --csv
run sweep --engine "$T/petrol.toml" --rpm 1000:6900:100 --load 2.5:100:2.5 --csv
# 60 speeds × 40 loads at 0.1° (the default step).
run sweep --engine "$T/petrol.toml" --rpm 1000:6900:100 --imep 0.5:20:0.5 --out "$T/m6040"
# The 100,000 points (each axis within its own cap).
run sweep --engine "$T/petrol.toml" --rpm 1000:10999:10 --imep 1:100:1 --out "$T/m100k"
# At the cap: 100 × 100 points.
run sweep --engine "$T/petrol.toml" --rpm 1000:10900:100 --imep 0.2:20:0.2 --out "$T/mcap"
# A speed-only sweep of 2,501 and of 10,000 speeds.
run sweep --engine data/vaz2108.toml --rpm 1000:6000:2 --out "$T/s2500"
run sweep --engine data/vaz2108.toml --rpm 1000:10999:1 --out "$T/s10k"
rm -rf "$T"
