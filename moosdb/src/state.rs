//! The DB's single-threaded state machine (spec §5.3–§5.9). Every packet from every
//! client is processed here one at a time under one lock.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use super::outbox::{Gate, Marks, Outbox};
use super::Link;

/// Fan-out: a notification into every subscriber's held mail, and the send.
#[path = "fanout.rs"]
mod fanout;
/// Replies to server requests and the DB's own variables (spec §5.8, §5.9).
#[path = "reports.rs"]
mod reports;
/// Registrations and wildcard registrations.
#[path = "subscriptions.rs"]
mod subscriptions;
use moos::text::wildcard_match;
use moos::wire::{DataType, Message, MsgType, MsgView, PacketBuilder, PACKET_HEADER_LEN};

const REFRESH_PERIOD: f64 = 2.0;

/// Largest per-client high-water mark: past a few MB a queue only adds latency.
pub(crate) const MAX_HIGH_WATER: usize = 8 << 20;
/// Smallest per-client high-water mark, however many clients share the cap.
const MIN_HIGH_WATER: usize = 64 << 10;
/// A queue past its high-water mark holds its publishers back until it has drained this
/// much (or half the mark, if less): a reader taking 2.5 MB/s releases them within the
/// default hold limit, so a slow reader holds them back in short pulses; only a slower
/// one (or a stalled one) sees its holds ended by the hold limit.
const HOLD_BAND: usize = 256 << 10;

/// Held mail starts with room for the packet header, filled in when it is sent.
const HDR: usize = PACKET_HEADER_LEN;

/// FNV-1a: variable and client names are short, and SipHash showed up in profiles.
/// (MOOS communities are trusted networks; hash flooding is not a concern here.)
#[derive(Default)]
pub(crate) struct Fnv(u64);

impl Hasher for Fnv {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        let mut h = if self.0 == 0 {
            0xcbf2_9ce4_8422_2325
        } else {
            self.0
        };
        for b in bytes {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
        self.0 = h;
    }
}

type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<Fnv>>;
type FastSet<K> = HashSet<K, BuildHasherDefault<Fnv>>;

pub(crate) struct Sub {
    client: Arc<str>,
    interval: f64,
    last_sent: f64,
    /// The client's slot, resolved by name when `slot_gen` was the clients generation.
    slot: Option<usize>,
    slot_gen: u64,
}

pub(crate) struct Var {
    data_type: DataType,
    dval: f64,
    sval: Vec<u8>,
    time: f64,
    source: String,
    source_aux: String,
    community: String,
    written_db: f64,
    write_count: u64,
    writers: FastSet<String>,
    freq: f64,
    subs: Vec<Sub>,
    /// Connection that last published this variable (its `published` set has the name).
    last_pub: u64,
}

impl Var {
    fn new(data_type: DataType) -> Var {
        Var {
            data_type,
            dval: -1.0,
            sval: Vec::new(),
            time: -1.0,
            source: String::new(),
            source_aux: String::new(),
            community: String::new(),
            written_db: -1.0,
            write_count: 0,
            writers: FastSet::default(),
            freq: 0.0,
            subs: Vec::new(),
            last_pub: 0,
        }
    }

    fn current(&self, key: &str) -> Message {
        let is_d = self.data_type == DataType::DOUBLE;
        Message {
            id: -1,
            msg_type: MsgType::NOTIFY,
            data_type: self.data_type,
            source: self.source.clone(),
            source_aux: self.source_aux.clone(),
            community: self.community.clone(),
            key: key.to_owned(),
            time: self.time,
            dval: if is_d { self.dval } else { -1.0 },
            dval2: -1.0,
            sval: if is_d { Vec::new() } else { self.sval.clone() },
        }
    }
}

#[derive(Default)]
struct Qos {
    recent: f64,
    max: f64,
    min: f64,
    avg: f64,
    n: u64,
}

struct Filter {
    app: String,
    var: String,
    interval: f64,
}

pub(crate) struct ClientRec {
    name: Arc<str>,
    pub conn_id: u64,
    is_async: bool,
    /// Mail waiting for this client: a packet-header gap, then the encoded messages
    /// (empty when `held_count` is 0).
    held: Vec<u8>,
    held_count: usize,
    filters: Vec<Filter>,
    pub out: Arc<Outbox>,
    /// The reader's side of the connection (to tell a dead one from a live one).
    link: Arc<Link>,
    /// A synchronous client got held mail during the packet being processed.
    touched: bool,
    consolidation: f64,
    qos: Option<Qos>,
    published: FastSet<String>,
}

/// Result of a handshake attempt.
pub(crate) enum Admit {
    Welcome,
    Poison(String),
}

pub(crate) struct State {
    pub community: String,
    db_name: String,
    hostname: String,
    start: f64,
    last_refresh: f64,
    vars: FastMap<String, Var>,
    /// Client name → slot in `slots`.
    clients: FastMap<String, usize>,
    slots: Vec<Option<ClientRec>>,
    free_slots: Vec<usize>,
    /// Bumped whenever a client connects or leaves (invalidates `Sub::slot`).
    client_gen: u64,
    /// Newest connection last.
    order: Vec<String>,
    /// Slots that may have held mail to push.
    dirty: Vec<usize>,
    /// Synchronous clients whose held mail grew during the packet being processed.
    touched: Vec<usize>,
    /// Cap on the bytes queued for all clients together.
    max_queue: usize,
    /// Bytes the DB holds for all clients together (queues, partial packets, values).
    total: Arc<AtomicUsize>,
    /// Bytes of the values table (variable names and string values), as added to `total`.
    values: usize,
    /// A connection silent (and not held back) this long is dead (`ClientTimeout`).
    client_timeout: Duration,
    response: Vec<(String, f64)>,
    scratch: Vec<u8>,
    encoded: Vec<u8>,
    targets: Vec<usize>,
    /// Outboxes given bytes without waking their writer: the reader thread must
    /// [`Outbox::try_flush`] them once the state lock is released.
    pub flush: Vec<Arc<Outbox>>,
    /// Clients cut off because they stalled.
    pub stalled: u64,
    pub delivered: u64,
}

impl State {
    pub fn new(
        community: &str,
        hostname: &str,
        response: &[(String, f64)],
        cap: (usize, Arc<AtomicUsize>),
        client_timeout: Duration,
        now: f64,
    ) -> State {
        let (max_queue, total) = cap;
        let mut vars = FastMap::default();
        for (n, t) in [
            ("DB_TIME", DataType::DOUBLE),
            ("DB_UPTIME", DataType::DOUBLE),
            ("DB_CLIENTS", DataType::DOUBLE),
            ("DB_EVENT", DataType::STRING),
            ("DB_VARSUMMARY", DataType::STRING),
            ("DB_QOS", DataType::STRING),
            ("DB_RWSUMMARY", DataType::STRING),
        ] {
            vars.insert(n.to_owned(), Var::new(t));
        }
        // Consolidation entries with wildcards go before explicit names (spec §5.11).
        let mut response = response.to_vec();
        response.sort_by_key(|(p, _)| !(p.contains('*') || p.contains('?')));
        State {
            community: community.to_owned(),
            db_name: format!("MOOSDB_{community}"),
            hostname: hostname.to_owned(),
            start: now,
            last_refresh: now,
            vars,
            clients: FastMap::default(),
            slots: Vec::new(),
            free_slots: Vec::new(),
            client_gen: 1,
            order: Vec::new(),
            dirty: Vec::new(),
            touched: Vec::new(),
            max_queue,
            total,
            values: 0,
            client_timeout,
            response,
            scratch: Vec::new(),
            encoded: Vec::new(),
            targets: Vec::new(),
            flush: Vec::new(),
            stalled: 0,
            delivered: 0,
        }
    }

    /// Handshake (spec §4.3 steps 4–8). On `Welcome`, the welcome packet is queued on `out`.
    /// A name held by a live connection is refused (as C++); one held by a connection
    /// known dead (see [`State::is_dead`]) is freed first (QUIRKS.md).
    pub fn admit(&mut self, hs: &Message, conn: (u64, Arc<Outbox>, Arc<Link>), now: f64) -> Admit {
        let (conn_id, out, link) = conn;
        let name = String::from_utf8_lossy(&hs.sval).into_owned();
        if name.is_empty() {
            return Admit::Poison("Failed to read receive client's name".into());
        }
        if let Some(old) = self.client(&name) {
            if !self.is_dead(old) {
                return Admit::Poison(format!("A client of this name (\"{name}\") already exists"));
            }
            tracing::warn!(client = %name, "reconnect under the name of a dead connection: closing the old one");
            self.remove_client(&name, "replaced by a reconnect", now);
        }
        let is_async = hs.key.eq_ignore_ascii_case(moos::wire::ASYNC_KEY);
        let welcome = Message {
            msg_type: MsgType::WELCOME,
            data_type: DataType::DOUBLE,
            source_aux: format!("hostname={}", self.hostname),
            community: self.community.clone(),
            time: now,
            dval: now - hs.time,
            sval: moos::wire::ASYNC_KEY.as_bytes().to_vec(),
            ..Message::default()
        };
        out.push_with(|b| {
            let mut p = PacketBuilder::new(b);
            let _ = p.push(&welcome);
            let _ = p.finish();
        });
        let consolidation = self
            .response
            .iter()
            .find(|(p, _)| wildcard_match(p, &name))
            .map(|(_, ms)| ms / 1000.0)
            .unwrap_or(0.0);
        let rec = ClientRec {
            name: Arc::from(name.as_str()),
            conn_id,
            is_async,
            held: Vec::new(),
            held_count: 0,
            filters: Vec::new(),
            out,
            link,
            touched: false,
            consolidation,
            qos: None,
            published: FastSet::default(),
        };
        let slot = match self.free_slots.pop() {
            Some(i) => {
                self.slots[i] = Some(rec);
                i
            }
            None => {
                self.slots.push(Some(rec));
                self.slots.len() - 1
            }
        };
        self.clients.insert(name.clone(), slot);
        self.client_gen += 1;
        self.order.push(name.clone());
        tracing::info!(client = %name, asynchronous = is_async, "client connected");
        self.db_notify_str("DB_EVENT", &format!("connected={name}"), now);
        Admit::Welcome
    }

    /// Connection `conn_id` of `name` closed (EOF, error or timeout): spec §5.5.
    pub fn disconnect(&mut self, name: &str, conn_id: u64, reason: &str, now: f64) {
        match self.client(name) {
            Some(c) if c.conn_id == conn_id => {}
            _ => return,
        }
        self.remove_client(name, reason, now);
    }

    /// The DB cuts off connection `conn_id` of `name` as stalled: `why` goes into the
    /// `DB_EVENT` (`stalled=<name>,reason=<why>`) posted before `disconnected=<name>`.
    pub fn cut_off(&mut self, name: &str, conn_id: u64, why: &str, now: f64) {
        match self.client(name) {
            Some(c) if c.conn_id == conn_id => {}
            _ => return,
        }
        self.stalled += 1;
        tracing::warn!(client = %name, why, "cutting off stalled client");
        self.db_notify_str("DB_EVENT", &format!("stalled={name},reason={why}"), now);
        self.remove_client(name, "stalled", now);
    }

    /// A connection known dead: its peer closed or reset it, a read or write failed,
    /// or it has been silent past the client timeout while not held back.
    fn is_dead(&self, c: &ClientRec) -> bool {
        c.link.is_dead(self.client_timeout) || c.out.is_dead()
    }

    /// Flow-control marks: the cap shared by `n` connected clients.
    fn marks_for(&self, n: usize) -> Marks {
        let n = n.max(1);
        let high = (self.max_queue / (2 * n)).clamp(MIN_HIGH_WATER, MAX_HIGH_WATER);
        Marks {
            high,
            low: high - (high / 2).min(HOLD_BAND),
            total_cap: self.max_queue,
            // A stalled client may take all the room left: a reader that pauses for a
            // moment (its own inbox full) loses nothing if the DB has room for it.
            stalled_cap: self.max_queue,
        }
    }

    /// The values table holds `delta` more bytes.
    fn values_grew(&mut self, delta: isize) {
        if delta > 0 {
            self.values += delta as usize;
            self.total.fetch_add(delta as usize, Ordering::Relaxed);
        } else if delta < 0 {
            let d = delta.unsigned_abs().min(self.values);
            self.values -= d;
            self.total.fetch_sub(d, Ordering::Relaxed);
        }
    }

    fn remove_client(&mut self, name: &str, reason: &str, now: f64) {
        let Some(slot) = self.clients.remove(name) else {
            return;
        };
        let Some(c) = self.slots[slot].take() else {
            return;
        };
        self.free_slots.push(slot);
        self.client_gen += 1;
        c.out.close();
        self.order.retain(|n| n != name);
        for v in self.vars.values_mut() {
            v.subs.retain(|s| &*s.client != name);
        }
        tracing::info!(client = %name, reason, "client disconnected");
        self.db_notify_str("DB_EVENT", &format!("disconnected={name}"), now);
    }

    fn client(&self, name: &str) -> Option<&ClientRec> {
        self.clients
            .get(name)
            .and_then(|&i| self.slots.get(i)?.as_ref())
    }

    fn client_mut(&mut self, name: &str) -> Option<&mut ClientRec> {
        self.clients
            .get(name)
            .and_then(|&i| self.slots.get_mut(i)?.as_mut())
    }

    fn recs(&self) -> impl Iterator<Item = &ClientRec> {
        self.slots.iter().flatten()
    }

    /// Names of the connected clients (any order).
    pub fn client_names(&self) -> Vec<String> {
        self.clients.keys().cloned().collect()
    }

    pub fn client_count(&self) -> usize {
        self.clients.len()
    }

    /// Close every client's outbox and socket.
    pub fn close_all(&self) {
        for c in self.recs() {
            c.out.close();
        }
    }

    /// Total bytes held or queued for all clients.
    /// (A synchronous client's held mail counts as of the last packet processed.)
    pub fn queued_bytes(&self) -> usize {
        self.recs().map(|c| c.out.queued()).sum()
    }

    pub fn client_queued(&self, name: &str) -> Option<usize> {
        self.client(name).map(|c| c.out.queued())
    }

    /// Publishers held back by client `name`'s queue (`None` if not connected).
    pub fn client_holding(&self, name: &str) -> Option<usize> {
        self.client(name).map(|c| c.out.holding())
    }

    /// One packet from client `name` (spec §5.3), decoded in place. `gate` is the
    /// sender's: the subscribers its messages fill may hold it back. A big packet comes
    /// in pieces, each processed as a packet; `first` is false for all but its first
    /// (a timing message counts only at the start of a packet).
    pub fn process(
        &mut self,
        name: &str,
        msgs: &[MsgView<'_>],
        gate: &Arc<Gate>,
        first: bool,
        now: (f64, f64),
    ) {
        let (local, now) = now;
        if msgs.is_empty() {
            tracing::debug!(client = %name, "packet with no content");
            return;
        }
        let Some(&slot) = self.clients.get(name) else {
            return;
        };
        let Some((consolidation, conn_id)) = self.slots[slot]
            .as_ref()
            .map(|c| (c.consolidation, c.conn_id))
        else {
            return;
        };
        let has_notify = msgs.iter().any(|m| m.msg_type == MsgType::NOTIFY);
        let mut timing = None;
        let mut rest = msgs;
        if first && msgs[0].msg_type == MsgType::TIMING {
            let mut t = msgs[0].to_message();
            rest = &msgs[1..];
            t.dval = local;
            t.dval2 = consolidation;
            self.record_qos(name, (t.dval - t.time) * 1000.0);
            timing = Some(t);
        }
        let mut q_replies: Vec<Message> = Vec::new();
        for m in rest {
            match m.msg_type {
                MsgType::NOTIFY => self.notify(m, Some((slot, conn_id)), now),
                MsgType::REGISTER => self.register(m.source, m.key, m.dval, now),
                MsgType::UNREGISTER => self.unregister(m.source, m.key),
                MsgType::WILDCARD_REGISTER => self.wildcard_register(m, now),
                MsgType::WILDCARD_UNREGISTER => self.wildcard_unregister(m),
                MsgType::SERVER_REQUEST => self.server_request(m, now, &mut q_replies),
                _ => {}
            }
        }
        if now - self.last_refresh > REFRESH_PERIOD {
            self.refresh(now);
        }
        let marks = self.marks_for(self.clients.len());
        let c = match self.clients.get(name) {
            Some(&i) => self.slots.get_mut(i).and_then(Option::as_mut),
            None => None,
        };
        let Some(c) = c else {
            return;
        };
        let sync_null = (!c.is_async).then(|| Message {
            dval: local,
            ..Message::default()
        });
        let take_held = !rest.is_empty() || !c.is_async;
        let mut buf = std::mem::take(&mut self.scratch);
        buf.clear();
        let mut p = PacketBuilder::new(&mut buf);
        if let Some(n) = &sync_null {
            let _ = p.push(n);
        } else if let Some(t) = &timing {
            let _ = p.push(t);
        }
        if take_held {
            if c.held_count > 0 {
                p.push_encoded(&c.held[HDR..], c.held_count);
            }
            self.delivered += c.held_count as u64;
            c.held.clear();
            c.held_count = 0;
            if !c.is_async {
                c.out.set_extra(0, None, marks);
            }
        }
        for r in q_replies.iter().rev() {
            let _ = p.push(r);
        }
        let nonempty = p.count() > 0;
        let _ = p.finish();
        if nonempty {
            c.out.push_with(|b| b.extend_from_slice(&buf));
        }
        self.scratch = buf;
        if has_notify {
            self.push_all(gate, marks, now);
        }
        let touched = std::mem::take(&mut self.touched);
        for &t in &touched {
            if let Some(c) = self.slots.get_mut(t).and_then(Option::as_mut) {
                c.touched = false;
                // A synchronous client drains only when it sends: never hold it back
                // for its own held mail.
                let from = (t != slot).then_some(gate);
                c.out.set_extra(c.held_bytes(), from, marks);
            }
        }
        self.touched = touched;
        self.touched.clear();
    }
}

impl ClientRec {
    /// Bytes of held mail (without the header gap).
    fn held_bytes(&self) -> usize {
        self.held.len().saturating_sub(HDR)
    }
}

/// String equality for the short names on the hot path, without a `memcmp` call.
#[inline]
fn same(a: &str, b: &str) -> bool {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    if a.len() != b.len() {
        return false;
    }
    if a.len() > 16 {
        return a == b;
    }
    a.iter().zip(b).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// Write the packet header into the gap at the start of held mail.
fn finish_header(held: &mut [u8], count: usize) {
    let len = held.len() as i32;
    held[0..4].copy_from_slice(&len.to_le_bytes());
    held[4..8].copy_from_slice(&(count as i32).to_le_bytes());
    held[8] = 0;
}

fn add_sub(v: &mut Var, client: &str, interval: f64) -> usize {
    if let Some(i) = v.subs.iter().position(|s| &*s.client == client) {
        v.subs[i].interval = interval;
        v.subs[i].last_sent = 0.0;
        i
    } else {
        v.subs.push(Sub {
            client: Arc::from(client),
            interval,
            last_sent: 0.0,
            slot: None,
            slot_gen: 0,
        });
        v.subs.len() - 1
    }
}
