//! Per-client outgoing byte queue, drained by the client's writer thread, with flow
//! control towards the publishers that fill it.
//!
//! Fan-out from a publisher's reader thread first tries a non-blocking send of the queued
//! bytes itself ([`Outbox::try_flush`], after the DB lock is released), which saves the
//! writer thread's wake-up; whatever the socket does not take at once is left to the
//! writer, which does the blocking writes. Only one of them writes at a time (`writing`),
//! so bytes stay in order.
//!
//! Nothing queued is ever dropped. Instead:
//! * each push records how many bytes each publisher added recently (a window that is
//!   halved every `high` bytes of traffic);
//! * when the queue passes the high-water mark, the heaviest recent contributors (those
//!   that together brought [`COVER`] of the window's bytes) get a hold on their [`Gate`]:
//!   their reader threads stop reading their sockets, so TCP flow control reaches them.
//!   A publisher that sent a few small messages has a negligible share and keeps going.
//!   Each further `high / 2` of growth picks again among the publishers still running;
//!   once the DB-wide total reaches its cap, every publisher still adding is held;
//! * the holds are released when the queue drains below the low-water mark, or at once
//!   when the outbox is closed (client gone or cut off as stalled).
//!
//! The stall clock is the writer thread's (`server::writer`): it gets what the direct
//! flushes could not send, so it is the one that sees a socket accept nothing.

use std::io::{ErrorKind, Write};
use std::net::{Shutdown, TcpStream};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

/// Share of a queue's recent bytes whose senders are held back at each step.
pub(crate) const COVER: f64 = 0.9;

/// An outbox reports its size to the DB-wide total only when it changed by this much
/// (so the shared counter is not touched on every push of a healthy flow; the total is
/// exact to within this per client).
const COUNT_STEP: usize = 64 << 10;

/// Buffers bigger than this are given back to the allocator once drained.
const KEEP_CAPACITY: usize = 1 << 20;

/// Whether a connection's reader may read from its socket: open unless some subscriber's
/// queue holds this publisher back.
pub(crate) struct Gate {
    holds: AtomicUsize,
    m: Mutex<()>,
    cv: Condvar,
}

impl Gate {
    pub fn new() -> Gate {
        Gate {
            holds: AtomicUsize::new(0),
            m: Mutex::new(()),
            cv: Condvar::new(),
        }
    }

    pub fn is_open(&self) -> bool {
        self.holds.load(Ordering::Acquire) == 0
    }

    fn hold(&self) {
        self.holds.fetch_add(1, Ordering::AcqRel);
    }

    fn release(&self) {
        if self.holds.fetch_sub(1, Ordering::AcqRel) == 1 {
            // Taking the lock orders this wake-up after a waiter's check.
            let _g = self.m.lock().unwrap_or_else(|p| p.into_inner());
            self.cv.notify_all();
        }
    }

    /// Wait until open, at most `timeout`. True if open.
    pub fn wait_open(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        let mut g = self.m.lock().unwrap_or_else(|p| p.into_inner());
        while !self.is_open() {
            let Some(left) = deadline.checked_duration_since(Instant::now()) else {
                return false;
            };
            g = self
                .cv
                .wait_timeout(g, left)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
        true
    }
}

/// Flow-control thresholds for one push (they depend on the DB cap and client count).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Marks {
    /// Per-client high-water mark (bytes).
    pub high: usize,
    /// Per-client low-water mark: holds are released below it.
    pub low: usize,
    /// Cap on the bytes queued for all clients together.
    pub total_cap: usize,
    /// A stalled client (see [`Outbox::set_stalled`]) is cut off when its queue reaches
    /// this, or when the DB-wide total reaches `total_cap` while its queue is past `high`.
    pub stalled_cap: usize,
}

struct Contrib {
    gate: Arc<Gate>,
    bytes: usize,
}

struct OutQ {
    buf: Vec<u8>,
    inflight: usize,
    closed: bool,
    /// Closed by the DB (both directions), not just by a failed write.
    cut: bool,
    /// The writer thread or a direct flush owns the socket's send side.
    writing: bool,
    /// An empty buffer kept for the next direct flush.
    spare: Vec<u8>,
    /// Bytes held for this client outside the outbox (a synchronous client's held mail).
    extra: usize,
    /// What this outbox currently adds to the DB-wide total.
    counted: usize,
    /// Publishers this client holds back.
    holding: Vec<Arc<Gate>>,
    /// Its socket accepted nothing for the hold limit: it holds no one back.
    stalled: bool,
    /// It held publishers back for the hold limit without draining to its low-water
    /// mark: it holds no one back until then (a quarter of the limit), so every such
    /// hold is followed by a time in which the publishers go on.
    cool_until: Option<Instant>,
    /// Its last hold was ended by the hold limit, not by draining: it is not keeping up
    /// (cut off, as a stalled one, when the DB-wide cap is reached).
    limited: bool,
    /// When it began holding publishers back (the current episode).
    held_since: Option<Instant>,
    low: usize,
    /// Queue size at which more publishers are held back (0: at the high-water mark).
    next_step: usize,
    /// Recent bytes per publisher.
    contrib: Vec<Contrib>,
    contrib_sum: usize,
    last_contrib: usize,
}

impl OutQ {
    fn new() -> OutQ {
        OutQ {
            buf: Vec::new(),
            inflight: 0,
            closed: false,
            cut: false,
            writing: false,
            spare: Vec::new(),
            extra: 0,
            counted: 0,
            holding: Vec::new(),
            stalled: false,
            cool_until: None,
            limited: false,
            held_since: None,
            low: 0,
            next_step: 0,
            contrib: Vec::new(),
            contrib_sum: 0,
            last_contrib: 0,
        }
    }

    fn queued(&self) -> usize {
        self.buf.len() + self.inflight + self.extra
    }

    fn account(&mut self, from: &Arc<Gate>, n: usize, high: usize) {
        let i = match self.contrib.get(self.last_contrib) {
            Some(c) if Arc::ptr_eq(&c.gate, from) => self.last_contrib,
            _ => match self.contrib.iter().position(|c| Arc::ptr_eq(&c.gate, from)) {
                Some(i) => i,
                None => {
                    self.contrib.push(Contrib {
                        gate: from.clone(),
                        bytes: 0,
                    });
                    self.contrib.len() - 1
                }
            },
        };
        self.last_contrib = i;
        self.contrib[i].bytes += n;
        self.contrib_sum += n;
        if self.contrib_sum > high {
            // Halve the window: shares follow the last `high`..`2 high` bytes.
            self.contrib_sum = 0;
            for c in &mut self.contrib {
                c.bytes /= 2;
                self.contrib_sum += c.bytes;
            }
            self.contrib.retain(|c| c.bytes > 0);
            self.last_contrib = 0;
        }
    }

    /// Past the high-water mark (or the next step beyond it), hold back the heaviest
    /// recent contributors not yet held; all of them if the DB-wide cap is reached.
    /// True if it held more publishers back.
    fn regulate(&mut self, m: Marks, total: &AtomicUsize) -> bool {
        let q = self.queued();
        if q < m.high || self.stalled {
            return false;
        }
        if let Some(t) = self.cool_until {
            if Instant::now() < t {
                return false;
            }
            self.cool_until = None;
        }
        let total = total.load(Ordering::Relaxed);
        let hard = total >= m.total_cap;
        if q < self.next_step && !hard {
            return false;
        }
        let mut cand: Vec<(usize, usize)> = self
            .contrib
            .iter()
            .enumerate()
            .filter(|(_, c)| c.bytes > 0 && !self.holding.iter().any(|g| Arc::ptr_eq(g, &c.gate)))
            .map(|(i, c)| (c.bytes, i))
            .collect();
        cand.sort_unstable_by(|a, b| b.cmp(a));
        let sum: usize = cand.iter().map(|c| c.0).sum();
        let want = if hard {
            sum
        } else {
            (sum as f64 * COVER).ceil() as usize
        };
        let mut got = 0;
        for (bytes, i) in cand {
            if got >= want {
                break;
            }
            got += bytes;
            let g = self.contrib[i].gate.clone();
            g.hold();
            self.holding.push(g);
        }
        let first = self.held_since.is_none();
        if !self.holding.is_empty() && first {
            self.held_since = Some(Instant::now());
        }
        tracing::trace!(queued = q, total, hard, "queue past its mark");
        // Released once drained below the low-water mark, or by the band since the hold
        // began (a queue far past its mark, after a hold ended by the limit, releases
        // its publishers as soon as it has shown that much progress).
        if first {
            self.low = m.low.max(q.saturating_sub(m.high - m.low));
        }
        self.next_step = q + m.high / 2;
        // A fresh window: the next step sees only who kept adding.
        self.contrib.clear();
        self.contrib_sum = 0;
        self.last_contrib = 0;
        true
    }

    /// A stalled client whose queue has reached its cap (or the DB-wide one) must go.
    fn over_cap(&self, m: Marks, total: &AtomicUsize) -> bool {
        let q = self.queued();
        let over =
            q >= m.stalled_cap || (q >= m.high && total.load(Ordering::Relaxed) >= m.total_cap);
        // Not keeping up: stalled, or its last hold ended by the hold limit.
        over && (self.stalled || self.limited)
    }

    fn release_if_drained(&mut self) {
        if !self.holding.is_empty() && self.queued() < self.low {
            self.limited = false;
            self.release_all();
        }
    }

    fn release_all(&mut self) {
        if !self.holding.is_empty() {
            tracing::debug!(
                queued = self.queued(),
                released = self.holding.len(),
                "publishers released"
            );
        }
        for g in self.holding.drain(..) {
            g.release();
        }
        self.held_since = None;
        self.next_step = 0;
    }
}

/// What [`Outbox::push_packet`] did.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Pushed {
    /// Bytes queued now.
    pub queued: usize,
    /// The queue was empty: the caller must try a flush.
    pub was_empty: bool,
    /// Stalled, and its queue reached its cap: the caller must cut the client off.
    pub over_cap: bool,
}

/// Bytes waiting to be written to one client.
pub(crate) struct Outbox {
    q: Mutex<OutQ>,
    cv: Condvar,
    stream: TcpStream,
    /// Bytes queued for all clients of the DB.
    total: Arc<AtomicUsize>,
    /// The client's name (for the logs).
    pub name: String,
}

impl Outbox {
    pub fn new(stream: TcpStream, total: Arc<AtomicUsize>, name: &str) -> Outbox {
        Outbox {
            q: Mutex::new(OutQ::new()),
            cv: Condvar::new(),
            stream,
            total,
            name: name.to_owned(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, OutQ> {
        self.q.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Bring the DB-wide total in line with this queue (in steps of [`COUNT_STEP`]).
    fn recount(&self, q: &mut OutQ) {
        let now = if q.closed { 0 } else { q.queued() };
        let before = q.counted;
        if now.abs_diff(before) < COUNT_STEP && !(now == 0 && before > 0) {
            return;
        }
        q.counted = now;
        if now >= before {
            self.total.fetch_add(now - before, Ordering::Relaxed);
        } else {
            self.total.fetch_sub(before - now, Ordering::Relaxed);
        }
    }

    /// Append bytes built by `f` (welcome and replies to the client's own requests;
    /// they count towards the total but not towards any publisher).
    pub fn push_with(&self, f: impl FnOnce(&mut Vec<u8>)) -> usize {
        let mut q = self.lock();
        if q.closed {
            return 0;
        }
        let was_empty = q.buf.is_empty();
        f(&mut q.buf);
        self.recount(&mut q);
        let queued = q.queued();
        drop(q);
        if was_empty {
            self.cv.notify_one();
        }
        queued
    }

    /// Queue the finished packet in `pkt`, added by the publisher behind `from`. When
    /// nothing is waiting, the buffers are swapped instead of copied; either way `pkt` is
    /// left empty (keeping some capacity) for the caller to reuse.
    /// With `wake` false the writer thread is not woken: when the returned `was_empty`
    /// says the queue was empty, the caller must call [`Outbox::try_flush`] soon (it hands
    /// the bytes to the writer if it cannot send them all). `over_cap`: the client is
    /// stalled and its queue reached its cap: the caller must cut it off.
    pub fn push_packet(
        &self,
        pkt: &mut Vec<u8>,
        wake: bool,
        from: Option<&Arc<Gate>>,
        marks: Marks,
    ) -> Pushed {
        let mut q = self.lock();
        if q.closed {
            pkt.clear();
            return Pushed::default();
        }
        let n = pkt.len();
        let was_empty = q.buf.is_empty();
        if was_empty {
            std::mem::swap(&mut q.buf, pkt);
        } else {
            q.buf.extend_from_slice(pkt);
        }
        pkt.clear();
        self.recount(&mut q);
        if let Some(g) = from {
            q.account(g, n, marks.high);
        }
        if q.regulate(marks, &self.total) {
            tracing::debug!(client = %self.name, queued = q.queued(), holding = q.holding.len(), "queue past its mark: publishers held back");
        }
        let pushed = Pushed {
            queued: q.queued(),
            was_empty,
            over_cap: q.over_cap(marks, &self.total),
        };
        drop(q);
        if was_empty && wake {
            self.cv.notify_one();
        }
        pushed
    }

    /// Writer side: the socket has accepted nothing for the hold limit while bytes
    /// waited. From now until it takes bytes again this client holds no publisher back
    /// (those it held go on at once); its queue grows up to its cap instead.
    pub fn set_stalled(&self) {
        let mut q = self.lock();
        if q.closed || q.stalled {
            return;
        }
        q.stalled = true;
        tracing::debug!(
            client = %self.name,
            queued = q.queued(),
            released = q.holding.len(),
            "socket accepts nothing: holding no one back"
        );
        q.release_all();
    }

    /// Writer side: a hold that has lasted `limit` without the queue draining to its
    /// low-water mark ends now, and this client holds no one back for a quarter of that.
    /// A socket can take bytes while its client reads nothing (kernel buffers growing
    /// take hundreds of KiB at a time), so taking bytes is not enough to hold everyone
    /// for longer: no hold lasts more than the limit.
    pub fn end_long_hold(&self, limit: Duration) {
        let mut q = self.lock();
        if q.held_since.is_some_and(|t| t.elapsed() >= limit) {
            q.cool_until = Some(Instant::now() + limit / 4);
            q.limited = true;
            tracing::debug!(
                client = %self.name,
                queued = q.queued(),
                released = q.holding.len(),
                "held publishers back for the hold limit: released"
            );
            q.release_all();
        }
    }

    /// Writer side: the socket accepts bytes again (after [`Outbox::set_stalled`]).
    pub fn progressed(&self) {
        self.lock().stalled = false;
    }

    /// A synchronous client's held mail (kept by the DB state until it polls) is now
    /// `held` bytes; `from` added what grew.
    pub fn set_extra(&self, held: usize, from: Option<&Arc<Gate>>, marks: Marks) {
        let mut q = self.lock();
        if q.closed {
            return;
        }
        let grew = held.saturating_sub(q.extra);
        q.extra = held;
        self.recount(&mut q);
        if grew > 0 {
            if let Some(g) = from {
                q.account(g, grew, marks.high);
            }
            q.regulate(marks, &self.total);
        } else {
            q.release_if_drained();
        }
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
            self.write_failed();
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
        if data.capacity() > KEEP_CAPACITY {
            data = Vec::new();
        }
        q.spare = data;
        self.recount(&mut q);
        q.release_if_drained();
        let pending = !q.buf.is_empty();
        drop(q);
        if pending {
            self.cv.notify_one();
        }
    }

    /// Writer side: `n` more bytes of the current chunk were accepted by the socket
    /// (reported in batches: it takes the lock the publishers push under).
    pub fn wrote(&self, n: usize) {
        let mut q = self.lock();
        q.inflight = q.inflight.saturating_sub(n);
        self.recount(&mut q);
        q.release_if_drained();
    }

    /// Bytes queued, being written, or held for this client.
    pub fn queued(&self) -> usize {
        self.lock().queued()
    }

    /// Publishers this client currently holds back.
    pub fn holding(&self) -> usize {
        self.lock().holding.len()
    }

    /// Known dead: a write failed, the DB closed it, or the peer reset the connection
    /// (a pending socket error).
    pub fn is_dead(&self) -> bool {
        self.lock().closed || matches!(self.stream.take_error(), Ok(Some(_)) | Err(_))
    }

    /// Closed by the DB: its reader should stop too.
    pub fn is_cut(&self) -> bool {
        self.lock().cut
    }

    /// Close: the writer stops after this, the memory is released, the publishers held
    /// back for this client go on, and the socket is shut down both ways.
    pub fn close(&self) {
        self.shut(Shutdown::Both);
    }

    /// A write failed (the client closed its side): as [`Outbox::close`], but the socket
    /// stays open for reading, so what the client sent before closing is still processed.
    pub fn write_failed(&self) {
        self.shut(Shutdown::Write);
    }

    fn shut(&self, how: Shutdown) {
        {
            let mut q = self.lock();
            q.closed = true;
            q.cut |= how == Shutdown::Both;
            q.buf = Vec::new();
            q.spare = Vec::new();
            q.extra = 0;
            q.contrib = Vec::new();
            q.contrib_sum = 0;
            self.recount(&mut q);
            q.release_all();
        }
        self.cv.notify_all();
        let _ = self.stream.shutdown(how);
    }

    /// Writer side: wait for bytes and swap them into `spare` (which must be empty).
    /// `done`: the bytes of the previous `take` are written. Returns false when closed.
    /// `drained` is set when nothing was waiting (the client had taken everything).
    pub fn take(&self, spare: &mut Vec<u8>, done: bool, drained: &mut bool) -> bool {
        let mut q = self.lock();
        *drained = q.buf.is_empty();
        if done {
            q.inflight = 0;
            q.writing = false;
            self.recount(&mut q);
            q.release_if_drained();
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

#[cfg(test)]
#[path = "outbox_tests.rs"]
mod tests;
