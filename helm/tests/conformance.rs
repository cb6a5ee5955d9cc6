//! The golden helm cases, replayed through the real `helm` binary.
//!
//! Cases whose behaviors are all built in must pass; cases naming a type the project
//! ships as a library need it and, without IVP_BEHAVIOR_DIRS and bundled libraries, must
//! fail with a clear unknown-type error (not wait). With the libraries loaded every case
//! passes or waits: helm/tests/plugins.rs.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;

/// The golden cases whose behavior types are all built in (`libs == false`), or which
/// need a library this project ships (`libs == true`): (file name, path). Cases waiting
/// for a type the project lacks are in neither.
fn cases(libs: bool) -> Vec<(String, PathBuf)> {
    let builtins = helm_engine::factory::BehaviorFactory::with_builtins();
    common::helm_cases()
        .into_iter()
        .filter(|f| {
            let case = helm_conform::load(f).expect("case reads");
            let spec = bhv::reader::parse_str(&case.bhv, &f.with_extension("bhv"))
                .expect("case bhv parses");
            let types: Vec<&str> = spec
                .behaviors
                .iter()
                .map(|b| b.type_name.as_str())
                .collect();
            let all_builtin = types.iter().all(|t| builtins.knows(t));
            let shipped = types
                .iter()
                .all(|t| helm_engine::factory::project_has_type(t));
            if libs {
                shipped && !all_builtin
            } else {
                all_builtin
            }
        })
        .map(|f| (common::file_name(&f), f))
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
    let mut n = 0;
    for (name, f) in cases(false) {
        let (ok, text) = conform(&f);
        n += 1;
        if !ok {
            let head: Vec<&str> = text.lines().take(6).collect();
            failures.push(format!("{name}:\n{}", head.join("\n")));
        }
    }
    println!(
        "helm conformance (built-in): {} passed, {} failed",
        n - failures.len(),
        failures.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn library_cases_need_their_libraries() {
    let cases = cases(true);
    assert!(cases.len() >= 10, "{cases:?}");
    for (name, f) in cases {
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

/// `helm conform --bench` prints each case's time beside the C++ helm's time recorded for
/// it, the ratios, and how many cases are at most 1/10 of it; a case without a recorded
/// timing gets its own time only.
#[test]
fn bench_puts_the_cpp_time_beside_ours() {
    let src = common::workspace().join("conformance/helm/timer_gate.toml");
    let cpp = helm_conform::CppTiming::beside(&src)
        .expect("readable")
        .expect("timer_gate has its C++ timing");
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("conform-bench");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    let bare = dir.join("timer_gate.toml");
    std::fs::copy(&src, &bare).expect("copy case");
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["conform", "--bench"])
        .arg(&src)
        .arg(&bare)
        .env_remove("IVP_BEHAVIOR_DIRS")
        .env("IVP_HELM_BUNDLED_DIR", "")
        .output()
        .expect("run helm");
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{text}");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");
    // bench timer_gate <us>  (C++ <mean>: <ratio>; median of <n> replays <us> vs <us>: <ratio>)
    let f: Vec<&str> = lines[0].split_whitespace().collect();
    assert_eq!(&f[..2], ["bench", "timer_gate"], "{text}");
    let num = |s: &str| -> f64 {
        s.trim_end_matches([':', ';', ')'])
            .parse()
            .unwrap_or_else(|_| panic!("{s:?} in {text}"))
    };
    let ours = num(f[2]);
    assert_eq!(f[3], "(C++", "{text}");
    assert_eq!(num(f[4]), (cpp.mean_us * 1e3).round() / 1e3, "{text}");
    assert!((num(f[5]) - ours / cpp.mean_us).abs() < 1e-3, "{text}");
    let reps = num(f[8]);
    assert!(reps >= 1.0, "{text}");
    assert_eq!(
        num(f[12]),
        (cpp.median_rep_us * 1e3).round() / 1e3,
        "{text}"
    );
    assert!(
        (num(f[13]) - num(f[10]) / cpp.median_rep_us).abs() < 1e-3,
        "{text}"
    );
    // The copy has no timing beside it: our time alone.
    let g: Vec<&str> = lines[1].split_whitespace().collect();
    assert_eq!(g.len(), 3, "{text}");
    assert_eq!(&g[..2], ["bench", "timer_gate"], "{text}");
    // Only the case with a timing counts.
    let within = usize::from(ours / cpp.mean_us <= 0.1);
    assert!(
        lines[2].starts_with(&format!(
            "at most 1/10 of the C++ time: {within} of 1 cases by the mean, "
        )),
        "{text}"
    );
    assert!(lines[2].contains("this machine: "), "{text}");
}
