//! Socket side of the DB: accept, handshake, per-client reader and writer threads.
//!
//! A reader stops reading while its connection's [`Gate`] is held (flow control, see
//! `outbox`), or while it waits for room to buffer a long message (`link::ReadShare`).
//! A writer marks its client stalled when the socket has accepted no bytes for the hold
//! limit (it then holds no one back), and cuts it off at the stall timeout.

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::link::{Link, ReadCounters, ReadShare, PIECE};
use super::outbox::{Gate, Outbox};
use super::state::Admit;
use super::Inner;
use moos::wire::{self, DataType, FrameReader, Message, MsgType, MsgView, Piece};

pub(crate) fn accept_loop(inner: Arc<Inner>, listener: TcpListener) {
    while !inner.stop.load(Ordering::SeqCst) {
        match listener.accept() {
            Ok((stream, peer)) => {
                let id = inner.next_conn.fetch_add(1, Ordering::Relaxed);
                let i2 = inner.clone();
                let r = std::thread::Builder::new()
                    .name(format!("moosdb-conn-{id}"))
                    .spawn(move || serve(i2, stream, peer, id));
                if let Err(e) = r {
                    tracing::error!(%peer, "cannot spawn connection thread: {e}");
                }
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => {
                tracing::warn!("accept failed: {e}");
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    }
}

/// A poison packet (`K`/`S`, reason in `sval`), spec §4.3 step 5.
pub(crate) fn poison_packet(reason: &str, now: f64) -> Vec<u8> {
    let m = Message {
        msg_type: MsgType::POISON,
        data_type: DataType::STRING,
        time: now,
        sval: reason.as_bytes().to_vec(),
        ..Message::default()
    };
    let mut out = Vec::new();
    let _ = wire::encode_packet(&[m], &mut out);
    out
}

/// Largest handshake packet (a client's name and options; real ones are a few hundred
/// bytes): a peer that starts a bigger one is not a MOOS client.
const MAX_HANDSHAKE: usize = 64 * 1024;

fn is_timeout(e: &std::io::Error) -> bool {
    matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut)
}

/// Read the handshake packet within the deadline; `Err` says why there is none (the
/// peer is dropped and that is logged).
fn read_handshake(
    inner: &Inner,
    stream: &mut TcpStream,
    fr: &mut FrameReader,
) -> Result<Vec<Message>, String> {
    let deadline = Instant::now() + inner.cfg.handshake_timeout;
    loop {
        match fr.next_frame() {
            Ok(Some(r)) => {
                return match wire::decode_packet_lenient(fr.frame(r), usize::MAX) {
                    Ok((msgs, _)) => Ok(msgs),
                    Err(_) => Ok(Vec::new()),
                };
            }
            Ok(None) => {}
            Err(e) => return Err(format!("bad handshake packet: {e}")),
        }
        if fr.pending() > MAX_HANDSHAKE {
            return Err(format!(
                "handshake packet larger than {} KiB",
                MAX_HANDSHAKE >> 10
            ));
        }
        let timeout = || {
            format!(
                "no complete handshake packet within {:.1} s",
                inner.cfg.handshake_timeout.as_secs_f64()
            )
        };
        let left = deadline
            .checked_duration_since(Instant::now())
            .ok_or_else(timeout)?;
        if left.is_zero() || stream.set_read_timeout(Some(left)).is_err() {
            return Err(timeout());
        }
        match fr.fill(stream) {
            Ok(0) => return Err("closed during the handshake".into()),
            Ok(_) => {}
            Err(e) if is_timeout(&e) => return Err(timeout()),
            Err(e) => return Err(format!("socket error during the handshake: {e}")),
        }
    }
}

fn serve(inner: Arc<Inner>, mut stream: TcpStream, peer: SocketAddr, conn_id: u64) {
    let _ = stream.set_nodelay(true);
    if stream
        .set_read_timeout(Some(inner.cfg.handshake_timeout))
        .is_err()
    {
        return;
    }
    let mut banner = [0u8; 32];
    match stream.read_exact(&mut banner) {
        Ok(()) if wire::banner_ok(&banner) => {}
        Ok(()) => {
            tracing::warn!(%peer, "not a MOOS client (bad banner): closing");
            return;
        }
        Err(e) => {
            // A port probe or a health check that connects and closes: worth a line, not
            // a warning.
            tracing::info!(%peer, "no banner ({e}): closing");
            return;
        }
    }
    let mut fr = FrameReader::new(inner.cfg.max_packet);
    let hs = match read_handshake(&inner, &mut stream, &mut fr) {
        Ok(hs) => hs,
        Err(why) => {
            tracing::warn!(%peer, "dropped before the handshake ended: {why}");
            return;
        }
    };
    let Some(hs) = hs.into_iter().next() else {
        let p = poison_packet("Failed to read receive client's name", inner.now());
        let _ = stream.write_all(&p);
        return;
    };
    let Ok(wstream) = stream.try_clone() else {
        return;
    };
    let Ok(ostream) = stream.try_clone() else {
        return;
    };
    let name = String::from_utf8_lossy(&hs.sval).into_owned();
    let out = Arc::new(Outbox::new(ostream, inner.total.clone(), &name));
    let gate = Arc::new(Gate::new());
    let link = Arc::new(Link::new());
    let is_async = hs.key.eq_ignore_ascii_case(wire::ASYNC_KEY);
    let admitted = {
        let now = inner.now();
        inner
            .lock()
            .admit(&hs, (conn_id, out.clone(), link.clone()), now)
    };
    if let Admit::Poison(reason) = admitted {
        tracing::info!(client = %name, %reason, "handshake refused");
        let _ = stream.set_write_timeout(Some(inner.cfg.send_timeout));
        let _ = stream.write_all(&poison_packet(&reason, inner.now()));
        return;
    }
    let (o2, i2, n2) = (out.clone(), inner.clone(), name.clone());
    let spawned = std::thread::Builder::new()
        .name(format!("moosdb-write-{conn_id}"))
        .spawn(move || writer(&i2, &o2, wstream, &n2, conn_id));
    let reason = if spawned.is_err() {
        "cannot spawn writer"
    } else {
        let conn = Conn {
            name: &name,
            conn_id,
            gate: &gate,
            out: &out,
            link: &link,
            // A synchronous client expects one reply per packet: its packets stay whole.
            piece: if is_async {
                PIECE
            } else {
                inner.cfg.max_packet
            },
        };
        read_loop(&inner, &mut stream, &mut fr, &conn)
    };
    link.set_dead();
    let now = inner.now();
    inner.lock().disconnect(&name, conn_id, reason, now);
    out.close();
}

/// One admitted connection, as its reader sees it.
struct Conn<'a> {
    name: &'a str,
    conn_id: u64,
    gate: &'a Arc<Gate>,
    out: &'a Outbox,
    link: &'a Link,
    /// Packets longer than this are taken in pieces (`FrameReader::next_piece`).
    piece: usize,
}

/// A decoded piece: where its views end, and whether it starts its packet.
struct Decoded {
    end: usize,
    first: bool,
}

fn read_loop(
    inner: &Inner,
    stream: &mut TcpStream,
    fr: &mut FrameReader,
    c: &Conn,
) -> &'static str {
    let name = c.name;
    let tick = inner.cfg.client_timeout.min(Duration::from_secs(1));
    if stream.set_read_timeout(Some(tick)).is_err() {
        return "socket error";
    }
    let mut last_rx = Instant::now();
    c.link.heard();
    let mut share = ReadShare::new(ReadCounters {
        total: &inner.total,
        big: &inner.big,
        big_cap: inner.cfg.max_queue_bytes / 2,
    });
    // Every packet (or piece of a big one) complete after one read is decoded in place
    // (views into the read buffer), then all are processed under one lock. A bad packet
    // ends the connection before any of that read's packets are processed.
    let mut pieces: Vec<Piece> = Vec::new();
    let mut decoded: Vec<Decoded> = Vec::new();
    let mut spare_views: Vec<MsgView<'static>> = Vec::new();
    let mut flush = Vec::new();
    loop {
        pieces.clear();
        loop {
            match fr.next_piece(c.piece) {
                Ok(Some(p)) => pieces.push(p),
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!(client = %name, "bad packet framing: {e}");
                    return "malformed packet";
                }
            }
        }
        if let Some(e) = fr.take_bad() {
            tracing::warn!(client = %name, "malformed message dropped (with the rest of its packet): {e}");
        }
        if !pieces.is_empty() {
            let mut views = recycle(std::mem::take(&mut spare_views));
            decoded.clear();
            for p in &pieces {
                let first = match p {
                    Piece::Packet(r) => {
                        match wire::decode_packet_views(fr.frame(r.clone()), usize::MAX, &mut views)
                        {
                            Ok(Some(e)) => {
                                tracing::warn!(client = %name, "malformed message dropped: {e}");
                            }
                            Ok(None) => {}
                            Err(e) => {
                                tracing::warn!(client = %name, "malformed packet: {e}");
                                return "malformed packet";
                            }
                        }
                        true
                    }
                    Piece::Messages {
                        range,
                        count,
                        first,
                    } => {
                        // Checked whole by the frame reader.
                        let mut b = fr.frame(range.clone());
                        for _ in 0..*count {
                            let Ok((m, used)) = MsgView::parse(b) else {
                                break;
                            };
                            views.push(m);
                            b = b.get(used..).unwrap_or_default();
                        }
                        *first
                    }
                };
                decoded.push(Decoded {
                    end: views.len(),
                    first,
                });
            }
            let now = inner.now();
            let mut st = inner.lock();
            let mut start = 0;
            for d in &decoded {
                st.process(name, &views[start..d.end], c.gate, d.first, (now, now));
                start = d.end;
            }
            std::mem::swap(&mut flush, &mut st.flush);
            drop(st);
            spare_views = recycle(views);
            for o in flush.drain(..) {
                o.try_flush();
            }
        }
        if inner.stop.load(Ordering::Relaxed) {
            return "shutdown";
        }
        // Room for what is buffered, and for the whole of a long message before more of
        // it is read: else wait, not reading (the publisher is held back, not dropped).
        share.buffered(fr.pending());
        if !share.reserve(fr.wanted(c.piece)) {
            tracing::info!(
                client = %name,
                kib = fr.wanted(c.piece) >> 10,
                "held back: waiting for room for a long message"
            );
            c.link.set_held(true);
            while !share.reserve(fr.wanted(c.piece)) {
                std::thread::sleep(Duration::from_millis(2));
                if inner.stop.load(Ordering::Relaxed) {
                    return "shutdown";
                }
                if c.out.is_cut() {
                    return "closed";
                }
            }
            c.link.set_held(false);
            last_rx = Instant::now();
        }
        if !c.gate.is_open() {
            // Held back for a subscriber's queue: the time does not count as silence.
            c.link.set_held(true);
            while !c.gate.wait_open(tick) {
                if inner.stop.load(Ordering::Relaxed) {
                    return "shutdown";
                }
                if c.out.is_cut() {
                    return "closed";
                }
            }
            c.link.set_held(false);
            last_rx = Instant::now();
        }
        match fr.fill(stream) {
            Ok(0) => return "closed by client",
            Ok(_) => {
                last_rx = Instant::now();
                c.link.heard();
            }
            Err(e) if is_timeout(&e) => {
                let silent = last_rx.elapsed();
                if silent > inner.cfg.client_timeout {
                    let why = format!("sent nothing for {:.1} s", silent.as_secs_f64());
                    let now = inner.now();
                    inner.lock().cut_off(name, c.conn_id, &why, now);
                    return "timeout";
                }
            }
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => return "socket error",
        }
    }
}

/// An empty vector of views with another lifetime, keeping the allocation (the standard
/// library collects in place when the element layout is the same).
fn recycle<'b>(mut v: Vec<MsgView<'_>>) -> Vec<MsgView<'b>> {
    v.clear();
    v.into_iter().map(|_| unreachable!()).collect()
}

/// The writer tells the outbox about progress within a chunk this often (bytes).
const REPORT_EVERY: usize = 256 << 10;

/// What a socket must accept within the hold limit to count as making progress (and so
/// hold publishers back): a subscriber that takes only a trickle (its kernel buffers
/// growing while it reads nothing, or a very slow link) would hold everyone to its pace.
const HOLD_PROGRESS: usize = 64 << 10;

/// The hold clock (`writer`): (window start, bytes accepted in it, marked stalled). A
/// window with [`HOLD_PROGRESS`] bytes is progress (a new window starts; a stalled
/// client holds again); one of `hold` without is a stall (a trickle does not add up
/// across windows).
fn hold_window(out: &Outbox, hold: Duration, w: &mut (Instant, usize, bool)) {
    let (since, bytes, marked) = w;
    if since.elapsed() >= hold / 4 {
        // At most once a tick: it takes the outbox lock the publishers push under.
        out.end_long_hold(hold);
    }
    if *bytes >= HOLD_PROGRESS {
        tracing::trace!(client = %out.name, bytes = *bytes, ms = since.elapsed().as_millis() as u64, "hold window");
        if std::mem::take(marked) {
            out.progressed();
        }
        *since = Instant::now();
        *bytes = 0;
    } else if since.elapsed() >= hold {
        *since = Instant::now();
        *bytes = 0;
        if !*marked {
            *marked = true;
            out.set_stalled();
        }
    }
}

/// Blocking writes of what the direct flushes left, in ticks short enough to notice a
/// stall in time: a client whose socket accepts less than [`HOLD_PROGRESS`] within the
/// hold limit is marked stalled (it holds no one back until it makes progress again),
/// and one that accepts nothing for the stall timeout is cut off.
fn writer(inner: &Inner, out: &Outbox, mut stream: TcpStream, name: &str, conn_id: u64) {
    let stall = inner.cfg.stall_timeout;
    let hold = inner.cfg.hold_limit;
    let tick = (stall / 10)
        .min(hold / 4)
        .clamp(Duration::from_millis(5), Duration::from_millis(100));
    let _ = stream.set_write_timeout(Some(tick));
    let mut spare = Vec::new();
    let mut done = false;
    let mut drained = false;
    // The hold clock: windows of the hold limit; a window in which the socket accepted
    // HOLD_PROGRESS bytes (or took all there was) is progress, one without marks the
    // client stalled.
    let mut hw = (Instant::now(), 0usize, false);
    while out.take(&mut spare, done, &mut drained) {
        if drained {
            hw.0 = Instant::now();
            hw.1 = 0;
            if std::mem::take(&mut hw.2) {
                out.progressed();
            }
        }
        done = true;
        // The stall clock: last progress, or when these bytes were handed over.
        let mut since = Instant::now();
        let mut sent = 0;
        let mut unreported = 0;
        // Progress since the last timeout (the clock is read only when a write times out).
        let mut progressed = false;
        while sent < spare.len() {
            match stream.write(&spare[sent..]) {
                Ok(0) => {
                    out.write_failed();
                    return;
                }
                Ok(n) => {
                    sent += n;
                    progressed = true;
                    hw.1 += n;
                    // A write that times out after taking a few bytes returns them, so
                    // the window is judged here too.
                    hold_window(out, hold, &mut hw);
                    unreported += n;
                    // Progress lets the queue fall below its low-water mark.
                    if unreported >= REPORT_EVERY && sent < spare.len() {
                        out.wrote(unreported);
                        unreported = 0;
                    }
                }
                Err(e) if is_timeout(&e) => {
                    if std::mem::take(&mut progressed) {
                        since = Instant::now();
                    }
                    hold_window(out, hold, &mut hw);
                    let stuck = since.elapsed();
                    if stuck >= stall {
                        let why = format!("accepted no bytes for {:.1} s", stuck.as_secs_f64());
                        let now = inner.now();
                        inner.lock().cut_off(name, conn_id, &why, now);
                        out.close();
                        return;
                    }
                    if inner.stop.load(Ordering::Relaxed) {
                        return;
                    }
                }
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => {
                    tracing::debug!(client = %name, "write to client failed: {e}");
                    out.write_failed();
                    return;
                }
            }
        }
        spare.clear();
        if spare.capacity() > 1 << 20 {
            spare = Vec::new();
        }
    }
}
