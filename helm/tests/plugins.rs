//! The behavior plugins under `plugins/`, loaded by the real `helm` binary.
//!
//! Builds the plugin crates into a target directory of this test run, points
//! IVP_BEHAVIOR_DIRS at the output folder and runs `helm conform` on every
//! `conformance/helm/plugin_*.toml` case. Also checks that bad library folders and files
//! are reported without crashing the helm. (With IVP_BEHAVIOR_DIRS unset, the plugin
//! cases fail with `unknown behavior type`: asserted in conformance.rs.)

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

const PLUGINS: &[&str] = &[
    "bhv-constant-speed",
    "bhv-constant-heading",
    "bhv-constant-depth",
    "bhv-station-keep",
    "bhv-template",
];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Build the plugins once per test binary; returns the folder holding the `.so` files.
fn plugin_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugins-target");
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let mut cmd = Command::new(cargo);
        cmd.current_dir(workspace())
            .arg("build")
            .arg("--quiet")
            .env("CARGO_TARGET_DIR", &target);
        for p in PLUGINS {
            cmd.arg("-p").arg(p);
        }
        let out = cmd.output().expect("run cargo build");
        assert!(
            out.status.success(),
            "building the plugins failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let dir = target.join("debug");
        for p in PLUGINS {
            let so = dir.join(format!("lib{}.so", p.replace('-', "_")));
            assert!(so.is_file(), "{} not built", so.display());
        }
        // Only the behavior libraries: the debug folder also holds deps/, build/ ...
        let only = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugins-lib");
        std::fs::create_dir_all(&only).unwrap();
        for p in PLUGINS {
            let name = format!("lib{}.so", p.replace('-', "_"));
            std::fs::copy(dir.join(&name), only.join(&name)).unwrap();
        }
        only
    })
}

fn helm_conform(case: &Path, dirs: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_helm"));
    cmd.current_dir(workspace()).arg("conform").arg(case);
    match dirs {
        Some(d) => cmd.env("IVP_BEHAVIOR_DIRS", d),
        None => cmd.env_remove("IVP_BEHAVIOR_DIRS"),
    };
    cmd.output().expect("run helm")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn plugin_cases() -> Vec<PathBuf> {
    let dir = workspace().join("conformance/helm");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            n.starts_with("plugin_") && n.ends_with(".toml")
        })
        .collect();
    v.sort();
    v
}

fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
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

#[test]
fn each_library_alone_offers_its_own_type() {
    // One library per folder, several folders: the colon-separated list is searched in
    // order and a case needing two libraries still finds both.
    let lib = plugin_dir();
    let mut dirs = Vec::new();
    for p in ["bhv-constant-heading", "bhv-constant-speed"] {
        let d = scratch(&format!("alone-{p}"));
        let name = format!("lib{}.so", p.replace('-', "_"));
        std::fs::copy(lib.join(&name), d.join(&name)).unwrap();
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
        std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
    }
    let out = helm_conform(&case, Some(d.to_str().unwrap()));
    let t = text(&out);
    assert!(t.contains("1 passed, 0 failed"), "{t}");
}
