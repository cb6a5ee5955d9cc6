//! `helm sim` with depth: the `missions/uuv` survey (dives, surfaces periodically, stays
//! above its depth limit, ends with MISSION=complete, and the picture gains its depth
//! strip), and BHV_OpRegion's breach in a run: the helm halts and the summary says why.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

mod common;

const PLUGINS: [&str; 3] = ["bhv-constant-depth", "bhv-depth", "bhv-region"];

/// The three plugin libraries the uuv mission names, in a folder of their own.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        common::lib_folder(&common::build_plugins(&PLUGINS), &PLUGINS, "sim-depth-lib")
    })
}

fn helm_sim(args: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    cmd.arg("sim").args(args).env("IVP_HELM_BUNDLED_DIR", "");
    common::behavior_dirs(&mut cmd, Some(plugin_dir()));
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

/// Every NAV_DEPTH value of an `.alog`, in order.
fn depths(alog: &str) -> Vec<f64> {
    alog.lines()
        .filter(|l| l.split_whitespace().nth(1) == Some("NAV_DEPTH"))
        .filter_map(|l| l.split_whitespace().nth(3)?.parse().ok())
        .collect()
}

/// The surfacing count the picture's depth strip prints.
fn strip_surfacings(svg: &str) -> usize {
    let at = svg
        .find("Depth over time")
        .expect("the depth strip is drawn");
    let tail = &svg[at..];
    let n = tail.split(" m, ").nth(1).expect("strip title");
    n.split_whitespace()
        .next()
        .and_then(|n| n.parse().ok())
        .expect("a count")
}

#[test]
fn uuv_surveys_at_depth_surfaces_periodically_and_ends_complete() {
    let out = common::temp_dir("helm-sim-uuv");
    let m = common::workspace().join("missions/uuv");
    let o = helm_sim(&[
        m.to_str().unwrap(),
        "--strict",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let s = summary(&out);
    assert_eq!(s["end_reason"], "MISSION=complete", "{s:#}");
    let end = s["sim_time_s"].as_f64().unwrap();
    assert!(
        (480.0..482.0).contains(&end),
        "the 480 s mission clock ends it: {end}"
    );
    assert_eq!(s["allstops"].as_array().map(Vec::len), Some(0), "{s:#}");
    assert_eq!(
        s["behavior_errors"].as_array().map(Vec::len),
        Some(0),
        "{s:#}"
    );
    assert!(s["waypoints_reached"].as_u64().unwrap() >= 6, "{s:#}");

    let alog = std::fs::read_to_string(out.join("uuv.alog")).expect("alog");
    let d = depths(&alog);
    let deepest = d.iter().cloned().fold(0.0, f64::max);
    assert!(
        (14.5..=20.0).contains(&deepest),
        "held 15 m, never below 20: {deepest}"
    );
    let ascents = alog
        .lines()
        .filter(|l| l.contains("PERIODIC_ASCEND") && l.trim_end().ends_with("true"))
        .count();
    assert!(ascents >= 3, "a surfacing every 100 s: {ascents}");
    assert!(!alog.contains("OPREGION_BREACH"), "stayed in its op region");

    let svg = std::fs::read_to_string(out.join("uuv.svg")).expect("svg");
    assert!(
        strip_surfacings(&svg) >= 2,
        "surfacings visible in the strip"
    );
}

#[test]
fn leaving_the_op_region_halts_the_helm_and_the_summary_says_why() {
    // The uuv mission with an op region that ends at x = 100 (the survey goes to 150).
    let dir = common::temp_dir("helm-sim-uuv-breach");
    let src = common::workspace().join("missions/uuv");
    std::fs::copy(src.join("uuv.moos"), dir.join("uuv.moos")).expect("copy");
    let bhv = std::fs::read_to_string(src.join("uuv.bhv")).expect("bhv");
    let small = "polygon   = -40,30 : 100,30 : 100,-140 : -40,-140";
    let bhv = bhv.replace("polygon   = -40,30 : 190,30 : 190,-140 : -40,-140", small);
    assert!(
        bhv.contains(small),
        "the mission's op region line changed: update this test"
    );
    std::fs::write(dir.join("uuv.bhv"), bhv).expect("write bhv");
    std::fs::write(dir.join("scenario.toml"), "[end]\nmax_time = 300\n").expect("scenario");
    let out = dir.join("out");
    let o = helm_sim(&[dir.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let s = summary(&out);
    // Halted (all-stop) for good: the stop rule of `helm run --embedded` ends the run.
    assert_eq!(s["end_reason"], "mission-over", "{s:#}");
    let stops = s["allstops"].as_array().unwrap();
    assert_eq!(stops[0]["reason"], "BehaviorError", "{s:#}");
    let errors = s["behavior_errors"].as_array().unwrap();
    let first = errors[0].as_str().unwrap();
    assert!(
        first.starts_with("opregion: BHV_OpRegion Polygon containment failure:  x=10"),
        "{first}"
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("all-stops: BehaviorError"), "{stdout}");
    assert!(stdout.contains("Polygon containment failure"), "{stdout}");
    // Halted just past the line: it never reached the far side of the survey.
    let x = s["end"]["x"].as_f64().unwrap();
    assert!((100.0..115.0).contains(&x), "stopped near x = 100: {x}");
    let alog = std::fs::read_to_string(out.join("uuv.alog")).expect("alog");
    assert!(alog
        .lines()
        .any(|l| l.contains("OPREGION_BREACH") && l.trim_end().ends_with("poly")));

    // --strict makes the behavior error the exit status.
    let o = helm_sim(&[
        dir.to_str().unwrap(),
        "--strict",
        "--out",
        dir.join("strict").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o));
}
