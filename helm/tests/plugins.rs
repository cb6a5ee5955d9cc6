//! The behavior plugins under `plugins/`, loaded by the real `helm` binary.
//!
//! Builds the plugin crates into a target directory of this test run, points
//! IVP_BEHAVIOR_DIRS at the output folder and runs `helm conform` on every
//! `conformance/helm/plugin_*.toml` case. Also checks that bad library folders and files
//! are reported without crashing the helm. (With IVP_BEHAVIOR_DIRS unset, the plugin
//! cases fail with `unknown behavior type`: asserted in conformance.rs.)
//!
//! Isolation (the second half): `BHV_TestFailure` (plugins/test-failure) fails on purpose
//! (panics, NaN, bad pieces, unknown variable) next to a BHV_Waypoint, driven through the
//! helm's library API; and a library built against another `behavior-api` version.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

use common::{scratch, text, workspace};

mod common;

const PLUGINS: &[&str] = common::SHIPPED_PLUGINS;

/// Built with the others, kept in a folder of its own (`failure_dir`).
const FAILURE_PLUGIN: &str = "bhv-test-failure";

/// Build the plugins once per test binary; returns the folder holding the `.so` files.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let all: Vec<&str> = PLUGINS.iter().copied().chain([FAILURE_PLUGIN]).collect();
        let built = common::build_plugins(&all);
        // Only the behavior libraries: the debug folder also holds deps/, build/ ...
        let only = common::lib_folder(&built, PLUGINS, "plugins-lib");
        common::lib_folder(&built, &[FAILURE_PLUGIN], "failure-lib");
        only
    })
}

/// The folder holding only `libbhv_test_failure.so`.
fn failure_dir() -> PathBuf {
    plugin_dir();
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("failure-lib")
}

fn helm_conform(case: &Path, dirs: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    // Exactly the folders given: no bundled libraries from next to the binary.
    cmd.current_dir(workspace())
        .arg("conform")
        .arg(case)
        .env("IVP_HELM_BUNDLED_DIR", "");
    common::behavior_dirs(&mut cmd, dirs);
    cmd.output().expect("run helm")
}

fn plugin_cases() -> Vec<PathBuf> {
    common::helm_cases()
        .into_iter()
        .filter(|p| common::file_name(p).starts_with("plugin_"))
        .collect()
}

#[test]
fn plugin_cases_pass_with_the_plugins_loaded() {
    let dir = plugin_dir().to_str().unwrap().to_string();
    let cases = plugin_cases();
    assert_eq!(cases.len(), 4, "{cases:?}");
    let mut failures = Vec::new();
    for case in &cases {
        let out = helm_conform(case, Some(&dir));
        let t = text(&out);
        if !(out.status.success() && t.contains("1 passed, 0 failed")) {
            failures.push(format!("{}:\n{t}", case.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `helm conform conformance/helm` with every shipped plugin loaded: each case passes or
/// waits for a type the project does not have yet; none fails.
#[test]
fn every_case_passes_or_waits_for_a_type_the_project_lacks() {
    let dir = plugin_dir().to_str().unwrap().to_string();
    let out = helm_conform(&workspace().join("conformance/helm"), Some(&dir));
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    let last = t.lines().rev().find(|l| l.contains(" passed, ")).unwrap();
    assert!(last.contains(" passed, 0 failed"), "{t}");
    let n_cases = common::helm_cases().len();
    let waiting: Vec<&str> = t
        .lines()
        .filter(|l| l.contains(": waiting for its behavior types: "))
        .collect();
    let passed: usize = last.split(' ').next().unwrap().parse().unwrap();
    assert_eq!(passed + waiting.len(), n_cases, "{t}");
    for line in &waiting {
        let types = line
            .split(": waiting for its behavior types: ")
            .nth(1)
            .unwrap();
        for ty in types.split(", ") {
            assert!(
                !helm_engine::factory::project_has_type(ty),
                "{ty} exists: {line}"
            );
        }
    }
    println!(
        "helm conformance (plugins loaded): {passed} passed, 0 failed, {} waiting",
        waiting.len()
    );
}

/// The list `helm conform` uses to tell "waiting" from "failed to load" names exactly the
/// types the shipped plugin libraries export.
#[test]
fn shipped_library_types_are_what_the_plugins_export() {
    let (factory, _) = helm_mission::factory_for(&[plugin_dir().to_path_buf()]);
    let mut exported: Vec<String> = factory
        .libraries()
        .iter()
        .flat_map(|l| l.types.iter().cloned())
        .collect();
    exported.sort();
    let mut listed: Vec<String> = helm_engine::factory::SHIPPED_LIBRARY_TYPES
        .iter()
        .map(|s| s.to_string())
        .collect();
    listed.sort();
    assert_eq!(exported, listed);
}

/// A case naming a type the project has, whose library is not loaded, fails (it does not
/// wait); one naming a type nobody has waits, names the type, and does not fail the run.
#[test]
fn a_missing_shipped_type_fails_but_an_unknown_one_waits() {
    let case = workspace().join("conformance/helm/plugin_constant_speed.toml");
    let out = helm_conform(&case, None);
    let t = text(&out);
    assert!(!out.status.success(), "{t}");
    assert!(t.contains("0 passed, 1 failed"), "{t}");
    let src = std::fs::read_to_string(&case).unwrap();
    assert!(src.contains("BHV_ConstantSpeed"), "the case changed");
    let dir = scratch("waiting-case");
    let file = dir.join("future_type.toml");
    std::fs::write(&file, src.replace("BHV_ConstantSpeed", "BHV_NotYetWritten")).unwrap();
    let out = helm_conform(&file, None);
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    assert!(
        t.contains(": waiting for its behavior types: BHV_NotYetWritten"),
        "{t}"
    );
    assert!(t.contains("0 passed, 0 failed, 1 waiting"), "{t}");
}

#[test]
fn each_library_alone_offers_its_own_type() {
    // One library per folder, several folders: the colon-separated list is searched in
    // order and a case needing two libraries still finds both.
    let lib = plugin_dir();
    let mut dirs = Vec::new();
    for p in ["bhv-constant-heading", "bhv-constant-speed"] {
        let d = scratch(format!("alone-{p}"));
        let name = common::lib_name(p);
        common::place(&lib.join(&name), &d.join(&name)).unwrap();
        dirs.push(d.to_str().unwrap().to_string());
    }
    let case = workspace().join("conformance/helm/plugin_constant_heading.toml");
    let out = helm_conform(&case, Some(&dirs.join(":")));
    let t = text(&out);
    assert!(t.contains("1 passed, 0 failed"), "{t}");
    // Only the heading library: ConstantSpeed is unknown.
    let out = helm_conform(&case, Some(&dirs[0]));
    let t = text(&out);
    assert!(t.contains("unknown behavior type BHV_ConstantSpeed"), "{t}");
    assert!(!out.status.success());
}

#[test]
fn empty_and_missing_directories_are_reported_not_fatal() {
    let empty = scratch("empty-dir");
    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such-dir");
    let _ = std::fs::remove_dir_all(&missing);
    let case = workspace().join("conformance/helm/plugin_constant_speed.toml");
    let dirs = format!("{}:{}", empty.display(), missing.display());
    let out = helm_conform(&case, Some(&dirs));
    let t = text(&out);
    assert!(t.contains("unknown behavior type BHV_ConstantSpeed"), "{t}");
    assert!(t.contains("0 passed, 1 failed"), "{t}");
    assert!(!t.contains("panicked"), "{t}");
    // The good folder after the bad ones still works.
    let dirs = format!("{dirs}:{}", plugin_dir().display());
    let out = helm_conform(&case, Some(&dirs));
    let t = text(&out);
    assert!(t.contains("1 passed, 0 failed"), "{t}");
}

#[test]
fn bad_library_files_are_skipped() {
    let d = scratch("bad-libs");
    // Garbage bytes with a library extension.
    std::fs::write(d.join("garbage.so"), b"this is not an ELF file\n").unwrap();
    // A real shared object that is not a behavior library (no root module): any .so
    // from the system, if there is one.
    for cand in [
        "/lib/x86_64-linux-gnu/libm.so.6",
        "/usr/lib/x86_64-linux-gnu/libm.so.6",
        "/lib64/libm.so.6",
        "/usr/lib/libm.so.6",
    ] {
        if Path::new(cand).is_file() {
            std::fs::copy(cand, d.join("libnotabehavior.so")).unwrap();
            break;
        }
    }
    let case = workspace().join("conformance/helm/plugin_constant_depth.toml");
    let out = helm_conform(&case, Some(d.to_str().unwrap()));
    let t = text(&out);
    assert!(t.contains("0 passed, 1 failed"), "{t}");
    assert!(t.contains("unknown behavior type BHV_ConstantDepth"), "{t}");
    assert!(!t.contains("panicked"), "{t}");
    // Bad files next to good ones do not stop the good ones from loading.
    for entry in std::fs::read_dir(plugin_dir()).unwrap() {
        let p = entry.unwrap().path();
        common::place(&p, &d.join(p.file_name().unwrap())).unwrap();
    }
    let out = helm_conform(&case, Some(d.to_str().unwrap()));
    let t = text(&out);
    assert!(t.contains("1 passed, 0 failed"), "{t}");
}

// ---------------------------------------------------------------------------------------
// Isolation: deliberately failing behaviors, through the helm's library API.
// ---------------------------------------------------------------------------------------

use helm_engine::config::HelmConfig;
use helm_engine::posting::{Posting, Value};
use helm_engine::{Helm, HelmState, Mail};

const T0: f64 = 1000.0;

/// The helm built from `bhv` text with the libraries of `dirs`, and its config warnings.
fn build(bhv_text: &str, dirs: &[PathBuf]) -> Helm {
    let (factory, _report) = helm_mission::factory_for(dirs);
    let (config, warnings) = HelmConfig::from_lines(&common::block_lines(&common::DRIVE_BLOCK));
    assert!(warnings.is_empty(), "{warnings:?}");
    let spec = bhv::reader::parse_str(bhv_text, Path::new("isolation.bhv")).expect("bhv parses");
    Helm::new(config, spec, &factory, "alpha", vec![])
}

/// Drives a helm as the conformance runner does: start-up at T0, then one iteration every
/// 0.25 s with fresh navigation mail, the helm's own subscribed postings echoed back first.
struct Drive {
    helm: Helm,
    step: usize,
    echo: Vec<Posting>,
    /// What each iteration published, in order.
    log: Vec<Vec<Posting>>,
}

impl Drive {
    fn start(mut helm: Helm) -> Drive {
        let echo = helm.startup(T0).to_vec();
        Drive {
            helm,
            step: 0,
            echo,
            log: Vec::new(),
        }
    }

    fn now(&self) -> f64 {
        T0 + 0.25 * self.step as f64
    }

    /// One iteration; returns its index in `log`.
    fn iterate(&mut self) -> usize {
        let now = self.now();
        let mut mail: Vec<Mail> = self
            .echo
            .iter()
            .filter(|p| self.helm.is_subscribed(&p.var))
            .map(|p| Mail {
                var: p.var.clone(),
                value: p.value.clone(),
                time: now,
                source: self.helm.app_name().to_string(),
                source_aux: p.source_aux.clone(),
            })
            .collect();
        // Ownship sits still at the origin, heading north.
        for var in ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"] {
            mail.push(Mail {
                var: var.into(),
                value: Value::Num(0.0),
                time: now,
                source: "uSimMarine".into(),
                source_aux: String::new(),
            });
        }
        self.helm.handle_mail(now, &mail);
        let out = self.helm.iterate(now).to_vec();
        self.echo = out.clone();
        self.log.push(out);
        self.step += 1;
        self.log.len() - 1
    }

    /// Iterate until the `n`th decision since start-up (first = 1); returns its log index.
    fn until_decision(&mut self, n: usize) -> usize {
        loop {
            let i = self.iterate();
            let seen = (0..=i).filter(|&k| self.decided(k)).count();
            if seen == n {
                return i;
            }
            assert!(seen < n, "decision {n} already passed");
            assert!(self.step < 200, "no decision {n} after 200 iterations");
        }
    }

    /// Whether iteration `i` went through the decision step (it posts IVPHELM_IPF_CNT).
    fn decided(&self, i: usize) -> bool {
        self.get(i, "IVPHELM_IPF_CNT").is_some()
    }

    /// The last value iteration `i` posted for `var`.
    fn get(&self, i: usize, var: &str) -> Option<&Value> {
        self.log[i]
            .iter()
            .rev()
            .find(|p| p.var == var)
            .map(|p| &p.value)
    }

    fn strs(&self, i: usize, var: &str) -> Vec<String> {
        self.log[i]
            .iter()
            .filter(|p| p.var == var)
            .filter_map(|p| match &p.value {
                Value::Str(s) => Some(s.clone()),
                Value::Num(_) => None,
            })
            .collect()
    }

    fn num(&self, i: usize, var: &str) -> Option<f64> {
        match self.get(i, var) {
            Some(Value::Num(v)) => Some(*v),
            _ => None,
        }
    }

    fn str_(&self, i: usize, var: &str) -> Option<String> {
        match self.get(i, var) {
            Some(Value::Str(s)) => Some(s.clone()),
            _ => None,
        }
    }

    /// The latest value of `var` posted at or before iteration `i`.
    fn latest(&self, i: usize, var: &str) -> Option<String> {
        (0..=i).rev().find_map(|k| match self.get(k, var) {
            Some(Value::Str(s)) => Some(s.clone()),
            Some(Value::Num(v)) => Some(format!("{v}")),
            None => None,
        })
    }

    fn dump(&self, from: usize) -> String {
        let mut out = String::new();
        for (k, posts) in self.log.iter().enumerate().skip(from) {
            out.push_str(&format!("--- iteration {k} (t={})\n", T0 + 0.25 * k as f64));
            for p in posts {
                if p.var == "BHV_IPF" || p.var == "IVPHELM_SUMMARY" {
                    continue;
                }
                out.push_str(&format!("  {} = {:?}\n", p.var, p.value));
            }
        }
        out
    }
}

/// A waypoint that keeps the vehicle going, and the failing behavior `tester` after it.
fn mission(failure_lines: &str) -> String {
    format!(
        "initialize DEPLOY = true

Behavior = BHV_Waypoint
{{
  name      = steer
  pwt       = 100
  condition = DEPLOY = true
  speed     = 1.2
  points    = 60,60 : 100,0
}}

Behavior = BHV_TestFailure
{{
  name      = tester
  pwt       = 50
  condition = DEPLOY = true
  speed     = 2
{failure_lines}
}}
"
    )
}

/// The stated outcome of a run-time failure at the `fail_at`-th decision: BHV_ERROR naming
/// `tester` (and containing each of `error_has`), IVPHELM_ALLSTOP=BehaviorError with zeros,
/// then `tester` disabled and the waypoint driving again (ALLSTOP back to clear).
fn assert_isolated_run_failure(failure: &str, error_has: &[&str]) {
    let lines = format!("  failure   = {failure}\n  fail_at   = 3");
    let helm = build(&mission(&lines), &[failure_dir()]);
    assert!(
        helm.config_warnings().is_empty(),
        "{:?}",
        helm.config_warnings()
    );
    let mut d = Drive::start(helm);
    // Two good decisions: both behaviors active, the decision is posted.
    for n in 1..=2 {
        let i = d.until_decision(n);
        assert_eq!(d.num(i, "IVPHELM_IPF_CNT"), Some(2.0), "{}", d.dump(0));
        assert!(d.num(i, "DESIRED_SPEED").is_some(), "{}", d.dump(0));
        assert_eq!(
            d.latest(i, "IVPHELM_ALLSTOP").as_deref(),
            Some("clear"),
            "{}",
            d.dump(0)
        );
    }
    // The failing decision.
    let bad = d.until_decision(3);
    let errors = d.strs(bad, "BHV_ERROR");
    assert!(
        errors
            .iter()
            .any(|e| e.contains("tester") && error_has.iter().all(|h| e.contains(h))),
        "{failure}: BHV_ERROR naming tester and {error_has:?} expected, got {errors:?}\n{}",
        d.dump(bad)
    );
    assert_eq!(
        d.str_(bad, "IVPHELM_ALLSTOP").as_deref(),
        Some("BehaviorError"),
        "{failure}\n{}",
        d.dump(bad)
    );
    assert_eq!(d.num(bad, "DESIRED_SPEED"), Some(0.0), "{}", d.dump(bad));
    assert_eq!(d.num(bad, "DESIRED_HEADING"), Some(0.0), "{}", d.dump(bad));
    // Afterwards: tester disabled, never running or active again; the waypoint drives.
    let after = d.until_decision(4);
    assert_eq!(
        d.latest(after, "IVPHELM_BHV_DISABLED").as_deref(),
        Some("tester"),
        "{failure}: tester should be disabled\n{}",
        d.dump(bad)
    );
    assert_eq!(
        d.str_(after, "IVPHELM_ALLSTOP").as_deref(),
        Some("clear"),
        "{failure}: the helm should recover\n{}",
        d.dump(bad)
    );
    for _ in 0..6 {
        d.iterate();
    }
    let last = d.log.len() - 1;
    for i in after..=last {
        assert_eq!(d.num(i, "IVPHELM_IPF_CNT"), Some(1.0), "{}", d.dump(bad));
        // The waypoint alone: its own speed, towards its first point (north-east).
        let v = d.num(i, "DESIRED_SPEED").expect("DESIRED_SPEED posted");
        assert!((v - 1.2).abs() < 1e-9, "speed {v}\n{}", d.dump(bad));
        let h = d.num(i, "DESIRED_HEADING").expect("DESIRED_HEADING posted");
        assert!((h - 45.0).abs() <= 1.0, "heading {h}\n{}", d.dump(bad));
        assert!(d.strs(i, "BHV_ERROR").is_empty(), "{}", d.dump(bad));
        for var in ["IVPHELM_BHV_RUNNING", "IVPHELM_BHV_ACTIVE"] {
            let v = d.latest(i, var).unwrap_or_default();
            assert!(!v.contains("tester"), "{var}={v}\n{}", d.dump(bad));
        }
    }
    assert_eq!(
        d.latest(last, "IVPHELM_BHV_DISABLED").as_deref(),
        Some("tester")
    );
    assert_eq!(d.latest(last, "IVPHELM_ALLSTOP").as_deref(), Some("clear"));
    assert_eq!(d.helm.state(), HelmState::Drive);
}

#[test]
fn isolation_panic_on_run_disables_the_behavior_and_the_helm_keeps_driving() {
    assert_isolated_run_failure(
        "panic_on_run",
        &["BHV_TestFailure deliberate panic in on_run (run 3)"],
    );
}

#[test]
fn isolation_bad_pieces_are_rejected_and_the_behavior_disabled() {
    assert_isolated_run_failure("bad_pieces", &["rejected"]);
}

#[test]
fn isolation_bounds_out_of_range_are_rejected_and_the_behavior_disabled() {
    assert_isolated_run_failure("bad_bounds", &["rejected"]);
}

#[test]
fn isolation_unknown_variable_is_rejected_and_the_behavior_disabled() {
    assert_isolated_run_failure("unknown_var", &["warp_factor"]);
}

#[test]
fn isolation_nan_is_rejected_and_the_behavior_disabled() {
    assert_isolated_run_failure("nan", &["NaN"]);
}

/// A NaN function: rejected with BHV_ERROR and a BehaviorError all-stop; the helm never
/// crashes.
#[test]
fn isolation_nan_is_never_trusted() {
    let helm = build(
        &mission("  failure   = nan\n  fail_at   = 3"),
        &[failure_dir()],
    );
    let mut d = Drive::start(helm);
    let bad = d.until_decision(3);
    assert!(
        d.strs(bad, "BHV_ERROR")
            .iter()
            .any(|e| e.starts_with("tester: ") && e.contains("NaN")),
        "{}",
        d.dump(bad)
    );
    assert_eq!(
        d.str_(bad, "IVPHELM_ALLSTOP").as_deref(),
        Some("BehaviorError")
    );
    assert_eq!(d.num(bad, "DESIRED_SPEED"), Some(0.0));
    for _ in 0..8 {
        let i = d.iterate();
        // Never a decision made from the NaN function.
        assert_ne!(d.num(i, "DESIRED_SPEED").unwrap_or(0.0), 2.0);
    }
}

/// Configuration-time failures: the helm is MALCONFIG with a problem naming `isolation.bhv`
/// and the line, iterates without driving, and nothing crashes.
fn assert_config_problem(bhv_text: &str, line: usize, has: &[&str]) -> Vec<String> {
    let helm = build(bhv_text, &[failure_dir()]);
    let warnings = helm.config_warnings().to_vec();
    let at = format!("isolation.bhv:{line}");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains(&at) && has.iter().all(|h| w.contains(h))),
        "a problem at {at} with {has:?} expected, got {warnings:?}"
    );
    assert_eq!(helm.state(), HelmState::Malconfig);
    let mut d = Drive::start(helm);
    for _ in 0..8 {
        let i = d.iterate();
        assert!(d.get(i, "DESIRED_SPEED").is_none(), "{}", d.dump(0));
    }
    assert_eq!(d.helm.state(), HelmState::Malconfig);
    warnings
}

#[test]
fn isolation_panic_on_param_is_a_configuration_problem() {
    // `failure = panic_on_param` is line 18 of the mission text.
    let text = mission("  failure   = panic_on_param");
    assert_eq!(
        text.lines().nth(17).unwrap().trim(),
        "failure   = panic_on_param"
    );
    assert_config_problem(&text, 18, &["failure"]);
}

#[test]
fn isolation_panic_on_create_is_a_configuration_problem() {
    // Panics at the end of creation (after all parameters): reported at the block.
    let text = mission("  failure   = panic_on_create");
    assert_eq!(
        text.lines().nth(11).unwrap().trim(),
        "Behavior = BHV_TestFailure"
    );
    assert_config_problem(
        &text,
        12,
        &["BHV_TestFailure deliberate panic while being created"],
    );
    let text = mission("  failure   = panic_on_helm_start");
    assert_config_problem(
        &text,
        12,
        &["BHV_TestFailure deliberate panic in on_helm_start"],
    );
}

fn ctor_mission() -> String {
    mission("").replace("BHV_TestFailure\n", "BHV_TestFailureCtor\n")
}

#[test]
fn isolation_panicking_constructor_is_a_configuration_problem() {
    assert_config_problem(&ctor_mission(), 12, &["BHV_TestFailureCtor"]);
}

#[test]
fn isolation_configuration_panics_name_the_panic_message() {
    let w = assert_config_problem(
        &ctor_mission(),
        12,
        &["BHV_TestFailureCtor deliberate panic in the constructor"],
    );
    assert!(
        !w.iter().any(|w| w.contains("unknown behavior type")),
        "{w:?}"
    );
    assert_config_problem(
        &mission("  failure   = panic_on_param"),
        18,
        &["BHV_TestFailure deliberate panic in set_param(failure = panic_on_param)"],
    );
}

// ---------------------------------------------------------------------------------------
// A library built against another behavior-api version.
// ---------------------------------------------------------------------------------------

/// Copies a source tree (not `target/`, not `Cargo.toml`: the caller writes its own).
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap();
        if name == "target" || name == "Cargo.toml" {
            continue;
        }
        let dest = to.join(name);
        if p.is_dir() {
            copy_dir(&p, &dest);
        } else {
            std::fs::copy(&p, &dest).unwrap();
        }
    }
}

/// Builds `libbhv_abi_future.so` (BHV_FromTheFuture, a copy of the template) against a copy
/// of behavior-api whose version is 0.2.0; `None` if cargo cannot build it offline.
/// Built once per test run: two tests use it, and they run in parallel.
fn future_abi_library() -> Option<PathBuf> {
    static LIB: OnceLock<Option<PathBuf>> = OnceLock::new();
    LIB.get_or_init(build_future_abi_library).clone()
}

fn build_future_abi_library() -> Option<PathBuf> {
    let root = scratch("abi-future");
    let ws = workspace();
    // behavior-api 0.2.0: the same code, a standalone manifest.
    let api = root.join("behavior-api");
    copy_dir(&ws.join("behavior-api"), &api);
    let abi_stable_req = "0.11";
    std::fs::write(
        api.join("Cargo.toml"),
        format!(
            "[package]\nname = \"behavior-api\"\nversion = \"0.2.0\"\nedition = \"2021\"\n\n\
             [dependencies]\nabi_stable = \"{abi_stable_req}\"\nivp = {{ path = {:?} }}\n\
             ivp-reflector = {{ path = {:?} }}\n\
             geometry = {{ path = {:?} }}\nmbutil = {{ path = {:?} }}\n\
             bhv = {{ path = {:?} }}\ncontacts = {{ path = {:?} }}\n\n\
             [workspace]\n",
            ws.join("ivp").display().to_string(),
            ws.join("ivp-reflector").display().to_string(),
            ws.join("geometry").display().to_string(),
            ws.join("mbutil").display().to_string(),
            ws.join("bhv").display().to_string(),
            ws.join("contacts").display().to_string()
        ),
    )
    .unwrap();
    // The plugin: the template, renamed.
    let plugin = root.join("plugin");
    std::fs::create_dir_all(plugin.join("src")).unwrap();
    let lib = std::fs::read_to_string(ws.join("plugins/template/src/lib.rs"))
        .unwrap()
        .replace("\"BHV_Template\"", "\"BHV_FromTheFuture\"");
    let lib = lib.split("#[cfg(test)]").next().unwrap().to_string();
    std::fs::write(plugin.join("src/lib.rs"), lib).unwrap();
    std::fs::write(
        plugin.join("Cargo.toml"),
        format!(
            "[package]\nname = \"bhv-abi-future\"\nversion = \"0.1.0\"\nedition = \"2021\"\n\n\
             [lib]\ncrate-type = [\"cdylib\"]\n\n\
             [dependencies]\nbehavior-api = {{ path = \"../behavior-api\" }}\n\
             abi_stable = \"{abi_stable_req}\"\n\n[workspace]\n"
        ),
    )
    .unwrap();
    // The workspace's lock file: the same abi_stable, resolvable offline.
    std::fs::copy(ws.join("Cargo.lock"), plugin.join("Cargo.lock")).unwrap();
    let target = common::plugins_target();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(&plugin)
        .args(["build", "--quiet", "--offline"])
        .env("CARGO_TARGET_DIR", &target)
        // As the workspace's dev profile: file:line only (disk).
        .env("CARGO_PROFILE_DEV_DEBUG", "line-tables-only")
        .output();
    match out {
        Ok(o) if o.status.success() => {}
        Ok(o) => {
            let err = String::from_utf8_lossy(&o.stderr);
            // Only a registry that cannot be reached offline is a reason to skip; a
            // compile error in the copy is a failure.
            assert!(
                err.contains("offline") || err.contains("failed to get"),
                "building the behavior-api 0.2.0 plugin failed:\n{err}"
            );
            eprintln!("SKIPPED: cannot build the behavior-api 0.2.0 plugin offline:\n{err}");
            return None;
        }
        Err(e) => {
            eprintln!("SKIPPED: cannot run cargo: {e}");
            return None;
        }
    }
    let so = target.join("debug/libbhv_abi_future.so");
    assert!(so.is_file(), "{} not built", so.display());
    Some(so)
}

#[test]
fn library_built_against_another_api_version_is_refused() {
    plugin_dir(); // the shared target dir has abi_stable built already
    let Some(future) = future_abi_library() else {
        return;
    };
    let d = scratch("abi-mixed");
    let bad = d.join("libbhv_abi_future.so");
    std::fs::copy(&future, &bad).unwrap();
    let good = "libbhv_template.so";
    common::place(&plugin_dir().join(good), &d.join(good)).unwrap();

    let (factory, report) = helm_mission::factory_for(std::slice::from_ref(&d));
    let report = report.join("\n");
    assert!(!factory.knows("BHV_FromTheFuture"), "{report}");
    assert!(factory.knows("BHV_Template"), "{report}");
    // The refusal names the file and both versions (ours, the library's).
    let skipped = format!("skipped {}", bad.display());
    let at = report
        .find(&skipped)
        .unwrap_or_else(|| panic!("{skipped} expected in\n{report}"));
    let reason = &report[at..];
    let ours = behavior_api::API_VERSION;
    assert_ne!(
        ours, "0.2.0",
        "the future library must be newer than the host"
    );
    assert!(
        reason.contains(ours) && reason.contains("0.2.0"),
        "both versions expected:\n{report}"
    );

    // The helm built on that folder: the good type works, the bad one is unknown.
    let good_bhv = "Behavior = BHV_Template\n{\n  name = t\n  speed = 1.5\n}\n";
    let (config, _) = HelmConfig::from_lines(&common::block_lines(&[
        ("domain", "course:0:359:360"),
        ("domain", "speed:0:4:41"),
    ]));
    let spec = bhv::reader::parse_str(good_bhv, Path::new("abi.bhv")).unwrap();
    let helm = Helm::new(config, spec, &factory, "alpha", vec![]);
    assert!(
        helm.config_warnings().is_empty(),
        "{:?}",
        helm.config_warnings()
    );
    let spec = bhv::reader::parse_str(
        "Behavior = BHV_FromTheFuture\n{\n  name = f\n}\n",
        Path::new("abi.bhv"),
    )
    .unwrap();
    let (config, _) = HelmConfig::from_lines(&common::block_lines(&[("domain", "speed:0:4:41")]));
    let helm = Helm::new(config, spec, &factory, "alpha", vec![]);
    let w = helm.config_warnings().join("\n");
    assert!(
        w.contains("abi.bhv:1: unknown behavior type BHV_FromTheFuture"),
        "{w}"
    );

    // Through the real binary too: reported, not fatal.
    let case = workspace().join("conformance/helm/plugin_constant_speed.toml");
    let out = helm_conform(&case, Some(d.to_str().unwrap()));
    let t = text(&out);
    assert!(!t.contains("panicked"), "{t}");
    assert!(out.status.code().is_some(), "killed by a signal: {t}");
}

#[test]
fn library_built_against_another_api_version_is_refused_in_one_line() {
    plugin_dir();
    let Some(future) = future_abi_library() else {
        return;
    };
    let d = scratch("abi-one-line");
    std::fs::copy(&future, d.join("libbhv_abi_future.so")).unwrap();
    let (_, report) = helm_mission::factory_for(std::slice::from_ref(&d));
    let line = report
        .iter()
        .find(|l| l.contains("libbhv_abi_future.so"))
        .expect("reported");
    assert!(
        !line.contains('\n') && line.contains(behavior_api::API_VERSION) && line.contains("0.2.0"),
        "{line}"
    );
}

/// The last release of `behavior-api` before contacts were added to the ABI (0.1.0).
const PREVIOUS_API_RELEASE: &str = "7b7850b";

/// The last release before the context's `_into` methods were added (0.1.1, contacts).
const CONTACTS_API_RELEASE: &str = "84fa08f";

/// The last release before `BehaviorLib::recycle_function` was added (0.1.2, the `_into`
/// context methods).
const INTO_API_RELEASE: &str = "7c0fafd";

/// Builds `package` from the source of `commit` (read from the repo's history, whose
/// `behavior-api` must be `api_version`), unchanged; returns a folder holding only its
/// library. The releases share one target folder, so their registry crates build once.
///
/// Sharing needs two guards. Cargo names a path crate's artifact by its place in the
/// workspace, so two releases' `contacts` land in the same file; and `git archive`
/// stamps files with the commit's time, older than any artifact. So the builds run one
/// at a time, and `tar -m` stamps each tree with the time it is unpacked: a release's
/// sources are then newer than every artifact the previous one left, and rebuild.
fn build_released_plugin(commit: &str, api_version: &str, package: &str) -> PathBuf {
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
    // A test that failed while holding the lock leaves nothing half-done that matters.
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let root = scratch(format!("release-{commit}"));
    let ws = workspace();
    let tree = root.join("tree");
    std::fs::create_dir_all(&tree).unwrap();
    let archive = Command::new("git")
        .current_dir(&ws)
        .args(["archive", "--format=tar", commit])
        .output()
        .expect("run git (the test reads the previous release from the repo's history)");
    assert!(
        archive.status.success(),
        "git archive {commit} failed (a shallow clone?): {}",
        String::from_utf8_lossy(&archive.stderr)
    );
    let mut tar = Command::new("tar")
        .current_dir(&tree)
        .args(["-x", "-m", "-f", "-"])
        .stdin(std::process::Stdio::piped())
        .spawn()
        .expect("run tar");
    std::io::Write::write_all(tar.stdin.as_mut().unwrap(), &archive.stdout).unwrap();
    assert!(tar.wait().unwrap().success());
    let old_api = std::fs::read_to_string(tree.join("behavior-api/Cargo.toml")).unwrap();
    assert!(
        old_api.contains(&format!("version = \"{api_version}\"")),
        "{old_api}"
    );
    let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("previous-release-target");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(&tree)
        .args(["build", "--quiet", "--offline", "-p", package])
        .env("CARGO_TARGET_DIR", &target)
        // As the workspace's dev profile: file:line only (disk).
        .env("CARGO_PROFILE_DEV_DEBUG", "line-tables-only")
        .output()
        .expect("run cargo");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lib = common::lib_name(package);
    let lib_dir = scratch(format!("release-{commit}-lib"));
    common::place(&target.join("debug").join(&lib), &lib_dir.join(&lib)).unwrap();
    lib_dir
}

/// A plugin built from the previous release's source (its `behavior-api` 0.1.0 and its
/// template, unchanged) loads into this helm and drives: the ABI grew additively.
#[test]
fn a_plugin_built_against_the_previous_release_still_loads_and_runs() {
    let lib_dir = build_released_plugin(PREVIOUS_API_RELEASE, "0.1.0", "bhv-template");
    // A mission driven only by the old library's BHV_Template (speed 1.5).
    let mission = scratch("previous-release-mission");
    std::fs::write(
        mission.join("old.moos"),
        "ServerHost = localhost\nServerPort = 9000\nCommunity = alpha\n\
         LatOrigin = 43.8253\nLongOrigin = -70.3304\n\n\
         ProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = old.bhv\n  \
         domain = speed:0:4:41\n  start_in_drive = true\n}\n\n\
         ProcessConfig = uSimMarine\n{\n  AppTick = 10\n}\n",
    )
    .unwrap();
    std::fs::write(
        mission.join("old.bhv"),
        "Behavior = BHV_Template\n{\n  name = old\n  speed = 1.5\n}\n",
    )
    .unwrap();
    let out_dir = mission.join("run");
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("sim")
        .arg(mission.join("old.moos"))
        .args(["--max-time", "10", "--out"])
        .arg(&out_dir)
        .env("IVP_BEHAVIOR_DIRS", &lib_dir)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .output()
        .expect("run helm sim");
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    let alog = std::fs::read_to_string(out_dir.join("old.alog")).unwrap();
    let speeds: Vec<&str> = alog
        .lines()
        .filter(|l| l.split_whitespace().nth(1) == Some("DESIRED_SPEED"))
        .filter_map(|l| l.split_whitespace().nth(3))
        .collect();
    assert!(speeds.len() > 10, "{speeds:?}\n{t}");
    assert!(
        speeds.iter().all(|v| v.parse::<f64>() == Ok(1.5)),
        "{speeds:?}"
    );
}

/// Loads the contact library in `lib_dir` (built from a release's source), checks that
/// nothing was skipped and that it passes `cases` at every step; returns its factory.
fn released_contact_plugin_passes(
    lib_dir: &Path,
    cases: &[&str],
) -> helm_engine::factory::BehaviorFactory {
    let (factory, report) = helm_mission::factory_for(&[lib_dir.to_path_buf()]);
    let report = report.join("\n");
    assert!(
        report.contains("BHV_AvoidCollision") && !report.contains("skipped"),
        "{report}"
    );
    for case in cases {
        let file = workspace().join(format!("conformance/helm/{case}.toml"));
        let out = helm_conform(&file, Some(lib_dir.to_str().unwrap()));
        let t = text(&out);
        assert!(
            out.status.success() && t.contains("1 passed, 0 failed"),
            "{case}:\n{t}"
        );
    }
    factory
}

/// The contact behaviors built from the 0.1.1 release's source (`plugins/contact`
/// against its `behavior-api` 0.1.1, unchanged) load through the frozen 0.1.1 shape
/// (`abi_v2`) and give the golden answers of the contact cases, every step: the 0.1.1
/// contact methods (`contact`, `contact_text`, `set_contact` ...) are called through it.
#[test]
fn a_contact_plugin_built_against_the_0_1_1_release_still_loads_and_runs() {
    let lib_dir = build_released_plugin(CONTACTS_API_RELEASE, "0.1.1", "bhv-contact");
    let cases = [
        "avd_ten_contacts",
        "cutrange_spawn_pursuit",
        "trail_contact",
    ];
    released_contact_plugin_passes(&lib_dir, &cases);
}

/// The contact behaviors built from the 0.1.2 release's source, whose root module lacks
/// `recycle_function` (0.1.3), load through the frozen 0.1.2 shape (`abi_v3`; the helm
/// frees their buffers itself) and give the golden answers, every step.
#[test]
fn a_contact_plugin_built_against_the_0_1_2_release_still_loads_and_runs() {
    let lib_dir = build_released_plugin(INTO_API_RELEASE, "0.1.2", "bhv-contact");
    let cases = ["avd_spawn_two", "cutrange_spawn_pursuit", "shadow_contact"];
    let factory = released_contact_plugin_passes(&lib_dir, &cases);
    // No way to hand functions back: the helm frees them. This build's library has one.
    assert!(factory.recycler("BHV_AvoidCollision").is_none());
    let (current, _) = helm_mission::factory_for(&[plugin_dir().to_path_buf()]);
    assert!(current.recycler("BHV_AvoidCollision").is_some());
    // A built-in behavior's functions go back to the host's own spare storage.
    assert!(
        current.recycler("BHV_Waypoint").is_some(),
        "built in: the host's own recycler"
    );
}

/// The helm binary copied into `<root>/bin` with `libs` in `<root>/<lib_sub>`.
fn installed_helm(root: &Path, lib_sub: &str, libs: &[&str]) -> PathBuf {
    let bin = root.join("bin");
    let lib = root.join(lib_sub);
    std::fs::create_dir_all(&bin).unwrap();
    std::fs::create_dir_all(&lib).unwrap();
    let helm = bin.join("helm");
    common::place(Path::new(env!("CARGO_BIN_EXE_helm")), &helm).unwrap();
    for name in libs {
        common::place(&plugin_dir().join(name), &lib.join(name)).unwrap();
    }
    helm
}

fn check_plugins_mission(helm: &Path, dirs: Option<&str>) -> Output {
    let mut cmd = Command::new(helm);
    cmd.current_dir(workspace())
        .arg("check")
        .arg("missions/plugins/plugins.moos")
        .env_remove("IVP_HELM_BUNDLED_DIR");
    common::behavior_dirs(&mut cmd, dirs);
    cmd.output().expect("run helm check")
}

const ALL_FOUR: [&str; 4] = [
    "libbhv_constant_speed.so",
    "libbhv_constant_heading.so",
    "libbhv_constant_depth.so",
    "libbhv_station_keep.so",
];

#[test]
fn bundled_libraries_next_to_the_binary_need_no_configuration() {
    // An unchanged MOOS-IvP mission names BHV_ConstantSpeed with no ivp_behavior_dir:
    // the libraries shipped beside the helm are found.
    let root = scratch("bundled-beside");
    let helm = installed_helm(&root, "bin", &ALL_FOUR);
    // A shared object that is not ours is not opened.
    std::fs::write(root.join("bin/libother.so"), b"not a library").unwrap();
    let out = check_plugins_mission(&helm, None);
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    assert!(!t.contains("libother"), "{t}");

    // The installed layout: bin/helm and lib/ivp-helm/.
    let root = scratch("bundled-installed");
    let helm = installed_helm(&root, "lib/ivp-helm", &ALL_FOUR);
    let out = check_plugins_mission(&helm, None);
    assert!(out.status.success(), "{}", text(&out));

    // Without them, the error names where it looked.
    let root = scratch("bundled-none");
    let helm = installed_helm(&root, "bin", &ALL_FOUR[1..]);
    let out = check_plugins_mission(&helm, None);
    let t = text(&out);
    assert!(!out.status.success(), "{t}");
    assert!(t.contains("unknown behavior type BHV_ConstantSpeed"), "{t}");
    assert!(t.contains("(bundled)"), "{t}");
}

#[test]
fn configured_folders_come_before_the_bundled_ones() {
    // ConstantSpeed from the configured folder, the rest from beside the binary; the
    // type both offer is not a duplicate warning (the configured one is simply used).
    let root = scratch("bundled-order");
    let helm = installed_helm(&root, "bin", &ALL_FOUR);
    let mine = scratch("bundled-order-mine");
    common::place(&plugin_dir().join(ALL_FOUR[0]), &mine.join(ALL_FOUR[0])).unwrap();
    let out = check_plugins_mission(&helm, Some(mine.to_str().unwrap()));
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    assert!(!t.contains("offered by"), "{t}");
    let from_mine = format!("BHV_ConstantSpeed  ({}", mine.display());
    assert!(t.contains(&from_mine), "{t}");
    assert!(t.contains("BHV_StationKeep  ("), "{t}");
}
