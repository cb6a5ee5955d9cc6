//! What a connection's reader shares with the rest of the DB: whether the connection is
//! known dead ([`Link`], for a reconnect under its name), and the bytes it buffers of
//! packets not yet complete ([`ReadShare`], counted against the DB-wide cap).

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// A connection's liveness as its reader sees it.
pub(crate) struct Link {
    born: Instant,
    /// Milliseconds after `born` when bytes last arrived.
    last_rx_ms: AtomicU64,
    /// The reader is held back (not reading): silence then means nothing.
    held: AtomicBool,
    /// A read failed or the peer closed its side.
    dead: AtomicBool,
}

impl Link {
    pub fn new() -> Link {
        Link {
            born: Instant::now(),
            last_rx_ms: AtomicU64::new(0),
            held: AtomicBool::new(false),
            dead: AtomicBool::new(false),
        }
    }

    fn ms(&self) -> u64 {
        self.born.elapsed().as_millis() as u64
    }

    /// Bytes arrived (or a hold ended: the silence before it does not count).
    pub fn heard(&self) {
        self.last_rx_ms.store(self.ms(), Ordering::Relaxed);
    }

    pub fn set_held(&self, held: bool) {
        self.held.store(held, Ordering::Relaxed);
        if !held {
            self.heard();
        }
    }

    pub fn set_dead(&self) {
        self.dead.store(true, Ordering::Relaxed);
    }

    /// Known dead: a read failed, the peer closed, or silent (not held back) for longer
    /// than `timeout`.
    pub fn is_dead(&self, timeout: Duration) -> bool {
        if self.dead.load(Ordering::Relaxed) {
            return true;
        }
        let silent = self
            .ms()
            .saturating_sub(self.last_rx_ms.load(Ordering::Relaxed));
        !self.held.load(Ordering::Relaxed) && silent > timeout.as_millis() as u64
    }
}

/// A packet no longer than this is read whole; a longer one is taken in pieces of about
/// this size (whole messages), so a reader buffers at most this plus one read, or one
/// message longer than this, which must be reserved first ([`ReadShare::reserve`]).
pub(crate) const PIECE: usize = 256 << 10;

/// The DB-wide counters a [`ReadShare`] keeps.
pub(crate) struct ReadCounters<'a> {
    /// Everything the DB holds (queues, partial packets, values).
    pub total: &'a AtomicUsize,
    /// Bytes reserved for messages longer than [`PIECE`], all connections.
    pub big: &'a AtomicUsize,
    /// Cap of `big`: half the DB's cap (the queues are held to the other half).
    pub big_cap: usize,
}

/// One connection's buffered bytes, as counted in the DB's total; and its reservation
/// for a long message, which it must hold before reading one (else it waits: a publisher
/// of long messages is held back by not reading, never dropped).
pub(crate) struct ReadShare<'a> {
    c: ReadCounters<'a>,
    /// What this connection adds to `total`.
    counted: usize,
    /// Its reservation in `big` (0: none).
    reserved: usize,
    /// Bytes its reader buffers.
    pending: usize,
}

impl<'a> ReadShare<'a> {
    pub fn new(c: ReadCounters<'a>) -> Self {
        ReadShare {
            c,
            counted: 0,
            reserved: 0,
            pending: 0,
        }
    }

    /// The reader buffers `pending` bytes now.
    pub fn buffered(&mut self, pending: usize) {
        self.pending = pending;
        self.recount();
    }

    fn recount(&mut self) {
        let now = self.pending.max(self.reserved);
        if now > self.counted {
            self.c
                .total
                .fetch_add(now - self.counted, Ordering::Relaxed);
        } else if now < self.counted {
            self.c
                .total
                .fetch_sub(self.counted - now, Ordering::Relaxed);
        }
        self.counted = now;
    }

    /// Make sure `want` bytes may be buffered at once. Up to [`PIECE`] needs nothing; a
    /// longer unit needs a reservation, granted while the reservations of all
    /// connections stay under their cap, or when there are none (so the longest
    /// message still goes through, one at a time). False: not granted, try again later.
    pub fn reserve(&mut self, want: usize) -> bool {
        if want <= PIECE {
            self.release();
            return true;
        }
        if want == self.reserved {
            return true;
        }
        self.release();
        let big = self.c.big;
        let mut cur = big.load(Ordering::Relaxed);
        loop {
            if cur != 0 && cur + want > self.c.big_cap {
                return false;
            }
            match big.compare_exchange_weak(cur, cur + want, Ordering::AcqRel, Ordering::Relaxed) {
                Ok(_) => break,
                Err(now) => cur = now,
            }
        }
        self.reserved = want;
        self.recount();
        true
    }

    fn release(&mut self) {
        if self.reserved > 0 {
            self.c.big.fetch_sub(self.reserved, Ordering::AcqRel);
            self.reserved = 0;
            self.recount();
        }
    }
}

impl Drop for ReadShare<'_> {
    fn drop(&mut self) {
        self.release();
        self.c.total.fetch_sub(self.counted, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_messages_are_reserved_within_the_cap_or_one_at_a_time() {
        let (total, big) = (AtomicUsize::new(0), AtomicUsize::new(0));
        let counters = || ReadCounters {
            total: &total,
            big: &big,
            big_cap: 3 << 20,
        };
        let (mut a, mut b, mut c) = (
            ReadShare::new(counters()),
            ReadShare::new(counters()),
            ReadShare::new(counters()),
        );
        assert!(a.reserve(PIECE), "a piece needs no reservation");
        assert!(a.reserve(2 << 20));
        assert!(!b.reserve(2 << 20), "over the cap while a holds one");
        assert!(c.reserve(1 << 20), "within the cap");
        // Alone, a message longer than the cap still goes through.
        drop(a);
        drop(c);
        assert!(b.reserve(8 << 20));
        assert_eq!(total.load(Ordering::Relaxed), 8 << 20);
        b.buffered(100);
        assert!(b.reserve(10), "done with the long one");
        assert_eq!(big.load(Ordering::Relaxed), 0);
        assert_eq!(total.load(Ordering::Relaxed), 100);
        drop(b);
        assert_eq!(total.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn silence_while_held_back_is_not_death() {
        let l = Link::new();
        assert!(!l.is_dead(Duration::from_millis(50)));
        l.set_held(true);
        std::thread::sleep(Duration::from_millis(60));
        assert!(!l.is_dead(Duration::from_millis(50)), "held back");
        l.set_held(false);
        assert!(!l.is_dead(Duration::from_millis(50)), "the hold just ended");
        std::thread::sleep(Duration::from_millis(60));
        assert!(
            l.is_dead(Duration::from_millis(50)),
            "silent past the timeout"
        );
        let l = Link::new();
        l.set_dead();
        assert!(l.is_dead(Duration::from_secs(60)));
    }
}
