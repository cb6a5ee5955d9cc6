//! The HTTP side: tiny_http serves the page (compiled into the binary) and the replay
//! API, a thread per request. The live WebSocket has a listener of its own ([`crate::ws`],
//! tungstenite): a long-lived connection upgraded inside tiny_http holds one of its pool
//! threads, and its pool can leave connections that arrive together queued behind them.
//!
//! What the page may do is fixed here: read frames, and press one of the mission's own
//! buttons (`POST /api/button/N`). A button press must carry the `X-Helm-View` header,
//! which another site's page cannot send without a CORS preflight this server never
//! grants, and an `Origin` (when the browser sends one) of this very server; on a
//! loopback address the `Host` must be a loopback name, so a DNS-rebinding page gets
//! nothing either.

use std::io::Cursor;
use std::net::SocketAddr;
use std::sync::Arc;
use std::thread::JoinHandle;

use serde_json::json;
use thiserror::Error;
use tiny_http::{Header, Method, Request, Response, StatusCode};

use crate::buttons::Button;
use crate::hosts::{host_name, loopback_host};
use crate::live::Hub;
use crate::runs::Runs;

const INDEX_HTML: &str = include_str!("../assets/index.html");
const APP_JS: &str = include_str!("../assets/app.js");
const STYLE_CSS: &str = include_str!("../assets/style.css");

#[derive(Debug, Error)]
pub enum ServerError {
    #[error("cannot serve on {addr}: {why}")]
    Bind { addr: SocketAddr, why: String },
}

/// What is being shown.
pub enum Mode {
    Replay(Runs),
    Live {
        hub: Arc<Hub>,
        client: Arc<moos::Client>,
        /// The DB's address, for the title.
        db: String,
    },
}

/// The served application.
pub struct App {
    pub mode: Mode,
    pub buttons: Vec<Button>,
    pub title: String,
}

/// A running server.
pub struct Serving {
    pub addr: SocketAddr,
    /// The live WebSocket's address (live only).
    pub ws_addr: Option<SocketAddr>,
    server: Arc<tiny_http::Server>,
    thread: Option<JoinHandle<()>>,
}

/// What every request handler knows of the server.
#[derive(Clone, Copy)]
struct Ctx {
    loopback: bool,
    ws_port: Option<u16>,
}

impl Serving {
    /// Serve until the process ends.
    pub fn join(mut self) {
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Serving {
    fn drop(&mut self) {
        self.server.unblock();
    }
}

/// Start serving `app` on `addr` (port 0: any free port; [`Serving::addr`] says which).
pub fn start(app: Arc<App>, addr: SocketAddr) -> Result<Serving, ServerError> {
    let server = tiny_http::Server::http(addr).map_err(|e| ServerError::Bind {
        addr,
        why: e.to_string(),
    })?;
    let bound = server
        .server_addr()
        .to_ip()
        .ok_or_else(|| ServerError::Bind {
            addr,
            why: "not an IP address".into(),
        })?;
    let ws_addr = match &app.mode {
        Mode::Live { hub, .. } => Some(
            crate::ws::start(hub.clone(), addr.ip(), bound.port()).map_err(|e| {
                ServerError::Bind {
                    addr,
                    why: format!("WebSocket listener: {e}"),
                }
            })?,
        ),
        Mode::Replay(_) => None,
    };
    let server = Arc::new(server);
    let srv = server.clone();
    let ctx = Ctx {
        loopback: bound.ip().is_loopback(),
        ws_port: ws_addr.map(|a| a.port()),
    };
    let thread = std::thread::Builder::new()
        .name("view-http".into())
        .spawn(move || {
            for rq in srv.incoming_requests() {
                let app = app.clone();
                let spawned = std::thread::Builder::new()
                    .name("view-request".into())
                    .spawn(move || handle(&app, rq, ctx));
                if let Err(e) = spawned {
                    tracing::warn!("cannot start a request thread: {e}");
                }
            }
        })
        .map_err(|e| ServerError::Bind {
            addr,
            why: e.to_string(),
        })?;
    Ok(Serving {
        addr: bound,
        ws_addr,
        server,
        thread: Some(thread),
    })
}

fn header(name: &str, value: &str) -> Option<Header> {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).ok()
}

fn request_header<'a>(rq: &'a Request, name: &str) -> Option<&'a str> {
    rq.headers()
        .iter()
        .find(|h| h.field.as_str().as_str().eq_ignore_ascii_case(name))
        .map(|h| h.value.as_str())
}

fn respond(rq: Request, status: u16, ctype: &str, body: Vec<u8>) {
    respond_with(rq, status, ctype, body, "");
}

/// A response; `connect` adds a source to the page's `connect-src` (the live socket).
fn respond_with(rq: Request, status: u16, ctype: &str, body: Vec<u8>, connect: &str) {
    let csp = format!(
        "default-src 'none'; script-src 'self'; style-src 'self'; connect-src 'self'{connect}; img-src 'self' data:; base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
    );
    let mut r = Response::new(
        StatusCode(status),
        Vec::new(),
        Cursor::new(body.clone()),
        Some(body.len()),
        None,
    );
    let headers = [
        ("Content-Type", ctype),
        ("Cache-Control", "no-store"),
        ("X-Content-Type-Options", "nosniff"),
        ("Referrer-Policy", "no-referrer"),
        // The page runs only its own script and talks only to this server.
        ("Content-Security-Policy", csp.as_str()),
    ];
    for (k, v) in headers {
        if let Some(h) = header(k, v) {
            r.add_header(h);
        }
    }
    if let Err(e) = rq.respond(r) {
        tracing::debug!("response not delivered: {e}");
    }
}

fn respond_json(rq: Request, status: u16, v: &impl serde::Serialize) {
    let body = serde_json::to_vec(v).unwrap_or_default();
    respond(rq, status, "application/json", body);
}

fn query(url: &str) -> impl Iterator<Item = (&str, &str)> {
    url.split_once('?')
        .map_or("", |(_, q)| q)
        .split('&')
        .filter_map(|kv| kv.split_once('='))
}

fn handle(app: &App, rq: Request, ctx: Ctx) {
    let host = request_header(&rq, "Host").unwrap_or("").to_owned();
    if ctx.loopback && !loopback_host(&host) {
        return respond(rq, 403, "text/plain", b"forbidden host".to_vec());
    }
    let url = rq.url().to_owned();
    let path = url.split('?').next().unwrap_or("");
    match (rq.method(), path) {
        (Method::Get, "/") => {
            // The live page may also open its WebSocket, on the same host name.
            let connect = ctx.ws_port.map_or(String::new(), |p| {
                let h = host_name(&host);
                let h = if h.contains(':') {
                    format!("[{h}]")
                } else {
                    h.to_owned()
                };
                format!(" ws://{h}:{p}")
            });
            respond_with(
                rq,
                200,
                "text/html; charset=utf-8",
                INDEX_HTML.into(),
                &connect,
            )
        }
        (Method::Get, "/app.js") => {
            respond(rq, 200, "text/javascript; charset=utf-8", APP_JS.into())
        }
        (Method::Get, "/style.css") => {
            respond(rq, 200, "text/css; charset=utf-8", STYLE_CSS.into())
        }
        (Method::Get, "/api/info") => respond_json(rq, 200, &info(app, ctx.ws_port)),
        (Method::Get, "/api/frame") => frame(app, rq, &url),
        (Method::Get, "/api/tracks") => tracks(app, rq),
        (Method::Post, p) if p.starts_with("/api/button/") => press(app, rq, &host, p),
        _ => respond(rq, 404, "text/plain", b"not found".to_vec()),
    }
}

fn info(app: &App, ws_port: Option<u16>) -> serde_json::Value {
    let buttons: Vec<&str> = app.buttons.iter().map(|b| b.label.as_str()).collect();
    match &app.mode {
        Mode::Replay(r) => {
            let runs: Vec<serde_json::Value> = r
                .runs
                .iter()
                .map(|run| {
                    let logs: Vec<&str> = run.logs.iter().map(|l| l.name.as_str()).collect();
                    json!({
                        "name": run.name,
                        "t0": run.t0(),
                        "t1": run.t1(),
                        "lines": run.lines(),
                        "skipped": run.skipped_summary(),
                        "bounds": run.bounds(),
                        "logs": logs,
                        "vehicles": run.vehicle_names(),
                    })
                })
                .collect();
            json!({"mode": "replay", "title": app.title, "buttons": buttons, "runs": runs, "table": r.table})
        }
        Mode::Live { db, .. } => {
            json!({"mode": "live", "title": app.title, "buttons": buttons, "db": db, "ws_port": ws_port})
        }
    }
}

fn frame(app: &App, rq: Request, url: &str) {
    let Mode::Replay(r) = &app.mode else {
        return respond(
            rq,
            409,
            "text/plain",
            b"live: frames come by WebSocket".to_vec(),
        );
    };
    let (mut t, mut run) = (0.0, 0usize);
    for (k, v) in query(url) {
        match k {
            "t" => {
                t = v
                    .parse()
                    .ok()
                    .filter(|t: &f64| t.is_finite())
                    .unwrap_or(0.0)
            }
            "run" => run = v.parse().unwrap_or(usize::MAX),
            _ => {}
        }
    }
    match r.runs.get(run) {
        Some(run) => respond_json(rq, 200, &run.frame(t)),
        None => respond(rq, 404, "text/plain", b"no such run".to_vec()),
    }
}

/// Every run's tracks, thinned, for the overview of a folder of runs.
fn tracks(app: &App, rq: Request) {
    let Mode::Replay(r) = &app.mode else {
        return respond_json(rq, 200, &Vec::<()>::new());
    };
    let all: Vec<_> = r.runs.iter().map(|run| run.tracks(400)).collect();
    respond_json(rq, 200, &all)
}

fn press(app: &App, rq: Request, host: &str, path: &str) {
    let Mode::Live { client, .. } = &app.mode else {
        return respond(rq, 409, "text/plain", b"a replay posts nothing".to_vec());
    };
    if request_header(&rq, "X-Helm-View") != Some("1") {
        return respond(
            rq,
            403,
            "text/plain",
            b"missing X-Helm-View header".to_vec(),
        );
    }
    if let Some(origin) = request_header(&rq, "Origin") {
        if origin != format!("http://{host}") {
            return respond(rq, 403, "text/plain", b"foreign origin".to_vec());
        }
    }
    let Some(b) = path
        .strip_prefix("/api/button/")
        .and_then(|n| n.parse::<usize>().ok())
        .and_then(|i| app.buttons.get(i))
    else {
        return respond(rq, 404, "text/plain", b"no such button".to_vec());
    };
    let mut posted = 0;
    for p in &b.postings {
        let r = if p.numeric {
            client.notify_double(&p.var, mbutil::atof(&p.value), None)
        } else {
            client.notify_string(&p.var, &p.value, None)
        };
        match r {
            Ok(()) => posted += 1,
            Err(e) => tracing::warn!("button {}: {} not posted: {e}", b.label, p.var),
        }
    }
    tracing::info!("button {} pressed: {posted} posting(s)", b.label);
    respond_json(rq, 200, &json!({"button": b.label, "posted": posted}))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// GET `path` from a server on 127.0.0.1: the body as JSON.
    fn get(addr: SocketAddr, path: &str) -> serde_json::Value {
        use std::io::{Read, Write};
        let mut s = std::net::TcpStream::connect(addr).unwrap();
        let rq = format!("GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n");
        s.write_all(rq.as_bytes()).unwrap();
        let mut text = String::new();
        s.read_to_string(&mut text).unwrap();
        let body = text.split_once("\r\n\r\n").map_or("", |(_, b)| b);
        serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {text}"))
    }

    #[test]
    fn a_fleets_run_is_served_with_every_vehicle_in_one_frame() {
        let dir = crate::runs::tests::folder("server-fleet");
        crate::runs::tests::fleet_runs(&dir, 2);
        let runs = crate::runs::open(&dir).unwrap();
        let app = App {
            title: "fleet".into(),
            mode: Mode::Replay(runs),
            buttons: Vec::new(),
        };
        let s = start(Arc::new(app), "127.0.0.1:0".parse().unwrap()).unwrap();
        let info = get(s.addr, "/api/info");
        assert_eq!(info["runs"].as_array().map(Vec::len), Some(2));
        assert_eq!(info["runs"][1]["vehicles"], json!(["abe", "ben"]));
        assert_eq!(
            info["runs"][1]["logs"],
            json!(["run-0001/abe.alog", "run-0001/ben.alog"])
        );
        let (t0, t1) = (
            info["runs"][1]["t0"].as_f64(),
            info["runs"][1]["t1"].as_f64(),
        );
        assert_eq!((t0, t1), (Some(0.0), Some(12.0)));
        // The middle of run 1: both vehicles, each where its own log puts it.
        let f = get(s.addr, "/api/frame?run=1&t=6");
        let at: Vec<(&str, f64)> = f["vehicles"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| (v["name"].as_str().unwrap(), v["x"].as_f64().unwrap()))
            .collect();
        assert_eq!(at, [("abe", 6.0), ("ben", 4.0)]);
        assert!(f["trails"]["abe"].is_array() && f["trails"]["ben"].is_array());
        let tracks = get(s.addr, "/api/tracks");
        assert_eq!(tracks[1].as_object().map(|t| t.len()), Some(2));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn queries() {
        let q: Vec<_> = query("/api/frame?run=2&t=3.5&x").collect();
        assert_eq!(q, [("run", "2"), ("t", "3.5")]);
    }
}
