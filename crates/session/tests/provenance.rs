//! Provenance in the reading pass (issue 37, item 8): `run` and Python's
//! `analyse` hash a diagram file (BLAKE3) as they read it, not in a second
//! read, and the engine file from the text that was read.

use enginedyn_session::{Input, Loaded, Method, Reader, Session};

fn b3(bytes: &[u8]) -> String {
    blake3::hash(bytes).to_hex().to_string()
}

#[test]
fn a_run_hashes_its_diagram_file_in_the_read() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let engine = root.join("data/vaz2108.toml");
    let diagram = root.join("data/vaz2108.csv");
    let loaded = Loaded::from_file(&engine).unwrap();
    let session = Session::new(
        loaded,
        Reader::default(),
        Method {
            step_deg: Some(0.5),
            ..Method::default()
        },
        enginedyn_pipeline::Scope::Summary,
    )
    .unwrap();
    let inputs = [Input::File(&diagram)];
    let out = session.analyse(&inputs).unwrap();
    let bytes = std::fs::read(&diagram).unwrap();
    assert_eq!(out.diagram_blake3, vec![Some(b3(&bytes))]);
    let inputs =
        enginedyn_session::inputs::of_hashed(&session.loaded, &inputs, &out.diagram_blake3)
            .unwrap();
    let json = inputs.json().to_string();
    assert!(json.contains(&b3(&bytes)), "{json}");
    assert!(
        json.contains(&b3(&std::fs::read(&engine).unwrap())),
        "{json}"
    );
}
