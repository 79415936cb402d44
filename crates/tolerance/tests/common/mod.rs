//! Loading the bundled engines and diagrams for the tests.

#![allow(dead_code)]

use enginedyn_engine::Engine;
use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Resampled};
use enginedyn_tolerance::{Evaluator, Input};

/// Every bundled engine (`data/*.toml`).
pub const BUNDLED: [&str; 7] = [
    "vaz2108",
    "single",
    "i3_two_stroke",
    "i6_diesel",
    "v8_crossplane",
    "v12_60",
    "scotch_yoke",
];

/// A bundled engine, its `[tolerances]` and its diagram on a `step` grid.
pub struct Case {
    pub engine: Engine,
    pub tolerances: Vec<(String, f64)>,
    pub diagram: Resampled,
    pub rpm: f64,
    pub step: f64,
}

pub fn case(name: &str, step: f64) -> Case {
    let path = format!("{}/../../data/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let engine = enginedyn_engine::file::read(std::path::Path::new(&path)).unwrap();
    let tolerances = enginedyn_engine::file::tolerances(&text).unwrap();
    let mut parse = ParseOptions::new(engine.cycle().to_degrees());
    parse.cylinder = Some(*engine.cylinder());
    let mut grid = GridOptions::new(step, Interp::Auto);
    grid.cylinder = Some(*engine.cylinder());
    let file = std::fs::File::open(engine.diagram().unwrap()).unwrap();
    let diagram = enginedyn_ingest::load(std::io::BufReader::new(file), &parse, &grid).unwrap();
    let rpm = diagram.rpm.or(engine.operating().rpm).unwrap();
    Case {
        engine,
        tolerances,
        diagram,
        rpm,
        step,
    }
}

impl Case {
    pub fn options(&self) -> enginedyn_pipeline::Options {
        enginedyn_pipeline::Options {
            step_deg: self.step,
            ..Default::default()
        }
    }
    /// The inputs of these tolerances (key, value).
    pub fn inputs(&self, tolerances: &[(&str, f64)]) -> Vec<Input> {
        let t: Vec<(String, f64)> = tolerances
            .iter()
            .map(|(k, v)| (k.to_string(), *v))
            .collect();
        enginedyn_tolerance::inputs(&self.engine, &t).unwrap().0
    }
    /// The file's own inputs.
    pub fn file_inputs(&self) -> Vec<Input> {
        enginedyn_tolerance::inputs(&self.engine, &self.tolerances)
            .unwrap()
            .0
    }
    pub fn evaluator(&self, inputs: &[Input]) -> Evaluator {
        Evaluator::new(
            &self.engine,
            &self.diagram,
            self.rpm,
            self.options(),
            inputs,
        )
        .unwrap()
    }
}

/// Deviations with `value` on the input named `name` (`piston_group_kg[1]`).
pub fn dev(inputs: &[Input], name: &str, value: f64) -> Vec<f64> {
    let mut d = vec![0.0; inputs.len()];
    let j = inputs.iter().position(|i| i.name() == name).unwrap();
    d[j] = value;
    d
}
