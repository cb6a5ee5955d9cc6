//! Per-client outgoing byte queue with a byte cap, drained by the client's writer thread.
//!
//! Fan-out from a publisher's reader thread first tries a non-blocking send of the queued
//! bytes itself ([`Outbox::try_flush`], after the DB lock is released), which saves the
//! writer thread's wake-up; whatever the socket does not take at once is left to the
//! writer, which does the blocking writes (with the send timeout). Only one of them writes
//! at a time (`writing`), so bytes stay in order.

use std::io::{ErrorKind, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::{Condvar, Mutex, MutexGuard};

struct OutQ {
    buf: Vec<u8>,
    inflight: usize,
    closed: bool,
    /// The writer thread or a direct flush owns the socket's send side.
    writing: bool,
    /// An empty buffer kept for the next direct flush.
    spare: Vec<u8>,
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
                writing: false,
                spare: Vec::new(),
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
    /// With `wake` false the writer thread is not woken: when the returned flag says the
    /// queue was empty, the caller must call [`Outbox::try_flush`] soon (it hands the
    /// bytes to the writer if it cannot send them all).
    pub fn push_packet(&self, pkt: &mut Vec<u8>, wake: bool) -> Result<(usize, bool), Overflow> {
        let mut q = self.lock();
        if q.closed {
            pkt.clear();
            return Ok((0, false));
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
        if was_empty && wake {
            self.cv.notify_one();
        }
        Ok((queued, was_empty))
    }

    /// Send the queued bytes now without blocking, unless a write is already under way
    /// (that writer picks them up). Bytes the socket does not take are put back in front
    /// and the writer thread is woken for them.
    pub fn try_flush(&self) {
        let mut q = self.lock();
        if q.closed || q.writing || q.buf.is_empty() {
            return;
        }
        q.writing = true;
        let mut data = std::mem::take(&mut q.spare);
        std::mem::swap(&mut data, &mut q.buf);
        q.inflight = data.len();
        drop(q);
        let mut sent = 0;
        let mut failed = None;
        if self.stream.set_nonblocking(true).is_ok() {
            while sent < data.len() {
                match (&self.stream).write(&data[sent..]) {
                    Ok(0) => {
                        failed = Some(ErrorKind::WriteZero);
                        break;
                    }
                    Ok(n) => sent += n,
                    Err(e) if e.kind() == ErrorKind::Interrupted => {}
                    Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                    Err(e) => {
                        failed = Some(e.kind());
                        break;
                    }
                }
            }
            if self.stream.set_nonblocking(false).is_err() {
                failed = Some(ErrorKind::Other);
            }
        }
        let mut q = self.lock();
        q.writing = false;
        q.inflight = 0;
        if let Some(kind) = failed {
            drop(q);
            tracing::debug!("write to client failed: {kind:?}");
            self.close();
            return;
        }
        if q.closed {
            return;
        }
        if sent < data.len() {
            data.drain(..sent);
            data.extend_from_slice(&q.buf);
            q.buf.clear();
            std::mem::swap(&mut q.buf, &mut data);
        }
        data.clear();
        q.spare = data;
        let pending = !q.buf.is_empty();
        drop(q);
        if pending {
            self.cv.notify_one();
        }
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
    /// `done`: the bytes of the previous `take` are written. Returns false when closed.
    pub fn take(&self, spare: &mut Vec<u8>, done: bool) -> bool {
        let mut q = self.lock();
        if done {
            q.inflight = 0;
            q.writing = false;
        }
        loop {
            if q.closed {
                return false;
            }
            if !q.buf.is_empty() && !q.writing {
                std::mem::swap(&mut q.buf, spare);
                q.inflight = spare.len();
                q.writing = true;
                return true;
            }
            q = self.cv.wait(q).unwrap_or_else(|p| p.into_inner());
        }
    }
}
