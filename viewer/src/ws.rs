//! The live WebSocket: a listener of its own beside the HTTP server (same address, the
//! next free port), tungstenite doing the upgrade handshake, one thread per viewer.
//!
//! A browser always sends `Origin` with a WebSocket: it must be the page's own
//! (`http://<this host>:<the page's port>`), so another site cannot read the feed; on a
//! loopback address the `Host` must be a loopback name (no DNS rebinding).

use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;

use tungstenite::handshake::server::{ErrorResponse, Request, Response};
use tungstenite::http::StatusCode;

use crate::hosts::{host_name, loopback_host};
use crate::live::Hub;

/// Listen on `ip` (any free port) for viewers of the page served on `page_port`.
pub fn start(hub: Arc<Hub>, ip: IpAddr, page_port: u16) -> std::io::Result<SocketAddr> {
    let listener = TcpListener::bind(SocketAddr::new(ip, 0))?;
    let addr = listener.local_addr()?;
    std::thread::Builder::new()
        .name("view-ws".into())
        .spawn(move || {
            for s in listener.incoming().flatten() {
                let hub = hub.clone();
                let spawned = std::thread::Builder::new()
                    .name("view-viewer".into())
                    .spawn(move || serve(&hub, s, page_port, ip.is_loopback()));
                if let Err(e) = spawned {
                    tracing::warn!("cannot start a viewer thread: {e}");
                }
            }
        })?;
    Ok(addr)
}

fn refuse(why: &str) -> ErrorResponse {
    let mut r = ErrorResponse::new(Some(why.to_owned()));
    *r.status_mut() = StatusCode::FORBIDDEN;
    r
}

/// Whether a handshake may go on (`Err`: the reason it may not).
pub(crate) fn allowed(
    host: Option<&str>,
    origin: Option<&str>,
    page_port: u16,
    loopback: bool,
) -> Result<(), &'static str> {
    let host = host.unwrap_or("");
    if loopback && !loopback_host(host) {
        return Err("forbidden host");
    }
    if let Some(o) = origin {
        let h = host_name(host);
        let h = if h.contains(':') {
            format!("[{h}]")
        } else {
            h.to_owned()
        };
        if o != format!("http://{h}:{page_port}") {
            return Err("foreign origin");
        }
    }
    Ok(())
}

// tungstenite's handshake callback returns its own (large) error response type.
#[allow(clippy::result_large_err)]
fn serve(hub: &Hub, stream: TcpStream, page_port: u16, loopback: bool) {
    let _ = stream.set_nodelay(true);
    let check = |req: &Request, resp: Response| {
        let h = |n: &str| req.headers().get(n).and_then(|v| v.to_str().ok());
        match allowed(h("Host"), h("Origin"), page_port, loopback) {
            Ok(()) => Ok(resp),
            Err(why) => Err(refuse(why)),
        }
    };
    let Ok(mut ws) = tungstenite::accept_hdr(stream, check) else {
        return;
    };
    loop {
        let (full, rx) = hub.subscribe();
        if ws.send(tungstenite::Message::text(full)).is_err() {
            return;
        }
        // Until the hub drops this viewer (too slow) and it needs the whole picture.
        while let Ok(m) = rx.recv() {
            if ws.send(tungstenite::Message::text(m.to_string())).is_err() {
                return;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_pages_own_origin_and_loopback_hosts() {
        assert_eq!(
            allowed(
                Some("127.0.0.1:5000"),
                Some("http://127.0.0.1:8080"),
                8080,
                true
            ),
            Ok(())
        );
        assert_eq!(allowed(Some("localhost:5000"), None, 8080, true), Ok(()));
        assert_eq!(
            allowed(
                Some("127.0.0.1:5000"),
                Some("http://evil.example"),
                8080,
                true
            ),
            Err("foreign origin")
        );
        assert_eq!(
            allowed(
                Some("127.0.0.1:5000"),
                Some("http://127.0.0.1:9999"),
                8080,
                true
            ),
            Err("foreign origin")
        );
        assert_eq!(
            allowed(Some("rebound.example:5000"), None, 8080, true),
            Err("forbidden host")
        );
        assert_eq!(
            allowed(
                Some("boat.local:5000"),
                Some("http://boat.local:8080"),
                8080,
                false
            ),
            Ok(())
        );
        assert_eq!(
            allowed(Some("[::1]:5000"), Some("http://[::1]:8080"), 8080, true),
            Ok(())
        );
    }
}
