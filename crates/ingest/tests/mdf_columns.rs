//! MDF4 read by columns (issue 42, item 4): what the reader makes of an MDF4
//! file, decoded by columns and taken whole, is what it makes of the same
//! samples decoded plainly by falcon_mdf (`Signal::values_f64`) and handed
//! to it row by row (`load_columns`): the same grid, bit for bit. On the
//! asammdf fixture (sorted, one ##DT: the decoder's own path), its records
//! split across two blocks of a data list at a byte inside a record (the
//! decoder's path, a record carried over), and its records unsorted
//! (falcon_mdf's path, read by columns all the same).

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, Resampled, load, load_columns};
use enginedyn_kinematics::{CrankSlider, Cylinder, Mechanism};
use falcon_mdf::Mf4File;

fn fixture() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/measured/mdf_angle_master.mf4"
    ))
    .unwrap()
}

fn options() -> (ParseOptions, GridOptions) {
    let cs = CrankSlider::new(0.027, 0.084, 0.0).unwrap();
    let cyl = Cylinder::new(Mechanism::CrankSlider(cs), 0.068, 8.5).unwrap();
    let mut o = ParseOptions::new(720.0);
    o.cylinder = Some(cyl);
    o.max_cylinder = 1;
    let mut g = GridOptions::new(0.1, Interp::Auto);
    g.cylinder = Some(cyl);
    (o, g)
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}

/// Appends a block (8-byte aligned); returns its offset.
fn append(b: &mut Vec<u8>, id: &[u8; 4], links: &[u64], data: &[u8]) -> u64 {
    while !b.len().is_multiple_of(8) {
        b.push(0);
    }
    let at = b.len() as u64;
    b.extend_from_slice(id);
    b.extend_from_slice(&[0; 4]);
    b.extend_from_slice(&((24 + 8 * links.len() + data.len()) as u64).to_le_bytes());
    b.extend_from_slice(&(links.len() as u64).to_le_bytes());
    for l in links {
        b.extend_from_slice(&l.to_le_bytes());
    }
    b.extend_from_slice(data);
    at
}

/// The fixture's data group, channel group, ##DT and its records' bytes
/// (14,400 records of 14 bytes).
fn parts(b: &[u8]) -> (usize, usize, usize, Vec<u8>) {
    let dg = u64_at(b, 88) as usize;
    let cg = u64_at(b, dg + 32) as usize;
    let dt = u64_at(b, dg + 40) as usize;
    assert_eq!(&b[dt..dt + 4], b"##DT");
    let len = u64_at(b, dt + 8) as usize;
    (dg, cg, dt, b[dt + 24..dt + len].to_vec())
}

/// The records in two ##DT blocks under a ##DL, cut 7 bytes into record
/// 5,000.
fn split() -> Vec<u8> {
    let mut b = fixture();
    let (dg, _, _, records) = parts(&b);
    let cut = 5_000 * 14 + 7;
    let dt1 = append(&mut b, b"##DT", &[], &records[..cut]);
    let dt2 = append(&mut b, b"##DT", &[], &records[cut..]);
    let mut d = vec![0u8, 0, 0, 0];
    d.extend_from_slice(&2u32.to_le_bytes());
    d.extend_from_slice(&0u64.to_le_bytes());
    d.extend_from_slice(&(cut as u64).to_le_bytes());
    let dl = append(&mut b, b"##DL", &[0, dt1, dt2], &d);
    b[dg + 40..dg + 48].copy_from_slice(&dl.to_le_bytes());
    b
}

/// The records unsorted: a 1-byte record id before each, a second channel
/// group (id 2, no records) beside the first.
fn unsorted() -> Vec<u8> {
    let mut b = fixture();
    let (dg, cg, _, records) = parts(&b);
    let dg_data = dg + 24 + 8 * u64_at(&b, dg + 16) as usize;
    b[dg_data] = 1;
    let mut cg2 = Vec::new();
    cg2.extend_from_slice(&2u64.to_le_bytes());
    cg2.extend_from_slice(&[0; 24]);
    let cg2 = append(&mut b, b"##CG", &[0; 6], &cg2);
    b[cg + 24..cg + 32].copy_from_slice(&cg2.to_le_bytes());
    let mut d = Vec::new();
    for r in records.chunks_exact(14) {
        d.push(1);
        d.extend_from_slice(r);
    }
    let dt = append(&mut b, b"##DT", &[], &d);
    b[dg + 40..dg + 48].copy_from_slice(&dt.to_le_bytes());
    b
}

/// The plain decode: falcon_mdf's samples of the master, `PCYL1` and
/// `Cycle`, named as the MDF4 reader names them.
fn plain(bytes: &[u8]) -> (Vec<String>, Vec<Vec<f64>>) {
    let file = Mf4File::from_bytes(bytes.to_vec()).unwrap();
    let cg = &file.data_groups()[0].channel_groups[0];
    let get = |name: &str| {
        let ch = cg.channels.iter().find(|c| c.name == name).unwrap();
        let s = file.signal(ch).unwrap();
        assert!(s.validity().is_none());
        s.values_f64().unwrap()
    };
    (
        vec!["crank_deg".into(), "PCYL1 [bar]".into(), "Cycle".into()],
        vec![get("Crank angle"), get("PCYL1"), get("Cycle")],
    )
}

fn bits(r: &Resampled) -> Vec<u64> {
    r.pressure
        .iter()
        .chain(r.cylinders.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

#[test]
fn columns_read_as_the_plain_decode_row_by_row() {
    let (o, g) = options();
    let whole = load(&fixture()[..], &o, &g).unwrap();
    assert_eq!(whole.cycles, 10);
    for (what, bytes) in [
        ("sorted", fixture()),
        ("split", split()),
        ("unsorted", unsorted()),
    ] {
        let (names, cols) = plain(&bytes);
        assert_eq!(cols[0].len(), 14_400, "{what}");
        let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let rows = load_columns(&names, &cols, &o, &g).unwrap();
        let by_columns = load(&bytes[..], &o, &g).unwrap();
        assert_eq!(by_columns.cycles, rows.cycles, "{what}");
        assert_eq!(bits(&by_columns), bits(&rows), "{what}: tolerance 0");
        assert_eq!(bits(&by_columns), bits(&whole), "{what}: as the fixture");
    }
}
