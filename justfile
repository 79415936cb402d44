# Longer recipes. The two everyday commands need no `just`:
#   cargo run --release          # the bundled example
#   cargo test --workspace       # the tests

# Run the bundled example and write its output folder.
example:
    cargo run --release -- run --out reports/vaz2108

# Regenerate the bundled diagram from its documented model.
data:
    cargo run --release -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 76 --stroke-mm 71 --lambda 0.26 --cr 9.9 --rpm 4900 --step 0.5 --out data/vaz2108.csv

# Regenerate the committed reports, one folder per bundled engine
# (deterministic: no timestamps or timings in what is written).
report:
    cargo build --release
    for engine in data/*.toml; do ./target/release/enginedyn run --engine "$engine" --out "reports/$(basename "$engine" .toml)" > /dev/null; done
    python3 .ci/check_reports.py reports/*

# Render each report page to a PNG with headless Chromium (Debian's package) to look at.
screenshots:
    for d in reports/*/; do chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking --disable-component-update --disable-sync --user-data-dir="$(mktemp -d)" --window-size=1300,5200 --screenshot="$d/report.png" "file://$(realpath "$d")/report.html"; done

# The checks CI runs.
ci:
    bash .ci/run

# Check the build against the interface contract.
contract:
    cargo build --release
    python3 ../shared/spec/check_contract.py target/release/enginedyn
