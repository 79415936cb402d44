//! Streaming: a 10,000-cycle file at 1° (7.2 million rows, about 120 MB of
//! text) read from a generator that implements `Read`, never written to
//! disk, stays under 32 MB of peak heap (counted by a global allocator in
//! this test binary). Memory is bounded by one cycle, not the file.

use enginedyn_ingest::{GridOptions, Interp, ParseOptions, load};
use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Read;
use std::sync::atomic::{AtomicUsize, Ordering};

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

#[test]
fn ten_thousand_cycles_in_bounded_memory() {
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
