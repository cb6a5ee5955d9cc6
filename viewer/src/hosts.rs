//! `Host` and `Origin` checks shared by the HTTP server and the WebSocket listener.

/// The host name of a `Host` header (`127.0.0.1:8080`, `[::1]:80`, `localhost`).
pub fn host_name(host: &str) -> &str {
    if let Some(rest) = host.strip_prefix('[') {
        return rest.split(']').next().unwrap_or("");
    }
    host.rsplit_once(':').map_or(host, |(h, _)| h)
}

/// A `Host` a page on a loopback address may be reached by.
pub fn loopback_host(host: &str) -> bool {
    matches!(
        host_name(host).to_ascii_lowercase().as_str(),
        "127.0.0.1" | "localhost" | "::1"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn host_names() {
        assert_eq!(host_name("127.0.0.1:8080"), "127.0.0.1");
        assert_eq!(host_name("[::1]:80"), "::1");
        assert_eq!(host_name("localhost"), "localhost");
        assert!(loopback_host("LOCALHOST:1") && !loopback_host("evil.example:80"));
    }
}
