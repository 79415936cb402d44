//! `enginedyn template` (issue 30, item 8): what it prints runs as it is
//! with the bundled diagram, for each variant the issue names, and holds
//! every key of the engine file's one key table.

use enginedyn_tests::{data, ok_json, run};

fn template(args: &[&str]) -> String {
    let mut all = vec!["template"];
    all.extend_from_slice(args);
    let out = run(&all);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stderr.is_empty(), "{args:?}: nothing on stderr");
    String::from_utf8(out.stdout).expect("UTF-8")
}

#[test]
fn each_variant_runs_with_the_bundled_diagram() {
    let dir = tempfile::tempdir().unwrap();
    let diagram = data("vaz2108.csv");
    for (i, args) in [
        &[][..],
        &["--cylinders", "1"],
        &["--cylinders", "6"],
        &["--layout", "vee", "--cylinders", "8"],
        &["--layout", "boxer", "--cylinders", "4"],
        &["--torsion"],
        &["--layout", "vee", "--cylinders", "6", "--torsion"],
        &["--layout", "vee", "--cylinders", "12"],
    ]
    .iter()
    .enumerate()
    {
        let text = template(args);
        let path = dir.path().join(format!("t{i}.toml"));
        std::fs::write(&path, &text).unwrap();
        let engine = path.to_str().unwrap();
        let j = ok_json(&["run", "--engine", engine, "--diagram", &diagram, "--json"]);
        // The template's engine: its cylinders, its speed, the diagram's IMEP.
        let z: usize = args
            .iter()
            .position(|a| *a == "--cylinders")
            .map_or(4, |p| args[p + 1].parse().unwrap());
        assert!(text.contains(&format!("\ncylinders = {z}\n")), "{args:?}");
        assert_eq!(j["rpm"].as_f64(), Some(4900.0), "{args:?}");
        let imep = j["imep_bar"].as_f64().unwrap();
        assert!((imep - 10.47).abs() < 0.01, "{args:?}: IMEP {imep}");
        // What it leaves to enginedyn is said.
        let notes: Vec<&str> = j["notes"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|n| n.as_str())
            .collect();
        assert!(
            notes.iter().any(|n| n.starts_with("defaults taken")),
            "{args:?}: {notes:?}"
        );
        if args.contains(&"--torsion") {
            let out = run(&["torsion", "--engine", engine, "--diagram", &diagram]);
            assert!(
                out.status.success(),
                "{args:?}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

/// Every key of the table is in the template (set, or commented out), each
/// after a comment giving its unit and default; the required keys are set
/// before any optional one.
#[test]
fn holds_every_key_required_first() {
    let text = template(&["--torsion", "--combustion", "diesel"]);
    for k in enginedyn_engine::keys::KEYS {
        if k.path() == "combustion.second" {
            // A table of its own.
            assert!(text.contains("\n[combustion.second]\n"));
            continue;
        }
        if k.section == "combustion.full_load" {
            // An inline table: `full_load = { rpm = [...], imep_bar = [...] }`.
            assert!(text.contains("\nfull_load = { rpm = "));
            continue;
        }
        assert!(
            text.contains(&format!("{} = ", k.key)),
            "{} is not in the template",
            k.path()
        );
    }
    let first_optional = text.find("\n# name = ").unwrap();
    for set in [
        "\ncycle = ",
        "\ncylinders = ",
        "\nbore_mm = ",
        "\nstroke_mm = ",
    ] {
        assert!(text.find(set).unwrap() < first_optional, "{set}");
    }
    assert!(text.contains("# bore_mm [mm], required: the cylinder bore."));
    assert!(text.contains(
        "# mechanical_efficiency, default 1.0 (noted): η_m: mean_torque_nm and power_kw"
    ));
}

#[test]
fn impossible_counts_exit_2_naming_the_flag() {
    for args in [
        &["template", "--layout", "vee", "--cylinders", "5"][..],
        &["template", "--layout", "boxer", "--cylinders", "3"],
        &["template", "--cylinders", "25"],
        &["template", "--cylinders", "0"],
        &["template", "--layout", "radial"],
    ] {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--cylinders") || err.contains("--layout"),
            "{args:?}: {err}"
        );
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}
