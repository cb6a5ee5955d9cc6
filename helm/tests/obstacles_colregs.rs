//! Obstacles and COLREGS in `helm sim` (issue 22 points 4 to 6), through the real
//! binary: missions/harbour's vehicle crosses the rocks to the pier without a hit (and,
//! its V24 template taken out, hits a rock, counted as uFldCollObDetect counts it);
//! a few jittered harbour runs fill the obstacle columns of runs.csv; missions/colregs'
//! crossing, head-on and overtaking scenarios are classified and pass as the rules ask;
//! a bad obstacle file is refused with its file:line before anything runs.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

mod common;

fn mission(name: &str) -> PathBuf {
    common::workspace().join("missions").join(name)
}

/// The obstacle, COLREGS and contact plugins, built once.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        const P: [&str; 2] = ["bhv-obstacle", "bhv-colregs"];
        common::lib_folder(&common::build_plugins(&P), &P, "simobs-plugins-lib")
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

fn run_ok(dir: &Path, extra: &[&str]) -> (PathBuf, serde_json::Value, String) {
    let out = common::temp_dir("simobs-out");
    let mut args = vec![s(dir), "--out", s(&out)];
    args.extend(extra);
    let o = helm_sim(&args);
    assert!(o.status.success(), "{}", common::text(&o));
    let t = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let sum = serde_json::from_str(&t).expect("summary.json is JSON");
    (out, sum, String::from_utf8_lossy(&o.stdout).into_owned())
}

/// A copy of missions/`name` in which `edit` changes the files' texts.
fn copy_of(name: &str, tag: &str, edit: impl Fn(&str, String) -> String) -> PathBuf {
    let d = common::temp_dir(&format!("simobs-{tag}"));
    for e in std::fs::read_dir(mission(name)).expect("read the mission") {
        let p = e.expect("entry").path();
        let file = p.file_name().expect("name").to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&p).expect("read");
        std::fs::write(d.join(&file), edit(&file, text)).expect("write");
    }
    d
}

#[test]
fn harbour_crosses_the_rocks_without_a_hit() {
    let (out, sum, stdout) = run_ok(&mission("harbour"), &[]);
    assert_eq!(sum["end_reason"], "mission-over", "{sum:#}");
    let ob = &sum["obstacles"];
    assert_eq!(ob["collisions"], 0, "{ob:#}");
    assert!(ob["closest_m"].as_f64().expect("closest") > 1.0, "{ob:#}");
    // Six rocks from the file and the pier from scenario.toml, each measured.
    let labels: Vec<&str> = ob["obstacles"]
        .as_array()
        .expect("obstacles")
        .iter()
        .map(|o| o["label"].as_str().expect("label"))
        .collect();
    assert_eq!(labels.len(), 7, "{labels:?}");
    assert!(
        labels.contains(&"rock_a") && labels.contains(&"pier"),
        "{labels:?}"
    );
    // The rocks near the track were alerted on and each alert spawned a V24.
    let alerts = ob["alerts"][0][1].as_u64().expect("alerts");
    let spawned = sum["vehicles"][0]["spawned_behaviors"]
        .as_u64()
        .expect("spawned");
    assert!(alerts >= 3, "{ob:#}");
    assert_eq!(spawned, alerts, "one avd_ob_ per alerted rock");
    assert!(
        ob["encounters"].as_u64().expect("encounters") >= 3,
        "{ob:#}"
    );
    assert!(stdout.contains("obstacles: 7"), "{stdout}");
    let svg = std::fs::read_to_string(out.join("harbour.svg")).expect("picture");
    assert!(
        svg.contains(">rock_a ") && svg.contains("<polygon"),
        "rocks drawn"
    );
}

#[test]
fn harbour_without_avoidance_hits_a_rock() {
    // The V24 template taken out: nothing asks for alerts, the transit runs into rock_a.
    let d = copy_of("harbour", "noavd", |file, text| {
        if file == "harbour.bhv" {
            text.split("Behavior = BHV_AvoidObstacleV24")
                .next()
                .expect("before the template")
                .to_string()
        } else {
            text
        }
    });
    let (out, sum, _) = run_ok(&d, &[]);
    let ob = &sum["obstacles"];
    assert!(
        ob["collisions"].as_u64().expect("collisions") >= 1,
        "{ob:#}"
    );
    assert_eq!(ob["closest_m"], 0.0, "inside a rock: {ob:#}");
    assert_eq!(sum["vehicles"][0]["spawned_behaviors"], 0);
    // The picture is named after the mission's folder (a copy here).
    let svg = std::fs::read_dir(&out)
        .expect("out")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|x| x == "svg"))
        .and_then(|p| std::fs::read_to_string(p).ok())
        .expect("picture");
    assert!(
        svg.contains("#c0392b\" stroke-width=\"1.5\"/>"),
        "the hit rock in red"
    );
}

#[test]
fn harbour_monte_carlo_fills_the_obstacle_columns() {
    let out = common::temp_dir("simobs-mc");
    let o = helm_sim(&[
        s(&mission("harbour")),
        "--runs",
        "8",
        "--seed",
        "3",
        "--jitter",
        "x=5,y=5,heading=20",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", common::text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("obstacle hit rate 0/8 runs"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv");
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).expect(name);
    let (coll, closest) = (col("ob_collisions"), col("ob_closest_m"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 8);
    for r in &rows {
        assert_eq!(r[coll], "0", "{r:?}");
        let d: f64 = r[closest].parse().expect("a distance");
        assert!(d > 1.0, "{r:?}");
    }
}

#[test]
fn colregs_situations_pass_as_the_rules_ask() {
    let cases = [
        ("scenario.toml", [("abe", "giveway"), ("ben", "standon")]),
        ("headon.toml", [("abe", "headon"), ("ben", "headon")]),
        (
            "overtaking.toml",
            [("abe", "overtaking"), ("ben", "overtaken")],
        ),
    ];
    for (file, want) in cases {
        let sc = mission("colregs").join(file);
        let (_, sum, stdout) = run_ok(&mission("colregs"), &["--scenario", s(&sc)]);
        assert_eq!(sum["collisions"], 0, "{file}: {sum:#}");
        let rules = sum["colregs"].as_array().expect("colregs");
        assert_eq!(rules.len(), 2, "{file}: {rules:#?}");
        for (r, (own, situation)) in rules.iter().zip(want) {
            assert_eq!(r["ownship"], own, "{file}");
            assert_eq!(r["situation"], situation, "{file}: {r:#}");
            assert_eq!(r["trigger"], "alert", "{file}: {r:#}");
            assert_eq!(r["passed"], true, "{file}: {r:#}");
        }
        assert!(stdout.contains("COLREGS abe vs ben"), "{stdout}");
    }
}

#[test]
fn colregs_monte_carlo_counts_give_way_crossings() {
    let out = common::temp_dir("simobs-mc-colregs");
    let o = helm_sim(&[
        s(&mission("colregs")),
        "--runs",
        "6",
        "--jitter",
        "x=10,y=10,heading=10",
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", common::text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("give-way crossings: 6 of 6 passed astern (100.0%, 95% interval"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out.join("runs.csv")).expect("runs.csv");
    let head = csv.lines().next().expect("header");
    assert!(
        head.ends_with(",rule_abe_ben,rule_ok_abe_ben,rule_ben_abe,rule_ok_ben_abe"),
        "{head}"
    );
    assert_eq!(
        csv.lines()
            .skip(1)
            .filter(|l| l.ends_with(",giveway,1,standon,1"))
            .count(),
        6,
        "{csv}"
    );
}

#[test]
fn a_bad_obstacle_file_is_refused_before_anything_runs() {
    let d = copy_of("harbour", "badfile", |file, text| {
        if file == "obstacles.txt" {
            text.replace(
                "label=rock_c",
                "label=rock_c\npoly = pts={0,0:10,0:5,1:10,10:0,10}",
            )
        } else {
            text
        }
    });
    let out = common::temp_dir("simobs-bad-out").join("x");
    let o = helm_sim(&[s(&d), "--out", s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{}", common::text(&o));
    assert!(err.contains("scenario.toml:6: bad obstacle file"), "{err}");
    assert!(
        err.contains("obstacles.txt:9: Poorly specified obstacle: pts={0,0:10,0:5,1:10,10:0,10}"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written");
}
