//! A diagram's provenance: the BLAKE3 of its bytes, taken in the pass that
//! reads it (no second read, so the hash is of the very bytes parsed), on
//! the reading thread, or on a thread of its own while a core is idle.
//! That thread reads the file too, a block ahead of the parse, and hands
//! each block it hashed to the reader: the reading thread spends nothing
//! on the system's copy out of the page cache (1.2 ms for a 6 MB diagram
//! on the bench machine, a fifth of its parse).
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

/// Blocks read ahead by the hashing thread: enough to ride over a pause of
/// either thread, few enough to bound the memory: twice this many blocks
/// (those sent and those coming back) and one being read.
const IN_FLIGHT: usize = 4;

/// The bytes of a block the hashing thread reads: large enough that the
/// threads meet a few times a megabyte, not at every read; small enough
/// that a 1 MB diagram is hashed beside its parse in four.
const BLOCK: usize = 1 << 18;

/// The bytes of a diagram's first block: small, so that the parse starts
/// as soon as a little is read and hashed.
const FIRST: usize = 1 << 14;

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
    /// On the reading thread's hashing worker, which reads them too and
    /// hands them over block by block.
    Aside {
        worker: Worker,
        /// The block being read from, and how far.
        block: Vec<u8>,
        at: usize,
        /// The hash, once the worker reached the end; `Err` once the
        /// source failed (every later read is an error, and the worker
        /// goes with this reader).
        hash: Option<Result<String, ()>>,
    },
}

/// What a hashing worker sends back for a diagram, in order.
enum Piece {
    /// The next bytes, hashed.
    Block(Vec<u8>),
    /// The source's error; the diagram ends there.
    Failed(std::io::Error),
    /// The end: the hash of every byte, in hex.
    End(String),
}

/// A diagram's source, read on the hashing worker.
type Source = Box<dyn Readable>;

/// A source the hashing worker can read; `Any`, so that a source the
/// worker could not take comes back as what it was.
trait Readable: std::io::Read + Send + std::any::Any {}

impl<T: std::io::Read + Send + 'static> Readable for T {}

/// A thread that reads and hashes for one reading thread, kept from one
/// diagram to the next with its blocks (no thread started, no block
/// allocated and faulted in, a diagram); it ends when the reading thread
/// does, or when a read stops before its hash was taken (an error).
struct Worker {
    to: SyncSender<Source>,
    pieces: Receiver<Piece>,
    /// The blocks read from, to be filled again.
    back: SyncSender<Vec<u8>>,
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
        let (to, jobs) = sync_channel::<Source>(1);
        let (give, pieces) = sync_channel::<Piece>(IN_FLIGHT);
        let (back, blocks) = sync_channel::<Vec<u8>>(IN_FLIGHT + 1);
        std::thread::Builder::new()
            .name("enginedyn-hash".into())
            .spawn(move || {
                for source in jobs {
                    if read_and_hash(source, &give, &blocks).is_err() {
                        // The reader is gone.
                        return;
                    }
                }
            })
            .ok()?;
        Some(Worker { to, pieces, back })
    }

    /// The next piece of the diagram.
    fn next(&self) -> std::io::Result<Piece> {
        self.pieces.recv().map_err(|_| stopped())
    }
}

/// One diagram on the worker: `source` read block by block (the first
/// [`FIRST`] bytes, then [`BLOCK`]), each block hashed and sent, then the
/// hash; a read error is sent and ends it. `Err` when the reader is gone.
fn read_and_hash(
    mut source: Source,
    give: &SyncSender<Piece>,
    blocks: &Receiver<Vec<u8>>,
) -> Result<(), std::sync::mpsc::SendError<Piece>> {
    let mut h = blake3::Hasher::new();
    let mut size = FIRST;
    loop {
        // A block that came back keeps its length (its bytes are read
        // over), so that only a new one is zeroed.
        let mut block = blocks
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(BLOCK));
        let stop = fill(&mut source, &mut block, size);
        // The bytes read before an end or an error go first.
        if !block.is_empty() {
            h.update(&block);
            give.send(Piece::Block(block))?;
        }
        match stop {
            Some(Ok(())) => return give.send(Piece::End(h.finalize().to_hex().to_string())),
            Some(Err(e)) => return give.send(Piece::Failed(e)),
            None => size = BLOCK,
        }
    }
}

/// Reads `source` into `block` (its bytes read over), up to `size` bytes:
/// `None` when it holds them all, else the end (`Ok`) or the source's
/// error, after the bytes read before it.
fn fill(source: &mut Source, block: &mut Vec<u8>, size: usize) -> Option<std::io::Result<()>> {
    block.resize(size, 0);
    let mut n = 0;
    let stop = loop {
        if n == size {
            break None;
        }
        match source.read(&mut block[n..]) {
            Ok(0) => break Some(Ok(())),
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => break Some(Err(e)),
        }
    };
    block.truncate(n);
    stop
}

fn stopped() -> std::io::Error {
    std::io::Error::other("the hashing thread stopped")
}

/// A reader that hashes (BLAKE3) every byte it passes on: a diagram's
/// provenance in the same pass that reads it, no second read.
pub struct Hashing<R> {
    /// The source, while it is read here (`None` once the worker has it).
    inner: Option<R>,
    hasher: Hasher,
    _held: Option<Held>,
}

impl<R: std::io::Read> Hashing<R> {
    /// Hashes what `inner` gives, on the reading thread.
    pub fn new(inner: R) -> Self {
        Self {
            inner: Some(inner),
            hasher: Hasher::Here(Box::default()),
            _held: None,
        }
    }

    /// Gives the hash of every byte (reading what is left first, when a
    /// reader stopped before the end), in hex as `b3sum` prints it.
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
            Hasher::Aside { worker, hash, .. } => {
                // Read to the end above: the worker waits for the next diagram.
                WORKER.with(|w| w.set(Some(worker)));
                hash.and_then(Result::ok).ok_or_else(stopped)
            }
        }
    }
}

impl<R: std::io::Read + Send + 'static> Hashing<R> {
    /// Reads and hashes `inner` on a thread of its own while a core is
    /// idle (module docs), else as [`Hashing::new`]. The hash is the same.
    pub fn beside(inner: R) -> Self {
        Self::beside_on(inner, cores())
    }

    fn beside_on(inner: R, cores: usize) -> Self {
        let held = Held::take(cores);
        let worker = (held.0 == 2).then(Worker::take).flatten();
        let (inner, hasher) = match worker {
            Some(worker) => match worker.to.send(Box::new(inner)) {
                Ok(()) => (
                    None,
                    Hasher::Aside {
                        worker,
                        block: Vec::new(),
                        at: 0,
                        hash: None,
                    },
                ),
                // The worker is gone; the source comes back with the error
                // and is read here (were it lost, a read would be an error).
                Err(e) => {
                    let source: Box<dyn std::any::Any> = e.0;
                    let inner = source.downcast::<R>().ok().map(|r| *r);
                    (inner, Hasher::Here(Box::default()))
                }
            },
            None => (Some(inner), Hasher::Here(Box::default())),
        };
        Self {
            inner,
            hasher,
            _held: Some(held),
        }
    }
}

impl<R: std::io::Read> std::io::Read for Hashing<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match &mut self.hasher {
            Hasher::Here(h) => {
                let Some(inner) = self.inner.as_mut() else {
                    return Err(stopped());
                };
                let n = inner.read(buf)?;
                h.update(&buf[..n]);
                Ok(n)
            }
            Hasher::Aside {
                worker,
                block,
                at,
                hash,
            } => loop {
                if *at < block.len() {
                    let n = buf.len().min(block.len() - *at);
                    buf[..n].copy_from_slice(&block[*at..*at + n]);
                    *at += n;
                    return Ok(n);
                }
                match hash {
                    Some(Err(())) => return Err(stopped()),
                    Some(Ok(_)) => return Ok(0),
                    None if buf.is_empty() => return Ok(0),
                    None => {}
                }
                if block.capacity() > 0 {
                    // Full (never, by the bounds) or the worker gone: dropped.
                    let _ = worker.back.try_send(std::mem::take(block));
                }
                match worker.next()? {
                    Piece::Block(b) => (*block, *at) = (b, 0),
                    Piece::End(h) => *hash = Some(Ok(h)),
                    Piece::Failed(e) => {
                        *hash = Some(Err(()));
                        return Err(e);
                    }
                }
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    /// A reader giving its bytes in pieces of the sizes asked, in turn,
    /// then, when `fails`, an error instead of the end.
    struct Pieces {
        bytes: Vec<u8>,
        at: usize,
        sizes: Vec<usize>,
        turn: usize,
        fails: bool,
    }

    impl Pieces {
        fn new(bytes: &[u8], sizes: Vec<usize>) -> Self {
            let bytes = bytes.to_vec();
            Self {
                bytes,
                at: 0,
                sizes,
                turn: 0,
                fails: false,
            }
        }
    }

    impl Read for Pieces {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let want = self.sizes[self.turn % self.sizes.len()].min(buf.len());
            self.turn += 1;
            let n = want.min(self.bytes.len() - self.at);
            if n == 0 && self.fails && !buf.is_empty() {
                return Err(std::io::Error::other("the disk went away"));
            }
            buf[..n].copy_from_slice(&self.bytes[self.at..self.at + n]);
            self.at += n;
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
        // Lengths about BLAKE3's chunk (1 KiB), about the first block
        // (16 KiB) and the next (256 KiB), and over several blocks; reads
        // of odd sizes, one of 600,000 bytes across three blocks; a read
        // stopped half way (finish reads on).
        for len in [
            0,
            1,
            1023,
            1024,
            1025,
            FIRST - 1,
            FIRST,
            FIRST + 1,
            64 * 1024 + 7,
            FIRST + BLOCK,
            FIRST + BLOCK + 1,
            1_000_003,
        ] {
            let data = bytes(len);
            let want = blake3::hash(&data).to_hex().to_string();
            for cores in [1, 2, 64] {
                let pieces = Pieces::new(&data, vec![1, 4096, 65536, 3, 600_000]);
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
        let mut dropped = Hashing::beside_on(std::io::Cursor::new(data.clone()), usize::MAX / 4);
        let mut half = vec![0u8; 300_000];
        dropped.read_exact(&mut half).unwrap();
        drop(dropped);
        for len in [700_001, 5, 0, 262_144, 262_145] {
            let r = Hashing::beside_on(std::io::Cursor::new(data[..len].to_vec()), usize::MAX / 4);
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

    /// The source's error reaches the reader, after the bytes before it,
    /// as it does when the hash is taken on the reading thread; the next
    /// diagram is read and hashed afresh.
    #[test]
    fn a_source_s_error_is_the_reader_s() {
        let data = bytes(300_000);
        for cores in [1, usize::MAX / 4] {
            let mut pieces = Pieces::new(&data, vec![70_000]);
            pieces.fails = true;
            let mut r = Hashing::beside_on(pieces, cores);
            let mut got = Vec::new();
            let e = r.read_to_end(&mut got).unwrap_err();
            assert_eq!(e.to_string(), "the disk went away");
            assert!(got == data, "every byte before the error ({cores} cores)");
            assert!(r.finish().is_err());
            let next = Hashing::beside_on(Pieces::new(&data, vec![4096]), cores);
            let want = blake3::hash(&data).to_hex().to_string();
            assert_eq!(next.finish().unwrap(), want);
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
        assert!(r.inner.is_none(), "the worker reads the source");
        let one = Hashing::beside_on(&b"x"[..], 1);
        assert!(matches!(one.hasher, Hasher::Here(_)));
        assert_eq!(one._held.as_ref().map(|h| h.0), Some(1));
        let before = BUSY.load(Ordering::Relaxed);
        assert!(before >= 3);
        drop((r, one));
    }
}
