//! `helm run`: the real binary on the alpha mission with an embedded MOOSDB and the
//! uSimMarine simulator, sped up with MOOSTimeWarp; a MALCONFIG mission; a busy port;
//! and (through the library, with an alog) what was actually posted.
//!
//! Every run gets its own free port and its own copy of the mission in a temp folder.

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{free_port, ALPHA_BHV, ALPHA_MOOS};

mod common;

/// The alpha mission with its own port and time warp (and `bhv` as its behavior file).
fn mission(tag: &str, port: u16, warp: f64, bhv: &str) -> PathBuf {
    let dir = common::temp_dir(&format!("helm-run-{tag}"));
    let text = common::with_params(
        ALPHA_MOOS,
        &[
            ("ServerPort", port.to_string()),
            ("MOOSTimeWarp", warp.to_string()),
        ],
    );
    std::fs::write(dir.join("alpha.moos"), text).expect("write mission");
    std::fs::write(dir.join("alpha.bhv"), bhv).expect("write bhv");
    dir.join("alpha.moos")
}

/// Run `helm run --embedded MISSION ARGS`, killing it if it outlives `limit`; its output
/// with stdout and stderr as text.
fn run_embedded(mission: &Path, args: &[&str], limit: Duration) -> (Output, String, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["run", "--embedded"])
        .arg(mission)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start helm");
    let t0 = Instant::now();
    loop {
        match child.try_wait().expect("wait helm") {
            Some(_) => break,
            None if t0.elapsed() > limit => {
                let _ = child.kill();
                let out = child.wait_with_output().expect("collect output");
                panic!(
                    "helm run did not end within {limit:?}\nstdout:\n{}\nstderr:\n{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                );
            }
            None => std::thread::sleep(Duration::from_millis(50)),
        }
    }
    let out = child.wait_with_output().expect("collect output");
    let (stdout, stderr) = text(&out);
    (out, stdout, stderr)
}

/// The `key=value` words of the `final:` line.
fn final_fields(stdout: &str) -> Vec<(String, String)> {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("final:"))
        .unwrap_or_else(|| panic!("no final line in:\n{stdout}"));
    line.split_whitespace()
        .filter_map(|w| w.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

fn field<'a>(f: &'a [(String, String)], key: &str) -> &'a str {
    f.iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
        .unwrap_or_else(|| panic!("no {key}= in {f:?}"))
}

fn num(f: &[(String, String)], key: &str) -> f64 {
    field(f, key)
        .parse()
        .unwrap_or_else(|_| panic!("{key} not a number in {f:?}"))
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The whole alpha mission (survey, return home) at warp 25: about 285 s of MOOS
/// time, ~12 s of real time. The run ends by itself once the mission is over.
#[test]
fn embedded_alpha_mission_completes_and_returns_home() {
    let m = mission("alpha", free_port(), 25.0, ALPHA_BHV);
    let (out, stdout, stderr) = run_embedded(
        &m,
        &["--duration", "600", "--quiet"],
        Duration::from_secs(90),
    );
    assert!(
        out.status.success(),
        "exit {:?}\n{stdout}\n{stderr}",
        out.status
    );
    assert!(
        !stdout.contains('$'),
        "--quiet prints no heartbeat:\n{stdout}"
    );
    let f = final_fields(&stdout);
    assert_eq!(field(&f, "reason"), "mission-over", "{stdout}");
    assert_eq!(field(&f, "state"), "DRIVE");
    assert_eq!(field(&f, "allstop"), "NothingToDo");
    assert!(num(&f, "desired_posts") > 100.0, "{f:?}");
    // Home is the return point 0,-20 (capture radius 2, plus the stop).
    let (x, y) = (num(&f, "x"), num(&f, "y"));
    assert!(x.abs() < 4.0 && (y + 20.0).abs() < 4.0, "not home: {x},{y}");
    // It took the survey's time, not a shortcut: > 200 MOOS s.
    assert!(num(&f, "time") > 200.0, "{f:?}");
}

/// A short run with the heartbeat: `$` per DRIVE iteration and the vehicle moving.
#[test]
fn embedded_run_stops_at_duration_with_heartbeat() {
    let m = mission("short", free_port(), 10.0, ALPHA_BHV);
    let (out, stdout, stderr) = run_embedded(&m, &["--duration", "30"], Duration::from_secs(60));
    assert!(
        out.status.success(),
        "exit {:?}\n{stdout}\n{stderr}",
        out.status
    );
    assert!(stdout.contains("$$$$"), "heartbeat:\n{stdout}");
    let f = final_fields(&stdout);
    assert_eq!(field(&f, "reason"), "duration");
    assert_eq!(field(&f, "state"), "DRIVE");
    // Start 0,-20 heading 180; the first waypoint is 60,-40: it went east and south.
    let (x, y) = (num(&f, "x"), num(&f, "y"));
    assert!(
        x > 10.0 && y < -20.0,
        "vehicle did not head for 60,-40: {x},{y}"
    );
    let t = num(&f, "time");
    assert!((30.0..32.0).contains(&t), "stopped at {t}");
}

/// A bad `.bhv` line: the problem is reported with file and line, the MALCONFIG box is
/// shown, nothing is ever commanded, and the run ends with exit 1 at --duration.
#[test]
fn malconfig_mission_reports_file_line_and_never_drives() {
    let bad = ALPHA_BHV.replacen(
        "  speed          = 2\n",
        "  speed          = 2\n  bogus_param = 7\n",
        1,
    );
    let line = bad
        .lines()
        .position(|l| l.contains("bogus_param"))
        .expect("bad line present")
        + 1;
    let m = mission("malconfig", free_port(), 10.0, &bad);
    let (out, stdout, stderr) =
        run_embedded(&m, &["--duration", "5", "--quiet"], Duration::from_secs(60));
    assert_eq!(out.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(stderr.contains(&format!("alpha.bhv:{line}:")), "{stderr}");
    assert!(stderr.contains("bogus_param"), "{stderr}");
    assert!(stderr.contains("NEVER DRIVE"), "{stderr}");
    assert!(stderr.contains("MALCONFIG for the whole run"), "{stderr}");
    let f = final_fields(&stdout);
    assert_eq!(field(&f, "state"), "MALCONFIG");
    assert_eq!(field(&f, "desired_posts"), "0");
    assert_eq!((field(&f, "x"), field(&f, "y")), ("0.00", "-20.00"));
}

/// With the port taken, `--embedded` says so and exits non-zero at once.
#[test]
fn busy_port_is_a_clear_error() {
    let taken = TcpListener::bind("127.0.0.1:0").expect("bind");
    let port = taken.local_addr().expect("addr").port();
    let m = mission("busy", port, 1.0, ALPHA_BHV);
    let (out, stdout, stderr) = run_embedded(&m, &["--quiet"], Duration::from_secs(20));
    assert!(!out.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains(&format!("port {port} is busy")), "{stderr}");
    drop(taken);
}

fn alog_entries(path: &Path) -> Vec<moos::alog::AlogEntry> {
    let f = std::fs::File::open(path).expect("alog written");
    moos::alog::read(std::io::BufReader::new(f))
        .expect("alog parses")
        .entries
}

fn options(m: &Path) -> helm_app::RunOptions {
    helm_app::RunOptions {
        mission: m.to_path_buf(),
        bhv: Vec::new(),
        alias: "pHelmIvP".into(),
        embedded: true,
        duration: Some(20.0),
        quiet: true,
    }
}

/// The alog holds the helm's postings (with source-aux) and the simulator's NAV_*.
#[test]
fn alog_records_postings_and_mail() {
    let m = mission("alog", free_port(), 10.0, ALPHA_BHV);
    let log = m.with_file_name("run.alog");
    let extras = helm_app::RunExtras {
        alog: Some(log.clone()),
        ..Default::default()
    };
    helm_app::run_with(&options(&m), &extras).expect("run ends well");
    let e = alog_entries(&log);
    let has = |key: &str, src: &str| e.iter().any(|x| x.key == key && x.source == src);
    assert!(has("NAV_X", "uSimMarine"));
    assert!(has("DESIRED_HEADING", "pHelmIvP"));
    assert!(has("IVPHELM_REGISTER", "pHelmIvP"));
    assert!(e
        .iter()
        .any(|x| x.key == "DEPLOY" && x.source_aux == "HELM_VAR_INIT"));
    assert!(e
        .iter()
        .any(|x| x.key == "IVPHELM_STATE"
            && x.value == moos::alog::AlogValue::String("DRIVE".into())));
    assert!(e.iter().any(|x| x.key == "IVPHELM_BHV_ACTIVE"
        && x.value == moos::alog::AlogValue::String("waypt_survey".into())));
}

/// A MALCONFIG helm posts IVPHELM_STATE=MALCONFIG and never a DESIRED_*.
#[test]
fn alog_of_malconfig_run_has_no_desired() {
    let bad = ALPHA_BHV.replacen("  pwt       = 100\n", "  pwt       = 100\n  nonsense\n", 1);
    let m = mission("alog-bad", free_port(), 10.0, &bad);
    let log = m.with_file_name("run.alog");
    let extras = helm_app::RunExtras {
        alog: Some(log.clone()),
        ..Default::default()
    };
    let r = helm_app::run_with(&options(&m), &extras);
    assert!(
        matches!(r, Err(helm_app::AppError::Malconfig { .. })),
        "{r:?}"
    );
    let e = alog_entries(&log);
    assert!(e.iter().any(|x| x.key == "IVPHELM_STATE"
        && x.value == moos::alog::AlogValue::String("MALCONFIG".into())));
    assert!(
        !e.iter().any(|x| x.key.starts_with("DESIRED_")),
        "a MALCONFIG helm commanded something"
    );
}
