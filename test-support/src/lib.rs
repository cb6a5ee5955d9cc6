//! What the integration tests that start real binaries share: a free loopback port, a
//! child process killed when the test ends (passing or not), a polling wait with a
//! limit, and the `moosdb` binary for a test that needs a MOOSDB beside its own binary.
//!
//! For tests only (a dev-dependency). It depends on the standard library alone and on
//! no crate of the workspace, so any crate's tests may use it.
//!
//! The waits poll and fail only past a generous limit: tests run on 2 shared cores beside
//! a build, so nothing here asserts on a schedule.

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

/// A port of 127.0.0.1 nobody listens on right now.
pub fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("bind an ephemeral port on 127.0.0.1")
}

/// A child process killed (and reaped) when dropped, so a failing test leaves nothing.
pub struct Proc(pub Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Polls `done` every 20 ms until it holds; panics naming `what` past `limit`.
pub fn wait_for(what: &str, limit: Duration, mut done: impl FnMut() -> bool) {
    let t0 = Instant::now();
    while !done() {
        assert!(t0.elapsed() < limit, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The `moosdb` binary beside `exe` (a test's `CARGO_BIN_EXE_<name>`: `cargo test
/// --workspace` builds both there); when only the test's crate was built, `moosdb` is
/// built into a target folder of its own, `<target>/<tag>` (the outer cargo may hold the
/// lock of the usual one), from `manifest_dir` (the test crate's `CARGO_MANIFEST_DIR`).
pub fn moosdb_beside(exe: &Path, manifest_dir: &str, tag: &str) -> PathBuf {
    let name = format!("moosdb{}", std::env::consts::EXE_SUFFIX);
    let beside = exe.with_file_name(&name);
    if beside.exists() {
        return beside;
    }
    let target = exe
        .parent()
        .and_then(Path::parent)
        .expect("the test binary lies in <target>/<profile>/")
        .join(tag);
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let st = Command::new(cargo)
        .args(["build", "-q", "-p", "moosdb", "--bin", "moosdb"])
        .env("CARGO_TARGET_DIR", &target)
        .current_dir(manifest_dir)
        .status()
        .expect("run cargo build");
    assert!(st.success(), "building moosdb failed");
    target.join("debug").join(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_port_is_bindable() {
        let p = free_port();
        assert!(p > 0);
        // Nobody took it in between on a quiet loopback: it binds.
        assert!(TcpListener::bind(("127.0.0.1", p)).is_ok());
    }

    #[test]
    fn wait_for_returns_once_done_and_counts_polls() {
        let mut n = 0;
        wait_for("three polls", Duration::from_secs(60), || {
            n += 1;
            n == 3
        });
        assert_eq!(n, 3);
    }

    #[test]
    #[should_panic(expected = "timed out waiting for never")]
    fn wait_for_panics_past_its_limit() {
        wait_for("never", Duration::ZERO, || false);
    }

    #[test]
    fn proc_kills_its_child_on_drop() {
        let child = Command::new("sleep")
            .arg("600")
            .spawn()
            .expect("start sleep");
        let pid = child.id();
        drop(Proc(child));
        // Reaped: no such process any more.
        assert!(!Path::new(&format!("/proc/{pid}")).exists());
    }

    #[test]
    fn moosdb_beside_prefers_the_binary_next_to_the_test() {
        let dir = std::env::temp_dir().join(format!("test-support-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let db = dir.join(format!("moosdb{}", std::env::consts::EXE_SUFFIX));
        std::fs::write(&db, b"").expect("write");
        let got = moosdb_beside(&dir.join("contactmgr"), ".", "unused");
        assert_eq!(got, db);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
