//! `helm sim`: the real binary on every mission (end reasons, determinism, Monte Carlo
//! reproducibility, scenario errors), and through the library: the decisions of a run
//! equal those of the engine fed the same mail, and a long loiter keeps memory flat and
//! skips no iteration.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Mutex, OnceLock};

use helm_engine::posting::Value;
use helm_engine::Mail;
use helm_sim::{Prepared, RunOptions, StartShift};

mod common;

fn mission(name: &str) -> PathBuf {
    common::workspace().join("missions").join(name)
}

fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir(&format!("helm-sim-{tag}"))
}

fn helm_sim(args: &[&str], dirs: Option<&Path>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    cmd.arg("sim").args(args).env("IVP_HELM_BUNDLED_DIR", "");
    common::behavior_dirs(&mut cmd, dirs);
    cmd.output().expect("run helm sim")
}

fn text(o: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        o.status,
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn summary(dir: &Path) -> serde_json::Value {
    let t = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&t).expect("summary.json is JSON")
}

/// Run `missions/<name>` into a fresh folder; returns the folder.
fn sim_mission(name: &str, extra: &[&str], dirs: Option<&Path>) -> PathBuf {
    let out = temp_dir(name);
    let m = mission(name);
    let mut args = vec![
        m.to_str().expect("utf-8 path"),
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend(extra);
    let o = helm_sim(&args, dirs);
    assert!(o.status.success(), "{}", text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    let svg = out.join(format!("{name}.svg"));
    assert!(
        stdout.contains(&format!("picture: {}", svg.display())),
        "the output says where the picture is:\n{stdout}"
    );
    out
}

fn assert_end(dir: &Path, reason: &str) -> serde_json::Value {
    let s = summary(dir);
    assert_eq!(s["end_reason"], reason, "{s:#}");
    for key in [
        "sim_time_s",
        "wall_time_s",
        "distance_m",
        "iterations",
        "allstops",
        "behavior_errors",
        "waypoints_reached",
    ] {
        assert!(!s[key].is_null(), "summary.json lacks {key}");
    }
    s
}

#[test]
fn alpha_ends_mission_over_with_every_output() {
    let dir = sim_mission("alpha", &[], None);
    let s = assert_end(&dir, "mission-over");
    let t = s["sim_time_s"].as_f64().expect("number");
    assert!((270.0..300.0).contains(&t), "alpha takes about 285 s: {t}");
    assert_eq!(s["waypoints_reached"], 6, "five survey points and home");
    assert!(s["distance_m"].as_f64().expect("number") > 500.0);
    assert_eq!(s["behavior_errors"].as_array().map(Vec::len), Some(0));
    // The vehicle is home.
    let (x, y) = (
        s["end"]["x"].as_f64().unwrap(),
        s["end"]["y"].as_f64().unwrap(),
    );
    assert!(x.hypot(y + 20.0) < 3.0, "ends near 0,-20: {x},{y}");
    let alog = std::fs::read_to_string(dir.join("alpha.alog")).expect("alog");
    assert!(alog.starts_with("%%%%"), "pLogger header");
    for has in [
        "NAV_X",
        "DESIRED_HEADING",
        "IVPHELM_STATE",
        "VIEW_SEGLIST",
        "DB_CLIENTS",
    ] {
        assert!(alog.contains(has), "alog lacks {has}");
    }
    let svg = std::fs::read_to_string(dir.join("alpha.svg")).expect("svg");
    for has in [
        "<svg",
        "vehicle track",
        "start",
        "end",
        " m</text>",
        "alpha_waypt_survey",
    ] {
        assert!(svg.contains(has), "picture lacks {has}");
    }
}

#[test]
fn two_runs_give_bit_identical_logs() {
    let a = sim_mission("bravo", &[], None);
    let b = sim_mission("bravo", &[], None);
    for f in ["bravo.alog", "bravo.svg"] {
        let (x, y) = (
            std::fs::read(a.join(f)).expect("first"),
            std::fs::read(b.join(f)).expect("second"),
        );
        assert!(x.len() > 1000, "{f} is not trivially small");
        assert!(x == y, "{f} differs between two runs");
    }
    let (mut sa, mut sb) = (summary(&a), summary(&b));
    sa["wall_time_s"] = 0.into();
    sb["wall_time_s"] = 0.into();
    assert_eq!(sa, sb);
}

#[test]
fn bravo_modes_and_timer_end_with_mission_complete() {
    let dir = sim_mission("bravo", &[], None);
    assert_end(&dir, "MISSION=complete");
    let alog = std::fs::read_to_string(dir.join("bravo.alog")).expect("alog");
    let modes: Vec<&str> = alog
        .lines()
        .filter(|l| l.split_whitespace().nth(1) == Some("MODE"))
        .filter_map(|l| l.split_whitespace().nth(3))
        .collect();
    let mut seen: Vec<&str> = modes.clone();
    seen.dedup();
    assert_eq!(seen, ["INACTIVE", "ACTIVE:SURVEYING", "ACTIVE:RETURNING"]);
    // The poke came from uPokeDB at 5 s.
    assert!(alog
        .lines()
        .any(|l| l.starts_with("5.000") && l.contains("DEPLOY") && l.contains("uPokeDB")));
}

#[test]
fn charlie_loiters_then_returns() {
    let dir = sim_mission("charlie", &[], None);
    let s = assert_end(&dir, "MISSION=complete");
    let t = s["sim_time_s"].as_f64().expect("number");
    assert!(t > 240.0, "loitered 240 s first: {t}");
    let svg = std::fs::read_to_string(dir.join("charlie.svg")).expect("svg");
    assert!(svg.contains("<polygon"), "the loiter polygon is drawn");
}

/// The plugin libraries, built as helm/tests/plugins.rs builds them (same target
/// folder, so the build is shared).
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        const PLUGINS: [&str; 4] = [
            "bhv-constant-speed",
            "bhv-constant-heading",
            "bhv-constant-depth",
            "bhv-station-keep",
        ];
        common::lib_folder(
            &common::build_plugins(&PLUGINS),
            &PLUGINS,
            "sim-plugins-lib",
        )
    })
}

#[test]
fn plugins_mission_keeps_station_and_ends_with_mission_complete() {
    let dir = sim_mission("plugins", &[], Some(plugin_dir()));
    let s = assert_end(&dir, "MISSION=complete");
    let (x, y) = (
        s["end"]["x"].as_f64().unwrap(),
        s["end"]["y"].as_f64().unwrap(),
    );
    assert!(
        (x - 60.0).hypot(y - 60.0) < 12.0,
        "within the outer ring: {x},{y}"
    );
    assert!(
        (s["end"]["depth"].as_f64().unwrap() - 5.0).abs() < 0.1,
        "held 5 m"
    );
}

#[test]
fn plugins_mission_without_the_libraries_runs_nothing() {
    let out = temp_dir("noplugins");
    let m = mission("plugins");
    let o = helm_sim(
        &[
            m.to_str().unwrap(),
            "--out",
            out.join("x").to_str().unwrap(),
        ],
        None,
    );
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("plugins.bhv:9: unknown behavior type BHV_ConstantDepth"),
        "{err}"
    );
    assert!(!out.join("x").exists(), "nothing written");
}

/// A copy of alpha with `scenario` as its scenario.toml.
fn alpha_with_scenario(tag: &str, scenario: &str) -> PathBuf {
    let d = temp_dir(tag);
    for f in ["alpha.moos", "alpha.bhv"] {
        std::fs::copy(mission("alpha").join(f), d.join(f)).expect("copy");
    }
    std::fs::write(d.join("scenario.toml"), scenario).expect("write scenario");
    d
}

#[test]
fn bad_scenarios_name_file_and_line_and_run_nothing() {
    let cases = [
        (
            "[end]\nmax_time = 60\n\n[[poke]]\nat = -3\nvar = \"DEPLOY\"\nvalue = 1\n",
            5,
        ),
        (
            "[[poke]]\nat = 1\nvar = \"DEPLOY\"\nvalue = \"x\"\ncolour = 2\n",
            5,
        ),
        ("[vehicle]\nx = \"west\"\n", 2),
        ("[end\nmax_time = 1\n", 1),
    ];
    for (scenario, line) in cases {
        let d = alpha_with_scenario("bad", scenario);
        let out = d.join("out");
        let o = helm_sim(&[d.to_str().unwrap(), "--out", out.to_str().unwrap()], None);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        let want = format!("{}:{line}: ", d.join("scenario.toml").display());
        assert!(err.contains(&want), "wanted `{want}` in:\n{err}");
        assert!(!out.exists(), "nothing run: {}", out.display());
    }
}

#[test]
fn scenario_pokes_start_overrides_and_end_conditions_apply() {
    // alpha without its own DEPLOY (poked at 20 s instead), started elsewhere, ended by
    // its first waypoint flag.
    let d = alpha_with_scenario(
        "poke",
        "[[poke]]\nat = 20\nvar = \"DEPLOY\"\nvalue = \"true\"\n\
         [end]\nmax_time = 500\n[[end.when]]\nvar = \"SURVEY_HIT\"\nvalue = 1\n\
         [vehicle]\nx = 30\ny = -30\nheading = 90\n",
    );
    let bhv = std::fs::read_to_string(d.join("alpha.bhv")).unwrap();
    std::fs::write(
        d.join("alpha.bhv"),
        bhv.replace("initialize   DEPLOY = true", "initialize   DEPLOY = false"),
    )
    .unwrap();
    let out = d.join("out");
    let o = helm_sim(&[d.to_str().unwrap(), "--out", out.to_str().unwrap()], None);
    assert!(o.status.success(), "{}", text(&o));
    let s = summary(&out);
    assert_eq!(s["end_reason"], "SURVEY_HIT=1");
    assert_eq!(
        (s["start"]["x"].as_f64(), s["start"]["heading"].as_f64()),
        (Some(30.0), Some(90.0))
    );
    let alog = std::fs::read_to_string(out.join("alpha.alog")).unwrap();
    let first_desired = alog
        .lines()
        .find(|l| l.split_whitespace().nth(1) == Some("DESIRED_SPEED") && !l.ends_with(" 0"))
        .and_then(|l| l.split_whitespace().next()?.parse::<f64>().ok())
        .expect("drives at some point");
    assert!(
        first_desired > 20.0,
        "drives only after the poke: {first_desired}"
    );
}

#[test]
fn monte_carlo_table_is_reproducible() {
    let run = |seed: &str| {
        let out = temp_dir("mc");
        let m = mission("alpha");
        let o = helm_sim(
            &[
                m.to_str().unwrap(),
                "--runs",
                "6",
                "--seed",
                seed,
                "--jitter",
                "x=5,y=5,heading=20",
                "--out",
                out.to_str().unwrap(),
            ],
            None,
        );
        assert!(o.status.success(), "{}", text(&o));
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            stdout.contains("end reasons  mission-over 6 (100.0%)"),
            "{stdout}"
        );
        std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv")
    };
    let (a, b, c) = (run("11"), run("11"), run("12"));
    assert_eq!(a, b, "same seed, same table");
    assert_ne!(a, c, "another seed, another table");
    let lines: Vec<&str> = a.lines().collect();
    assert_eq!(lines.len(), 7, "header and six rows:\n{a}");
    assert!(lines[0].starts_with("run,seed,end_reason,sim_time_s,distance_m,"));
    assert!(lines[1].starts_with("0,11,mission-over,"));
    assert!(lines[6].starts_with("5,16,mission-over,"));
    // Perturbed starts: the runs differ.
    let distances: std::collections::BTreeSet<&str> = lines[1..]
        .iter()
        .filter_map(|l| l.split(',').nth(4))
        .collect();
    assert!(distances.len() > 1, "distances differ between runs:\n{a}");
}

/// The helm's mail, rebuilt from the bus log alone: what was posted in
/// `[since, until)` on the variables `subs`.
fn mail_between(log: &[Mail], since: f64, until: f64, subs: &[String]) -> Vec<Mail> {
    log.iter()
        .filter(|m| m.time >= since && m.time < until && subs.contains(&m.var))
        .cloned()
        .collect()
}

#[test]
fn decisions_equal_those_of_the_engine_fed_the_same_mail() {
    let prep = Prepared::load(&mission("alpha"), &[], None).expect("alpha loads");
    let out = prep
        .run(
            StartShift::default(),
            &RunOptions {
                record: true,
                ..RunOptions::default()
            },
        )
        .expect("runs");
    assert_eq!(out.end_reason, "mission-over");
    // The sim's decisions, per helm iteration time, from the log.
    let decided = |var: &str| -> Vec<(f64, f64)> {
        out.log
            .iter()
            .filter(|m| m.var == var && m.source == "pHelmIvP")
            .filter_map(|m| match m.value {
                Value::Num(v) => Some((m.time, v)),
                Value::Str(_) => None,
            })
            .collect()
    };
    // A fresh engine, its mail rebuilt from the log (NAV_* of the simulator, the
    // helm's own postings coming back, DB_CLIENTS), one helm period at a time.
    let t0 = helm_sim::run::SIM_EPOCH;
    let mut helm = prep.recipe.build();
    helm.startup(t0);
    let period = 1.0 / prep.helm_tick;
    let mut replay: Vec<(&str, f64, f64)> = Vec::new();
    let mut last = t0;
    for k in 1..=out.iterations {
        let now = t0 + k as f64 * period;
        let mail = mail_between(&out.log, last, now, helm.subscriptions());
        last = now;
        if !mail.is_empty() {
            helm.handle_mail(now, &mail);
        }
        for p in helm.iterate(now) {
            if let (Some(var), Value::Num(v)) = (
                ["DESIRED_HEADING", "DESIRED_SPEED"]
                    .into_iter()
                    .find(|v| *v == p.var),
                &p.value,
            ) {
                replay.push((var, now, *v));
            }
        }
    }
    for var in ["DESIRED_HEADING", "DESIRED_SPEED"] {
        let sim = decided(var);
        let eng: Vec<(f64, f64)> = replay
            .iter()
            .filter(|r| r.0 == var)
            .map(|r| (r.1, r.2))
            .collect();
        assert!(sim.len() > 1000, "{var}: {} decisions", sim.len());
        assert_eq!(sim, eng, "{var}: helm sim and the engine decide alike");
    }
}

/// Bytes allocated and not yet freed by the current thread: the soak runs on one
/// thread, so this is its own memory, whatever other tests of this binary do meanwhile
/// (they share the process RSS).
struct CountingAlloc;

thread_local! {
    static LIVE: std::cell::Cell<i64> = const { std::cell::Cell::new(0) };
}

fn count(delta: i64) {
    let _ = LIVE.try_with(|c| c.set(c.get() + delta));
}

// SAFETY: forwards to the system allocator; the counter has no destructor and does not
// allocate.
unsafe impl std::alloc::GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, l: std::alloc::Layout) -> *mut u8 {
        count(l.size() as i64);
        unsafe { std::alloc::System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: std::alloc::Layout) {
        count(-(l.size() as i64));
        unsafe { std::alloc::System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: std::alloc::Layout, new: usize) -> *mut u8 {
        count(new as i64 - l.size() as i64);
        unsafe { std::alloc::System.realloc(p, l, new) }
    }
}

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc;

fn live_bytes() -> i64 {
    LIVE.with(|c| c.get())
}

fn rss_kb() -> u64 {
    let s = std::fs::read_to_string("/proc/self/statm").unwrap_or_default();
    let pages: u64 = s
        .split_whitespace()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    pages * 4
}

/// Memory after the first simulated hour and at the end of a soak.
#[derive(Debug, Default, Clone, Copy)]
struct Mem {
    live_1h: i64,
    live_end: i64,
    rss_1h_kb: u64,
    rss_end_kb: u64,
}

/// Loiter forever for `hours` of simulated time.
fn soak(hours: f64) -> Mem {
    let d = temp_dir("soak");
    std::fs::copy(
        mission("charlie").join("charlie.moos"),
        d.join("charlie.moos"),
    )
    .unwrap();
    let bhv = std::fs::read_to_string(mission("charlie").join("charlie.bhv")).unwrap();
    std::fs::write(
        d.join("charlie.bhv"),
        bhv.replace("  duration  = 240\n", ""),
    )
    .unwrap();
    std::fs::write(d.join("scenario.toml"), "[end]\nmission_over = true\n").unwrap();
    let prep = Prepared::load(&d, &[], None).expect("loads");
    let max = hours * 3600.0;
    let marks = Mutex::new(Mem::default());
    let progress = |t: f64| {
        if let Ok(mut m) = marks.lock() {
            if m.rss_1h_kb == 0 && t >= 3600.0 {
                m.rss_1h_kb = rss_kb();
                m.live_1h = live_bytes();
            }
        }
    };
    let out = prep
        .run(
            StartShift::default(),
            &RunOptions {
                max_time: Some(max),
                progress: Some(&progress),
                ..RunOptions::default()
            },
        )
        .expect("runs");
    let (rss_end_kb, live_end) = (rss_kb(), live_bytes());
    assert_eq!(out.end_reason, "max-time", "loiters forever");
    assert_eq!(out.sim_time_s, max);
    // No iteration skipped: one per helm period.
    assert_eq!(out.iterations, (max * prep.helm_tick) as u64);
    assert!(
        out.observer.allstops.is_empty(),
        "{:?}",
        out.observer.allstops
    );
    let m = *marks.lock().unwrap();
    Mem {
        rss_end_kb,
        live_end,
        ..m
    }
}

/// Memory flat over a long loiter: the run's own live heap does not grow after the
/// first simulated hour. In CI (debug build) 3 simulated hours; the 24-hour soak, which
/// also checks the process RSS, is
/// `cargo test --release -p helm --test sim -- --ignored soak_24h`.
#[test]
fn soak_3h_memory_flat_no_iteration_skipped() {
    let m = soak(3.0);
    eprintln!("3 h soak: {m:?}");
    assert!(m.rss_1h_kb > 0 && m.live_1h > 0, "{m:?}");
    assert!(
        m.live_end - m.live_1h < 64 * 1024,
        "the run's heap grew: {m:?}"
    );
}

#[test]
#[ignore = "24 simulated hours: run with --release"]
fn soak_24h() {
    let t = std::time::Instant::now();
    let m = soak(24.0);
    eprintln!("24 h soak: {:.1} s wall, {m:?}", t.elapsed().as_secs_f64());
    assert!(
        m.live_end - m.live_1h < 64 * 1024,
        "the run's heap grew: {m:?}"
    );
    assert!(m.rss_end_kb < m.rss_1h_kb + 2048, "RSS grew: {m:?}");
}

/// FNV-1a, 64 bits: a fixed, dependency-free fingerprint of a file's bytes.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// The `.alog` of each repo mission is bit for bit what it was when these fingerprints
/// were recorded (first before the helm crate was split into engine, app and simulator
/// crates, and unchanged by the split; then again when the helm began posting
/// IVPHELM_LEDGER_SUMMARY every iteration, the only difference; plugins again when its
/// mission gained the timer that ends it clean; all four when IVPHELM_COMPLETED_COUNT
/// stopped being posted at the first decision, as the contact cases recorded it). A change that alters what the helm or the simulator does changes them; such
/// a change records the new values here, in its own commit, saying why.
#[test]
fn mission_alogs_are_bit_identical_to_the_recorded_ones() {
    let golden = [
        ("alpha", 0x2694_3c67_14fa_bf6b_u64),
        ("bravo", 0x4342_c22e_9e65_f5a8),
        ("charlie", 0xf800_8784_591d_5d35),
        ("plugins", 0xb44c_8f8d_590a_e9c7),
    ];
    let mut changed = Vec::new();
    for (name, want) in golden {
        // From the repo root with a relative path, as the README runs it: the `.alog`
        // names the `.bhv` file as given (PLOGGER_CMD), so the path must not vary.
        let out = temp_dir(&format!("golden-{name}"));
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
        cmd.current_dir(common::workspace())
            .args(["sim", &format!("missions/{name}"), "--out"])
            .arg(&out)
            .env("IVP_HELM_BUNDLED_DIR", "");
        let dirs = (name == "plugins").then(plugin_dir);
        common::behavior_dirs(&mut cmd, dirs);
        let o = cmd.output().expect("run helm sim");
        assert!(o.status.success(), "{}", text(&o));
        let alog = std::fs::read(out.join(format!("{name}.alog"))).expect("alog");
        let got = fnv1a(&alog);
        if got != want {
            changed.push(format!("{name}: {got:#018x} (recorded {want:#018x})"));
        }
    }
    assert!(changed.is_empty(), "alogs changed:\n{}", changed.join("\n"));
}

/// `--runs N --alogs` keeps every run's log beside `runs.csv`, and `helm view` opens the
/// folder as N runs with the Monte Carlo table (its rows in the logs' order).
#[test]
fn monte_carlo_logs_open_as_runs_in_helm_view() {
    let out = temp_dir("mc-alogs");
    let m = mission("alpha");
    let o = helm_sim(
        &[
            m.to_str().unwrap(),
            "--runs",
            "3",
            "--jitter",
            "x=5,y=5,heading=20",
            "--alogs",
            "--max-time",
            "60",
            "--out",
            out.to_str().unwrap(),
        ],
        None,
    );
    assert!(o.status.success(), "{}", text(&o));
    let runs = viewer::runs::open(&out).expect("the folder opens as runs");
    let names: Vec<&str> = runs.runs.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["run-0000.alog", "run-0001.alog", "run-0002.alog"]);
    assert!(
        runs.table.columns.iter().any(|c| c == "seed"),
        "{:?}",
        runs.table.columns
    );
    let run_col = runs.table.columns.iter().position(|c| c == "run").unwrap();
    let rows: Vec<&str> = runs
        .table
        .rows
        .iter()
        .map(|r| r[run_col].as_str())
        .collect();
    assert_eq!(rows, ["0", "1", "2"]);
    // Each log is its own run: the starts differ (jitter), so the logs differ.
    let a = std::fs::read(out.join("run-0000.alog")).unwrap();
    let b = std::fs::read(out.join("run-0001.alog")).unwrap();
    assert_ne!(a, b);
}
