//! A diagram's provenance: the BLAKE3 of its bytes, taken in the pass that
//! reads it (no second read, so the hash is of the very bytes parsed), on
//! the reading thread, or on a thread of its own while a core is idle.
//!
//! A core is idle when fewer readers hash at once than the machine has
//! cores: `run` on one file and `batch --jobs 1` on two cores hash beside
//! the parse; `batch --jobs 2` (or two Python threads) on two cores hash
//! on their own threads, where a third thread would only take turns. A
//! process told to keep to one thread (`OMP_NUM_THREADS=1`, as Dask's
//! workers are, or `RAYON_NUM_THREADS=1`) hashes on its reading thread.
//!
//! ```
//! use std::io::Read;
//! let mut r = enginedyn_session::hashing::Hashing::new(&b"crank_deg,pressure_bar\n"[..]);
//! let mut text = String::new();
//! r.read_to_string(&mut text).unwrap();
//! assert_eq!(r.finish().unwrap(), blake3::hash(text.as_bytes()).to_hex().to_string());
//! ```

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};

/// Threads that read and hash a diagram now, in this process: a reader
/// counts one, a reader whose hash runs beside it two.
static BUSY: AtomicUsize = AtomicUsize::new(0);

/// Blocks in flight to the hashing thread: enough to ride over a pause of
/// either thread, few enough to bound the memory: twice this many blocks
/// (those sent and those coming back) and one being filled.
const IN_FLIGHT: usize = 4;

/// The bytes of a block sent to the hashing thread: large enough that the
/// threads meet a few times a megabyte, not at every read; small enough
/// that a 1 MB diagram is hashed beside its parse in four.
const BLOCK: usize = 1 << 18;

/// The cores this process may use (1 when unknown): the machine's, as
/// its affinity and cgroup quota allow, and no more than a thread count
/// the process was told to keep to ([`THREAD_LIMITS`]).
fn cores() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| {
        let machine = std::thread::available_parallelism().map_or(1, |n| n.get());
        let told = THREAD_LIMITS.map(|k| std::env::var(k).ok());
        cores_of(machine, &told)
    })
}

/// Variables that tell a process how many threads to keep to: Dask's
/// worker processes start with `OMP_NUM_THREADS=1` (as do many job
/// scripts that run several processes on one machine), where a hashing
/// thread would take a core another worker uses.
const THREAD_LIMITS: [&str; 2] = ["OMP_NUM_THREADS", "RAYON_NUM_THREADS"];

/// `machine` cores, or fewer when a limit in `told` (the variables'
/// values; unset, empty, zero or not a number: no limit) says so.
fn cores_of(machine: usize, told: &[Option<String>]) -> usize {
    told.iter()
        .flatten()
        .filter_map(|v| v.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .fold(machine, usize::min)
}

/// Threads held in the count of busy readers, given back when it is
/// dropped.
pub struct Held(usize);

impl Held {
    /// One thread for the reader, and one more for its hash if that leaves
    /// no more threads busy than there are cores.
    fn take(cores: usize) -> Self {
        let mut now = BUSY.load(Ordering::Relaxed);
        loop {
            let want = if now + 2 <= cores { 2 } else { 1 };
            match BUSY.compare_exchange_weak(now, now + want, Ordering::AcqRel, Ordering::Relaxed) {
                Ok(_) => return Held(want),
                Err(seen) => now = seen,
            }
        }
    }
}

/// Counts `threads` more as reading (a batch's other workers, whose
/// readers would otherwise see a core idle that they will soon take) until
/// the guard is dropped.
pub fn reading(threads: usize) -> Held {
    BUSY.fetch_add(threads, Ordering::AcqRel);
    Held(threads)
}

impl Drop for Held {
    fn drop(&mut self) {
        BUSY.fetch_sub(self.0, Ordering::AcqRel);
    }
}

/// Where the bytes are hashed.
enum Hasher {
    /// On the reading thread, as they pass.
    Here(Box<blake3::Hasher>),
    /// On the reading thread's hashing worker: each block copied and sent.
    Aside {
        worker: Worker,
        /// The block being filled, sent when it holds [`BLOCK`] bytes.
        filling: Vec<u8>,
    },
}

/// What a hashing worker is sent.
enum Message {
    /// The next bytes.
    Block(Vec<u8>),
    /// The end of a diagram: its hash goes back, the next one begins.
    End,
}

/// A thread that hashes for one reading thread, kept from one diagram to
/// the next with its blocks (no thread started, no block allocated and
/// faulted in, a diagram); it ends when the reading thread does, or when a
/// read stops before its hash was taken (an error).
struct Worker {
    to: SyncSender<Message>,
    /// The blocks hashed, to be filled again.
    back: Receiver<Vec<u8>>,
    /// Each diagram's hash, in hex.
    hashes: Receiver<String>,
}

thread_local! {
    /// The reading thread's hashing worker, while no reader holds it.
    static WORKER: std::cell::Cell<Option<Worker>> = const { std::cell::Cell::new(None) };
}

impl Worker {
    /// The reading thread's worker, or a new one; `None` when no thread can
    /// be started (the caller then hashes on its own thread).
    fn take() -> Option<Worker> {
        WORKER.with(std::cell::Cell::take).or_else(Worker::start)
    }

    fn start() -> Option<Worker> {
        let (to, from) = sync_channel::<Message>(IN_FLIGHT);
        let (give_back, back) = sync_channel::<Vec<u8>>(IN_FLIGHT + 1);
        let (give_hash, hashes) = sync_channel::<String>(1);
        std::thread::Builder::new()
            .name("enginedyn-hash".into())
            .spawn(move || {
                let mut h = blake3::Hasher::new();
                for message in from {
                    match message {
                        Message::Block(block) => {
                            h.update(&block);
                            // Full (never, by the bounds) or the reader gone: dropped.
                            let _ = give_back.try_send(block);
                        }
                        Message::End => {
                            if give_hash.send(h.finalize().to_hex().to_string()).is_err() {
                                return;
                            }
                            h.reset();
                        }
                    }
                }
            })
            .ok()?;
        Some(Worker { to, back, hashes })
    }

    fn send(&self, message: Message) -> std::io::Result<()> {
        self.to.send(message).map_err(|_| stopped())
    }

    /// An empty block to fill: one that came back, or a new one.
    fn block(&self) -> Vec<u8> {
        let mut b = self
            .back
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(BLOCK));
        b.clear();
        b
    }

    /// The diagram's hash once its last block is sent; the worker then
    /// waits for the reading thread's next diagram.
    fn end(self, last: Vec<u8>) -> std::io::Result<String> {
        if !last.is_empty() {
            self.send(Message::Block(last))?;
        }
        self.send(Message::End)?;
        let hash = self.hashes.recv().map_err(|_| stopped())?;
        WORKER.with(|w| w.set(Some(self)));
        Ok(hash)
    }
}

fn stopped() -> std::io::Error {
    std::io::Error::other("the hashing thread stopped")
}

/// A reader that hashes (BLAKE3) every byte it passes on: a diagram's
/// provenance in the same pass that reads it, no second read.
pub struct Hashing<R> {
    inner: R,
    hasher: Hasher,
    _held: Option<Held>,
}

impl<R: std::io::Read> Hashing<R> {
    /// Hashes what `inner` gives, on the reading thread.
    pub fn new(inner: R) -> Self {
        Self {
            inner,
            hasher: Hasher::Here(Box::default()),
            _held: None,
        }
    }

    /// Hashes what `inner` gives on a thread of its own while a core is
    /// idle (module docs), else as [`Hashing::new`]. The hash is the same.
    pub fn beside(inner: R) -> Self {
        Self::beside_on(inner, cores())
    }

    fn beside_on(inner: R, cores: usize) -> Self {
        let held = Held::take(cores);
        let hasher = match (held.0 == 2).then(Worker::take).flatten() {
            Some(worker) => Hasher::Aside {
                worker,
                filling: Vec::new(),
            },
            None => Hasher::Here(Box::default()),
        };
        Self {
            inner,
            hasher,
            _held: Some(held),
        }
    }

    /// Reads what is left (a reader that stopped before the end), then
    /// gives the hash of every byte, in hex as `b3sum` prints it.
    pub fn finish(mut self) -> std::io::Result<String> {
        let mut rest = [0u8; 1 << 14];
        loop {
            match std::io::Read::read(&mut self, &mut rest) {
                Ok(0) => break,
                Ok(_) => {}
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        match self.hasher {
            Hasher::Here(h) => Ok(h.finalize().to_hex().to_string()),
            Hasher::Aside { worker, filling } => worker.end(filling),
        }
    }
}

impl<R: std::io::Read> std::io::Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        if n == 0 {
            return Ok(0);
        }
        match &mut self.hasher {
            Hasher::Here(h) => {
                h.update(&buf[..n]);
            }
            Hasher::Aside { worker, filling } => {
                let mut rest = &buf[..n];
                while !rest.is_empty() {
                    if filling.capacity() == 0 {
                        *filling = worker.block();
                    }
                    let take = rest.len().min(BLOCK - filling.len());
                    filling.extend_from_slice(&rest[..take]);
                    rest = &rest[take..];
                    if filling.len() >= BLOCK {
                        worker.send(Message::Block(std::mem::take(filling)))?;
                    }
                }
            }
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// A reader giving its bytes in pieces of the sizes asked, in turn.
    struct Pieces<'a> {
        bytes: &'a [u8],
        sizes: Vec<usize>,
        turn: usize,
    }

    impl Read for Pieces<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let want = self.sizes[self.turn % self.sizes.len()].min(buf.len());
            self.turn += 1;
            let n = want.min(self.bytes.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            Ok(n)
        }
    }

    fn bytes(n: usize) -> Vec<u8> {
        (0..n)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect()
    }

    #[test]
    fn the_hash_beside_is_the_hash_of_the_bytes_read() {
        // Lengths about BLAKE3's chunk (1 KiB) and over several blocks of
        // 256 KiB; reads of odd sizes, one of 600,000 bytes across three
        // blocks; a read stopped half way (finish reads on).
        for len in [0, 1, 1023, 1024, 1025, 64 * 1024 + 7, 1_000_003] {
            let data = bytes(len);
            let want = blake3::hash(&data).to_hex().to_string();
            for cores in [1, 2, 64] {
                let pieces = Pieces {
                    bytes: &data,
                    sizes: vec![1, 4096, 65536, 3, 600_000],
                    turn: 0,
                };
                let mut r = Hashing::beside_on(pieces, cores);
                let mut head = vec![0u8; len / 2];
                r.read_exact(&mut head).unwrap();
                assert_eq!(head, data[..len / 2]);
                assert_eq!(r.finish().unwrap(), want, "{len} bytes, {cores} cores");
            }
        }
    }

    #[test]
    fn a_worker_kept_for_the_next_diagram_starts_afresh() {
        // One thread's diagrams in turn: the first read stops half way and
        // is dropped (an error: its worker goes), the next ones reuse the
        // worker and its blocks; each hash is its own bytes'.
        let data = bytes(700_001);
        let mut dropped = Hashing::beside_on(&data[..], usize::MAX / 4);
        let mut half = vec![0u8; 300_000];
        dropped.read_exact(&mut half).unwrap();
        drop(dropped);
        for len in [700_001, 5, 0, 262_144, 262_145] {
            let r = Hashing::beside_on(&data[..len], usize::MAX / 4);
            assert!(matches!(r.hasher, Hasher::Aside { .. }));
            let want = blake3::hash(&data[..len]).to_hex().to_string();
            assert_eq!(r.finish().unwrap(), want, "{len} bytes");
            assert!(WORKER.with(|w| {
                let kept = w.take();
                let some = kept.is_some();
                w.set(kept);
                some
            }));
        }
    }

    #[test]
    fn a_thread_limit_caps_the_cores() {
        let s = |v: &str| Some(v.to_string());
        assert_eq!(cores_of(8, &[None, None]), 8);
        assert_eq!(cores_of(8, &[s("1"), None]), 1);
        assert_eq!(cores_of(8, &[s(" 3 "), s("2")]), 2);
        assert_eq!(cores_of(2, &[s("16"), None]), 2);
        for ignored in ["", "0", "two", "-1", "1.5"] {
            assert_eq!(cores_of(4, &[s(ignored), None]), 4, "{ignored:?}");
        }
    }

    #[test]
    fn a_hash_goes_beside_only_while_a_core_is_idle() {
        // The count is the process's: other tests' readers may hold some,
        // so judge by what this reader took, on a machine of many cores and
        // on one of a single core.
        let r = Hashing::beside_on(&b"x"[..], usize::MAX / 4);
        assert!(matches!(r.hasher, Hasher::Aside { .. }));
        let one = Hashing::beside_on(&b"x"[..], 1);
        assert!(matches!(one.hasher, Hasher::Here(_)));
        assert_eq!(one._held.as_ref().map(|h| h.0), Some(1));
        let before = BUSY.load(Ordering::Relaxed);
        assert!(before >= 3);
        drop((r, one));
    }
}
