//! `moosdb`: an embeddable MOOSDB (spec §4.3, §5.3–§5.11), and the `moosdb` binary.
//!
//! It depends on `moos` (wire codec, mission reader, text helpers) and must not depend on
//! the helm; the MOOS client (in `moos`) does not depend on it.
//!
//! ```no_run
//! use moosdb::{Db, DbConfig};
//! let db = Db::start(DbConfig { port: 0, ..DbConfig::default() }).unwrap();
//! println!("listening on {}", db.port());
//! db.shutdown();
//! ```
//!
//! Threads: one acceptor, and per client one reader (decodes packets in place, then
//! processes them under the single state lock, so packets are handled one at a time as in
//! C++) and one writer for that client's outbox. Each notification is encoded once per
//! incoming packet and copied into every subscriber's held mail; after the lock is
//! released the publisher's reader sends each subscriber's new packet itself with a
//! non-blocking write, and only what the socket does not take is left to that
//! subscriber's writer thread.
//!
//! # Overload
//!
//! The DB never drops a message for a subscriber that keeps reading, never drops a
//! publisher, and its memory stays under [`DbConfig::max_queue_bytes`]: queues, incoming
//! packets and the values table all count (`Inner::total`).
//!
//! * **Slow but reading.** Each client's queue has a high-water mark: the cap divided
//!   among the connected clients (`max_queue_bytes / (2 × clients)`, between 64 KiB and
//!   8 MiB). Past it the DB stops reading from the publishers that filled the queue (the
//!   heaviest recent contributors, 90 % of its recent bytes; a publisher posting a few
//!   messages a second is not among them), so TCP flow control slows them down, until
//!   the queue has drained 256 KiB (or half the mark). Time a publisher is held back
//!   does not count as silence.
//! * **Stalled** (issue 19). Back-pressure comes only from subscribers making progress:
//!   one whose socket takes less than 64 KiB in [`DbConfig::hold_limit`] holds no one
//!   back (until it does again), and no hold lasts longer than the hold limit (kernel
//!   buffers take bytes for a while from a client that reads nothing). The queue of such
//!   a client grows instead; when the DB-wide total reaches the cap it is cut off (the
//!   largest first), as is a client whose socket accepts no bytes for
//!   [`DbConfig::stall_timeout`], or that sends nothing for [`DbConfig::client_timeout`]:
//!   its memory is released and it gets the current values again when it reconnects.
//! * **Large packets.** A packet longer than 256 KiB is taken in pieces of whole messages
//!   (`wire::FrameReader::next_piece`), each processed as it arrives; a message longer
//!   than that is read only once the DB has room for all of it (`link::ReadShare`),
//!   else the publisher waits, not read.
//! * **Reconnects.** A handshake under the name of a connected client is refused while
//!   that connection is live (as C++), and welcomed once it is known dead: the old one
//!   is closed first (QUIRKS.md).
//!
//! # `DB_EVENT` values
//!
//! | value | when |
//! |---|---|
//! | `connected=<name>` | a client completed the handshake (as C++) |
//! | `disconnected=<name>` | a client left, for whatever reason (as C++) |
//! | `stalled=<name>,reason=accepted no bytes for <s> s` | posted just before `disconnected=`: its socket took nothing for `stall_timeout` |
//! | `stalled=<name>,reason=accepted no bytes while its queue reached <n> KiB` | posted just before `disconnected=`: not making progress when the cap was reached |
//! | `stalled=<name>,reason=sent nothing for <s> s` | posted just before `disconnected=`: silent for `client_timeout` |

mod link;
mod outbox;
mod server;
mod state;

pub(crate) use link::Link;

use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpListener};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Duration;

use thiserror::Error;

use moos::mission::MissionFile;
use state::State;

/// DB settings. `Default` gives port 9000 on 127.0.0.1, community `#1`, warp 1,
/// 5 s client timeout, 5 s stall timeout, 0.1 s hold limit, 64 MiB cap for all clients
/// together.
#[derive(Clone, Debug)]
pub struct DbConfig {
    /// TCP port; 0 picks an ephemeral one (see [`Db::port`]).
    pub port: u16,
    /// Address to listen on (loopback by default).
    pub bind: IpAddr,
    /// Community name (mission `Community`).
    pub community: String,
    /// Time-warp factor, 0 < warp ≤ 400.
    pub time_warp: f64,
    /// Drop a client after this much real time without receiving anything (mission
    /// `ClientTimeout`).
    pub client_timeout: Duration,
    /// Cut off a client whose socket accepted no bytes for this long while some were
    /// waiting (mission `StallTimeout`, seconds).
    pub stall_timeout: Duration,
    /// A client whose socket accepted no bytes for this long while some were waiting
    /// holds no publisher back any more, until it takes bytes again (mission
    /// `HoldLimit`, seconds).
    pub hold_limit: Duration,
    /// Cap on the bytes held and queued for all clients together (mission `MaxQueueMB`,
    /// MiB). Publishers are held back before it is reached; nothing is dropped.
    pub max_queue_bytes: usize,
    /// Largest packet accepted from a client.
    pub max_packet: usize,
    /// The handshake packet must arrive within this time.
    pub handshake_timeout: Duration,
    /// A blocked write of a handshake refusal fails after this time.
    pub send_timeout: Duration,
    /// Consolidation delays (`--response`): (client-name pattern, milliseconds).
    pub response: Vec<(String, f64)>,
    /// Host name sent in the welcome (`hostname=<..>`); the machine's name if `None`.
    pub hostname: Option<String>,
}

impl Default for DbConfig {
    fn default() -> Self {
        DbConfig {
            port: 9000,
            bind: IpAddr::V4(Ipv4Addr::LOCALHOST),
            community: "#1".into(),
            time_warp: 1.0,
            client_timeout: Duration::from_secs(5),
            stall_timeout: Duration::from_secs(5),
            hold_limit: DEFAULT_HOLD_LIMIT,
            max_queue_bytes: 64 * 1024 * 1024,
            max_packet: moos::wire::DEFAULT_MAX_PACKET,
            handshake_timeout: Duration::from_secs(5),
            send_timeout: Duration::from_secs(6),
            response: Vec::new(),
            hostname: None,
        }
    }
}

impl DbConfig {
    /// Apply the mission globals the DB reads: `ServerPort`, `Community`,
    /// `MOOSTimeWarp`, `ClientTimeout` (spec §7.2), and this DB's own `StallTimeout`,
    /// `HoldLimit` (seconds) and `MaxQueueMB` (MiB).
    pub fn apply_mission(&mut self, m: &MissionFile) {
        if let Some(p) = m.global_f64("ServerPort") {
            if (0.0..=65535.0).contains(&p) {
                self.port = p as u16;
            }
        }
        if let Some(c) = m.global("Community") {
            self.community = c;
        }
        if let Some(w) = m.global_f64("MOOSTimeWarp") {
            if moos::time::warp_ok(w) {
                self.time_warp = w;
            }
        }
        if let Some(t) = m.global_f64("ClientTimeout") {
            if t > 0.0 && t.is_finite() {
                self.client_timeout = Duration::from_secs_f64(t);
            }
        }
        if let Some(t) = m.global_f64("StallTimeout") {
            if t > 0.0 && t.is_finite() {
                self.stall_timeout = Duration::from_secs_f64(t);
            }
        }
        if let Some(t) = m.global_f64("HoldLimit") {
            if t > 0.0 && t.is_finite() {
                self.hold_limit = Duration::from_secs_f64(t);
            }
        }
        if let Some(mb) = m.global_f64("MaxQueueMB") {
            if let Some(b) = mib_to_bytes(mb) {
                self.max_queue_bytes = b;
            }
        }
    }
}

/// Default [`DbConfig::hold_limit`]: a stalled subscriber may hold the publishers back
/// this long at most, so the longest gap it causes others stays well under 250 ms.
pub const DEFAULT_HOLD_LIMIT: Duration = Duration::from_millis(100);

/// `mb` MiB in bytes, if it is a usable cap (at least 1 MiB).
pub fn mib_to_bytes(mb: f64) -> Option<usize> {
    (1.0..=1e6)
        .contains(&mb)
        .then_some((mb * 1024.0 * 1024.0) as usize)
}

/// Why the DB could not start.
#[derive(Debug, Error)]
pub enum DbError {
    #[error("cannot listen on {addr}: {source}")]
    Bind {
        addr: SocketAddr,
        #[source]
        source: std::io::Error,
    },
    #[error("invalid time warp {0} (must be 0 < warp <= 400)")]
    BadWarp(f64),
    #[error("socket setup failed: {0}")]
    Io(#[from] std::io::Error),
}

/// Counters for monitoring and tests.
#[derive(Clone, Debug, Default)]
pub struct DbStats {
    pub clients: usize,
    /// Clients cut off because they stalled.
    pub stalled: u64,
    pub delivered: u64,
    pub queued_bytes: usize,
}

pub(crate) struct Inner {
    state: Mutex<State>,
    cfg: DbConfig,
    /// Bytes the DB holds for all clients: queues (kept by the outboxes), incomplete
    /// packets (`link::ReadShare`) and the values table (the state).
    total: Arc<AtomicUsize>,
    /// Bytes reserved for incomplete messages longer than a piece (`link::ReadShare`).
    big: AtomicUsize,
    stop: AtomicBool,
    next_conn: AtomicU64,
}

impl Inner {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
    fn now(&self) -> f64 {
        moos::time::local_time(self.cfg.time_warp)
    }
}

/// A running MOOSDB. Dropping it shuts it down.
pub struct Db {
    inner: Arc<Inner>,
    addr: SocketAddr,
    acceptor: Option<JoinHandle<()>>,
}

impl Db {
    /// Bind and start serving.
    pub fn start(cfg: DbConfig) -> Result<Db, DbError> {
        if !moos::time::warp_ok(cfg.time_warp) {
            return Err(DbError::BadWarp(cfg.time_warp));
        }
        let addr = SocketAddr::new(cfg.bind, cfg.port);
        let listener = TcpListener::bind(addr).map_err(|source| DbError::Bind { addr, source })?;
        let addr = listener.local_addr()?;
        listener.set_nonblocking(true)?;
        let hostname = cfg.hostname.clone().unwrap_or_else(hostname);
        let now = moos::time::local_time(cfg.time_warp);
        let total = Arc::new(AtomicUsize::new(0));
        let state = State::new(
            &cfg.community,
            &hostname,
            &cfg.response,
            (cfg.max_queue_bytes, total.clone()),
            cfg.client_timeout,
            now,
        );
        let inner = Arc::new(Inner {
            state: Mutex::new(state),
            cfg,
            total,
            big: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
            next_conn: AtomicU64::new(1),
        });
        let i2 = inner.clone();
        let acceptor = std::thread::Builder::new()
            .name("moosdb-accept".into())
            .spawn(move || server::accept_loop(i2, listener))?;
        tracing::info!(%addr, community = %inner.cfg.community, "MOOSDB started");
        Ok(Db {
            inner,
            addr,
            acceptor: Some(acceptor),
        })
    }

    /// The port actually bound.
    pub fn port(&self) -> u16 {
        self.addr.port()
    }

    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Names of the connected clients.
    pub fn client_names(&self) -> Vec<String> {
        let mut v: Vec<String> = self.inner.lock().client_names();
        v.sort();
        v
    }

    /// Bytes currently held or queued for all clients.
    pub fn queued_bytes(&self) -> usize {
        self.inner.lock().queued_bytes()
    }

    /// Every byte the DB counts against its cap (queues, incomplete packets, values
    /// table; the queues to within 64 KiB per client).
    pub fn held_bytes(&self) -> usize {
        self.inner.total.load(Ordering::Relaxed)
    }

    /// Bytes held or queued for one client (`None` if not connected).
    pub fn client_queued_bytes(&self, name: &str) -> Option<usize> {
        self.inner.lock().client_queued(name)
    }

    /// How many publishers client `name`'s queue holds back (`None` if not connected).
    pub fn client_holding(&self, name: &str) -> Option<usize> {
        self.inner.lock().client_holding(name)
    }

    pub fn stats(&self) -> DbStats {
        let s = self.inner.lock();
        DbStats {
            clients: s.client_count(),
            stalled: s.stalled,
            delivered: s.delivered,
            queued_bytes: s.queued_bytes(),
        }
    }

    /// Stop accepting, close every client connection and wait for the acceptor.
    pub fn shutdown(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.inner.stop.store(true, Ordering::SeqCst);
        if let Some(h) = self.acceptor.take() {
            let _ = h.join();
        }
        self.inner.lock().close_all();
    }
}

impl Drop for Db {
    fn drop(&mut self) {
        self.stop();
    }
}

pub use moos::time::hostname;

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn mission_sets_stall_timeout_and_queue_cap() {
        let m = MissionFile::parse(
            "ServerPort = 9001\nClientTimeout = 7\nStallTimeout = 2.5\nMaxQueueMB = 128\nHoldLimit = 0.3\n",
            Path::new("t.moos"),
        )
        .expect("parse");
        let mut cfg = DbConfig::default();
        assert_eq!(cfg.stall_timeout, Duration::from_secs(5));
        assert_eq!(cfg.max_queue_bytes, 64 << 20);
        cfg.apply_mission(&m);
        assert_eq!(cfg.stall_timeout, Duration::from_millis(2500));
        assert_eq!(cfg.max_queue_bytes, 128 << 20);
        assert_eq!(cfg.client_timeout, Duration::from_secs(7));
        assert_eq!(cfg.hold_limit, Duration::from_millis(300));
    }

    #[test]
    fn unusable_values_keep_the_defaults() {
        let m = MissionFile::parse("StallTimeout = -1\nMaxQueueMB = 0.5\n", Path::new("t.moos"))
            .expect("parse");
        let mut cfg = DbConfig::default();
        cfg.apply_mission(&m);
        assert_eq!(cfg.stall_timeout, Duration::from_secs(5));
        assert_eq!(cfg.max_queue_bytes, 64 << 20);
        assert_eq!(mib_to_bytes(1.0), Some(1 << 20));
        assert_eq!(mib_to_bytes(f64::NAN), None);
    }
}
