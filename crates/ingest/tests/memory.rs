//! Streaming: a 10,000-cycle file at 1° (7.2 million rows, about 120 MB of
//! text) read from a generator that implements `Read`, never written to
//! disk, stays under 32 MB of peak heap (counted by a global allocator in
//! this test binary). Memory is bounded by one cycle, not the file.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load};
use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Read;
use std::sync::atomic::{AtomicUsize, Ordering};

#[path = "support/ods_with.rs"]
mod ods_with;

struct Counting;
static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator and only counts bytes.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let n = NOW.fetch_add(l.size(), Ordering::Relaxed) + l.size();
        PEAK.fetch_max(n, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        NOW.fetch_sub(l.size(), Ordering::Relaxed);
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Writes `cycle,crank_deg,pressure_bar` rows on demand.
struct Generator {
    cycle: usize,
    k: usize,
    cycles: usize,
    pending: Vec<u8>,
    pos: usize,
    header: bool,
}

impl Read for Generator {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.pos == self.pending.len() {
            self.pending.clear();
            self.pos = 0;
            if !self.header {
                self.header = true;
                self.pending
                    .extend_from_slice(b"# rpm = 2000\ncycle,crank_deg,pressure_bar\n");
            } else if self.cycle < self.cycles {
                use std::io::Write;
                let d = (self.k as f64 - 10.0 + 360.0).rem_euclid(720.0) - 360.0;
                let p = 1.0
                    + 50.0 * (-(d / 30.0).powi(2)).exp() * (1.0 + 0.01 * (self.cycle % 7) as f64);
                let _ = writeln!(self.pending, "{},{},{p:.5}", self.cycle, self.k);
                self.k += 1;
                if self.k == 720 {
                    self.k = 0;
                    self.cycle += 1;
                }
            } else {
                return Ok(0);
            }
        }
        let n = buf.len().min(self.pending.len() - self.pos);
        buf[..n].copy_from_slice(&self.pending[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}

/// The heap counter is one for the test binary: one reader at a time.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
fn ten_thousand_cycles_in_bounded_memory() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let cycles = 10_000;
    let src = std::io::BufReader::with_capacity(
        1 << 16,
        Generator {
            cycle: 0,
            k: 0,
            cycles,
            pending: Vec::new(),
            pos: 0,
            header: false,
        },
    );
    let before = NOW.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let r = load(
        src,
        &ParseOptions::new(720.0),
        &GridOptions::new(0.1, Interp::Auto),
    )
    .unwrap();
    let peak = PEAK.load(Ordering::Relaxed) - before;
    assert_eq!(r.cycles, cycles);
    assert_eq!(r.stats.len(), cycles);
    assert_eq!(r.rpm, Some(2000.0));
    assert!(peak < 32 << 20, "peak heap {} MB", peak >> 20);
    eprintln!(
        "peak heap {:.1} MB for {} rows",
        peak as f64 / 1048576.0,
        cycles * 720
    );
}

/// Lines made on demand by `line(n)` (`None` ends the file).
struct Made<F> {
    n: usize,
    line: F,
    pending: Vec<u8>,
    pos: usize,
}

impl<F: FnMut(usize) -> Option<String>> Read for Made<F> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.pos == self.pending.len() {
            self.pending.clear();
            self.pos = 0;
            match (self.line)(self.n) {
                Some(l) => {
                    self.pending.extend_from_slice(l.as_bytes());
                    self.pending.push(b'\n');
                    self.n += 1;
                }
                None => return Ok(0),
            }
        }
        let n = buf.len().min(self.pending.len() - self.pos);
        buf[..n].copy_from_slice(&self.pending[self.pos..self.pos + n]);
        self.pos += n;
        Ok(n)
    }
}

/// What `read` gives, and the peak heap it took beyond what was held before.
fn peak_of<T>(read: impl FnOnce() -> T) -> (T, usize) {
    let before = NOW.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let r = read();
    (r, PEAK.load(Ordering::Relaxed) - before)
}

fn bar(deg: f64, k: usize) -> f64 {
    let d = (deg - 10.0 + 360.0).rem_euclid(720.0) - 360.0;
    1.0 + 50.0 * (-(d / 30.0).powi(2)).exp() * (1.0 + 0.01 * (k % 7) as f64)
}

/// One cycle per column (60 columns side by side, 100 blocks of them:
/// 6,000 cycles, 4.4 million values) holds one cycle of every column; a
/// time record (7.2 kHz, a TDC pulse per revolution, 1,000 cycles, 864,000
/// samples) holds the first 65,536 samples and then a revolution.
#[test]
fn other_layouts_in_bounded_memory() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let src = Made {
        n: 0,
        pending: Vec::new(),
        pos: 0,
        line: |n: usize| {
            let (block, row) = (n / 720, n % 720);
            (block < 100).then(|| {
                let mut l = format!("{row}");
                for k in 0..60 {
                    l.push_str(&format!("\t{:.4}", bar(row as f64, block * 60 + k)));
                }
                l.push('\t');
                l
            })
        },
    };
    let mut o = ParseOptions::new(720.0);
    o.columns = Some(vec!["crank_deg".into(), "pressure_bar...".into()]);
    let (r, peak) = peak_of(|| {
        load(
            std::io::BufReader::with_capacity(1 << 16, src),
            &o,
            &GridOptions::new(1.0, Interp::Auto),
        )
        .unwrap()
    });
    assert_eq!(r.cycles, 6000);
    assert!(peak < 8 << 20, "per column: peak heap {} MB", peak >> 20);
    eprintln!("per column: peak heap {:.1} MB", peak as f64 / 1048576.0);

    // 432 samples a revolution at 1000 rpm; the record starts at firing TDC.
    let per_rev = 432;
    let src = Made {
        n: 0,
        pending: Vec::new(),
        pos: 0,
        line: |n: usize| {
            if n == 0 {
                return Some("time_s,pressure_bar,tdc".into());
            }
            let i = n - 1;
            (i < 2000 * per_rev).then(|| {
                let deg = (i as f64 + 0.5) * 360.0 / per_rev as f64;
                let in_rev = deg.rem_euclid(360.0);
                let pulse = if in_rev < 3.0 { 5.0 } else { 0.2 };
                format!(
                    "{:.9},{:.5},{pulse}",
                    i as f64 / 7200.0,
                    bar(deg.rem_euclid(720.0), 0)
                )
            })
        },
    };
    let (r, peak) = peak_of(|| {
        load(
            std::io::BufReader::with_capacity(1 << 16, src),
            &ParseOptions::new(720.0),
            &GridOptions::new(1.0, Interp::Auto),
        )
        .unwrap()
    });
    assert!(r.cycles >= 998, "{} cycles: {:?}", r.cycles, r.notes);
    assert!(peak < 8 << 20, "time record: peak heap {} MB", peak >> 20);
    eprintln!("time record: peak heap {:.1} MB", peak as f64 / 1048576.0);
}

/// The error reading `bytes` gives (a panic if it reads).
fn refused(bytes: &[u8]) -> String {
    enginedyn_ingest::parse(std::io::Cursor::new(bytes), &ParseOptions::new(720.0))
        .unwrap_err()
        .to_string()
}

/// A damaged .xls whose one cell's row and column bytes were changed
/// (row 65,535, column 255) would make calamine lay out a table of 65,536 ×
/// 256 cells (hundreds of MB) as it opens the workbook; the sheet's span is
/// refused first, in a few MB.
#[test]
fn a_damaged_xls_cell_address_is_refused_in_bounded_memory() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut xls = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/measured/libreoffice_cycles.xls"
    ))
    .unwrap();
    // The first NUMBER record (type 0x0203, 14 bytes): its row and column.
    let at = xls
        .windows(4)
        .position(|w| w == [0x03, 0x02, 0x0e, 0x00])
        .unwrap();
    assert!(at % 512 < 504, "the record's address lies in one sector");
    xls[at + 4..at + 8].copy_from_slice(&[0xff, 0xff, 0xff, 0x00]);
    let (e, peak) = peak_of(|| refused(&xls));
    eprintln!("damaged .xls: peak heap {:.1} MB", peak as f64 / 1048576.0);
    assert!(
        e.contains("sheet 1 of the .xls spans 65,536 rows × 256 columns"),
        "{e}"
    );
    assert!(peak < 16 << 20, "peak heap {} MB", peak >> 20);
}

/// An .ods of 35 KB whose one row of 16,000 valued cells is repeated 6,000
/// times would make calamine write out 96 million cells (3.1 GB and 7.6 s
/// before it gave up); the sheet's span is refused first, in a few MB.
#[test]
fn a_repeated_ods_row_is_refused_in_bounded_memory() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let ods = ods_with::ods_with(
        r#"<table:table-row table:number-rows-repeated="6000"><table:table-cell office:value-type="float" office:value="1" table:number-columns-repeated="16000"><text:p>1</text:p></table:table-cell></table:table-row>"#,
    );
    let (e, peak) = peak_of(|| refused(&ods));
    eprintln!(
        "repeated .ods row: peak heap {:.1} MB",
        peak as f64 / 1048576.0
    );
    assert!(
        e.contains("sheet 1 of the .ods spans 6,001 rows × 16,000 columns"),
        "{e}"
    );
    assert!(peak < 16 << 20, "peak heap {} MB", peak >> 20);
}
