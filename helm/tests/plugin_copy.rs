//! Issue 20, points 8 and 9: what a plugin author copies builds outside this repository
//! and drives a mission in `helm sim`.
//!
//! * `plugins/template`, copied to a temporary folder and edited as its README says
//!   (package renamed, `behavior-api` path pointed at this checkout), builds on its own
//!   and its behavior runs in `helm sim`.
//! * `behavior-api/TUTORIAL.md`: each Rust block, pasted whole as a crate's `src/lib.rs`
//!   under the tutorial's `Cargo.toml`, builds and passes its own tests; the tutorial's
//!   mission, with the tutorial's library, drives in `helm sim`.
//!
//! The builds are offline, into the shared plugin target folder of these tests (the
//! dependencies are compiled once). A registry that cannot be reached offline skips;
//! a compile error fails.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{text, workspace};

mod common;

/// Copy a crate folder (without `target/`).
fn copy_crate(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for e in std::fs::read_dir(from)
        .expect("read crate folder")
        .flatten()
    {
        let p = e.path();
        let dest = to.join(e.file_name());
        if p.is_dir() {
            if e.file_name() != "target" {
                copy_crate(&p, &dest);
            }
        } else {
            std::fs::copy(&p, &dest).expect("copy");
        }
    }
}

/// `cargo <args> --offline` in `dir`; `None` (skip) if the registry is out of reach.
fn cargo(dir: &Path, args: &[&str]) -> Option<Output> {
    // The workspace's lock file: the same abi_stable, resolvable offline.
    let lock = dir.join("Cargo.lock");
    if !lock.exists() {
        std::fs::copy(workspace().join("Cargo.lock"), &lock).expect("copy Cargo.lock");
    }
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let o = Command::new(cargo)
        .current_dir(dir)
        .args(args)
        .args(["--offline", "--quiet"])
        .env("CARGO_TARGET_DIR", common::plugins_target())
        // As the workspace's dev profile: file:line only (disk).
        .env("CARGO_PROFILE_DEV_DEBUG", "line-tables-only")
        .output()
        .expect("run cargo");
    if !o.status.success() {
        let err = String::from_utf8_lossy(&o.stderr);
        if err.contains("offline") && err.contains("registry") {
            eprintln!("SKIPPED: cannot build offline:\n{err}");
            return None;
        }
        panic!("cargo {args:?} in {} failed:\n{}", dir.display(), text(&o));
    }
    Some(o)
}

/// `file` with `from` replaced by `to`; `from` must be there (the README or tutorial
/// says to edit exactly that).
fn edit(file: &Path, from: &str, to: &str) {
    let t = std::fs::read_to_string(file).expect("read");
    assert!(t.contains(from), "{} has no `{from}`:\n{t}", file.display());
    std::fs::write(file, t.replace(from, to)).expect("write");
}

/// The library `lib<name>.so` just built, alone in a folder of its own.
fn lib_alone(root: &Path, crate_name: &str) -> PathBuf {
    let name = format!("lib{}.so", crate_name.replace('-', "_"));
    let dir = root.join("lib");
    std::fs::create_dir_all(&dir).expect("mkdir");
    std::fs::copy(
        common::plugins_target().join("debug").join(&name),
        dir.join(&name),
    )
    .expect("the library was built");
    dir
}

/// `helm sim MISSION --strict` with only `libs` for behavior libraries; the summary.
fn sim(mission: &Path, libs: &Path, max_time: &str) -> serde_json::Value {
    let out = mission.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("sim")
        .arg(mission)
        .args(["--max-time", max_time, "--strict", "--out"])
        .arg(&out)
        .env("IVP_BEHAVIOR_DIRS", libs)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .output()
        .expect("run helm sim");
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let s = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    serde_json::from_str(&s).expect("summary is JSON")
}

#[test]
fn the_template_copied_out_of_the_repo_builds_and_drives() {
    let root = common::outside_dir("helm-template-copy");
    let copy = root.join("bhv-mine");
    copy_crate(&workspace().join("plugins/template"), &copy);
    // As plugins/template/README.md says: rename, point behavior-api at the checkout.
    let manifest = copy.join("Cargo.toml");
    edit(&manifest, "name = \"bhv-template\"", "name = \"bhv-mine\"");
    let api = workspace().join("behavior-api");
    edit(
        &manifest,
        "path = \"../../behavior-api\"",
        &format!("path = {:?}", api.display().to_string()),
    );
    edit(
        &copy.join("src/lib.rs"),
        "\"BHV_Template\" =>",
        "\"BHV_Mine\" =>",
    );
    let m = std::fs::read_to_string(&manifest).expect("read");
    assert!(!m.contains(".workspace"), "nothing inherited:\n{m}");
    if cargo(&copy, &["build"]).is_none() {
        return;
    }
    let libs = lib_alone(&root, "bhv-mine");

    let mission = root.join("mission");
    std::fs::create_dir_all(&mission).expect("mkdir");
    std::fs::write(
        mission.join("mine.moos"),
        "ServerHost = localhost\nServerPort = 9000\nCommunity = mine\n\
         LatOrigin = 43.8253\nLongOrigin = -70.3304\n\n\
         ProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = mine.bhv\n  \
         domain = speed:0:4:41\n  start_in_drive = true\n}\n\n\
         ProcessConfig = uSimMarine\n{\n  AppTick = 10\n}\n",
    )
    .expect("write");
    std::fs::write(
        mission.join("mine.bhv"),
        "Behavior = BHV_Mine\n{\n  name = mine\n  speed = 1.5\n}\n",
    )
    .expect("write");
    let s = sim(&mission, &libs, "30");
    assert_eq!(s["drove"], true, "{s}");
    let speed = s["end"]["speed"].as_f64().expect("end speed");
    assert!((speed - 1.5).abs() < 0.1, "BHV_Mine held 1.5 m/s: {s}");
}

/// The fenced blocks of a Markdown text: (info string, body).
fn blocks(md: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut open: Option<(String, String)> = None;
    for line in md.lines() {
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(info)) => open = Some((info.trim().to_string(), String::new())),
            (Some(_), Some(_)) => out.extend(open.take()),
            (Some((_, body)), None) => {
                body.push_str(line);
                body.push('\n');
            }
            (None, None) => {}
        }
    }
    out
}

#[test]
fn the_tutorial_pasted_as_shown_builds_and_its_mission_drives() {
    let md =
        std::fs::read_to_string(workspace().join("behavior-api/TUTORIAL.md")).expect("TUTORIAL.md");
    let blocks = blocks(&md);
    let find = |info: &str, has: &str| -> Vec<String> {
        blocks
            .iter()
            .filter(|(i, b)| i == info && b.contains(has))
            .map(|(_, b)| b.clone())
            .collect()
    };
    let manifest = find("toml", "[package]");
    assert_eq!(manifest.len(), 1, "one Cargo.toml in the tutorial");
    let api = workspace().join("behavior-api");
    let manifest =
        manifest[0].replace("/path/to/ivp-helm/behavior-api", &api.display().to_string());
    let rust = find("rust", "");
    assert_eq!(rust.len(), 2, "the behavior and the contact behavior");
    let root = common::outside_dir("helm-tutorial");
    for (k, code) in rust.iter().enumerate() {
        // What rustdoc would hide is not there: the block is the whole file.
        for l in code.lines() {
            let t = l.trim_start();
            assert!(
                !(t == "#" || t.starts_with("# ")),
                "a rustdoc hidden line in block {k}: {l}"
            );
        }
        let dir = root.join(format!("crate-{k}"));
        std::fs::create_dir_all(dir.join("src")).expect("mkdir");
        let name = if k == 0 {
            "bhv-cruise".to_string()
        } else {
            format!("tutorial-block-{k}")
        };
        std::fs::write(
            dir.join("Cargo.toml"),
            manifest.replace("name = \"bhv-cruise\"", &format!("name = \"{name}\"")),
        )
        .expect("write");
        std::fs::write(dir.join("src/lib.rs"), code).expect("write");
        // Its own tests run (and fail the build on a wrong assertion), then the library.
        let Some(tested) = cargo(&dir, &["test"]) else {
            return;
        };
        let said = text(&tested);
        assert!(
            said.contains("test result: ok. 1 passed"),
            "its test ran: {said}"
        );
        cargo(&dir, &["build"]);
    }
    let libs = lib_alone(&root, "bhv-cruise");

    let mission = root.join("cruise");
    std::fs::create_dir_all(&mission).expect("mkdir");
    let moos = find("text", "ProcessConfig = pHelmIvP");
    let bhv = find("text", "Behavior = BHV_Cruise");
    assert_eq!((moos.len(), bhv.len()), (1, 1), "the mission's two files");
    assert!(moos[0].contains("start_in_drive = true"));
    std::fs::write(mission.join("cruise.moos"), &moos[0]).expect("write");
    std::fs::write(mission.join("cruise.bhv"), &bhv[0]).expect("write");
    // The tutorial's commands: `helm check cruise`, `helm sim cruise --max-time 120`.
    assert!(md.contains("helm check cruise\nhelm sim cruise --max-time 120\n"));
    let o = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("check")
        .arg(&mission)
        .env("IVP_BEHAVIOR_DIRS", &libs)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .output()
        .expect("run helm check");
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("BHV_Cruise"), "{}", text(&o));
    let s = sim(&mission, &libs, "120");
    assert_eq!(s["drove"], true, "{s}");
    let end = &s["end"];
    let heading = end["heading"].as_f64().expect("heading");
    let speed = end["speed"].as_f64().expect("speed");
    // From heading 90 it turned through north to 350, and holds 1.5 m/s.
    assert!((heading - 350.0).abs() < 5.0, "{s}");
    assert!((speed - 1.5).abs() < 0.1, "{s}");
}
