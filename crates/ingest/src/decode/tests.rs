//! The columns [`Plain`] decodes against falcon_mdf's plain decode of the
//! same file (`Signal::values_f64`, NaN where `Signal::validity` says
//! invalid), bit for bit, on files written here to defeat the shortcuts:
//! several data groups, fields at odd bit offsets and widths, a linear
//! conversion, invalidation bits, records split across the blocks of a data
//! list, a window shorter than a block, records cut short, and unsorted
//! records (which are not the plain shape and must say so).

use super::Plain;
use falcon_mdf::Mf4File;

/// A little MDF 4.10 writer: blocks appended, 8-byte aligned.
struct Writer(Vec<u8>);

impl Writer {
    fn new() -> Self {
        let mut id = Vec::new();
        id.extend_from_slice(b"MDF     4.10    test    ");
        id.extend_from_slice(&[0; 4]);
        id.extend_from_slice(&410u16.to_le_bytes());
        id.resize(64, 0);
        let mut w = Writer(id);
        // ##HD: six links (the first data group set later), 32 bytes of data.
        w.block(b"##HD", &[0; 6], &[0; 32]);
        w
    }
    fn block(&mut self, id: &[u8; 4], links: &[u64], data: &[u8]) -> u64 {
        while !self.0.len().is_multiple_of(8) {
            self.0.push(0);
        }
        let at = self.0.len() as u64;
        self.0.extend_from_slice(id);
        self.0.extend_from_slice(&[0; 4]);
        self.0
            .extend_from_slice(&((24 + 8 * links.len() + data.len()) as u64).to_le_bytes());
        self.0
            .extend_from_slice(&(links.len() as u64).to_le_bytes());
        for l in links {
            self.0.extend_from_slice(&l.to_le_bytes());
        }
        self.0.extend_from_slice(data);
        at
    }
    /// A ##DZ block of `raw` (the records of a ##DT), deflated, and
    /// transposed first by records of `columns` bytes when given: the
    /// first `len / columns` records column by column, the rest as is.
    fn dz(&mut self, raw: &[u8], columns: Option<u32>) -> u64 {
        use std::io::Write as _;
        let data = match columns {
            Some(c) => {
                let (c, lines) = (c as usize, raw.len() / c as usize);
                let mut t = vec![0; raw.len()];
                for r in 0..lines {
                    for k in 0..c {
                        t[k * lines + r] = raw[r * c + k];
                    }
                }
                t[lines * c..].copy_from_slice(&raw[lines * c..]);
                t
            }
            None => raw.to_vec(),
        };
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
        z.write_all(&data).unwrap();
        let packed = z.finish().unwrap();
        let mut d = b"DT".to_vec();
        d.push(u8::from(columns.is_some()));
        d.push(0);
        d.extend_from_slice(&columns.unwrap_or(0).to_le_bytes());
        d.extend_from_slice(&(raw.len() as u64).to_le_bytes());
        d.extend_from_slice(&(packed.len() as u64).to_le_bytes());
        d.extend_from_slice(&packed);
        self.block(b"##DZ", &[], &d)
    }
    fn set(&mut self, at: u64, link: usize, to: u64) {
        let k = at as usize + 24 + 8 * link;
        self.0[k..k + 8].copy_from_slice(&to.to_le_bytes());
    }
    fn text(&mut self, s: &str) -> u64 {
        let mut d = s.as_bytes().to_vec();
        d.push(0);
        self.block(b"##TX", &[], &d)
    }
    /// A channel: (name, type (0 fixed, 2 master), data type (0 uint, 2
    /// int, 4 float), bit offset, byte offset, bits, invalidation bit,
    /// linear conversion (offset, factor)).
    #[allow(clippy::type_complexity)]
    fn channel(
        &mut self,
        (name, kind, dt, bit, byte, bits, inval, linear): (
            &str,
            u8,
            u8,
            u8,
            u32,
            u32,
            Option<u32>,
            Option<(f64, f64)>,
        ),
        next: u64,
    ) -> u64 {
        let tx = self.text(name);
        let cc = match linear {
            Some((a0, a1)) => {
                let mut d = vec![1u8, 0, 0, 0, 0, 0, 2, 0];
                for v in [0.0f64, 0.0, a0, a1] {
                    d.extend_from_slice(&v.to_le_bytes());
                }
                self.block(b"##CC", &[0; 4], &d)
            }
            None => 0,
        };
        let mut d = vec![kind, if kind == 2 { 1 } else { 0 }, dt, bit];
        d.extend_from_slice(&byte.to_le_bytes());
        d.extend_from_slice(&bits.to_le_bytes());
        d.extend_from_slice(&(if inval.is_some() { 2u32 } else { 0 }).to_le_bytes());
        d.extend_from_slice(&inval.unwrap_or(0).to_le_bytes());
        d.extend_from_slice(&[0; 4]);
        d.extend_from_slice(&[0; 48]);
        self.block(b"##CN", &[next, 0, tx, 0, cc, 0, 0, 0], &d)
    }
    /// A data group of one channel group (record id `rec_id` when the data
    /// are unsorted) with `channels`, `data` + `inval` bytes a record,
    /// `count` records declared, its data at `data_at`; returns the data
    /// group's block.
    #[allow(clippy::type_complexity)]
    fn group(
        &mut self,
        channels: &[(&str, u8, u8, u8, u32, u32, Option<u32>, Option<(f64, f64)>)],
        (data, inval, count): (u32, u32, u64),
        rec_id: u8,
        data_at: u64,
    ) -> u64 {
        let mut next = 0;
        for c in channels.iter().rev() {
            next = self.channel(*c, next);
        }
        let mut d = Vec::new();
        d.extend_from_slice(&1u64.to_le_bytes());
        d.extend_from_slice(&count.to_le_bytes());
        d.extend_from_slice(&[0; 8]);
        d.extend_from_slice(&data.to_le_bytes());
        d.extend_from_slice(&inval.to_le_bytes());
        let cg = self.block(b"##CG", &[0, next, 0, 0, 0, 0], &d);
        let mut dg = vec![rec_id];
        dg.extend_from_slice(&[0; 7]);
        self.block(b"##DG", &[0, cg, data_at, 0], &dg)
    }
}

/// Deterministic bytes (a 64-bit LCG).
fn noise(n: usize, seed: u64) -> Vec<u8> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 56) as u8
        })
        .collect()
}

/// Channels of the first group: every shape the decoder reads (integers
/// with and without a linear conversion), in a 42-byte record with one invalidation byte (43: records straddle blocks).
#[allow(clippy::type_complexity)]
const WIDE: &[(&str, u8, u8, u8, u32, u32, Option<u32>, Option<(f64, f64)>)] = &[
    ("t", 2, 4, 0, 0, 64, None, None),
    ("u5 at bit 5", 0, 0, 5, 8, 5, None, None),
    ("i12 at bit 2", 0, 2, 2, 9, 12, Some(0), None),
    ("i8", 0, 2, 0, 11, 8, None, None),
    ("u64 linear", 0, 0, 0, 12, 64, None, Some((1e3, -3.0e-7))),
    ("i64", 0, 2, 0, 20, 64, Some(7), None),
    ("f32", 0, 4, 0, 28, 32, Some(3), None),
    ("f64 linear", 0, 4, 0, 32, 64, None, Some((-3.0, 0.25))),
    ("i16 linear", 0, 2, 0, 40, 16, Some(5), Some((-2.5, 0.125))),
    ("u1 at bit 7", 0, 0, 7, 41, 1, None, None),
    // Whole aligned integers laid over the bytes above (their own reads).
    ("u32 linear", 0, 0, 0, 20, 32, None, Some((1.0, 0.5))),
    ("i32", 0, 2, 0, 24, 32, Some(1), None),
    ("u16", 0, 0, 0, 28, 16, None, None),
    (
        "i16 at byte 30, linear",
        0,
        2,
        0,
        30,
        16,
        None,
        Some((0.0, -1e-3)),
    ),
];

/// The test file: group 1 `WIDE` (50 records in three ##DT blocks under a
/// ##DL, cut at odd bytes); group 2 a master and a u16 whose one ##DT holds
/// 10.5 records of the 11 declared; group 3 the same channels, unsorted;
/// group 4 `WIDE` again, deflated ([`Writer::dz`]) under a ##HL and a ##DL:
/// transposed with a record's 43 bytes (9 records, then 13 bytes as they
/// are), a plain ##DT, deflated alone, transposed again (10 records and 20
/// bytes). Returns the bytes and each data group's block.
fn file() -> (Vec<u8>, Vec<u64>) {
    let mut w = Writer::new();
    let records = noise(50 * 43, 1);
    let dt1 = w.block(b"##DT", &[], &records[..100]);
    let dt2 = w.block(b"##DT", &[], &records[100..1_333]);
    let dt3 = w.block(b"##DT", &[], &records[1_333..]);
    let mut d = vec![0u8, 0, 0, 0];
    d.extend_from_slice(&3u32.to_le_bytes());
    for at in [0u64, 100, 1_333] {
        d.extend_from_slice(&at.to_le_bytes());
    }
    let dl = w.block(b"##DL", &[0, dt1, dt2, dt3], &d);
    let dg1 = w.group(WIDE, (42, 1, 50), 0, dl);
    let short = &[
        ("t", 2, 4, 0, 0, 64, None, None),
        ("u16", 0, 0, 0, 8, 16, None, None),
    ];
    let cut = w.block(b"##DT", &[], &noise(10 * 10 + 5, 2));
    let dg2 = w.group(short, (10, 0, 11), 0, cut);
    let mut unsorted = Vec::new();
    for r in noise(20 * 10, 3).chunks(10) {
        unsorted.push(1);
        unsorted.extend_from_slice(r);
    }
    let dt = w.block(b"##DT", &[], &unsorted);
    let dg3 = w.group(short, (10, 0, 20), 1, dt);
    let records = noise(50 * 43, 4);
    let cuts = [0, 400, 1_333, 1_700, 50 * 43];
    let blocks = [
        w.dz(&records[..400], Some(43)),
        w.block(b"##DT", &[], &records[400..1_333]),
        w.dz(&records[1_333..1_700], None),
        w.dz(&records[1_700..], Some(43)),
    ];
    let mut d = vec![0u8, 0, 0, 0];
    d.extend_from_slice(&4u32.to_le_bytes());
    for at in &cuts[..4] {
        d.extend_from_slice(&(*at as u64).to_le_bytes());
    }
    let mut links = vec![0];
    links.extend(blocks);
    let dl = w.block(b"##DL", &links, &d);
    let hl = w.block(b"##HL", &[dl], &[1, 0, 1, 0, 0, 0, 0, 0]);
    let dg4 = w.group(WIDE, (42, 1, 50), 0, hl);
    w.set(64, 0, dg1);
    w.set(dg1, 0, dg2);
    w.set(dg2, 0, dg3);
    w.set(dg3, 0, dg4);
    (w.0, vec![dg1, dg2, dg3, dg4])
}

/// falcon_mdf's plain decode of every channel of data group `dg`'s first
/// channel group, and [`Plain`]'s (`None`: not the plain shape), read in
/// windows of `chunk` records.
#[allow(clippy::type_complexity)]
fn both(bytes: &[u8], at: u64, dg: usize, chunk: usize) -> (Vec<Vec<u64>>, Option<Vec<Vec<u64>>>) {
    let file = Mf4File::from_bytes(bytes.to_vec()).unwrap();
    let cg = &file.data_groups()[dg].channel_groups[0];
    let channels: Vec<_> = cg.channels.iter().collect();
    let want = channels
        .iter()
        .map(|ch| {
            let s = file.signal(ch).unwrap();
            let mut v = s.values_f64().unwrap();
            if let Some(valid) = s.validity() {
                for (x, ok) in v.iter_mut().zip(valid) {
                    if !ok {
                        *x = f64::NAN;
                    }
                }
            }
            v.iter().map(|x| x.to_bits()).collect()
        })
        .collect();
    let plain = Plain::new(
        bytes,
        at,
        cg.data_bytes_len(),
        cg.inval_bytes_len(),
        cg.sample_count,
        &channels,
    );
    let got = plain.map(|p| {
        let mut all = vec![Vec::new(); channels.len()];
        let mut cols = Vec::new();
        let mut next = 0;
        let read = p
            .read(
                chunk,
                &mut cols,
                |e| panic!("{e}"),
                |cols, first, n| {
                    assert_eq!(first, next, "windows in order");
                    assert!(n <= chunk && cols.iter().all(|c| c.len() == n));
                    for (a, c) in all.iter_mut().zip(cols) {
                        a.extend(c.iter().map(|x| x.to_bits()));
                    }
                    next += n;
                    Ok::<(), ()>(())
                },
            )
            .unwrap();
        assert_eq!(read, next);
        all
    });
    (want, got)
}

/// A group of `WIDE`'s 50 records (data group `dg`, block `at`) read in
/// windows of `chunk`: the decoder's columns are falcon_mdf's, channel by
/// channel; returns them.
fn wide_alike(bytes: &[u8], at: u64, dg: usize, chunk: usize) -> Vec<Vec<u64>> {
    let (want, got) = both(bytes, at, dg, chunk);
    assert_eq!(want[0].len(), 50);
    let got = got.expect("the plain shape");
    for (k, (w, g)) in want.iter().zip(&got).enumerate() {
        assert_eq!(w, g, "data group {dg}, {} (window {chunk})", WIDE[k].0);
    }
    got
}

#[test]
fn the_columns_are_falcon_mdf_s_samples_bit_for_bit() {
    let (bytes, dgs) = file();
    // Windows of 1, of 7 (shorter than a block, not dividing 50) and whole.
    for chunk in [1, 7, 1 << 17] {
        let got = wide_alike(&bytes, dgs[0], 0, chunk);
        // Some samples invalid, some not: the bits were read.
        let nan = |c: &Vec<u64>| c.iter().filter(|&&x| f64::from_bits(x).is_nan()).count();
        assert!((1..50).contains(&nan(&got[8])), "{}", nan(&got[8]));
    }
    // Cut short: falcon_mdf reads the 10 whole records; so does the decoder.
    let (want, got) = both(&bytes, dgs[1], 1, 4);
    assert_eq!(want[0].len(), 10);
    assert_eq!(Some(want), got);
}

/// Deflated blocks, transposed or not, beside a plain one and with
/// records across their edges, read as falcon_mdf reads them.
#[test]
fn deflated_blocks_are_falcon_mdf_s_samples_bit_for_bit() {
    let (bytes, dgs) = file();
    for chunk in [1, 7, 1 << 17] {
        wide_alike(&bytes, dgs[3], 3, chunk);
    }
}

/// A deflated stream damaged, or a block that expands to less than it
/// declares: the decoder's error is falcon_mdf's, word for word.
#[test]
fn a_damaged_deflated_block_is_falcon_mdf_s_error() {
    let (bytes, dgs) = file();
    let first_dz = bytes.windows(4).rposition(|w| w == b"##DZ").unwrap();
    // ##DZ: 24 bytes of header, no links, 24 of its own, then the stream.
    let mut flipped = bytes.clone();
    for x in &mut flipped[first_dz + 52..first_dz + 60] {
        *x ^= 0x5A;
    }
    let mut short = bytes.clone();
    short[first_dz + 32..first_dz + 40].copy_from_slice(&151u64.to_le_bytes());
    for damaged in [flipped, short] {
        let file = Mf4File::from_bytes(damaged.clone()).unwrap();
        let cg = &file.data_groups()[3].channel_groups[0];
        let channels: Vec<_> = cg.channels.iter().collect();
        let want = file.signal(channels[0]).unwrap_err().to_string();
        let plain = Plain::new(
            &damaged,
            dgs[3],
            cg.data_bytes_len(),
            cg.inval_bytes_len(),
            cg.sample_count,
            &channels,
        )
        .expect("the plain shape");
        let got = plain
            .read(7, &mut Vec::new(), |e| e.to_string(), |_, _, _| Ok(()))
            .unwrap_err();
        assert!(want.starts_with("Decompression error"), "{want}");
        assert_eq!(got, want);
    }
}

/// The blockwise un-transposition against the plain rule (record `r`'s
/// byte `k` was stored at `k * lines + r`, the bytes after the whole
/// records as they are), about every edge of its 8 × 8 squares.
#[test]
fn the_blockwise_un_transposition_is_the_plain_one() {
    for columns in 1..=19 {
        for len in (0..=20 * columns + 9).chain([1_000 * columns + 5]) {
            let t = noise(len, (columns * 7_919 + len) as u64);
            let lines = len / columns;
            let mut want = t.clone();
            for r in 0..lines {
                for k in 0..columns {
                    want[r * columns + k] = t[k * lines + r];
                }
            }
            let mut got = vec![1, 2, 3];
            super::un_transpose(&t, columns, &mut got);
            assert_eq!(got, want, "{columns} columns, {len} bytes");
        }
    }
}

/// A data block that declares links (none belong there) is left to
/// falcon_mdf, which reads its data at byte 24 whatever it declares.
#[test]
fn a_data_block_with_links_is_not_the_plain_shape() {
    for dz in [false, true] {
        let mut w = Writer::new();
        let records = noise(10 * 43, 5);
        let block = if dz {
            let at = w.dz(&records, Some(43));
            let d = w.0[at as usize + 24..].to_vec();
            w.block(b"##DZ", &[0], &d)
        } else {
            w.block(b"##DT", &[0], &records)
        };
        let dg = w.group(WIDE, (42, 1, 10), 0, block);
        w.set(64, 0, dg);
        let file = Mf4File::from_bytes(w.0.clone()).unwrap();
        let cg = &file.data_groups()[0].channel_groups[0];
        let channels: Vec<_> = cg.channels.iter().collect();
        let plain = Plain::new(
            &w.0,
            dg,
            cg.data_bytes_len(),
            cg.inval_bytes_len(),
            cg.sample_count,
            &channels,
        );
        assert!(
            plain.is_none(),
            "a ##{} with a link",
            if dz { "DZ" } else { "DT" }
        );
    }
}

#[test]
fn unsorted_records_are_not_the_plain_shape() {
    let (bytes, dgs) = file();
    let (want, got) = both(&bytes, dgs[2], 2, 7);
    assert_eq!(want[0].len(), 20, "falcon_mdf reads them");
    assert!(got.is_none());
}

#[test]
fn the_fixtures_read_alike() {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/measured/"
    );
    // The angle master (float32 pressure, a u16 counter) and the time
    // master (transposed ##DZ blocks): plain.
    for (name, plain) in [
        ("mdf_angle_master.mf4", true),
        ("mdf_time_master_dz.mf4", true),
    ] {
        let bytes = std::fs::read(format!("{dir}{name}")).unwrap();
        let mut at = u64::from_le_bytes(bytes[88..96].try_into().unwrap());
        let mut dg = 0;
        while at != 0 {
            let (want, got) = both(&bytes, at, dg, 1000);
            match got {
                Some(got) => assert_eq!(want, got, "{name}, data group {dg}"),
                None => assert!(!plain, "{name}, data group {dg}"),
            }
            at = u64::from_le_bytes(
                bytes[at as usize + 24..at as usize + 32]
                    .try_into()
                    .unwrap(),
            );
            dg += 1;
        }
    }
}
