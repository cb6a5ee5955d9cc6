//! Helpers of the viewer's integration tests: the real `helm` binary, processes that are
//! killed when the test ends, and headless Chromium driven over the DevTools protocol.

// Each test binary compiles this module on its own and uses only some of it.
#![allow(dead_code)]

pub mod cdp;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// The root of the workspace.
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace")
        .to_path_buf()
}

/// `target/<profile>` of this test binary (`target/<profile>/deps/<test>`).
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable");
    exe.parent()
        .and_then(Path::parent)
        .expect("target/<profile>")
        .to_path_buf()
}

/// The `helm` binary beside this test, built first (cargo is a no-op when it is fresh),
/// so `cargo test -p viewer` tests the `helm view` of this very source.
pub fn helm_bin() -> PathBuf {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        let dir = profile_dir();
        let mut c = Command::new(env!("CARGO"));
        c.current_dir(workspace())
            .args(["build", "-p", "helm", "--bin", "helm"]);
        if dir.file_name().is_some_and(|n| n == "release") {
            c.arg("--release");
        }
        let out = c.output().expect("run cargo build -p helm");
        assert!(
            out.status.success(),
            "cargo build -p helm failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let bin = dir.join("helm");
        assert!(bin.exists(), "{} missing after the build", bin.display());
        bin
    })
    .clone()
}

/// Where the tests keep their screenshots: `target/viewer-artifacts/`.
pub fn artifacts() -> PathBuf {
    let d = profile_dir()
        .parent()
        .expect("target")
        .join("viewer-artifacts");
    std::fs::create_dir_all(&d).expect("create target/viewer-artifacts");
    d
}

/// A new empty folder `<prefix>-<n>` under `CARGO_TARGET_TMPDIR` (`n` counts this
/// process's calls). The names repeat from run to run, so runs reuse their folders
/// instead of leaving one per process id in the system temp dir.
pub fn temp_dir(prefix: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("{prefix}-{}", N.fetch_add(1, Ordering::SeqCst)));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create temp dir");
    d
}

// A free port, and children killed (and reaped) when dropped so a failing test leaves
// nothing: shared with the other crates' tests.
#[allow(unused_imports)]
pub use test_support::{free_port, Proc};

/// Start `helm view ARGS --port 0` and return it with the page's URL (from its first
/// line of output).
pub fn helm_view(args: &[&str]) -> (Proc, String) {
    let mut child = Command::new(helm_bin())
        .arg("view")
        .args(args)
        .args(["--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("start helm view");
    let out = child.stdout.take().expect("stdout");
    let mut line = String::new();
    let read = BufReader::new(out).read_line(&mut line);
    let p = Proc(child);
    assert!(
        read.is_ok_and(|n| n > 0),
        "helm view printed nothing (it failed; see its stderr above)"
    );
    let url = line
        .trim()
        .strip_prefix("helm view: ")
        .unwrap_or_else(|| panic!("unexpected first line {line:?}"))
        .to_owned();
    (p, url)
}

/// Wait until something listens on 127.0.0.1:`port`.
pub fn wait_port(port: u16, limit: Duration) {
    let start = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            start.elapsed() < limit,
            "nothing listens on port {port} after {limit:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// A raw HTTP exchange (for requests a browser would not make): the status code.
pub fn http_status(addr: &str, request: &str) -> u16 {
    let mut s = TcpStream::connect(addr).expect("connect to helm view");
    s.set_read_timeout(Some(Duration::from_secs(20))).ok();
    s.write_all(request.as_bytes()).expect("send request");
    let mut buf = Vec::new();
    let _ = s.take(4096).read_to_end(&mut buf);
    let text = String::from_utf8_lossy(&buf);
    text.split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or_else(|| panic!("no status line in {text:?}"))
}
