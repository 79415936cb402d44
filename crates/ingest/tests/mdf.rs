//! The MDF4 source (issue 31, "MDF4"): the fixtures asammdf wrote
//! (`tests/fixtures/measured/make_mdf_fixtures.py`) read to the IMEP of the
//! script's independent calculation, `--group` and its errors, a file with
//! no pressure, and cut or damaged files as errors, never panics.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Peg, Resampled, load, parse};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(format!(
        "{}/../../tests/fixtures/measured/{name}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}

/// data/single.toml's cylinder: bore 68 mm, stroke 54 mm, rod 84 mm, ε 8.5.
fn cylinder() -> Cylinder {
    let cs = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
    Cylinder::new(Mechanism::CrankSlider(cs), 0.068, 8.5).unwrap()
}

/// The CLI's options for data/single.toml on the default 0.1° grid.
fn options() -> (ParseOptions, GridOptions) {
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cylinder());
    o.max_cylinder = 1;
    let mut g = GridOptions::new(0.1, Interp::Auto);
    g.cylinder = Some(cylinder());
    (o, g)
}

/// The mean of the cycles' IMEP (bar).
fn imep_bar(r: &Resampled) -> f64 {
    r.stats.iter().map(|s| s.imep_pa.unwrap()).sum::<f64>() / r.stats.len() as f64 / 1e5
}

fn error(bytes: &[u8], o: &ParseOptions) -> String {
    match parse(bytes, o) {
        Ok(_) => panic!("read, where an error was expected"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn an_angle_master_is_the_crank_angle() {
    let (o, g) = options();
    let r = load(&fixture("mdf_angle_master.mf4")[..], &o, &g).unwrap();
    assert_eq!(r.cycles, 10);
    // expected.json, `mdf_angle_master.mf4`: the float32 pressures asammdf
    // reads back, the same interpolant (spline) and rule; only the order of
    // summation differs (measured: 1e-11).
    let want = 10.082438299;
    let got = imep_bar(&r);
    assert!((got - want).abs() <= 1e-9 * want, "{got} against {want}");
    assert!(
        r.notes
            .iter()
            .any(|n| n.contains("`crank_deg` as crank angle (deg), `PCYL1 [bar]` as pressure")),
        "{:?}",
        r.notes
    );
    // One group: no note about which.
    assert!(!r.notes.iter().any(|n| n.contains("--group")));
}

#[test]
fn a_compressed_time_master_with_a_tdc_pulse() {
    let bytes = fixture("mdf_time_master_dz.mf4");
    assert!(bytes.windows(4).any(|w| w == b"##DZ"), "compressed blocks");
    let (mut o, mut g) = options();
    o.gain_bar_per_v = Some(20.0);
    o.relative = true;
    g.peg = Some(Peg::Bar(0.95e5));
    let r = load(&bytes[..], &o, &g).unwrap();
    // The record runs from firing TDC to 1440°: one whole window
    // (−360…+360° around the firing TDC at 720°), the halves at the ends
    // left out (INTERFACE.md, "A cycle is the window around its firing TDC").
    assert_eq!(r.cycles, 1, "{:?}", r.notes);
    // expected.json: angles from the pulse, reconstructed by the script as
    // INTERFACE.md says (tolerance 2e-4, the pulse angles against the true
    // ones; measured against enginedyn: 3e-15).
    let want = 10.123986728208;
    let got = imep_bar(&r);
    assert!((got - want).abs() <= 2e-4 * want, "{got} against {want}");
    assert!(
        (got - want).abs() <= 1e-9 * want,
        "same reconstruction: {got}"
    );
    // The first group holds temperatures: the second is read, with a note.
    assert!(
        r.notes
            .iter()
            .any(|n| n
                == "read group 2 of 2 (the first that holds a pressure); --group N reads another"),
        "{:?}",
        r.notes
    );
    assert!(r.notes.iter().any(|n| n.contains("`TDC [V]` as TDC pulse")));
    // --group 2 reads the same, without the note.
    o.group = Some(2);
    let r2 = load(&bytes[..], &o, &g).unwrap();
    assert_eq!(imep_bar(&r2).to_bits(), got.to_bits());
    assert!(!r2.notes.iter().any(|n| n.contains("--group")));
}

#[test]
fn group_errors_list_the_groups() {
    let (mut o, _) = options();
    o.gain_bar_per_v = Some(20.0);
    o.relative = true;
    let angle = fixture("mdf_angle_master.mf4");
    for n in [0, 2, 99] {
        o.group = Some(n);
        let e = error(&angle, &o);
        assert!(
            e.starts_with(&format!(
                "--group {n}: the MDF4 file has 1 channel group, numbered from 1: group 1 `Indicating`: `crank_deg`, `PCYL1 [bar]`, `Cycle`"
            )),
            "{e}"
        );
    }
    o.group = Some(1);
    let e = error(&fixture("mdf_time_master_dz.mf4"), &o);
    assert!(
        e.starts_with("--group 1: group 1 holds no pressure channel (by its name and unit)"),
        "{e}"
    );
    assert!(
        e.contains("group 2 `Fast 72 kHz`: `time_s`, `PCYL1 [V]`, `TDC [V]`, `Engine speed [rpm]`"),
        "{e}"
    );
}

#[test]
fn a_file_without_a_pressure_says_what_it_holds() {
    let (o, _) = options();
    let e = error(&fixture("mdf_no_pressure.mf4"), &o);
    assert!(
        e.starts_with("no channel group holds a pressure channel (by its name and unit"),
        "{e}"
    );
    assert!(
        e.contains(
            "group 1 `Slow`: `time_s`, `Oil temperature [degC]`, `Status` (variable length)"
        ),
        "{e}"
    );
    // --columns with --group names the channels: a temperature read as a
    // pressure is then the plausibility pass's to refuse, not a number.
    let mut o = o;
    o.group = Some(1);
    o.columns = Some(vec!["time_s".into(), "pressure_bar".into()]);
    assert!(parse(&fixture("mdf_no_pressure.mf4")[..], &o).is_err());
}

#[test]
fn a_cut_or_damaged_file_is_an_error() {
    let (mut o, _) = options();
    o.gain_bar_per_v = Some(20.0);
    o.relative = true;
    for name in ["mdf_angle_master.mf4", "mdf_time_master_dz.mf4"] {
        let bytes = fixture(name);
        let n = bytes.len();
        // Cut anywhere: past the identification block every cut loses a
        // block the file links to.
        for k in (1..64)
            .map(|k| k * n / 64)
            .chain([n - 1, n - 8, 64, 65, 100])
        {
            let e = error(&bytes[..k], &o);
            assert!(
                e.starts_with("the MDF4 file is damaged or cut short"),
                "{name} cut at {k}: {e}"
            );
        }
        // Only the identifier: an MDF file with nothing in it.
        assert!(parse(&bytes[..8], &o).is_err());
    }
    // An MDF 3 file: named, with the way to convert it.
    let mut v3 = fixture("mdf_angle_master.mf4");
    v3[8..12].copy_from_slice(b"3.30");
    let e = error(&v3, &o);
    assert!(
        e.starts_with("an MDF 3.30 file: enginedyn reads MDF 4"),
        "{e}"
    );
}

#[test]
fn damaged_compressed_blocks_are_errors() {
    let (mut o, mut g) = options();
    o.gain_bar_per_v = Some(20.0);
    o.relative = true;
    g.peg = Some(Peg::Bar(0.95e5));
    let bytes = fixture("mdf_time_master_dz.mf4");
    let want = imep_bar(&load(&bytes[..], &o, &g).unwrap());
    let dz: Vec<usize> = bytes
        .windows(4)
        .enumerate()
        .filter(|(_, w)| *w == b"##DZ")
        .map(|(i, _)| i)
        .collect();
    let mut refused = 0;
    for &at in &dz {
        // ##DZ: a 24-byte header, no links, the original block type (2),
        // the zip type, a reserved byte, the zip parameter (4), the
        // expanded length (u64 at 32), the packed length (u64 at 40), then
        // the deflate stream (at 48).
        let len = u64::from_le_bytes(bytes[at + 40..at + 48].try_into().unwrap()) as usize;
        let mut flipped = bytes.clone();
        for x in &mut flipped[at + 48 + len / 2..at + 48 + len / 2 + len.min(64) / 2] {
            *x ^= 0x5A;
        }
        let mut lie = bytes.clone();
        lie[at + 32..at + 40].copy_from_slice(&(1u64 << 40).to_le_bytes());
        for (what, b) in [("a damaged stream", flipped), ("a declared 1 TiB", lie)] {
            // An error, or (a block of the group not read) the same figure.
            match load(&b[..], &o, &g) {
                Err(_) => refused += 1,
                Ok(r) => assert_eq!(imep_bar(&r).to_bits(), want.to_bits(), "{what} at {at}"),
            }
        }
    }
    // Every block of the group read is refused both ways.
    // Two blocks: the slow group's (not read: a damaged stream gives the
    // same figure, a declared 1 TiB passes the bound on decoded bytes,
    // which counts every block) and the fast group's, refused both ways.
    assert_eq!(dz.len(), 2);
    assert_eq!(refused, 3);
}
