# Longer recipes. The two everyday commands need no `just`:
#   cargo run --release          # the bundled example
#   cargo test --workspace       # the tests

# Run the bundled example and write its output folder.
example:
    cargo run --release -- run --out reports/vaz2108

# Regenerate every bundled diagram from its documented model (data/README.md;
# the table is enginedyn_synth::bundled::DIAGRAMS, crates/synth/src/bundled.rs).
data:
    cargo run --release -q -p enginedyn-synth --example bundled

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
