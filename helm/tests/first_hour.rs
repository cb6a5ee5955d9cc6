//! Issue 20, a new user's first hour: each trap a new user fell into, driven through
//! the real binary as the user drove it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;

fn helm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(args)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .env_remove("IVP_BEHAVIOR_DIRS")
        .output()
        .expect("run helm")
}

fn summary(dir: &Path) -> serde_json::Value {
    let t = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&t).expect("summary.json is JSON")
}

/// missions/alpha copied to a fresh folder, its `.moos` passed through `edit`.
fn alpha_copy(tag: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    let dir = common::outside_dir(&format!("helm-first-hour-{tag}"));
    let src = common::workspace().join("missions/alpha");
    for f in ["alpha.bhv", "scenario.toml"] {
        std::fs::copy(src.join(f), dir.join(f)).expect("copy");
    }
    let moos = std::fs::read_to_string(src.join("alpha.moos")).expect("alpha.moos");
    std::fs::write(dir.join("alpha.moos"), edit(&moos)).expect("write");
    dir
}

/// alpha with its uSimMarine block replaced by `block` (the lines inside the braces).
fn alpha_with_sim_block(tag: &str, block: &str) -> PathBuf {
    let block = block.to_string();
    alpha_copy(tag, move |m| {
        let start = m.find("ProcessConfig = uSimMarine").expect("sim block");
        let end = start + m[start..].find('}').expect("block end") + 1;
        format!(
            "{}ProcessConfig = uSimMarine\n{{\n{block}\n}}\n{}",
            &m[..start],
            &m[end..]
        )
    })
}

fn sim(dir: &Path, extra: &[&str]) -> (Output, PathBuf) {
    let out = dir.join("out");
    let mut args = vec![
        "sim",
        dir.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend(extra);
    (helm(&args), out)
}

// ---- point 1: the simulator block is read strictly --------------------------------

#[test]
fn keyed_start_pos_sets_the_start_pose() {
    let dir = alpha_with_sim_block(
        "startpos",
        "  AppTick = 10\n  start_pos = x=100, y=-100, heading=90, speed=0\n  turn_rate = 20",
    );
    let (o, out) = sim(&dir, &["--max-time", "1"]);
    assert!(o.status.success(), "{}", common::text(&o));
    let s = summary(&out);
    assert_eq!(s["start"]["x"], 100.0, "{s}");
    assert_eq!(s["start"]["y"], -100.0, "{s}");
    assert_eq!(s["start"]["heading"], 90.0, "{s}");
}

#[test]
fn positional_start_pos_and_v22_block_name() {
    let dir = alpha_copy("v22", |m| {
        m.replace(
            "ProcessConfig = uSimMarine",
            "ProcessConfig = uSimMarineV22",
        )
        .replace("start_x       = 0\n", "START_POS = 30,-40,270,0\n")
    });
    let (o, out) = sim(&dir, &["--max-time", "1"]);
    assert!(o.status.success(), "{}", common::text(&o));
    let s = summary(&out);
    assert_eq!(
        (s["start"]["x"].as_f64(), s["start"]["y"].as_f64()),
        (Some(30.0), Some(-20.0)),
        "start_y after start_pos wins: {s}"
    );
}

#[test]
fn bad_sim_values_stop_the_run_and_check_names_file_and_line() {
    let dir = alpha_with_sim_block(
        "badsim",
        "  AppTick = 10\n  turn_rate = banana\n  start_heading = north\n  strat_x = 5",
    );
    let (o, out) = sim(&dir, &[]);
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(!out.join("summary.json").exists(), "nothing run: {t}");
    let moos = dir.join("alpha.moos");
    let lines: Vec<&str> = std::fs::read_to_string(&moos)
        .expect("read")
        .leak()
        .lines()
        .collect();
    let line_of = |needle: &str| lines.iter().position(|l| l.contains(needle)).expect("line") + 1;
    let stderr = String::from_utf8_lossy(&o.stderr);
    for (needle, what) in [("banana", "a number > 0"), ("north", "a number")] {
        let at = format!("{}:{}: ", moos.display(), line_of(needle));
        assert!(
            stderr
                .lines()
                .any(|l| l.contains(&at) && l.contains(what) && l.contains(needle)),
            "{at} {what}: {t}"
        );
    }
    let c = helm(&["check", moos.to_str().expect("utf-8")]);
    let ct = common::text(&c);
    assert_eq!(c.status.code(), Some(1), "{ct}");
    let stdout = String::from_utf8_lossy(&c.stdout);
    let at = format!("{}:{}: ", moos.display(), line_of("strat_x"));
    assert!(
        stdout.lines().any(|l| l.starts_with("warning: ")
            && l.contains(&at)
            && l.contains("did you mean `start_x`")),
        "{ct}"
    );
    assert_eq!(
        stdout.lines().filter(|l| l.starts_with("error: ")).count(),
        2,
        "{ct}"
    );
}

// ---- point 2: a helm that never drove says so and does not turn the vehicle -----------

#[test]
fn a_parked_helm_is_named_and_the_vehicle_is_not_turned() {
    let dir = alpha_copy("parked", |m| m.replace("start_in_drive = true", ""));
    let (o, out) = sim(&dir, &["--max-time", "30"]);
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    let first = stdout.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("PROBLEM: the helm stayed in PARK")
            && first.contains("start_in_drive = true")
            && first.contains("MOOS_MANUAL_OVERRIDE=false"),
        "{t}"
    );
    assert!(
        stdout.contains("helm PARK"),
        "the state is in the summary: {t}"
    );
    let s = summary(&out);
    assert_eq!(s["drove"], false, "{s}");
    assert_eq!(s["start"]["heading"], 180.0, "{s}");
    assert_eq!(
        s["end"]["heading"], 180.0,
        "the all-stop's heading 0 did not turn it: {s}"
    );
    let svg = std::fs::read_to_string(out.join("alpha.svg")).expect("svg");
    assert!(
        svg.contains("the helm stayed in PARK"),
        "the picture says it too"
    );
    let (strict, _) = sim(&dir, &["--max-time", "30", "--strict"]);
    assert_eq!(strict.status.code(), Some(3), "{}", common::text(&strict));
}

#[test]
fn a_driving_helm_has_no_problem_line() {
    let dir = alpha_copy("driving", |m| m.to_string());
    let (o, out) = sim(&dir, &["--strict"]);
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(!t.contains("PROBLEM"), "{t}");
    assert_eq!(summary(&out)["drove"], true);
}

// ---- point 3: a panic is counted apart, said first, and fails the run ------------------

#[test]
fn a_behavior_panic_is_said_first_and_exits_3() {
    let built = common::build_plugins(&["bhv-test-failure"]);
    let libs = common::lib_folder(&built, &["bhv-test-failure"], "first-hour-failure");
    let dir = alpha_copy("panic", |m| m.to_string());
    let bhv = std::fs::read_to_string(dir.join("alpha.bhv")).expect("bhv");
    std::fs::write(
        dir.join("alpha.bhv"),
        format!(
            "{bhv}\nBehavior = BHV_TestFailure\n{{\n  name = boom\n  pwt = 100\n  failure = panic_on_run\n  fail_at = 3\n}}\n"
        ),
    )
    .expect("write");
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args([
            "sim",
            dir.to_str().expect("utf-8"),
            "--out",
            out.to_str().expect("utf-8"),
        ])
        .env("IVP_HELM_BUNDLED_DIR", "")
        .env("IVP_BEHAVIOR_DIRS", &libs)
        .output()
        .expect("run helm");
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(3), "{t}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout
            .lines()
            .next()
            .unwrap_or_default()
            .starts_with("PROBLEM: 1 behavior panic(s)"),
        "{t}"
    );
    let s = summary(&out);
    assert_eq!(
        s["behavior_panics"].as_array().map(Vec::len),
        Some(1),
        "{s}"
    );
}

// ---- point 4: every shipped mission ends clean ------------------------------------------

#[test]
fn every_shipped_mission_ends_clean_under_strict() {
    let built = common::build_plugins(&[
        "bhv-constant-speed",
        "bhv-constant-heading",
        "bhv-constant-depth",
        "bhv-station-keep",
        // missions/uuv
        "bhv-depth",
        "bhv-region",
        // missions/encounter and missions/fleet: BHV_AvoidCollision.
        "bhv-contact",
        // missions/harbour: BHV_AvoidObstacleV24; missions/colregs: BHV_AvdColregsV22.
        "bhv-obstacle",
        "bhv-colregs",
    ]);
    let mut seen = 0;
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(common::workspace().join("missions"))
        .expect("missions/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    for m in dirs {
        let out = common::outside_dir("helm-first-hour-clean");
        let o = Command::new(env!("CARGO_BIN_EXE_helm"))
            .args([
                "sim",
                m.to_str().expect("utf-8"),
                "--strict",
                "--out",
                out.to_str().expect("utf-8"),
            ])
            .env("IVP_HELM_BUNDLED_DIR", &built)
            .env_remove("IVP_BEHAVIOR_DIRS")
            .output()
            .expect("run helm");
        let t = common::text(&o);
        assert_eq!(o.status.code(), Some(0), "{}: {t}", m.display());
        let s = summary(&out);
        assert_eq!(
            s["behavior_errors"].as_array().map(Vec::len),
            Some(0),
            "{}: {s}",
            m.display()
        );
        let failures: Vec<&serde_json::Value> = s["allstops"]
            .as_array()
            .expect("allstops")
            .iter()
            .filter(|a| a["reason"] != "NothingToDo")
            .collect();
        assert!(failures.is_empty(), "{}: {s}", m.display());
        seen += 1;
    }
    assert!(seen >= 4, "the four missions at least: {seen}");
}

// ---- point 5: .bhv problems say which, all of them, in line order ----------------------

const PROBLEM_BHV: &str = "initialize DEPLOY = true

Behavior = BHV_Loiter
{
  name      = loiter
  pwt       = -1
  condition = DEPLOY = true
  spede     = 3
  polygon   = pts={0,0:20,0:5,5:0,20}
}

Behavior = BHV_Waypiont
{
  name   = go
  points = 0,0
}
";

#[test]
fn bhv_problems_say_which_in_one_pass_in_line_order() {
    let dir = alpha_copy("bhvwords", |m| m.to_string());
    std::fs::write(dir.join("alpha.bhv"), PROBLEM_BHV).expect("write");
    let moos = dir.join("alpha.moos");
    let o = helm(&["check", moos.to_str().expect("utf-8")]);
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    let bhv = dir.join("alpha.bhv");
    let at = |n: usize| format!("{}:{n}: ", bhv.display());
    let stdout = String::from_utf8_lossy(&o.stdout);
    let problems: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with(&bhv.display().to_string()))
        .collect();
    assert_eq!(problems.len(), 4, "{t}");
    assert!(
        problems[0].starts_with(&at(6))
            && problems[0].contains("bad value: pwt = -1 (expected a number >= 0)"),
        "{t}"
    );
    assert!(
        problems[1].starts_with(&at(8))
            && problems[1].contains("unknown parameter of BHV_Loiter: spede = 3")
            && problems[1].contains("did you mean `speed`?"),
        "{t}"
    );
    assert!(
        problems[2].starts_with(&at(9))
            && problems[2].contains("bad value: polygon = pts={0,0:20,0:5,5:0,20}")
            && problems[2].contains("convex polygon"),
        "{t}"
    );
    assert!(
        problems[3].starts_with(&at(12))
            && problems[3]
                .contains("unknown behavior type BHV_Waypiont (did you mean BHV_Waypoint?)"),
        "{t}"
    );
}

/// A MOOS-IvP user's mission naming a real helm type this helm lacks hears that the type
/// is real (not a typo) and how a library for it would load.
#[test]
fn a_real_helm_type_we_lack_is_named_as_such() {
    let dir = alpha_copy("realtype", |m| m.to_string());
    let bhv = "initialize DEPLOY = true\n\nBehavior = BHV_PeriodicSpeed\n{\n  name = ps\n}\n";
    std::fs::write(dir.join("alpha.bhv"), bhv).expect("write");
    let moos = dir.join("alpha.moos");
    let o = helm(&["check", moos.to_str().expect("utf-8")]);
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    let line = t
        .lines()
        .find(|l| l.contains("alpha.bhv:3: unknown behavior type BHV_PeriodicSpeed"))
        .unwrap_or_else(|| panic!("no line for the type:\n{t}"));
    assert!(
        line.contains("the real helm has this type and this helm does not yet")
            && line.contains("IVP_BEHAVIOR_DIRS"),
        "{line}"
    );
}

#[test]
fn a_bhv_given_as_mission_and_a_missing_bhv_say_so() {
    let dir = alpha_copy("bhvmission", |m| {
        m.replace("behaviors    = alpha.bhv", "behaviors    = alpah.bhv")
    });
    let bhv = dir.join("alpha.bhv");
    for cmd in ["check", "sim", "run"] {
        let o = helm(&[cmd, bhv.to_str().expect("utf-8")]);
        let t = common::text(&o);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {t}");
        assert!(
            t.contains("this is a behavior file (.bhv); give the mission file (.moos)"),
            "{cmd}: {t}"
        );
    }
    let moos = dir.join("alpha.moos");
    let o = helm(&["check", moos.to_str().expect("utf-8")]);
    let t = common::text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    let line = std::fs::read_to_string(&moos)
        .expect("read")
        .lines()
        .position(|l| l.contains("alpah.bhv"))
        .expect("line")
        + 1;
    assert!(
        t.contains(&format!(
            "{}:{line}: behaviors = alpah.bhv: Could not find File: ",
            moos.display()
        )),
        "{t}"
    );
}

// ---- point 6: loader messages give the whole reason ------------------------------------

#[test]
fn a_library_that_cannot_be_opened_gives_the_whole_reason() {
    let libs = common::outside_dir("helm-first-hour-fake-lib");
    std::fs::write(libs.join("libfake.so"), "not a library").expect("write");
    let moos = common::workspace().join("missions/alpha/alpha.moos");
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["check", moos.to_str().expect("utf-8")])
        .env("IVP_HELM_BUNDLED_DIR", "")
        .env("IVP_BEHAVIOR_DIRS", &libs)
        .output()
        .expect("run helm");
    let t = common::text(&o);
    let line = t
        .lines()
        .find(|l| l.contains("skipped"))
        .unwrap_or_else(|| panic!("{t}"));
    let lib = libs.join("libfake.so").display().to_string();
    // The path the library was opened at and the system's reason after it.
    let after = line
        .split_once("Could not open library at:")
        .map(|(_, r)| r.trim())
        .unwrap_or_default();
    assert!(after.starts_with(&lib), "{t}");
    assert!(
        after.len() > lib.len() + 5,
        "a reason follows the path: {t}"
    );
}

// ---- point 7: one exit code per kind of failure, documented -----------------------------

#[test]
fn a_missing_file_is_exit_2_for_every_command_and_help_lists_the_codes() {
    let missing = "/no/such/mission.moos";
    for args in [
        vec!["check", missing],
        vec!["sim", missing],
        vec!["run", missing],
        vec!["conform", "/no/such/case.toml"],
    ] {
        let o = helm(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", common::text(&o));
    }
    let help = helm(&["--help"]);
    let h = String::from_utf8_lossy(&help.stdout);
    for code in [
        "0  done",
        "1  the mission is wrong",
        "2  usage",
        "3  the run went wrong",
        "4  the environment",
    ] {
        assert!(h.contains(code), "{code}: {h}");
    }
}

// ---- point 11: a CLI without surprises ---------------------------------------------------

#[test]
fn check_takes_a_folder_and_conform_recurses_and_refuses_nothing() {
    let o = helm(&[
        "check",
        common::workspace()
            .join("missions/alpha")
            .to_str()
            .expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o));
    let empty = common::outside_dir("helm-first-hour-no-cases");
    let o = helm(&["conform", empty.to_str().expect("utf-8")]);
    assert_eq!(o.status.code(), Some(2), "{}", common::text(&o));
    assert!(common::text(&o).contains("no conformance cases"));
    // The repository's conformance/ holds the helm cases one folder down.
    let o = helm(&[
        "conform",
        common::workspace()
            .join("conformance")
            .to_str()
            .expect("utf-8"),
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    let last = out.lines().last().unwrap_or_default();
    let passed: usize = last
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    assert!(passed > 0, "{}", common::text(&o));
}

#[test]
fn help_is_one_text_and_a_phelmivp_link_refuses_subcommands() {
    let a = helm(&["-help"]);
    let b = helm(&["--help"]);
    assert_eq!(a.stdout, b.stdout);
    let h = String::from_utf8_lossy(&b.stdout);
    assert!(
        h.contains("IVP_BEHAVIOR_DIRS")
            && h.contains("HELM_VERBOSE")
            && h.contains("helm sim missions/alpha"),
        "{h}"
    );
    let dir = common::outside_dir("helm-first-hour-link");
    let link = dir.join("pHelmIvP");
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_helm"), &link).expect("link");
    let o = Command::new(&link)
        .args(["sim", "missions/alpha"])
        .output()
        .expect("run the link");
    assert_eq!(o.status.code(), Some(2), "{}", common::text(&o));
    assert!(common::text(&o).contains("run it as `helm sim ...`"));
}

#[test]
fn run_embedded_takes_a_mission_folder() {
    // alpha on a port of its own, copied into a folder: the folder is the argument.
    let port = common::free_port();
    let dir = alpha_copy("run-dir", |m| {
        m.replace("ServerPort = 9000", &format!("ServerPort = {port}"))
    });
    let alog = dir.join("run.alog");
    let o = helm(&[
        "run",
        "--embedded",
        dir.to_str().expect("utf-8"),
        "--duration",
        "20",
        "--quiet",
        "--alog",
        alog.to_str().expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o));
    let log = std::fs::read_to_string(&alog).expect("the run wrote its log");
    assert!(
        log.lines().any(|l| l.contains("DESIRED_SPEED")),
        "the helm of the folder's mission ran"
    );
}

/// `helm run --quiet` and `HELM_VERBOSE=quiet` print the last line alone: no library
/// report, no embedded-DB line, no heartbeat; `HELM_VERBOSE=terse` keeps the heartbeat.
#[test]
fn run_quiet_is_quiet_and_helm_verbose_is_read() {
    let port = common::free_port();
    let dir = alpha_copy("run-quiet", |m| {
        m.replace("ServerPort = 9000", &format!("ServerPort = {port}"))
    });
    let d = dir.to_str().expect("utf-8");
    let run = |flag: Option<&str>, env: Option<&str>| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_helm"));
        c.args(["run", "--embedded", d, "--duration", "4"]);
        if let Some(f) = flag {
            c.arg(f);
        }
        match env {
            Some(v) => c.env("HELM_VERBOSE", v),
            None => c.env_remove("HELM_VERBOSE"),
        };
        c.output().expect("run helm")
    };
    for (flag, env) in [(Some("--quiet"), None), (None, Some("quiet"))] {
        let o = run(flag, env);
        assert_eq!(o.status.code(), Some(0), "{}", common::text(&o));
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("final:"), "the last line stays: {out}");
        for noisy in ["Embedded MOOSDB", "Loading behavior", "$", "*"] {
            assert!(
                !out.lines()
                    .any(|l| !l.starts_with("final:") && l.contains(noisy)),
                "{flag:?}/{env:?}: {noisy:?} printed: {out}"
            );
        }
    }
    let o = run(None, Some("terse"));
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains('$') || out.contains('*'),
        "terse keeps the heartbeat: {out}"
    );
    let o = run(None, Some("loud"));
    assert_eq!(
        o.status.code(),
        Some(2),
        "a bad HELM_VERBOSE is a usage error"
    );
    assert!(common::text(&o).contains("HELM_VERBOSE"));
}

// ---- point 12: Ctrl-C during a Monte Carlo keeps the finished runs ----------------------

#[test]
fn ctrl_c_during_a_monte_carlo_keeps_the_finished_runs() {
    let dir = alpha_copy("interrupt", |m| m.to_string());
    let out = dir.join("mc");
    let child = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args([
            "sim",
            dir.to_str().expect("utf-8"),
            "--runs",
            "200",
            "--out",
        ])
        .arg(&out)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .env_remove("IVP_BEHAVIOR_DIRS")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start helm sim --runs 200");
    let (o, lines, progressed) = common::interrupt_after_first_run(child);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(130), "{stdout}\n{lines:?}");
    // "alpha: interrupted after N of 200 runs", and runs.csv holds those N rows.
    let said = stdout
        .lines()
        .find_map(|l| l.strip_prefix("alpha: interrupted after "))
        .unwrap_or_else(|| panic!("{stdout}"));
    let n: usize = said
        .strip_suffix(" of 200 runs")
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{said}"));
    assert!(n as u64 >= progressed && n < 200, "{n} after {progressed}");
    let csv = std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv kept");
    assert_eq!(
        csv.lines().count(),
        n + 1,
        "header and one row per finished run"
    );
    let summary = std::fs::read_to_string(out.join("summary.txt")).expect("summary.txt");
    assert!(summary.starts_with(&format!("alpha: interrupted after {n} of 200 runs")));
    assert!(
        !out.join("runs.svg").exists(),
        "no picture of a Monte Carlo that did not finish"
    );
}

// ---- point 14 (rest): NothingToDo at a mission's normal end is no failure ----------------

#[test]
fn nothing_to_do_at_the_normal_end_is_not_a_failure() {
    let dir = alpha_copy("nothing-to-do", |m| m.to_string());
    let (o, out) = sim(&dir, &[]);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(0), "{stdout}");
    // alpha's helm says NothingToDo once its waypoints are done: listed apart.
    let stops = summary(&out)["allstops"].to_string();
    assert!(stops.contains("NothingToDo"), "{stops}");
    let line = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("all-stops:"))
        .unwrap_or_default();
    assert!(
        line.contains("all-stops: none (idle, no behavior active: NothingToDo at"),
        "{stdout}"
    );
    let svg = std::fs::read_to_string(out.join("alpha.svg")).expect("svg");
    assert!(
        svg.contains(" 0 all-stop(s)"),
        "the picture counts no failure"
    );
    // A Monte Carlo does not count it as a run with an all-stop.
    let (o, _) = sim(&dir, &["--runs", "2"]);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(stdout.contains("runs with all-stop  none"), "{stdout}");
}

// ---- point 10: a helm copied alone says where its bundled libraries belong -------------

#[test]
fn a_helm_copied_alone_says_its_bundled_libraries_are_missing() {
    let dir = common::outside_dir("helm-first-hour-alone");
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).expect("mkdir");
    let helm = bin.join("helm");
    std::fs::copy(env!("CARGO_BIN_EXE_helm"), &helm)
        .expect("copy the binary, as cargo install does");
    let mission = common::workspace().join("missions/plugins");
    let out = dir.join("out");
    for args in [
        vec!["check"],
        vec!["sim", "--out", out.to_str().expect("utf-8")],
    ] {
        let cmd = args[0];
        let o = Command::new(&helm)
            .args(&args)
            .arg(&mission)
            .env_remove("IVP_HELM_BUNDLED_DIR")
            .env_remove("IVP_BEHAVIOR_DIRS")
            .output()
            .expect("run the copied helm");
        let t = common::text(&o);
        assert_eq!(o.status.code(), Some(1), "{cmd}: {t}");
        let said = format!(
            "BHV_ConstantSpeed (directories searched: {} (bundled)): it is one of the helm's \
             shipped libraries: bundled behavior libraries not found beside {} (nor in \
             ../lib/ivp-helm from it); set IVP_BEHAVIOR_DIRS=",
            bin.display(),
            helm.display()
        );
        assert!(t.contains(&said), "{cmd}: {t}");
        assert!(!t.contains("did you mean BHV_ConstantSpeed"), "{t}");
    }
    // Beside the libraries it finds them: the same mission is fine.
    let four = [
        "bhv-constant-speed",
        "bhv-constant-heading",
        "bhv-constant-depth",
        "bhv-station-keep",
    ];
    let built = common::build_plugins(&four);
    for p in four {
        let name = common::lib_name(p);
        common::place(&built.join(&name), &bin.join(&name)).expect("place a library");
    }
    let o = Command::new(&helm)
        .args(["check", mission.to_str().expect("utf-8")])
        .env_remove("IVP_HELM_BUNDLED_DIR")
        .env_remove("IVP_BEHAVIOR_DIRS")
        .output()
        .expect("run the copied helm");
    assert_eq!(o.status.code(), Some(0), "{}", common::text(&o));
}
