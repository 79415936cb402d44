//! Reads CSV files with `parse_stream` and prints a checksum of every
//! angle and value (bits), for A/B comparisons of the text parser:
//! `cargo run --release -p enginedyn-ingest --example parse_file -- FILE...`.
fn main() {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut n = 0usize;
    let mut mix = |x: f64| {
        h ^= x.to_bits();
        h = h.wrapping_mul(0x100_0000_01b3);
    };
    let opts = enginedyn_ingest::ParseOptions::new(720.0);
    for path in std::env::args().skip(1) {
        let f = std::io::BufReader::new(std::fs::File::open(&path).expect("open"));
        let r = enginedyn_ingest::parse_stream(f, &opts, |t| {
            for (&a, &v) in t.trace.angle_deg.iter().zip(&t.trace.values) {
                mix(a);
                mix(v);
                n += 1;
            }
            Ok(())
        });
        if let Err(e) = r {
            println!("{path}: {e}");
        }
    }
    println!("{n} samples, checksum {h:016x}");
}
