//! An asynchronous MOOS V10 client (spec §4.2, §5.1, §5.2, §6).
//!
//! A background thread connects, handshakes, sends a `T` heartbeat at least once a
//! second, batches posts into packets, applies the skew filter, and reconnects with
//! back-off, re-registering every subscription when the DB comes back. The application
//! drives it from its iterate loop:
//!
//! ```no_run
//! use moos::client::{Client, ClientConfig};
//! let c = Client::connect(ClientConfig::new("localhost", 9000, "pMyApp")).unwrap();
//! c.register("NAV_X", 0.0).unwrap();
//! c.notify_double("DESIRED_SPEED", 2.0, None).unwrap();
//! let mut mail = Vec::new();
//! c.fetch(&mut mail);
//! ```

mod session;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use thiserror::Error;

use crate::text::format_g;
use crate::wire::{DataType, Message, MsgType};

/// Client settings.
#[derive(Clone, Debug)]
pub struct ClientConfig {
    /// DB host name or address (`LOCALHOST` works).
    pub host: String,
    pub port: u16,
    /// The name this client uses with the DB (must be unique there).
    pub name: String,
    /// Time-warp factor; must match the DB's.
    pub time_warp: f64,
    /// Apply the welcome skew and the timing-echo skew filter. As the C++ client does
    /// when not quiet, correction is turned off when the DB reports our own host name.
    pub skew_correction: bool,
    /// First reconnect delay; doubles up to `reconnect_max`.
    pub reconnect_min: Duration,
    pub reconnect_max: Duration,
    /// How long [`Client::connect`] waits for the first handshake.
    pub connect_timeout: Duration,
    /// Real-time period of the `T` heartbeat.
    pub heartbeat: Duration,
    /// Largest packet accepted from the DB.
    pub max_packet: usize,
    /// Drop the connection (and reconnect) when nothing arrives from the DB for this
    /// long, real time. A live DB answers every `T` heartbeat with an echo, so silence
    /// means a hung DB or a peer that stopped mid-packet; the C++ client would wait on
    /// it forever (spec §5.6), a helm at sea must not.
    pub silence_timeout: Duration,
    /// A write to the DB that blocks longer than this fails and drops the connection
    /// (so a stalled DB cannot make queued posts pile up without bound).
    pub send_timeout: Duration,
    /// Mail held for the application, at most (bytes, about): past it the client stops
    /// reading from the DB until [`Client::fetch`] makes room, so the DB's flow control
    /// holds the publishers back instead of this process growing without bound.
    pub max_inbox_bytes: usize,
}

impl ClientConfig {
    pub fn new(host: &str, port: u16, name: &str) -> ClientConfig {
        ClientConfig {
            host: host.to_owned(),
            port,
            name: name.to_owned(),
            time_warp: 1.0,
            skew_correction: true,
            reconnect_min: Duration::from_millis(100),
            reconnect_max: Duration::from_secs(2),
            connect_timeout: Duration::from_secs(5),
            heartbeat: Duration::from_secs(1),
            max_packet: crate::wire::DEFAULT_MAX_PACKET,
            silence_timeout: Duration::from_secs(5),
            send_timeout: Duration::from_secs(6),
            max_inbox_bytes: 64 << 20,
        }
    }
}

/// Client failures.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ClientError {
    /// The DB refused the handshake (for example a duplicate name). Final.
    #[error("the DB refused the connection: {0}")]
    Poisoned(String),
    #[error("not connected to the DB")]
    NotConnected,
    #[error("no connection to the DB within {0:?}")]
    Timeout(Duration),
    #[error("invalid argument: {0}")]
    BadArgument(String),
    #[error("client is shut down")]
    Closed,
}

pub(crate) struct St {
    pub connected: bool,
    pub poisoned: Option<String>,
    pub connects: u64,
    pub out: Vec<u8>,
    pub out_count: usize,
    pub inbox: Vec<Message>,
    /// About how many bytes `inbox` holds (see `ClientConfig::max_inbox_bytes`).
    pub inbox_bytes: usize,
    pub regs: BTreeMap<String, f64>,
    pub wilds: Vec<(String, String, f64)>,
    pub next_id: i32,
    pub skew: f64,
    pub skew_enabled: bool,
    pub outgoing_delay: f64,
    pub community: String,
    pub db_host: String,
    pub packets_received: u64,
}

/// Called on the client's reader thread each time mail arrives (libMOOS's on-mail
/// callback). While it runs, the client reads nothing more from the DB.
pub type MailCallback = Box<dyn Fn() + Send + Sync>;

pub(crate) struct Shared {
    pub cfg: ClientConfig,
    pub on_mail: Option<MailCallback>,
    pub st: Mutex<St>,
    /// Signals the writer: posts queued, connection lost, stop.
    pub out_cv: Condvar,
    /// Signals mail or connection changes to the application.
    pub mail_cv: Condvar,
    /// Signals the reader: the application fetched (room in the inbox), or stop.
    pub room_cv: Condvar,
    pub stop: AtomicBool,
}

impl Shared {
    pub fn lock(&self) -> MutexGuard<'_, St> {
        self.st.lock().unwrap_or_else(|p| p.into_inner())
    }
    pub fn local_time(&self) -> f64 {
        crate::time::local_time(self.cfg.time_warp)
    }

    /// Queue a message (id and source set here). Caller holds the lock.
    pub fn enqueue(&self, st: &mut St, mut m: Message) {
        if m.msg_type == MsgType::SERVER_REQUEST {
            m.id = -2;
        } else {
            m.id = st.next_id;
            st.next_id = st.next_id.wrapping_add(1);
        }
        m.source.clone_from(&self.cfg.name);
        m.community.clear();
        if m.encode_into(&mut st.out).is_ok() {
            st.out_count += 1;
            if st.out_count == 1 {
                self.out_cv.notify_all();
            }
        }
    }
}

/// A MOOS client. Dropping it disconnects.
pub struct Client {
    shared: Arc<Shared>,
    io: Option<JoinHandle<()>>,
}

fn wildcard_payload(app: &str, var: &str, interval: f64) -> Vec<u8> {
    format!(
        "AppPattern={app},VarPattern={var},Interval={}",
        format_g(interval)
    )
    .into_bytes()
}

impl Client {
    /// Start the client in the background without waiting for the DB.
    pub fn start(cfg: ClientConfig) -> Result<Client, ClientError> {
        Client::start_inner(cfg, None)
    }

    /// [`Client::connect`], calling `on_mail` on the reader thread whenever mail arrives
    /// (it typically calls [`Client::fetch`] through a handle it shares). The client can
    /// only close once the callback has returned.
    pub fn connect_with_mail_callback(
        cfg: ClientConfig,
        on_mail: MailCallback,
    ) -> Result<Client, ClientError> {
        let t = cfg.connect_timeout;
        let c = Client::start_inner(cfg, Some(on_mail))?;
        c.wait_connected(t)?;
        Ok(c)
    }

    fn start_inner(
        cfg: ClientConfig,
        on_mail: Option<MailCallback>,
    ) -> Result<Client, ClientError> {
        if cfg.name.is_empty() {
            return Err(ClientError::BadArgument("empty client name".into()));
        }
        if !crate::time::warp_ok(cfg.time_warp) {
            return Err(ClientError::BadArgument(format!(
                "time warp {} (must be 0 < warp <= 400)",
                cfg.time_warp
            )));
        }
        let shared = Arc::new(Shared {
            cfg,
            on_mail,
            st: Mutex::new(St {
                connected: false,
                poisoned: None,
                connects: 0,
                out: Vec::new(),
                out_count: 0,
                inbox: Vec::new(),
                inbox_bytes: 0,
                regs: BTreeMap::new(),
                wilds: Vec::new(),
                next_id: 0,
                skew: 0.0,
                skew_enabled: true,
                outgoing_delay: 0.0,
                community: String::new(),
                db_host: String::new(),
                packets_received: 0,
            }),
            out_cv: Condvar::new(),
            mail_cv: Condvar::new(),
            room_cv: Condvar::new(),
            stop: AtomicBool::new(false),
        });
        let s2 = shared.clone();
        let io = std::thread::Builder::new()
            .name(format!("moos-client-{}", shared.cfg.name))
            .spawn(move || session::run(s2))
            .map_err(|e| ClientError::BadArgument(format!("cannot spawn thread: {e}")))?;
        Ok(Client {
            shared,
            io: Some(io),
        })
    }

    /// Start and wait (up to `cfg.connect_timeout`) for the first successful handshake.
    pub fn connect(cfg: ClientConfig) -> Result<Client, ClientError> {
        let t = cfg.connect_timeout;
        let c = Client::start(cfg)?;
        c.wait_connected(t)?;
        Ok(c)
    }

    /// Wait until connected; fails at once if the DB poisoned us.
    pub fn wait_connected(&self, timeout: Duration) -> Result<(), ClientError> {
        let deadline = Instant::now() + timeout;
        let mut st = self.shared.lock();
        loop {
            if let Some(p) = &st.poisoned {
                return Err(ClientError::Poisoned(p.clone()));
            }
            if st.connected {
                return Ok(());
            }
            let Some(left) = deadline.checked_duration_since(Instant::now()) else {
                return Err(ClientError::Timeout(timeout));
            };
            st = self
                .shared
                .mail_cv
                .wait_timeout(st, left)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
    }

    pub fn name(&self) -> &str {
        &self.shared.cfg.name
    }
    pub fn is_connected(&self) -> bool {
        self.shared.lock().connected
    }
    /// Number of successful handshakes so far (reconnects included).
    pub fn connection_count(&self) -> u64 {
        self.shared.lock().connects
    }
    /// Community learnt from the welcome.
    pub fn community(&self) -> String {
        self.shared.lock().community.clone()
    }
    /// Current skew estimate (s).
    pub fn skew(&self) -> f64 {
        self.shared.lock().skew
    }
    /// MOOSTime: wall × warp + skew.
    pub fn moos_time(&self) -> f64 {
        let skew = self.shared.lock().skew;
        self.shared.local_time() + skew
    }

    /// Post any message (source and id are filled in). Fails when not connected: like
    /// the C++ client, nothing is buffered across disconnections.
    pub fn post(&self, m: Message) -> Result<(), ClientError> {
        let mut st = self.shared.lock();
        if !st.connected {
            return Err(ClientError::NotConnected);
        }
        self.shared.enqueue(&mut st, m);
        Ok(())
    }

    fn time_or_now(&self, t: Option<f64>) -> f64 {
        t.unwrap_or_else(|| self.moos_time())
    }

    pub fn notify_double(&self, var: &str, val: f64, time: Option<f64>) -> Result<(), ClientError> {
        self.post(Message::notify_double(var, val, self.time_or_now(time)))
    }
    pub fn notify_string(
        &self,
        var: &str,
        val: &str,
        time: Option<f64>,
    ) -> Result<(), ClientError> {
        self.post(Message::notify_string(var, val, self.time_or_now(time)))
    }
    /// Binary notification; an empty payload is refused (as in C++).
    pub fn notify_binary(
        &self,
        var: &str,
        val: &[u8],
        time: Option<f64>,
    ) -> Result<(), ClientError> {
        if val.is_empty() {
            return Err(ClientError::BadArgument("empty binary payload".into()));
        }
        self.post(Message::notify_binary(var, val, self.time_or_now(time)))
    }
    /// Notification with `source_aux` set.
    pub fn notify_with_aux(&self, mut m: Message, source_aux: &str) -> Result<(), ClientError> {
        m.source_aux = source_aux.to_owned();
        self.post(m)
    }

    fn control(
        &self,
        msg_type: MsgType,
        data_type: DataType,
        key: &str,
        dval: f64,
        sval: Vec<u8>,
    ) -> Message {
        Message {
            msg_type,
            data_type,
            key: key.to_owned(),
            time: self.moos_time(),
            dval,
            sval,
            ..Message::default()
        }
    }

    /// Subscribe to `var`, at most one delivery per `interval` s of MOOS time (0 = every
    /// write). Remembered and re-sent after every reconnect.
    pub fn register(&self, var: &str, interval: f64) -> Result<(), ClientError> {
        if var.is_empty() {
            return Err(ClientError::BadArgument("empty variable name".into()));
        }
        let m = self.control(
            MsgType::REGISTER,
            DataType::DOUBLE,
            var,
            interval,
            Vec::new(),
        );
        let mut st = self.shared.lock();
        st.regs.insert(var.to_owned(), interval);
        if st.connected {
            self.shared.enqueue(&mut st, m);
        }
        Ok(())
    }

    /// Unsubscribe from `var`.
    pub fn unregister(&self, var: &str) -> Result<(), ClientError> {
        let m = self.control(MsgType::UNREGISTER, DataType::DOUBLE, var, 0.0, Vec::new());
        let mut st = self.shared.lock();
        if st.regs.remove(var).is_some() && st.connected {
            self.shared.enqueue(&mut st, m);
        }
        Ok(())
    }

    /// Wildcard subscription (`*` and `?` in both patterns; no commas).
    pub fn register_wildcard(
        &self,
        var_pat: &str,
        app_pat: &str,
        interval: f64,
    ) -> Result<(), ClientError> {
        check_patterns(var_pat, app_pat)?;
        let name = self.shared.cfg.name.clone();
        let m = self.control(
            MsgType::WILDCARD_REGISTER,
            DataType::STRING,
            &name,
            -1.0,
            wildcard_payload(app_pat, var_pat, interval),
        );
        let mut st = self.shared.lock();
        st.wilds.retain(|(v, a, _)| !(v == var_pat && a == app_pat));
        st.wilds
            .push((var_pat.to_owned(), app_pat.to_owned(), interval));
        if st.connected {
            self.shared.enqueue(&mut st, m);
        }
        Ok(())
    }

    /// Wildcard unsubscription (the DB keeps the filter for future variables).
    pub fn unregister_wildcard(&self, var_pat: &str, app_pat: &str) -> Result<(), ClientError> {
        check_patterns(var_pat, app_pat)?;
        let name = self.shared.cfg.name.clone();
        let m = self.control(
            MsgType::WILDCARD_UNREGISTER,
            DataType::STRING,
            &name,
            -1.0,
            wildcard_payload(app_pat, var_pat, 0.0),
        );
        let mut st = self.shared.lock();
        st.wilds.retain(|(v, a, _)| !(v == var_pat && a == app_pat));
        if st.connected {
            self.shared.enqueue(&mut st, m);
        }
        Ok(())
    }

    /// Send a server request (`ALL`, `VAR_SUMMARY`, `PROC_SUMMARY`, `DB_CLEAR`); replies
    /// arrive as mail with id -2.
    pub fn server_request(&self, what: &str) -> Result<(), ClientError> {
        let m = self.control(
            MsgType::SERVER_REQUEST,
            DataType::STRING,
            what,
            -1.0,
            Vec::new(),
        );
        self.post(m)
    }

    /// Bytes of posts not yet handed to the socket (a publisher that must not outrun
    /// the DB can wait while this is large).
    pub fn unsent_bytes(&self) -> usize {
        self.shared.lock().out.len()
    }

    /// About how many bytes of received mail wait for [`Client::fetch`] (bounded by
    /// `ClientConfig::max_inbox_bytes` plus one read).
    pub fn pending_mail_bytes(&self) -> usize {
        self.shared.lock().inbox_bytes
    }

    /// Move all received mail, in arrival order, to the end of `out`. Returns how many.
    pub fn fetch(&self, out: &mut Vec<Message>) -> usize {
        let mut st = self.shared.lock();
        let n = st.inbox.len();
        if out.is_empty() {
            std::mem::swap(out, &mut st.inbox);
        } else {
            out.append(&mut st.inbox);
        }
        st.inbox_bytes = 0;
        self.shared.room_cv.notify_all();
        n
    }

    /// Wait up to `timeout` for mail; true if there is some.
    pub fn wait_for_mail(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        let mut st = self.shared.lock();
        while st.inbox.is_empty() {
            let Some(left) = deadline.checked_duration_since(Instant::now()) else {
                return false;
            };
            st = self
                .shared
                .mail_cv
                .wait_timeout(st, left)
                .unwrap_or_else(|p| p.into_inner())
                .0;
        }
        true
    }

    /// Stop the background thread and close the connection.
    pub fn close(mut self) {
        self.stop();
    }

    fn stop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        self.shared.out_cv.notify_all();
        self.shared.room_cv.notify_all();
        if let Some(h) = self.io.take() {
            let _ = h.join();
        }
    }
}

impl Drop for Client {
    fn drop(&mut self) {
        self.stop();
    }
}

fn check_patterns(var: &str, app: &str) -> Result<(), ClientError> {
    if var.is_empty() || app.is_empty() || var.contains(',') || app.contains(',') {
        return Err(ClientError::BadArgument(format!(
            "bad wildcard patterns {var:?} / {app:?}"
        )));
    }
    Ok(())
}
