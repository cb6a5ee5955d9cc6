//! The golden helm cases, replayed through the real `helm` binary.
//!
//! Cases whose behaviors are all built in must pass; the `plugin_*` cases need behavior
//! libraries and, without IVP_BEHAVIOR_DIRS and bundled libraries, must fail with a clear
//! unknown-type error.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

/// The golden cases that need behavior libraries (`plugin_*`), or those that do not:
/// (file name, path).
fn cases(plugin: bool) -> Vec<(String, PathBuf)> {
    common::helm_cases()
        .into_iter()
        .map(|f| (common::file_name(&f), f))
        .filter(|(name, _)| name.starts_with("plugin_") == plugin)
        .collect()
}

fn conform(file: &Path) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("conform")
        .arg(file)
        .env_remove("IVP_BEHAVIOR_DIRS")
        .env("IVP_HELM_BUNDLED_DIR", "")
        .output()
        .expect("run helm");
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    (out.status.success(), text)
}

#[test]
fn builtin_cases_match_the_real_helm() {
    let mut failures = Vec::new();
    let (mut n, mut waiting) = (0, 0);
    for (name, f) in cases(false) {
        let (ok, text) = conform(&f);
        if ok && text.contains(": waiting for its behavior types: ") {
            waiting += 1;
            continue;
        }
        n += 1;
        if !ok {
            let head: Vec<&str> = text.lines().take(6).collect();
            failures.push(format!("{name}:\n{}", head.join("\n")));
        }
    }
    println!(
        "helm conformance (built-in): {} passed, {} failed, {waiting} waiting",
        n - failures.len(),
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn plugin_cases_need_their_libraries() {
    for (name, f) in cases(true) {
        let (ok, text) = conform(&f);
        assert!(!ok, "{name} passed without its behavior libraries");
        assert!(
            text.contains("unknown behavior type BHV_"),
            "{name}: expected an unknown-behavior-type error, got:\n{text}"
        );
        assert!(
            text.contains(".bhv:"),
            "{name}: error must name file:line:\n{text}"
        );
    }
}

#[test]
fn a_case_that_differs_fails_with_case_step_variable_expected_and_got() {
    let src = common::workspace().join("conformance/helm/timer_gate.toml");
    let text = std::fs::read_to_string(&src).expect("timer_gate case");
    assert!(
        text.contains("GO = \"true\""),
        "the case changed: pick another value"
    );
    let tampered = text.replacen("GO = \"true\"", "GO = \"later\"", 1);
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("conform-tampered");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let file = dir.join("timer_gate.toml");
    std::fs::write(&file, tampered).expect("write case");
    let (ok, text) = conform(&file);
    assert!(!ok, "a tampered case must fail:\n{text}");
    let line = text
        .lines()
        .find(|l| l.starts_with("timer_gate step "))
        .unwrap_or_else(|| panic!("no difference line:\n{text}"));
    assert!(
        line.contains(" GO: expected \"later\" got \"true\""),
        "{line}"
    );
    assert!(text.trim_end().ends_with("0 passed, 1 failed"), "{text}");
}
