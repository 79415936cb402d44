//! A cancel token: a front end (the Python package's Ctrl-C, a GUI's stop
//! button) sets it from another thread, and the long loops (a file's
//! reads, an array's samples, a batch's files) stop at their next check.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A flag shared by the caller and the work; `Cancel::default()` is never
/// set. Two tokens compare equal (options that differ only by their token
/// are the same options).
#[derive(Debug, Clone, Default)]
pub struct Cancel(Option<Arc<AtomicBool>>);

/// What a cancelled read says (the caller raises its own interrupt).
pub const CANCELLED: &str = "cancelled";

impl Cancel {
    /// A token that can be set.
    pub fn new() -> Self {
        Self(Some(Arc::new(AtomicBool::new(false))))
    }

    /// Asks the work to stop.
    pub fn cancel(&self) {
        if let Some(f) = &self.0 {
            f.store(true, Ordering::Relaxed);
        }
    }

    /// Whether the work was asked to stop.
    pub fn is_cancelled(&self) -> bool {
        self.0.as_ref().is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// `Err` once cancelled.
    pub fn check(&self) -> Result<(), crate::IngestError> {
        if self.is_cancelled() {
            Err(crate::IngestError::Io(cancel_error()))
        } else {
            Ok(())
        }
    }
}

impl PartialEq for Cancel {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// The I/O error a cancelled read returns.
pub fn cancel_error() -> std::io::Error {
    std::io::Error::other(CANCELLED)
}

/// A reader that fails with [`cancel_error`] once its token is set: each
/// block read checks it (a file's read is cancelled within one block).
#[derive(Debug)]
pub struct Cancellable<R> {
    inner: R,
    cancel: Cancel,
}

impl<R> Cancellable<R> {
    /// `inner`, stopped by `cancel`.
    pub fn new(inner: R, cancel: Cancel) -> Self {
        Self { inner, cancel }
    }

    /// The reader it wraps.
    pub fn into_inner(self) -> R {
        self.inner
    }
}

impl<R: std::io::Read> std::io::Read for Cancellable<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.cancel.is_cancelled() {
            return Err(cancel_error());
        }
        self.inner.read(buf)
    }
}

impl<R: std::io::BufRead> std::io::BufRead for Cancellable<R> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.cancel.is_cancelled() {
            return Err(cancel_error());
        }
        self.inner.fill_buf()
    }
    fn consume(&mut self, amt: usize) {
        self.inner.consume(amt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::BufRead;

    #[test]
    fn a_set_token_stops_a_read_and_an_unset_one_never_does() {
        let c = Cancel::new();
        let mut r = Cancellable::new(&b"a\nb\n"[..], c.clone());
        let mut line = String::new();
        r.read_line(&mut line).unwrap();
        assert_eq!(line, "a\n");
        c.cancel();
        assert_eq!(r.fill_buf().unwrap_err().to_string(), CANCELLED);
        assert!(Cancel::default().check().is_ok());
        assert!(c.check().is_err());
    }
}
