//! The client's connection thread: connect, handshake, writer loop; plus the reader.

use std::io::{ErrorKind, Write};
use std::net::{Shutdown, SocketAddr, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{wildcard_payload, Shared};
use crate::wire::{self, DataType, FrameReader, Message, MsgType, PacketBuilder};

enum End {
    /// Connection lost: reconnect.
    Lost,
    /// A reconnect refused: retry with back-off.
    Refused,
    /// Poisoned or stopping: finish.
    Final,
}

pub(super) fn run(sh: Arc<Shared>) {
    let mut backoff = sh.cfg.reconnect_min;
    while !sh.stop.load(Ordering::SeqCst) {
        match connect(&sh) {
            Some(stream) => {
                match session(&sh, stream) {
                    End::Final => break,
                    End::Lost => backoff = sh.cfg.reconnect_min,
                    End::Refused => backoff = (backoff * 2).min(sh.cfg.reconnect_max),
                }
                if sh.stop.load(Ordering::SeqCst) {
                    break;
                }
                pause(&sh, backoff);
            }
            None => {
                pause(&sh, backoff);
                backoff = (backoff * 2).min(sh.cfg.reconnect_max);
            }
        }
    }
    let mut st = sh.lock();
    st.connected = false;
    sh.mail_cv.notify_all();
}

/// Sleep that a stop request interrupts.
fn pause(sh: &Shared, d: Duration) {
    let deadline = Instant::now() + d;
    let mut st = sh.lock();
    while !sh.stop.load(Ordering::SeqCst) {
        let Some(left) = deadline.checked_duration_since(Instant::now()) else {
            return;
        };
        st = sh
            .out_cv
            .wait_timeout(st, left)
            .unwrap_or_else(|p| p.into_inner())
            .0;
    }
}

fn connect(sh: &Shared) -> Option<TcpStream> {
    let addrs: Vec<SocketAddr> = match (sh.cfg.host.as_str(), sh.cfg.port).to_socket_addrs() {
        Ok(a) => a.collect(),
        Err(e) => {
            tracing::debug!(host = %sh.cfg.host, "cannot resolve DB host: {e}");
            return None;
        }
    };
    for a in addrs {
        if let Ok(s) = TcpStream::connect_timeout(&a, Duration::from_secs(1)) {
            return Some(s);
        }
    }
    None
}

fn handshake(sh: &Shared, stream: &mut TcpStream, fr: &mut FrameReader) -> Result<Message, End> {
    let _ = stream.set_nodelay(true);
    let hs = Message {
        msg_type: MsgType::DATA,
        data_type: DataType::STRING,
        key: wire::ASYNC_KEY.into(),
        time: sh.local_time(),
        sval: sh.cfg.name.as_bytes().to_vec(),
        ..Message::default()
    };
    // Banner and handshake in one write: the DB reads the banner with one recv(32).
    let mut buf = wire::BANNER.to_vec();
    if wire::encode_packet(&[hs], &mut buf).is_err() || stream.write_all(&buf).is_err() {
        return Err(End::Lost);
    }
    let _ = stream.set_read_timeout(Some(Duration::from_secs(5)));
    loop {
        match fr.next_frame() {
            Ok(Some(r)) => {
                let msgs = wire::decode_packet(fr.frame(r), usize::MAX).map_err(|_| End::Lost)?;
                return msgs.into_iter().next().ok_or(End::Lost);
            }
            Ok(None) => {}
            Err(_) => return Err(End::Lost),
        }
        match fr.fill(stream) {
            Ok(n) if n > 0 => {}
            _ => return Err(End::Lost),
        }
    }
}

fn session(sh: &Arc<Shared>, mut stream: TcpStream) -> End {
    let mut fr = FrameReader::new(sh.cfg.max_packet);
    {
        let mut st = sh.lock();
        st.skew = 0.0;
    }
    let welcome = match handshake(sh, &mut stream, &mut fr) {
        Ok(w) => w,
        Err(e) => return e,
    };
    if welcome.msg_type == MsgType::POISON && sh.lock().connects > 0 {
        // A reconnect refused, typically "a client of this name already exists": the DB
        // has not yet noticed that our previous connection is gone (it was frozen, or
        // the network dropped). It will, so try again; only a first refusal is final.
        tracing::warn!(client = %sh.cfg.name, reason = %welcome.string(), "DB refused the reconnect; retrying");
        return End::Refused;
    }
    if welcome.msg_type == MsgType::POISON {
        let reason = welcome.string().into_owned();
        tracing::error!(client = %sh.cfg.name, %reason, "DB refused the handshake");
        let mut st = sh.lock();
        st.poisoned = Some(reason);
        sh.mail_cv.notify_all();
        return End::Final;
    }
    let db_host =
        crate::text::find_value(&welcome.source_aux, "hostname", false).unwrap_or_default();
    let (Ok(rstream), Ok(wstream)) = (stream.try_clone(), stream.try_clone()) else {
        return End::Lost;
    };
    let dead = Arc::new(AtomicBool::new(false));
    // A DB that holds this publisher back (flow control) reads neither its data nor its
    // heartbeats, so silence alone does not mean a dead DB: see `WriteState`.
    let writing = Arc::new(WriteState::default());
    {
        let mut st = sh.lock();
        st.community = welcome.community.clone();
        st.skew_enabled =
            sh.cfg.skew_correction && (db_host.is_empty() || db_host != crate::time::hostname());
        st.skew = if st.skew_enabled { welcome.dval } else { 0.0 };
        st.db_host = db_host;
        st.connected = true;
        st.connects += 1;
        st.out.clear();
        st.out_count = 0;
        st.outgoing_delay = 0.0;
        // Re-issue every subscription.
        let now = sh.local_time() + st.skew;
        let regs: Vec<(String, f64)> = st.regs.iter().map(|(k, v)| (k.clone(), *v)).collect();
        for (k, iv) in regs {
            let m = Message {
                msg_type: MsgType::REGISTER,
                data_type: DataType::DOUBLE,
                key: k,
                time: now,
                dval: iv,
                ..Message::default()
            };
            sh.enqueue(&mut st, m);
        }
        for (v, a, iv) in st.wilds.clone() {
            let m = Message {
                msg_type: MsgType::WILDCARD_REGISTER,
                data_type: DataType::STRING,
                key: sh.cfg.name.clone(),
                time: now,
                sval: wildcard_payload(&a, &v, iv),
                ..Message::default()
            };
            sh.enqueue(&mut st, m);
        }
        sh.mail_cv.notify_all();
    }
    tracing::info!(client = %sh.cfg.name, community = %welcome.community, "connected to the DB");
    let (sh2, d2, w2) = (sh.clone(), dead.clone(), writing.clone());
    let reader = std::thread::Builder::new()
        .name(format!("moos-client-rd-{}", sh.cfg.name))
        .spawn(move || read_loop(sh2, rstream, fr, d2, w2));
    if reader.is_ok() {
        write_loop(sh, wstream, &dead, &writing);
    }
    if let Ok(h) = &reader {
        if !dead.load(Ordering::SeqCst) {
            // Closing with unread data in the socket makes the kernel reset the
            // connection and discard what the DB has not read yet (it may be holding this
            // publisher back). So: end our side, and read until the DB, having processed
            // everything, closes too; for at most LINGER.
            let _ = stream.shutdown(Shutdown::Write);
            let deadline = Instant::now() + LINGER;
            while !h.is_finished() && Instant::now() < deadline {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
    }
    dead.store(true, Ordering::SeqCst);
    let _ = stream.shutdown(Shutdown::Both);
    if let Ok(h) = reader {
        let _ = h.join();
    }
    let mut st = sh.lock();
    st.connected = false;
    st.out.clear();
    st.out_count = 0;
    sh.mail_cv.notify_all();
    tracing::info!(client = %sh.cfg.name, "disconnected from the DB");
    if sh.stop.load(Ordering::SeqCst) {
        End::Final
    } else {
        End::Lost
    }
}

/// How long a closing client waits for the DB to take what it sent.
const LINGER: Duration = Duration::from_secs(2);

/// How long a write may make no progress before the DB is taken for dead.
const HELD_LIMIT: Duration = Duration::from_secs(60);

/// Milliseconds of the system clock, never 0.
fn epoch_ms() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(1, |d| d.as_millis() as u64)
        .max(1)
}

/// What the reader needs to know of the writer to tell a DB that holds us back from a
/// dead one.
#[derive(Default)]
struct WriteState {
    /// While the writer is inside a write: the time (ms, see `epoch_ms`) of its last
    /// progress; 0 when it is not writing. The writer itself judges a write that makes
    /// no progress (HELD_LIMIT).
    in_write: AtomicU64,
    /// When a write that had to wait for room in the socket (the DB was not reading us)
    /// last went through (the DB took bytes again: held back, not dead); 0 never. After
    /// the writes end, what they queued can still wait behind the DB's flow control with
    /// nothing coming back for longer than the silence timeout: for HELD_LIMIT after
    /// such a write, silence is not death. (A frozen DB takes nothing: no such write.)
    held_at: AtomicU64,
}

/// A write call that took this long waited for room in the socket.
const WAITED: Duration = Duration::from_millis(20);

/// `write_all` that records its progress in `w` (see `WriteState`).
fn write_tracked(stream: &mut TcpStream, mut buf: &[u8], w: &WriteState) -> std::io::Result<()> {
    let writing = &w.in_write;
    writing.store(epoch_ms(), Ordering::SeqCst);
    let r = loop {
        if buf.is_empty() {
            break Ok(());
        }
        let t = Instant::now();
        match stream.write(buf) {
            Ok(0) => break Err(std::io::Error::from(ErrorKind::WriteZero)),
            Ok(n) => {
                if t.elapsed() >= WAITED {
                    w.held_at.store(epoch_ms(), Ordering::SeqCst);
                }
                buf = &buf[n..];
                writing.store(epoch_ms(), Ordering::SeqCst);
            }
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            // A DB applying flow control may hold this publisher for a while (slow
            // subscribers drain slowly on a loaded machine): keep waiting while the hold
            // is shorter than HELD_LIMIT; only then is the DB taken for dead.
            Err(e)
                if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut)
                    && epoch_ms().saturating_sub(writing.load(Ordering::SeqCst))
                        < HELD_LIMIT.as_millis() as u64 => {}
            Err(e) => break Err(e),
        }
    };
    writing.store(0, Ordering::SeqCst);
    r
}

fn write_loop(sh: &Shared, mut stream: TcpStream, dead: &AtomicBool, writing: &WriteState) {
    let _ = stream.set_write_timeout(Some(sh.cfg.send_timeout));
    let wait = Duration::from_millis(333);
    let mut last_t: Option<Instant> = None;
    let mut batch: Vec<u8> = Vec::new();
    let mut body: Vec<u8> = Vec::new();
    let warp = sh.cfg.time_warp;
    loop {
        let (count, delay) = {
            let mut st = sh.lock();
            let deadline = Instant::now() + wait;
            while st.out_count == 0
                && !dead.load(Ordering::SeqCst)
                && !sh.stop.load(Ordering::SeqCst)
            {
                let t_due = last_t.is_none_or(|t| t.elapsed() >= sh.cfg.heartbeat);
                let Some(left) = deadline.checked_duration_since(Instant::now()) else {
                    break;
                };
                if t_due {
                    break;
                }
                st = sh
                    .out_cv
                    .wait_timeout(st, left)
                    .unwrap_or_else(|p| p.into_inner())
                    .0;
            }
            // On stop, what was posted before still goes out.
            if dead.load(Ordering::SeqCst) || (sh.stop.load(Ordering::SeqCst) && st.out_count == 0)
            {
                return;
            }
            body.clear();
            std::mem::swap(&mut body, &mut st.out);
            let n = st.out_count;
            st.out_count = 0;
            (n, st.outgoing_delay)
        };
        let t_due = last_t.is_none_or(|t| t.elapsed() >= sh.cfg.heartbeat);
        if count == 0 && !t_due {
            continue;
        }
        batch.clear();
        let mut p = PacketBuilder::new(&mut batch);
        if t_due {
            let t = Message {
                msg_type: MsgType::TIMING,
                data_type: DataType::DOUBLE,
                key: wire::TIMING_KEY.into(),
                time: sh.local_time(),
                dval: 0.0,
                ..Message::default()
            };
            let _ = p.push(&t);
            last_t = Some(Instant::now());
        }
        // Split big batches into packets of about MAX_OUT_PACKET bytes at message
        // boundaries, so no single packet floods the DB's per-subscriber queues.
        let mut pos = 0;
        while pos < body.len() {
            let (end, n) = chunk_end(&body, pos, MAX_OUT_PACKET);
            p.push_encoded(&body[pos..end], n);
            pos = end;
            if pos < body.len() {
                let _ = p.finish();
                p = PacketBuilder::new(&mut batch);
            }
        }
        let _ = p.finish();
        if let Err(e) = write_tracked(&mut stream, &batch, writing) {
            tracing::warn!(client = %sh.cfg.name, "write to the DB failed, dropping the connection: {e}");
            dead.store(true, Ordering::SeqCst);
            return;
        }
        let w = if warp > 1.0 { warp * 0.2 / 1000.0 } else { 0.0 };
        let sleep = delay.max(w);
        if sleep > 0.0 && sleep.is_finite() {
            std::thread::sleep(Duration::from_secs_f64(sleep.min(1.0)));
        }
    }
}

/// Largest packet the client builds from queued posts (one bigger message still goes alone).
const MAX_OUT_PACKET: usize = 128 * 1024;

/// End offset and message count of the run of encoded messages starting at `pos` that
/// fits in `max` bytes (at least one message).
fn chunk_end(body: &[u8], pos: usize, max: usize) -> (usize, usize) {
    let mut end = pos;
    let mut n = 0;
    while end + 4 <= body.len() {
        let len = i32::from_le_bytes([body[end], body[end + 1], body[end + 2], body[end + 3]]);
        let len = usize::try_from(len).unwrap_or(0).max(1);
        if n > 0 && end + len - pos > max {
            break;
        }
        end = (end + len).min(body.len());
        n += 1;
    }
    (end, n)
}

fn read_loop(
    sh: Arc<Shared>,
    mut stream: TcpStream,
    mut fr: FrameReader,
    dead: Arc<AtomicBool>,
    writing: Arc<WriteState>,
) {
    let _ = stream.set_read_timeout(Some(Duration::from_millis(250)));
    let mut last_rx = Instant::now();
    loop {
        loop {
            let msgs = match fr.next_frame() {
                Ok(Some(r)) => match wire::decode_packet_lenient(fr.frame(r), usize::MAX) {
                    Ok((m, err)) => {
                        if let Some(e) = err {
                            tracing::warn!("malformed message from DB dropped: {e}");
                        }
                        m
                    }
                    Err(e) => {
                        tracing::warn!(client = %sh.cfg.name, "malformed packet from DB, dropping the connection: {e}");
                        return finish(&sh, &dead);
                    }
                },
                Ok(None) => break,
                Err(e) => {
                    tracing::warn!(client = %sh.cfg.name, "bad packet from DB, dropping the connection: {e}");
                    return finish(&sh, &dead);
                }
            };
            if deliver(&sh, msgs) {
                if let Some(cb) = &sh.on_mail {
                    cb();
                }
            }
        }
        if wait_for_room(&sh, &dead) {
            // We chose not to read: that silence is ours, not the DB's.
            last_rx = Instant::now();
        }
        // Not on `stop`: a closing client reads until the DB closes (see LINGER).
        if dead.load(Ordering::SeqCst) {
            return finish(&sh, &dead);
        }
        match fr.fill(&mut stream) {
            Ok(0) => return finish(&sh, &dead),
            Ok(_) => last_rx = Instant::now(),
            Err(e)
                if matches!(
                    e.kind(),
                    ErrorKind::WouldBlock | ErrorKind::TimedOut | ErrorKind::Interrupted
                ) =>
            {
                // While a write is under way the DB may be holding us back (it reads
                // neither our data nor our heartbeats): the writer judges that case.
                // Soon after a write had to wait, the bytes it queued may still be held.
                let writing_now = writing.in_write.load(Ordering::SeqCst) != 0;
                let held = writing.held_at.load(Ordering::SeqCst);
                let limit = if held != 0
                    && epoch_ms().saturating_sub(held) < HELD_LIMIT.as_millis() as u64
                {
                    HELD_LIMIT.max(sh.cfg.silence_timeout)
                } else {
                    sh.cfg.silence_timeout
                };
                if last_rx.elapsed() > limit && !writing_now {
                    tracing::warn!(
                        client = %sh.cfg.name,
                        pending = fr.pending(),
                        "nothing from the DB for {:?}: dropping the connection",
                        limit
                    );
                    return finish(&sh, &dead);
                }
            }
            Err(_) => return finish(&sh, &dead),
        }
    }
}

/// While the inbox is over its cap, read nothing (TCP then holds the DB back) until the
/// application fetches, the connection dies or the client stops. True if it waited.
fn wait_for_room(sh: &Shared, dead: &AtomicBool) -> bool {
    let mut st = sh.lock();
    if st.inbox_bytes <= sh.cfg.max_inbox_bytes {
        return false;
    }
    tracing::debug!(client = %sh.cfg.name, bytes = st.inbox_bytes, "inbox full: not reading until mail is fetched");
    while st.inbox_bytes > sh.cfg.max_inbox_bytes / 2
        && !dead.load(Ordering::SeqCst)
        && !sh.stop.load(Ordering::SeqCst)
    {
        st = sh
            .room_cv
            .wait_timeout(st, Duration::from_millis(250))
            .unwrap_or_else(|p| p.into_inner())
            .0;
    }
    true
}

/// About what a message costs in the inbox.
fn inbox_cost(m: &Message) -> usize {
    std::mem::size_of::<Message>()
        + m.key.len()
        + m.sval.len()
        + m.source.len()
        + m.source_aux.len()
        + m.community.len()
}

fn finish(sh: &Shared, dead: &AtomicBool) {
    dead.store(true, Ordering::SeqCst);
    let _g = sh.lock();
    sh.out_cv.notify_all();
}

/// Spec §5.2: timing echo handling, then hand the mail over. True if there was mail.
fn deliver(sh: &Shared, mut msgs: Vec<Message>) -> bool {
    if msgs.is_empty() {
        return false;
    }
    let tr = sh.local_time();
    let mut st = sh.lock();
    st.packets_received += 1;
    let first = msgs[0].msg_type;
    if first == MsgType::TIMING {
        let t = msgs.remove(0);
        if st.skew_enabled && st.packets_received > 1 {
            let measured = t.dval - (t.time + tr) / 2.0;
            if measured.is_finite() {
                st.skew = if st.skew == 0.0 {
                    measured
                } else {
                    0.9 * st.skew + 0.1 * measured
                };
            }
        }
        if t.dval2.is_finite() && t.dval2 >= 0.0 {
            st.outgoing_delay = t.dval2;
        }
    }
    msgs.retain(|m| m.msg_type != MsgType::NULL);
    if msgs.is_empty() {
        return false;
    }
    st.inbox_bytes += msgs.iter().map(inbox_cost).sum::<usize>();
    // Waiters only sleep on an empty inbox, so only that transition needs a wake-up.
    if st.inbox.is_empty() {
        st.inbox = msgs;
        sh.mail_cv.notify_all();
    } else {
        st.inbox.append(&mut msgs);
    }
    true
}
