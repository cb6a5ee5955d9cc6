//! Helpers shared by the overload tests: the real `moosdb` as a child process, flooding
//! publishers, checking subscribers and a `DB_EVENT` watcher.
#![allow(dead_code)] // each test file uses its own part

use std::io::{BufRead, BufReader};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use moos::client::{Client, ClientConfig};
use moos::wire::Message;

pub struct DbProc {
    pub child: Child,
    pub port: u16,
}

impl DbProc {
    /// `moosdb` on an ephemeral port of 127.0.0.1, with `args` besides.
    pub fn start(args: &[String]) -> DbProc {
        let mut child = Command::new(env!("CARGO_BIN_EXE_moosdb"))
            .args(["--moos_port=0", "--bind=127.0.0.1"])
            .args(args)
            .env(
                "RUST_LOG",
                std::env::var("MOOSDB_LOG").unwrap_or_else(|_| "warn".into()),
            )
            .stdout(Stdio::piped())
            .spawn()
            .expect("start moosdb");
        let port = read_port(child.stdout.take().expect("stdout"));
        DbProc { child, port }
    }

    /// `VmRSS` or `VmHWM` of the DB process, in bytes.
    pub fn mem(&self, field: &str) -> usize {
        proc_status(self.child.id(), field)
    }
}

impl Drop for DbProc {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The port from the DB's "listening on port N" line; any other line on its stdout is
/// passed on to stderr, so the pipe never fills or breaks.
/// The flood tests run one at a time: each saturates the machine on purpose, and two
/// at once on 2 cores measure the machine rather than the DB.
pub fn serial() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

pub fn read_port(out: ChildStdout) -> u16 {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines() {
            let Ok(line) = line else { break };
            if let Some(p) = line.strip_prefix("moosdb listening on port ") {
                let _ = tx.send(p.trim().parse::<u16>().ok());
            } else {
                eprintln!("moosdb: {line}");
            }
        }
    });
    rx.recv_timeout(Duration::from_secs(10))
        .ok()
        .flatten()
        .expect("moosdb did not report its port")
}

pub fn proc_status(pid: u32, field: &str) -> usize {
    let s = std::fs::read_to_string(format!("/proc/{pid}/status")).expect("status");
    let kb: usize = s
        .lines()
        .find_map(|l| l.strip_prefix(field)?.strip_prefix(':'))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or_else(|| panic!("no {field} in status"));
    kb * 1024
}

pub fn client(port: u16, name: &str) -> Client {
    Client::connect(ClientConfig::new("127.0.0.1", port, name)).expect("connect")
}

/// Publishers posting `<p>:<i>:<payload>` to `var` as fast as their connection takes it,
/// until `stop`. Each returns how many it posted, and its client, kept open until the
/// check: a client closing waits at most 2 s for the DB to take its last bytes, and the
/// DB may hold it back longer than that.
pub fn flooders(
    port: u16,
    n: usize,
    var: &str,
    stop: &Arc<AtomicBool>,
    payload: usize,
) -> Vec<JoinHandle<(usize, Client)>> {
    (0..n)
        .map(|p| {
            let c = client(port, &format!("flood{p}"));
            let (stop, var) = (stop.clone(), var.to_owned());
            std::thread::spawn(move || {
                let payload = "x".repeat(payload);
                let mut i = 0;
                while !stop.load(Ordering::Relaxed) {
                    // Keep the client's own backlog short: the socket (and so the DB's
                    // flow control) sets the pace.
                    if c.unsent_bytes() > 256 * 1024 {
                        std::thread::sleep(Duration::from_micros(300));
                        continue;
                    }
                    // Batches of about 20 KB, or one message if longer.
                    for _ in 0..(20_000 / payload.len().max(1)).clamp(1, 100) {
                        c.notify_string(&var, &format!("{p}:{i}:{payload}"), None)
                            .expect("post");
                        i += 1;
                    }
                }
                (i, c)
            })
        })
        .collect()
}

/// Memory the DB may use beyond its cap (`--max_queue_mb`), for up to 12 connections:
/// per connection a read buffer (a piece of 256 KiB and a read of 64 KiB) and two write
/// buffers kept for reuse (up to 1 MiB each, touched only as far as used); thread
/// stacks; the allocator's slack; a cut-off client's last chunk, freed by its writer
/// within a tick of the cut. Measured peaks were 6-20 MiB over the cap.
pub const OVERHEAD: usize = 24 << 20;

/// Inbox cap of the subscribers that must get everything (see [`Reader::with`]).
pub const READER_INBOX: usize = 1 << 30;

/// A subscriber that reads everything; a slow one's mail callback sleeps 0.3 ms per packet.
pub struct Reader {
    pub c: Client,
    pub next: Vec<usize>,
    pub got: usize,
}

impl Reader {
    pub fn new(port: u16, name: &str, vars: &[&str], publishers: usize) -> Reader {
        Reader::with(port, name, vars, publishers, true)
    }

    pub fn with(port: u16, name: &str, vars: &[&str], publishers: usize, slow: bool) -> Reader {
        let mut cfg = ClientConfig::new("127.0.0.1", port, name);
        // This test's own checking (a debug build) is slower than the flood: with the
        // default inbox cap the client would stop reading until the next fetch, and a
        // subscriber that reads nothing for the DB's hold limit is a stalled one (its
        // queue no longer holds the publishers back, and it is cut off at the cap).
        // These readers are slow, not stalled.
        cfg.max_inbox_bytes = READER_INBOX;
        let c = if slow {
            Client::connect_with_mail_callback(
                cfg,
                Box::new(|| std::thread::sleep(Duration::from_micros(300))),
            )
        } else {
            Client::connect(cfg)
        }
        .expect("connect");
        for v in vars {
            c.register(v, 0.0).expect("register");
        }
        Reader {
            c,
            next: vec![0; publishers],
            got: 0,
        }
    }

    /// Fetch and check order; returns the non-flood mail.
    pub fn drain(&mut self, flood_var: &str) -> Vec<Message> {
        let mut mail = Vec::new();
        self.c.wait_for_mail(Duration::from_millis(20));
        self.c.fetch(&mut mail);
        let mut other = Vec::new();
        for m in mail {
            if m.key != flood_var {
                other.push(m);
                continue;
            }
            let s = m.string();
            let mut it = s.splitn(3, ':');
            let p: usize = it.next().and_then(|x| x.parse().ok()).expect("publisher");
            let i: usize = it.next().and_then(|x| x.parse().ok()).expect("index");
            assert_eq!(
                i, self.next[p],
                "publisher {p}: message lost or out of order"
            );
            self.next[p] += 1;
            self.got += 1;
        }
        other
    }
}

/// DB_EVENT values seen by a dedicated watcher, with when they arrived.
pub struct Events {
    seen: Arc<Mutex<Vec<(Instant, String)>>>,
    stop: Arc<AtomicBool>,
    h: Option<JoinHandle<()>>,
}

impl Events {
    pub fn watch(port: u16) -> Events {
        let c = client(port, "watcher");
        c.register("DB_EVENT", 0.0).expect("register");
        let seen = Arc::new(Mutex::new(Vec::new()));
        let stop = Arc::new(AtomicBool::new(false));
        let (s2, st2) = (seen.clone(), stop.clone());
        let h = std::thread::spawn(move || {
            let mut mail = Vec::new();
            while !st2.load(Ordering::Relaxed) {
                c.wait_for_mail(Duration::from_millis(20));
                mail.clear();
                c.fetch(&mut mail);
                let now = Instant::now();
                let mut s = s2.lock().expect("events");
                s.extend(
                    mail.iter()
                        .filter(|m| m.key == "DB_EVENT")
                        .map(|m| (now, m.string().into_owned())),
                );
            }
        });
        Events {
            seen,
            stop,
            h: Some(h),
        }
    }

    pub fn first(&self, pred: impl Fn(&str) -> bool) -> Option<(Instant, String)> {
        let s = self.seen.lock().expect("events");
        s.iter().find(|(_, e)| pred(e)).cloned()
    }

    pub fn all(&self) -> Vec<String> {
        let s = self.seen.lock().expect("events");
        s.iter().map(|(_, e)| e.clone()).collect()
    }
}

impl Drop for Events {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.h.take() {
            let _ = h.join();
        }
    }
}
