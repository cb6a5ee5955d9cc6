//! Helpers shared by the integration tests of the `helm` crate (`mod common;` in each).

// Each test binary compiles this module on its own and uses only some of it.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

use helm_conform::{build_helm, Case};
use helm_engine::config::BlockLine;
use helm_engine::factory::BehaviorFactory;
use helm_engine::Helm;

/// The alpha mission of the repo, as shipped.
pub const ALPHA_MOOS: &str = include_str!("../../../missions/alpha/alpha.moos");
pub const ALPHA_BHV: &str = include_str!("../../../missions/alpha/alpha.bhv");

/// The behavior libraries this project ships (`plugins/*`), by package name.
pub const SHIPPED_PLUGINS: &[&str] = &[
    "bhv-constant-speed",
    "bhv-constant-heading",
    "bhv-constant-depth",
    "bhv-station-keep",
    "bhv-template",
    "bhv-visuals",
    "bhv-depth",
    "bhv-survey",
    "bhv-contact",
    "bhv-colregs",
    "bhv-obstacle",
    "bhv-region",
    "bhv-convoy",
];

/// The root of the workspace (the repo).
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace")
        .to_path_buf()
}

/// The golden helm cases, `conformance/helm/*.toml`, sorted.
pub fn helm_cases() -> Vec<PathBuf> {
    let dir = workspace().join("conformance/helm");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("conformance folder {} missing: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no cases in {}", dir.display());
    files
}

/// The file name of `p`, as text.
pub fn file_name(p: &Path) -> String {
    p.file_name()
        .unwrap_or_default()
        .to_string_lossy()
        .into_owned()
}

/// `d`, emptied: removed if it was there, then created.
pub fn fresh_dir(d: PathBuf) -> PathBuf {
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create scratch dir");
    d
}

/// `CARGO_TARGET_TMPDIR/<rel>`, emptied.
pub fn scratch(rel: impl AsRef<Path>) -> PathBuf {
    fresh_dir(Path::new(env!("CARGO_TARGET_TMPDIR")).join(rel))
}

/// A new empty folder `<prefix>-<n>` under `CARGO_TARGET_TMPDIR` (`n` counts the calls
/// of this test binary, so every call gets its own). The names repeat from run to run,
/// so a run empties and reuses the last run's folders instead of adding more: simulator
/// outputs are hundreds of MB, and a folder per process id filled the disk.
pub fn temp_dir(prefix: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    fresh_dir(
        Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("{prefix}-{}", N.fetch_add(1, Ordering::SeqCst))),
    )
}

/// A new empty folder `<prefix>-<n>` OUTSIDE the repository, for what must not see
/// its workspace (a crate built as a user would build it, a helm run the way a new
/// user runs it): in the system temp dir, under a folder named after this checkout's
/// path, so two checkouts testing at once never share one, and the names repeat from
/// run to run (bounded disk, as [`temp_dir`]).
pub fn outside_dir(prefix: &str) -> PathBuf {
    use std::hash::{Hash, Hasher};
    static N: AtomicUsize = AtomicUsize::new(0);
    let mut h = std::collections::hash_map::DefaultHasher::new();
    workspace().hash(&mut h);
    fresh_dir(
        std::env::temp_dir()
            .join(format!("ivp-helm-tests-{:016x}", h.finish()))
            .join(format!("{prefix}-{}", N.fetch_add(1, Ordering::SeqCst))),
    )
}

/// `src` at `dst`, as a hard link where the file system allows it, else as a copy;
/// `dst` is replaced. The tests place the same 25 MB libraries and the helm binary in
/// many folders: copies of them filled the disk. A replaced `dst` that a running helm
/// has loaded stays loaded (only its name goes), and cargo and the linker replace their
/// outputs instead of writing into them, so a link never changes under a test.
pub fn place(src: &Path, dst: &Path) -> std::io::Result<()> {
    match std::fs::remove_file(dst) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    std::fs::hard_link(src, dst).or_else(|_| std::fs::copy(src, dst).map(|_| ()))
}

/// A port of 127.0.0.1 nobody listens on right now.
pub fn free_port() -> u16 {
    let l = TcpListener::bind("127.0.0.1:0").expect("bind an ephemeral port");
    l.local_addr().expect("local addr").port()
}

/// What a process wrote: stdout, then stderr.
pub fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Set IVP_BEHAVIOR_DIRS of `cmd` to `dirs`, or unset it for `None`.
pub fn behavior_dirs<D: AsRef<OsStr>>(cmd: &mut Command, dirs: Option<D>) -> &mut Command {
    match dirs {
        Some(d) => cmd.env("IVP_BEHAVIOR_DIRS", d),
        None => cmd.env_remove("IVP_BEHAVIOR_DIRS"),
    }
}

/// `moos` (a mission file's text) with each line that sets one of `params` (the name
/// before `=`) setting it to the given value instead, indentation kept.
pub fn with_params(moos: &str, params: &[(&str, String)]) -> String {
    moos.lines()
        .map(|l| {
            let t = l.trim_start();
            let name = t.split('=').next().unwrap_or("").trim();
            match params.iter().find(|(p, _)| *p == name) {
                Some((p, v)) => format!("{}{p} = {v}", &l[..l.len() - t.len()]),
                None => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The helm block of the library-level tests: course and speed domains, in drive at once.
pub const DRIVE_BLOCK: [(&str, &str); 3] = [
    ("domain", "course:0:359:360"),
    ("domain", "speed:0:4:41"),
    ("start_in_drive", "true"),
];

/// Helm block lines `name = value`, numbered from 1.
pub fn block_lines(lines: &[(&str, &str)]) -> Vec<BlockLine> {
    lines
        .iter()
        .enumerate()
        .map(|(i, (name, value))| BlockLine {
            line: i + 1,
            name: name.to_string(),
            value: value.to_string(),
        })
        .collect()
}

/// The target folder of the plugin builds, one for every test binary of this crate (so
/// a plugin is compiled once per `cargo test`).
pub fn plugins_target() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("plugins-target")
}

/// The library a plugin package builds: `bhv-constant-speed` gives
/// `libbhv_constant_speed.so`.
pub fn lib_name(package: &str) -> String {
    format!("lib{}.so", package.replace('-', "_"))
}

/// Build the plugin `packages` of the workspace into [`plugins_target`]; returns the
/// folder holding their libraries (with cargo's deps/, build/ ... beside them).
pub fn build_plugins(packages: &[&str]) -> PathBuf {
    let target = plugins_target();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(workspace())
        .args(["build", "--quiet"])
        .env("CARGO_TARGET_DIR", &target);
    for p in packages {
        cmd.arg("-p").arg(p);
    }
    let out = cmd.output().expect("run cargo build");
    assert!(
        out.status.success(),
        "building the plugins failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let built = target.join("debug");
    for p in packages {
        let so = built.join(lib_name(p));
        assert!(so.is_file(), "{} not built", so.display());
    }
    built
}

/// Copy the libraries of `packages` from `built` into `CARGO_TARGET_TMPDIR/<folder>`, a
/// folder of behavior libraries only; returns it.
pub fn lib_folder(built: &Path, packages: &[&str], folder: &str) -> PathBuf {
    let only = Path::new(env!("CARGO_TARGET_TMPDIR")).join(folder);
    std::fs::create_dir_all(&only).expect("create the library folder");
    for p in packages {
        let name = lib_name(p);
        place(&built.join(&name), &only.join(&name)).expect("place the library");
    }
    only
}

/// `helm check` of a mission (`moos`, whose behavior file is `m.bhv`) with `bhv` as its
/// behavior file and the behavior libraries of `packages`, in the scratch folder
/// `<group>/<name>`: the exit code, the output, and the `.bhv` path (for file:line
/// messages). The libraries are built and copied into `<group>-libs` once per test
/// binary: a second copy would rewrite a library another test's helm may be loading.
pub fn check_bhv(
    group: &str,
    packages: &[&str],
    name: &str,
    moos: &str,
    bhv: &str,
) -> (i32, String, String) {
    static LIBS: std::sync::Mutex<Vec<(String, PathBuf)>> = std::sync::Mutex::new(Vec::new());
    let libs = {
        let mut known = LIBS.lock().unwrap_or_else(|e| e.into_inner());
        match known.iter().find(|(g, _)| g == group) {
            Some((_, dir)) => dir.clone(),
            None => {
                let folder = format!("{}-libs", group.replace('_', "-"));
                let dir = lib_folder(&build_plugins(packages), packages, &folder);
                known.push((group.to_string(), dir.clone()));
                dir
            }
        }
    };
    let d = scratch(Path::new(group).join(name));
    std::fs::write(d.join("m.moos"), moos).expect("write mission");
    std::fs::write(d.join("m.bhv"), bhv).expect("write bhv");
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("check")
        .arg(d.join("m.moos"))
        .env("IVP_BEHAVIOR_DIRS", &libs)
        .env("IVP_HELM_BUNDLED_DIR", "")
        .output()
        .expect("run helm");
    let path = d.join("m.bhv").display().to_string();
    (out.status.code().unwrap_or(-1), text(&out), path)
}

/// A golden case (the conformance format) named `name`: `bhv` in drive with course and
/// speed domains, then `steps` iterations 0.25 s apart from 1000 s, each mailed zero
/// navigation and the mail entries `extra` gives for its step (TOML text, each entry
/// `, ["VAR", value]`).
pub fn nav_case(name: &str, bhv: &str, steps: usize, extra: impl Fn(usize) -> String) -> Case {
    let mut text = format!(
        "name = \"{name}\"\ndomain = [\"course:0:359:360\", \"speed:0:4:41\"]\ncheck = []\nbhv = '''\n{bhv}'''\n[config]\nstart_in_drive = \"true\"\n"
    );
    for k in 0..steps {
        let t = 1000.0 + 0.25 * k as f64;
        text.push_str(&format!(
            "[[step]]\ntime = {t}\nmail = [[\"NAV_X\", 0.0], [\"NAV_Y\", 0.0], [\"NAV_HEADING\", 0.0], [\"NAV_SPEED\", 0.0]"
        ));
        text.push_str(&extra(k));
        text.push_str("]\n");
    }
    toml::from_str(&text).expect("case parses")
}

/// The helm of case `c` (read from `file`, for messages) with the built-in behaviors.
pub fn builtin_case_helm(c: &Case, file: &str) -> Helm {
    build_helm(c, Path::new(file), &BehaviorFactory::with_builtins()).expect("helm builds")
}

/// A `helm sim --runs N` child (stderr piped, off a terminal): wait for its first
/// progress line that counts a finished run, send SIGINT, and return its output, its
/// stderr lines and the count that line gave.
#[allow(dead_code)] // not every test file interrupts a Monte Carlo
pub fn interrupt_after_first_run(
    mut child: std::process::Child,
) -> (std::process::Output, Vec<String>, u64) {
    use std::io::BufRead;
    let stderr = child.stderr.take().expect("stderr piped");
    let (tx, rx) = std::sync::mpsc::channel();
    let reader = std::thread::spawn(move || {
        let mut all = Vec::new();
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            let _ = tx.send(line.clone());
            all.push(line);
        }
        all
    });
    let progressed = loop {
        match rx.recv_timeout(std::time::Duration::from_secs(300)) {
            Ok(l) if l.starts_with("runs ") => {
                let n: u64 = l[5..]
                    .split('/')
                    .next()
                    .and_then(|n| n.parse().ok())
                    .unwrap_or(0);
                if n >= 1 {
                    break n;
                }
            }
            Ok(_) => {}
            Err(e) => panic!("no progress line off a terminal: {e}"),
        }
    };
    // SAFETY: kill(2) on our own child's pid.
    let sent = unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
    assert_eq!(sent, 0);
    let o = child.wait_with_output().expect("wait");
    let lines = reader.join().expect("reader");
    (o, lines, progressed)
}
