//! `helm sim` on fleets (issue 23), through the real binary: missions/encounter avoids
//! (and collides when avoidance is off), runs are bit-identical, the comms model's range
//! and drops act, a malformed NODE_REPORT is counted, bad scenarios and flags are refused
//! with their file:line or flag before anything runs, and shards merged equal one run.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

mod common;

fn mission(name: &str) -> PathBuf {
    common::workspace().join("missions").join(name)
}

/// The contact plugins (BHV_AvoidCollision), built once.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        const P: [&str; 1] = ["bhv-contact"];
        common::lib_folder(&common::build_plugins(&P), &P, "fleet-plugins-lib")
    })
}

fn helm_sim(args: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    cmd.arg("sim").args(args).env("IVP_HELM_BUNDLED_DIR", "");
    common::behavior_dirs(&mut cmd, Some(plugin_dir()));
    cmd.output().expect("run helm sim")
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn summary(dir: &Path) -> serde_json::Value {
    let t = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&t).expect("summary.json is JSON")
}

/// A copy of missions/encounter with `scenario` appended to its scenario.toml (or
/// replacing it, when `replace`).
fn encounter_copy(tag: &str, scenario: &str, replace: bool) -> PathBuf {
    let d = common::temp_dir(&format!("fleet-{tag}"));
    for e in std::fs::read_dir(mission("encounter")).expect("read missions/encounter") {
        let p = e.expect("entry").path();
        std::fs::copy(&p, d.join(p.file_name().expect("name"))).expect("copy");
    }
    let base = std::fs::read_to_string(d.join("scenario.toml")).expect("scenario");
    let text = if replace {
        scenario.to_string()
    } else {
        base + scenario
    };
    std::fs::write(d.join("scenario.toml"), text).expect("write scenario");
    d
}

fn run_ok(dir: &Path, extra: &[&str]) -> (PathBuf, serde_json::Value, String) {
    let out = common::temp_dir("fleet-out");
    let mut args = vec![s(dir), "--out", s(&out)];
    args.extend(extra);
    let o = helm_sim(&args);
    assert!(o.status.success(), "{}", common::text(&o));
    let sum = summary(&out);
    (out, sum, String::from_utf8_lossy(&o.stdout).into_owned())
}

#[test]
fn encounter_spawns_avoidance_and_keeps_clear() {
    let (out, sum, stdout) = run_ok(&mission("encounter"), &[]);
    assert_eq!(sum["end_reason"], "mission-over", "{sum:#}");
    assert_eq!(sum["collisions"], 0, "{sum:#}");
    assert_eq!(sum["near_misses"], 0, "{sum:#}");
    // Without avoidance the two would pass through each other (0 m; see below).
    let closest = sum["closest_m"].as_f64().expect("closest_m");
    assert!(
        closest > 8.0,
        "closest approach {closest} m, under min_util_cpa_dist"
    );
    for v in sum["vehicles"].as_array().expect("vehicles") {
        assert!(v["spawned_behaviors"].as_u64() >= Some(1), "{v:#}");
        assert!(v["node_reports_received"].as_u64() > Some(50), "{v:#}");
        assert_eq!(v["malformed_node_reports"], 0);
        assert!(v["end"]["y"].as_f64().is_some());
    }
    let comms = &sum["comms"];
    assert!(
        comms["out_of_range"].as_u64() > Some(0),
        "they start 170 m apart: {comms}"
    );
    for f in ["abe.alog", "ben.alog", "encounter.svg"] {
        assert!(out.join(f).is_file(), "{f} written");
    }
    let abe = std::fs::read_to_string(out.join("abe.alog")).expect("abe.alog");
    assert!(
        abe.contains("CONTACT_INFO") && abe.contains("bname=avd_ben"),
        "the alert spawned avd_ben"
    );
    assert!(abe.contains("NODE_REPORT_LOCAL") && abe.contains("NAME=abe,X="));
    let svg = std::fs::read_to_string(out.join("encounter.svg")).expect("svg");
    assert!(
        svg.contains("dodgerblue") && svg.contains("orangered"),
        "tracks in their colours"
    );
    assert!(
        svg.contains(" m abe-ben at "),
        "the closest approach is marked"
    );
    assert!(stdout.contains("collisions (< 3 m) 0"), "{stdout}");
}

#[test]
fn encounter_without_avoidance_collides_and_runs_are_bit_identical() {
    let d = encounter_copy(
        "noavoid",
        "\n[[poke]]\nat = 0\nvar = \"AVOID\"\nvalue = false\n",
        false,
    );
    let (a, sum, _) = run_ok(&d, &[]);
    assert!(sum["collisions"].as_u64() >= Some(1), "{sum:#}");
    assert!(sum["closest_m"].as_f64() < Some(3.0), "{sum:#}");
    assert_eq!(sum["encounters"], 1, "one event, counted once: {sum:#}");
    let (b, _, _) = run_ok(&d, &[]);
    for f in ["abe.alog", "ben.alog"] {
        let x = std::fs::read(a.join(f)).expect("log");
        let y = std::fs::read(b.join(f)).expect("log");
        assert!(x == y, "{f} differs between two runs");
    }
}

#[test]
fn comms_range_and_drops_decide_who_hears_whom() {
    // 5 m of range: until they are that close (after 50 s they are still 28 m apart)
    // nobody hears anybody and nothing is spawned.
    let d = encounter_copy("deaf", "", false);
    let text = std::fs::read_to_string(d.join("scenario.toml"))
        .expect("scenario")
        .replace("range = 100", "range = 5");
    std::fs::write(d.join("scenario.toml"), text).expect("write");
    let (_, sum, _) = run_ok(&d, &["--max-time", "50"]);
    assert_eq!(sum["comms"]["delivered"], 0, "{sum:#}");
    for v in sum["vehicles"].as_array().expect("vehicles") {
        assert_eq!(v["spawned_behaviors"], 0, "{v:#}");
    }
    // Half the reports lost: some dropped, some delivered, still avoided.
    let d = encounter_copy("lossy", "", false);
    let text = std::fs::read_to_string(d.join("scenario.toml"))
        .expect("scenario")
        .replace("range = 100", "range = 100\ndrop = 50\nlatency = 1");
    std::fs::write(d.join("scenario.toml"), text).expect("write");
    let (_, sum, _) = run_ok(&d, &["--max-time", "90"]);
    let c = &sum["comms"];
    let (dropped, delivered) = (c["dropped"].as_u64(), c["delivered"].as_u64());
    assert!(dropped > Some(50) && delivered > Some(50), "{c}");
}

#[test]
fn malformed_node_reports_are_counted_not_fatal() {
    let d = encounter_copy(
        "malformed",
        "\n[[poke]]\nat = 2\nvar = \"NODE_REPORT\"\nvalue = \"X=5,Y=garbage\"\nvehicle = \"abe\"\n\
         [[poke]]\nat = 3\nvar = \"NODE_REPORT\"\nvalue = \"NAME=zed\"\nvehicle = \"abe\"\n",
        false,
    );
    let (_, sum, stdout) = run_ok(&d, &["--max-time", "20"]);
    assert_eq!(sum["vehicles"][0]["malformed_node_reports"], 2, "{sum:#}");
    assert_eq!(sum["vehicles"][1]["malformed_node_reports"], 0, "{sum:#}");
    assert!(
        stdout.contains("abe: 2 malformed NODE_REPORT(s)"),
        "{stdout}"
    );
}

#[test]
fn bad_scenarios_and_flags_are_refused_before_anything_runs() {
    let v = "[[vehicle]]\nname = \"abe\"\nmission = \"encounter.moos\"\n";
    let cases = [
        (
            format!("{v}max_speed = 3\n"),
            "scenario.toml:4:",
            "unknown field",
        ),
        (
            "[[vehicle]]\nname = \"abe\"\nmission = \"nowhere.moos\"\n".to_string(),
            "scenario.toml:3:",
            "no such file",
        ),
        (
            format!("{v}\n[[vehicle]]\nname = \"abe\"\nmission = \"encounter.moos\"\n"),
            "scenario.toml:6:",
            "two vehicles named `abe`",
        ),
        (
            format!("{v}\n[comms]\nrange = -10\n"),
            "scenario.toml:6:",
            "range",
        ),
    ];
    for (text, at, what) in cases {
        let d = encounter_copy("bad", &text, true);
        let out = common::temp_dir("fleet-bad-out").join("x");
        let o = helm_sim(&[s(&d), "--out", s(&out)]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{text}\n{}", common::text(&o));
        assert!(err.contains(at) && err.contains(what), "{text}\n{err}");
        assert!(!out.exists(), "nothing written for {text}");
    }
    for shard in ["0/4", "5/4", "2/0", "x"] {
        let o = helm_sim(&[s(&mission("encounter")), "--runs", "4", "--shard", shard]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{shard}: {err}");
        assert!(err.contains("--shard"), "{shard}: {err}");
    }
}

/// `--shard K/4` four times, merged, gives the table of one `--runs` run, byte for byte;
/// shards of another run set are refused.
#[test]
fn four_shards_merged_equal_one_run() {
    let m = mission("encounter");
    let common_args = [
        "--runs",
        "6",
        "--seed",
        "11",
        "--jitter",
        "x=8,y=8,heading=15",
        "--max-time",
        "80",
    ];
    let whole = common::temp_dir("fleet-whole");
    let mut args = vec![s(&m), "--out", s(&whole)];
    args.extend(common_args);
    let o = helm_sim(&args);
    assert!(o.status.success(), "{}", common::text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("collision rate 0/6 runs"), "{stdout}");
    assert!(stdout.contains("95% interval"), "{stdout}");

    let base = common::temp_dir("fleet-shards");
    let mut dirs = Vec::new();
    for k in 1..=4 {
        let d = base.join(format!("shard-{k}"));
        let shard = format!("{k}/4");
        let mut args = vec![s(&m), "--out", s(&d), "--shard", &shard];
        args.extend(common_args);
        let o = helm_sim(&args);
        assert!(o.status.success(), "{}", common::text(&o));
        assert!(d.join("shard.json").is_file());
        dirs.push(d);
    }
    let merged = base.join("merged");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    cmd.args(["sim", "merge"]);
    // Given in another order than 1..4: the merge sorts.
    for d in dirs.iter().rev() {
        cmd.arg(d);
    }
    let o = cmd.arg("--out").arg(&merged).output().expect("merge");
    assert!(o.status.success(), "{}", common::text(&o));
    let one = std::fs::read(whole.join("runs.csv")).expect("runs.csv");
    let joined = std::fs::read(merged.join("runs.csv")).expect("merged runs.csv");
    assert!(one == joined, "merged table differs from the single run's");
    let table = String::from_utf8_lossy(&one);
    assert!(table.starts_with("run,seed,end_reason,") && table.contains(",cpa_abe_ben,"));
    assert_eq!(table.lines().count(), 7);

    // A shard of another run set (another seed) is refused.
    let other = base.join("other");
    let mut args = vec![s(&m), "--out", s(&other), "--shard", "4/4"];
    args.extend(common_args);
    let seed_at = args.iter().position(|a| *a == "11").expect("seed");
    args[seed_at] = "12";
    assert!(helm_sim(&args).status.success());
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["sim", "merge"])
        .args(&dirs[..3])
        .arg(&other)
        .arg("--out")
        .arg(base.join("bad"))
        .output()
        .expect("merge");
    assert_eq!(o.status.code(), Some(1), "{}", common::text(&o));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("another run set"),
        "{}",
        common::text(&o)
    );
    // A missing shard, and no shard at all.
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["sim", "merge"])
        .args(&dirs[..3])
        .arg("--out")
        .arg(base.join("bad2"))
        .output()
        .expect("merge");
    assert_eq!(o.status.code(), Some(1), "{}", common::text(&o));
    assert!(
        common::text(&o).contains("shard(s) 4 of 4 missing"),
        "{}",
        common::text(&o)
    );
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .args(["sim", "merge"])
        .output()
        .expect("merge");
    assert_eq!(o.status.code(), Some(2), "{}", common::text(&o));
}

/// missions/fleet's expected outcome (its README line) over its 240 s: each transit has
/// crossed the middle and met loiterers and other transits by then.
#[test]
fn fleet_of_eight_avoids_each_other() {
    let (out, sum, _) = run_ok(&mission("fleet"), &[]);
    assert_eq!(sum["end_reason"], "max-time");
    assert_eq!(sum["collisions"], 0, "{sum:#}");
    let vehicles = sum["vehicles"].as_array().expect("vehicles");
    assert_eq!(vehicles.len(), 8);
    for v in vehicles {
        assert_eq!(v["helm_state"], "DRIVE", "{v:#}");
        let name = v["name"].as_str().expect("name");
        if name.starts_with('t') {
            assert!(v["spawned_behaviors"].as_u64() >= Some(1), "{v:#}");
        }
        assert!(out.join(format!("{name}.alog")).is_file());
    }
    assert_eq!(sum["pairs"].as_array().map(Vec::len), Some(28));
    assert_eq!(sum["behavior_errors"].as_array().map(Vec::len), Some(0));
    assert!(sum["allstops"].is_array());
}

/// Ctrl-C during a fleet Monte Carlo keeps the finished runs (as for one vehicle):
/// "interrupted after N of M runs", runs.csv with N rows, no shard file, exit 130.
#[test]
fn ctrl_c_during_a_fleet_monte_carlo_keeps_the_finished_runs() {
    let out = common::temp_dir("fleet-interrupt").join("out");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    cmd.args([
        "sim",
        s(&mission("encounter")),
        "--runs",
        "400",
        "--out",
        s(&out),
    ])
    .env("IVP_HELM_BUNDLED_DIR", "")
    .stdout(std::process::Stdio::piped())
    .stderr(std::process::Stdio::piped());
    common::behavior_dirs(&mut cmd, Some(plugin_dir()));
    let child = cmd.spawn().expect("start helm sim --runs 400");
    let (o, lines, progressed) = common::interrupt_after_first_run(child);
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    assert_eq!(o.status.code(), Some(130), "{stdout}\n{lines:?}");
    let said = stdout
        .lines()
        .find_map(|l| l.strip_prefix("encounter: interrupted after "))
        .unwrap_or_else(|| panic!("{stdout}"));
    let n: usize = said
        .strip_suffix(" of 400 runs")
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{said}"));
    assert!(n as u64 >= progressed && n < 400, "{n} after {progressed}");
    let csv = std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv kept");
    assert_eq!(
        csv.lines().count(),
        n + 1,
        "header and one row per finished run"
    );
    assert!(out.join("summary.txt").exists());
    assert!(!out.join("shard.json").exists());
    let _ = std::fs::remove_dir_all(&out);
}

/// `--alogs` on a fleet: each run's vehicle logs in `run-0000/`, ... (they were silently
/// not written), with the helms' functions in them; the runs are the same as without.
#[test]
fn fleet_runs_write_their_logs_with_alogs() {
    let m = mission("encounter");
    let common_args = [
        "--runs",
        "3",
        "--seed",
        "4",
        "--jitter",
        "x=5,y=5,heading=10",
    ];
    let (with, without) = (
        common::temp_dir("fleet-alogs"),
        common::temp_dir("fleet-no-alogs"),
    );
    for (dir, extra) in [(&with, Some("--alogs")), (&without, None)] {
        let mut args = vec![s(&m), "--out", s(dir), "--max-time", "40"];
        args.extend(common_args);
        args.extend(extra);
        let o = helm_sim(&args);
        assert!(o.status.success(), "{}", common::text(&o));
    }
    for run in ["run-0000", "run-0001", "run-0002"] {
        for vehicle in ["abe", "ben"] {
            let log = with.join(run).join(format!("{vehicle}.alog"));
            let text = std::fs::read_to_string(&log).unwrap_or_else(|e| panic!("{log:?}: {e}"));
            assert!(
                text.contains("NODE_REPORT") && text.contains("BHV_IPF"),
                "{log:?}"
            );
        }
    }
    assert!(!with.join("run-0003").exists());
    assert!(!without.join("run-0000").exists());
    let table = |d: &Path| std::fs::read(d.join("runs.csv")).expect("runs.csv");
    assert!(table(&with) == table(&without), "logs changed the runs");
}
