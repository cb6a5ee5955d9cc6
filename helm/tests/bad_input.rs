//! `helm check` on bad input files (issue 10, point 4): a `.bhv` with invalid UTF-8, a
//! 100 MB file, a file that includes itself (`#include` is nsplug's, not the helm's or
//! MOOS's: bhv-format.md §1, moos-wire.md §7), an unreadable file. Each gives one line
//! naming the file and line (where a line applies) and showing the line, a non-zero
//! exit, and never a hang (every run is killed after 30 s, which fails the test).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;

const MISSION: &str = "ServerHost = localhost\nServerPort = 9000\nCommunity = alpha\nLatOrigin = 43.8\nLongOrigin = -70.3\n\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n  behaviors = m.bhv\n  domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";

const GOOD_BHV: &str = "initialize DEPLOY = true\n\nBehavior = BHV_Waypoint\n{\n  name = go\n  condition = DEPLOY = true\n  speed = 2\n  points = 0,0 : 10,10\n}\n";

fn scratch(name: &str) -> PathBuf {
    common::scratch(Path::new("bad_input").join(name))
}

/// `helm check DIR/m.moos`: (exit code, stdout + stderr, seconds taken).
fn check(d: &Path) -> (i32, String, f64) {
    check_as(d, None)
}

/// As [`check`], run through `wrapper` (a command and its arguments) if given.
fn check_as(d: &Path, wrapper: Option<&[&str]>) -> (i32, String, f64) {
    let t0 = Instant::now();
    let mut cmd = match wrapper {
        Some([w, args @ ..]) => {
            let mut c = Command::new(w);
            c.args(args).arg(env!("CARGO_BIN_EXE_helm"));
            c
        }
        _ => Command::new(env!("CARGO_BIN_EXE_helm")),
    };
    let mut child = cmd
        .arg("check")
        .arg(d.join("m.moos"))
        .env_remove("IVP_BEHAVIOR_DIRS")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run helm");
    while child.try_wait().expect("wait").is_none() {
        if t0.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("helm check hung on {}", d.display());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().expect("output");
    (
        out.status.code().unwrap_or(-1),
        common::text(&out),
        t0.elapsed().as_secs_f64(),
    )
}

/// The one output line that names `file` (with `:line` if given) and says `what`.
fn error_line<'a>(text: &'a str, file: &Path, line: Option<usize>, what: &str) -> &'a str {
    let at = match line {
        Some(n) => format!("{}:{n}:", file.display()),
        None => file.display().to_string(),
    };
    text.lines()
        .find(|l| l.contains(&at) && l.contains(what))
        .unwrap_or_else(|| panic!("no line with [{at}] and [{what}] in:\n{text}"))
}

#[test]
fn bhv_with_invalid_utf8() {
    let d = scratch("utf8");
    std::fs::write(d.join("m.moos"), MISSION).expect("write");
    let mut bhv = GOOD_BHV.replace("name = go", "name = g\u{1}o").into_bytes();
    let at = bhv.iter().position(|&b| b == 1).expect("marker");
    bhv[at] = 0xff;
    std::fs::write(d.join("m.bhv"), &bhv).expect("write");
    let (code, text, _) = check(&d);
    assert_eq!(code, 1, "{text}");
    let l = error_line(&text, &d.join("m.bhv"), Some(5), "invalid UTF-8");
    assert!(l.contains("(line: name = g\u{fffd}o)"), "{l}");
}

#[test]
fn a_100_megabyte_bhv_and_mission_are_refused_at_once() {
    let d = scratch("huge");
    std::fs::write(d.join("m.moos"), MISSION).expect("write");
    let line = "// a comment line, repeated to make a very large behavior file ...........\n";
    let mut big = String::with_capacity(100 << 20);
    while big.len() < 100 << 20 {
        big.push_str(line);
    }
    std::fs::write(d.join("m.bhv"), &big).expect("write 100 MB");
    let (code, text, secs) = check(&d);
    assert_eq!(code, 1, "{text}");
    error_line(&text, &d.join("m.bhv"), None, "larger than");
    assert!(secs < 10.0, "took {secs} s");
    // The mission itself: 100 MB (sparse).
    let f = std::fs::File::create(d.join("m.moos")).expect("create");
    f.set_len(100 << 20).expect("set_len");
    drop(f);
    let (code, text, secs) = check(&d);
    assert_eq!(code, 2, "{text}");
    error_line(&text, &d.join("m.moos"), None, "larger than");
    assert!(secs < 10.0, "took {secs} s");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn files_that_include_themselves() {
    let d = scratch("include");
    std::fs::write(d.join("m.moos"), MISSION).expect("write");
    let bhv = format!("#include m.bhv\n{GOOD_BHV}");
    std::fs::write(d.join("m.bhv"), bhv).expect("write");
    let (code, text, _) = check(&d);
    assert_eq!(code, 1, "{text}");
    let l = error_line(&text, &d.join("m.bhv"), Some(1), "nsplug directive");
    assert!(l.contains("(line: #include m.bhv)"), "{l}");

    std::fs::write(d.join("m.bhv"), GOOD_BHV).expect("write");
    std::fs::write(d.join("m.moos"), format!("{MISSION}#include m.moos\n")).expect("write");
    let (code, text, _) = check(&d);
    assert_eq!(code, 2, "{text}");
    let l = error_line(&text, &d.join("m.moos"), Some(14), "nsplug directive");
    assert!(l.contains("(line: #include m.moos)"), "{l}");
}

/// chmod 000 does not stop root from reading: as root, the helm runs as `nobody`
/// (setpriv) to see the file unreadable. `None`: nothing can make it unreadable here.
fn unreadable(p: &Path) -> Option<Option<&'static [&'static str]>> {
    use std::os::unix::fs::PermissionsExt;
    const NOBODY: &[&str] = &[
        "setpriv",
        "--reuid=65534",
        "--regid=65534",
        "--clear-groups",
    ];
    std::fs::set_permissions(p, std::fs::Permissions::from_mode(0o000)).expect("chmod");
    if std::fs::read(p).is_err() {
        return Some(None);
    }
    // Root: can `nobody` run the helm (setpriv present, the path open to others)?
    let runs = Command::new(NOBODY[0])
        .args(&NOBODY[1..])
        .arg(env!("CARGO_BIN_EXE_helm"))
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if runs {
        return Some(Some(NOBODY));
    }
    println!(
        "skipped: running as root without a way to run as nobody, {} stays readable",
        p.display()
    );
    None
}

#[test]
fn unreadable_files() {
    use std::os::unix::fs::PermissionsExt;
    let d = scratch("unreadable");
    std::fs::write(d.join("m.moos"), MISSION).expect("write");
    std::fs::write(d.join("m.bhv"), GOOD_BHV).expect("write");
    // The folder readable by all (for the nobody run); the files not.
    std::fs::set_permissions(&d, std::fs::Permissions::from_mode(0o755)).expect("chmod");
    if let Some(wrapper) = unreadable(&d.join("m.bhv")) {
        let (code, text, _) = check_as(&d, wrapper);
        assert_eq!(code, 1, "{text}");
        error_line(&text, &d.join("m.bhv"), None, "ermission denied");
    }
    if let Some(wrapper) = unreadable(&d.join("m.moos")) {
        let (code, text, _) = check_as(&d, wrapper);
        assert_eq!(code, 2, "{text}");
        error_line(&text, &d.join("m.moos"), None, "ermission denied");
    }
    for f in ["m.moos", "m.bhv"] {
        let _ = std::fs::set_permissions(d.join(f), std::fs::Permissions::from_mode(0o644));
    }
    // A directory where a file should be (readable by anyone, root included).
    std::fs::remove_file(d.join("m.bhv")).expect("rm");
    std::fs::create_dir(d.join("m.bhv")).expect("mkdir");
    let (code, text, _) = check(&d);
    assert_eq!(code, 1, "{text}");
    error_line(&text, &d.join("m.bhv"), None, "Could not find File");
}

#[test]
fn a_fifo_is_refused_not_waited_on() {
    // Opening a FIFO waits for a writer, possibly forever: refused at once instead.
    let d = scratch("fifo");
    std::fs::write(d.join("m.moos"), MISSION).expect("write");
    let mkfifo = |p: &Path| {
        Command::new("mkfifo")
            .arg(p)
            .status()
            .is_ok_and(|s| s.success())
    };
    if !mkfifo(&d.join("m.bhv")) {
        println!("skipped: no mkfifo");
        return;
    }
    let (code, text, secs) = check(&d);
    assert_eq!(code, 1, "{text}");
    error_line(&text, &d.join("m.bhv"), None, "FIFO");
    assert!(secs < 10.0, "took {secs} s");
    std::fs::remove_file(d.join("m.moos")).expect("rm");
    assert!(mkfifo(&d.join("m.moos")));
    let (code, text, _) = check(&d);
    assert_eq!(code, 2, "{text}");
    error_line(&text, &d.join("m.moos"), None, "FIFO");
}
