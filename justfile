# Longer recipes. The two everyday commands need no `just`:
#   cargo run --release          # the bundled example
#   cargo test --workspace       # the tests

# Run the bundled example and write its output folder.
example:
    cargo run --release -- run --out reports/vaz2108

# Regenerate every bundled diagram from its documented model (data/README.md).
data:
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 76 --stroke-mm 71 --lambda 0.26 --cr 9.9 --rpm 4900 --step 0.5 --out data/vaz2108.csv
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset diesel --bore-mm 130 --stroke-mm 150 --lambda 0.2830188679245283 --cr 17 --rpm 2200 --step 0.5 --heat-j 6500 --out data/i6_diesel.csv
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 99 --stroke-mm 92 --lambda 0.2967741935483871 --cr 10.2 --rpm 5200 --step 0.5 --heat-j 1450 --out data/v8_crossplane.csv
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 68 --stroke-mm 54 --lambda 0.32142857142857145 --cr 8.5 --rpm 3600 --step 0.5 --heat-j 400 --out data/single.csv
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 88 --stroke-mm 75 --lambda 0.26785714285714285 --cr 11 --rpm 6500 --step 0.5 --heat-j 935 --out data/v12_60.csv
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset two-stroke --bore-mm 73.5 --stroke-mm 78 --lambda 0.2708333333333333 --cr 7.5 --rpm 4200 --step 0.5 --heat-j 500 --out data/i3_two_stroke.csv
    cargo run --release -q -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 101.6 --stroke-mm 88.4 --lambda 0.30524861878453036 --cr 9.2 --rpm 4400 --step 0.5 --heat-j 1469 --out data/v6_90.csv

# Regenerate the committed reports, one folder per bundled engine
# (deterministic: no timestamps or timings in what is written).
report:
    cargo build --release
    for engine in data/*.toml; do ./target/release/enginedyn run --engine "$engine" --out "reports/$(basename "$engine" .toml)" > /dev/null; done
    python3 .ci/check_reports.py reports/*

# Accuracy against speed for every bundled engine: reports/<engine>/accuracy.csv
# and accuracy.svg. They hold run times, so they differ from run to run and
# are regenerated here, not by `just report`.
accuracy:
    cargo build --release
    for engine in data/*.toml; do ./target/release/enginedyn accuracy --engine "$engine" --out "reports/$(basename "$engine" .toml)" > /dev/null; done

# Render each report page to a PNG with headless Chromium (Debian's package) to look at.
screenshots:
    for d in reports/*/; do chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking --disable-component-update --disable-sync --user-data-dir="$(mktemp -d)" --window-size=1300,5200 --screenshot="$d/report.png" "file://$(realpath "$d")/report.html"; done

# The reader on one-cycle-per-column text and .xlsx against the long layout and pandas (benches/RESULTS.md).
bench-layouts:
    python3 benches/layouts.py

# Every measured-like fixture against the release build (tests/fixtures/measured/expected.json).
fixtures:
    cargo build --release
    python3 tests/fixtures/measured/check_fixtures.py target/release/enginedyn

# The checks CI runs.
ci:
    bash .ci/run

# Check the build against the interface contract.
contract:
    cargo build --release
    python3 ../shared/spec/check_contract.py target/release/enginedyn

# enginedyn against the Python yardsticks (installs numpy, pandas, pyarrow with pip when missing).
bench files="40" cycles="50":
    bash benches/bench.sh {{files}} {{cycles}}

# Fuzz the streaming reader, the engine file, a whole run and the CSV parser
# (needs a nightly toolchain and cargo-fuzz; fuzz/README.md).
fuzz:
    @if rustup toolchain list | grep -q nightly; then cd fuzz && for t in diagram_stream engine_file whole_run diagram_csv; do cargo +nightly fuzz run $t -- -max_total_time=120 -rss_limit_mb=2048 || exit 1; done; else echo "just fuzz needs a nightly toolchain (rustup toolchain install nightly) and cargo install cargo-fuzz; the stable property tests in crates/ingest/tests/no_panic.rs run in CI instead"; fi
