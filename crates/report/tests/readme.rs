//! The README's account of `run --out DIR`'s charts comes from the code:
//! the number it states is the number of charts `run_figures` draws for a
//! pressure diagram, and it names each of them, in report order.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions};
use enginedyn_pipeline::Options;
use enginedyn_report::{RUN_CHARTS, run_figures};
use std::path::Path;

const WORDS: [&str; 13] = [
    "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
    "eleven", "twelve",
];

#[test]
fn readme_counts_and_names_the_run_charts() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let engine = enginedyn_engine::file::read(&root.join("data/vaz2108.toml")).unwrap();
    let parse = ParseOptions {
        cylinder: Some(*engine.cylinder()),
        ..ParseOptions::new(engine.cycle().to_degrees())
    };
    let grid = GridOptions::new(1.0, Interp::Auto);
    let file = std::fs::File::open(engine.diagram().unwrap()).unwrap();
    let r = enginedyn_ingest::load(std::io::BufReader::new(file), &parse, &grid).unwrap();
    let opts = Options {
        step_deg: 1.0,
        ..Options::default()
    };
    let a =
        enginedyn_pipeline::analyse(&engine, &r, engine.operating().rpm.unwrap(), &opts).unwrap();
    let drawn: Vec<String> = run_figures(&engine, &a)
        .into_iter()
        .map(|f| f.file)
        .collect();
    assert_eq!(drawn, RUN_CHARTS, "RUN_CHARTS is what run_figures draws");

    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let text = readme.split_whitespace().collect::<Vec<_>>().join(" ");
    let stated = format!("{} SVG charts (", WORDS[drawn.len()]);
    let at = text
        .find(&stated)
        .unwrap_or_else(|| panic!("README does not say `{stated}…`"));
    // The list in the parentheses names every chart, in report order.
    let list = &text[at + stated.len()..];
    let list = &list[..list.find(';').unwrap_or(list.len())];
    let named: Vec<&str> = list.split(", ").map(|s| s.trim_matches('`')).collect();
    assert_eq!(named, drawn, "README names {named:?}");
}
