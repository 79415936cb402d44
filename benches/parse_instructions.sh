#!/bin/sh
# Instructions of the text parse (valgrind's callgrind, deterministic where
# wall time on a shared machine is not): `batch --parse-only` and the full
# batch on one bench file, for each binary given, with the self cost of the
# text path's functions (fast::long, the row template's carry and seed,
# the learning of a cell's shape).
#
# usage: sh benches/parse_instructions.sh FILE.csv ENGINE.toml BIN...
# e.g.   sh benches/parse_instructions.sh /tmp/bench/d0000.csv \
#            /tmp/bench/engine.toml /tmp/enginedyn-old target/release/enginedyn
set -eu
file=$1 engine=$2
shift 2
out=$(mktemp -d)
bytes=$(wc -c < "$file")
for bin in "$@"; do
    for mode in parse-only full; do
        flag=""
        [ "$mode" = parse-only ] && flag=--parse-only
        valgrind --tool=callgrind --callgrind-out-file="$out/cg" \
            "$bin" batch --engine "$engine" --jobs 1 $flag "$file" \
            > /dev/null 2> "$out/log" || true
        total=$(grep -o 'refs: *[0-9,]*' "$out/log" | tr -dc 0-9)
        echo "$bin $mode: $total instructions"
        if [ "$mode" = parse-only ]; then
            callgrind_annotate "$out/cg" 2> /dev/null \
                | grep -E 'fast::long|template::|number::Shapes' \
                | awk -v b="$bytes" '{ n = $1; gsub(",", "", n); printf "    %.2f a byte: %s\n", n / b, $0 }' \
                | sed 's/ *\[.*\]//'
        fi
    done
done
rm -rf "$out"
