//! An offline command whose reader goes away (`helm sim ... | head`) ends quietly, as
//! `cat` does, instead of panicking on the broken pipe.

use std::os::unix::process::ExitStatusExt;
use std::process::{Command, Stdio};

mod common;

fn ends_quietly(args: &[&str]) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_helm"))
        .current_dir(common::workspace())
        .args(args)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run helm");
    // The reader is gone before the first line is written.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    let sigpipe = out.status.signal() == Some(13);
    assert!(
        sigpipe || out.status.success(),
        "{args:?}: {:?} {err}",
        out.status
    );
}

#[test]
fn check_help_and_interface_end_quietly_on_a_closed_pipe() {
    ends_quietly(&["check", "missions/alpha/alpha.moos"]);
    ends_quietly(&["--help"]);
    ends_quietly(&["-i"]);
    ends_quietly(&["conform", "conformance/helm"]);
}
