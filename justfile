# Longer recipes. The two everyday commands need no `just`:
#   cargo run --release          # the bundled example
#   cargo test --workspace       # the tests

# Run the bundled example and write its output folder.
example:
    cargo run --release -- run --out reports/vaz2108

# Regenerate the bundled diagram from its documented model.
data:
    cargo run --release -p enginedyn-synth --bin enginedyn-synth -- --preset petrol --bore-mm 76 --stroke-mm 71 --lambda 0.26 --cr 9.9 --rpm 4900 --step 0.5 --out data/vaz2108.csv

# Regenerate the committed reports (deterministic: no timestamps).
report:
    cargo build --release
    ./target/release/enginedyn run --out reports/vaz2108 > /dev/null

# The checks CI runs.
ci:
    bash .ci/run

# Check the build against the interface contract.
contract:
    cargo build --release
    python3 ../shared/spec/check_contract.py target/release/enginedyn
