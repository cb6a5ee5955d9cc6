//! Per-client outgoing byte queue with a byte cap, drained by the client's writer thread.

use std::net::{Shutdown, TcpStream};
use std::sync::{Condvar, Mutex, MutexGuard};

struct OutQ {
    buf: Vec<u8>,
    inflight: usize,
    closed: bool,
}

/// Bytes waiting to be written to one client. Producers never block: a push that would
/// take the queue past `cap` closes the queue (and the socket) instead.
pub(crate) struct Outbox {
    q: Mutex<OutQ>,
    cv: Condvar,
    cap: usize,
    stream: TcpStream,
}

/// The push would exceed the byte cap; the outbox is now closed.
#[derive(Debug)]
pub(crate) struct Overflow;

impl Outbox {
    pub fn new(stream: TcpStream, cap: usize) -> Outbox {
        Outbox {
            q: Mutex::new(OutQ {
                buf: Vec::new(),
                inflight: 0,
                closed: false,
            }),
            cv: Condvar::new(),
            cap,
            stream,
        }
    }

    fn lock(&self) -> MutexGuard<'_, OutQ> {
        self.q.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Append bytes built by `f`. On overflow the bytes are discarded and the outbox closed.
    pub fn push_with(&self, f: impl FnOnce(&mut Vec<u8>)) -> Result<usize, Overflow> {
        let mut q = self.lock();
        if q.closed {
            return Ok(0);
        }
        let before = q.buf.len();
        f(&mut q.buf);
        let queued = q.buf.len() + q.inflight;
        if queued > self.cap {
            q.buf.truncate(before);
            drop(q);
            self.close();
            tracing::debug!(queued, cap = self.cap, "outbox over cap");
            return Err(Overflow);
        }
        let was_empty = before == 0;
        drop(q);
        if was_empty {
            self.cv.notify_one();
        }
        Ok(queued)
    }

    /// Queue the finished packet in `pkt` (same cap rule as [`Outbox::push_with`]). When
    /// nothing is waiting, the buffers are swapped instead of copied; either way `pkt` is
    /// left empty (keeping some capacity) for the caller to reuse.
    pub fn push_packet(&self, pkt: &mut Vec<u8>) -> Result<usize, Overflow> {
        let mut q = self.lock();
        if q.closed {
            pkt.clear();
            return Ok(0);
        }
        let was_empty = q.buf.is_empty();
        let queued = q.buf.len() + pkt.len() + q.inflight;
        if queued > self.cap {
            drop(q);
            pkt.clear();
            self.close();
            tracing::debug!(queued, cap = self.cap, "outbox over cap");
            return Err(Overflow);
        }
        if was_empty {
            std::mem::swap(&mut q.buf, pkt);
        } else {
            q.buf.extend_from_slice(pkt);
        }
        drop(q);
        pkt.clear();
        if was_empty {
            self.cv.notify_one();
        }
        Ok(queued)
    }

    pub fn cap(&self) -> usize {
        self.cap
    }

    /// Bytes queued or being written.
    pub fn queued(&self) -> usize {
        let q = self.lock();
        q.buf.len() + q.inflight
    }

    /// Close: the writer stops after this and the socket is shut down both ways.
    pub fn close(&self) {
        {
            let mut q = self.lock();
            q.closed = true;
            q.buf = Vec::new();
        }
        self.cv.notify_all();
        let _ = self.stream.shutdown(Shutdown::Both);
    }

    /// Writer side: wait for bytes and swap them into `spare` (which must be empty).
    /// Returns false when closed.
    pub fn take(&self, spare: &mut Vec<u8>) -> bool {
        let mut q = self.lock();
        q.inflight = 0;
        loop {
            if q.closed {
                return false;
            }
            if !q.buf.is_empty() {
                std::mem::swap(&mut q.buf, spare);
                q.inflight = spare.len();
                return true;
            }
            q = self.cv.wait(q).unwrap_or_else(|p| p.into_inner());
        }
    }
}
