//! The helm started the pAntler way, `helm MISSION NAME`, as a child process against our
//! MOOSDB (the `moos::db` the `moosdb` binary runs) with the uSimMarine simulator closing
//! the loop; the pHelmIvP flags; AppCasting; IVPHELM_REGISTER rounds; and a standby helm
//! in a second process taking over from a killed or frozen primary (helm.md §1, §10,
//! §12, contacts-appcast.md §5).

use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::free_port;
use moos::client::{Client, ClientConfig};
use moos::db::{Db, DbConfig};
use moos::mission::MissionFile;
use moos::wire::Message;

mod common;

const HELM: &str = env!("CARGO_BIN_EXE_helm");

const BHV: &str = "\
initialize DEPLOY = true
initialize RETURN = false

Behavior = BHV_Waypoint
{
  name      = waypt_survey
  pwt       = 100
  condition = RETURN = false
  condition = DEPLOY = true
  updates   = SURVEY_UPDATE
  endflag   = RETURN = true

  speed          = 2
  capture_radius = 4
  slip_radius    = 10
  points         = 60,-40 : 60,-160 : 150,-160 : 180,-100 : 150,-40
}
";

fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir(&format!("helm-phelmivp-{tag}"))
}

/// A helm block named `name` (extra lines added), for the mission below.
fn block(name: &str, extra: &str) -> String {
    format!(
        "ProcessConfig = {name}\n{{\n  AppTick = 4\n  behaviors = mission.bhv\n  \
         domain = course:0:359:360\n  domain = speed:0:4:41\n  start_in_drive = true\n{extra}}}\n"
    )
}

/// The DB, the simulator, and the mission folder of one test.
struct Bench {
    db: Option<Db>,
    sim: Option<helm_app::embedded_sim::Sim>,
    dir: PathBuf,
    mission: PathBuf,
    port: u16,
    warp: f64,
    children: Vec<Child>,
}

impl Bench {
    fn new(tag: &str, warp: f64, blocks: &str) -> Bench {
        let dir = temp_dir(tag);
        let port = free_port();
        let text = format!(
            "ServerHost = localhost\nServerPort = {port}\nCommunity = alpha\n\
             MOOSTimeWarp = {warp}\nLatOrigin = 43.8253\nLongOrigin = -70.3304\n\n{blocks}\n\
             ProcessConfig = uSimMarine\n{{\n  AppTick = 10\n  start_x = 0\n  start_y = -20\n\
             start_heading = 180\n}}\n"
        );
        let mission = dir.join("mission.moos");
        std::fs::write(&mission, text).expect("write mission");
        std::fs::write(dir.join("mission.bhv"), BHV).expect("write bhv");
        let m = MissionFile::read(&mission).expect("mission parses");
        let mut cfg = DbConfig::default();
        cfg.apply_mission(&m);
        let db = Db::start(cfg).expect("start the MOOSDB");
        let sim = helm_app::embedded_sim::Sim::start(&m).expect("start uSimMarine");
        Bench {
            db: Some(db),
            sim: Some(sim),
            dir,
            mission,
            port,
            warp,
            children: Vec::new(),
        }
    }

    /// A client of the test, subscribed to `vars`.
    fn watcher(&self, name: &str, vars: &[&str]) -> Client {
        let mut cfg = ClientConfig::new("127.0.0.1", self.port, name);
        cfg.time_warp = self.warp;
        let c = Client::connect(cfg).expect("watcher connects");
        for v in vars {
            c.register(v, 0.0).expect("register");
        }
        c
    }

    /// Start `helm ARGS` with its output in files of the test folder; returns its index.
    fn spawn(&mut self, args: &[&str], tag: &str) -> usize {
        let out = std::fs::File::create(self.dir.join(format!("{tag}.out"))).expect("out");
        let err = std::fs::File::create(self.dir.join(format!("{tag}.err"))).expect("err");
        let child = Command::new(HELM)
            .args(args)
            .current_dir(&self.dir)
            .stdin(Stdio::null())
            .stdout(out)
            .stderr(err)
            .spawn()
            .expect("start helm");
        self.children.push(child);
        self.children.len() - 1
    }

    fn pid(&self, i: usize) -> String {
        self.children[i].id().to_string()
    }

    fn signal(&self, i: usize, sig: &str) {
        let ok = Command::new("kill")
            .args([format!("-{sig}"), self.pid(i)])
            .status()
            .expect("run kill")
            .success();
        assert!(ok, "kill -{sig} failed");
    }

    /// Wait for child `i` to exit within `limit`; its exit code.
    fn wait_exit(&mut self, i: usize, limit: Duration) -> Option<i32> {
        let t0 = Instant::now();
        while t0.elapsed() < limit {
            if let Some(st) = self.children[i].try_wait().expect("wait") {
                return Some(st.code().unwrap_or(-1));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        None
    }

    fn output(&self, tag: &str) -> String {
        let out = std::fs::read_to_string(self.dir.join(format!("{tag}.out"))).unwrap_or_default();
        let err = std::fs::read_to_string(self.dir.join(format!("{tag}.err"))).unwrap_or_default();
        format!("--- stdout\n{out}\n--- stderr\n{err}")
    }
}

impl Drop for Bench {
    fn drop(&mut self) {
        for c in &mut self.children {
            let _ = Command::new("kill")
                .args(["-CONT", &c.id().to_string()])
                .status();
            let _ = c.kill();
            let _ = c.wait();
        }
        if let Some(s) = self.sim.take() {
            s.stop();
        }
        if let Some(d) = self.db.take() {
            d.shutdown();
        }
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Collect mail until `done` says so or `limit` passes; returns everything read.
fn read_until(
    c: &Client,
    limit: Duration,
    mut done: impl FnMut(&[Message]) -> bool,
) -> (Vec<Message>, bool) {
    let t0 = Instant::now();
    let mut all = Vec::new();
    let mut batch = Vec::new();
    while t0.elapsed() < limit {
        c.wait_for_mail(Duration::from_millis(50));
        batch.clear();
        c.fetch(&mut batch);
        all.append(&mut batch);
        if done(&all) {
            return (all, true);
        }
    }
    (all, false)
}

fn from<'a>(msgs: &'a [Message], var: &str, source: &str) -> Vec<&'a Message> {
    msgs.iter()
        .filter(|m| m.key == var && m.source == source)
        .collect()
}

#[test]
fn pantler_launch_connects_under_its_name_drives_and_ends_on_sigterm_and_sigint() {
    let name = "pHelmIvP_Alpha";
    let mut b = Bench::new("pantler", 10.0, &block(name, ""));
    let w = b.watcher(
        "watcher",
        &[
            "DESIRED_SPEED",
            "IVPHELM_STATE",
            "IVPHELM_REGISTER",
            "NAV_Y",
        ],
    );
    let mission = b.mission.display().to_string();
    let h = b.spawn(&[&mission, name], "helm");
    // Drives: DESIRED_SPEED > 0 from NAME, and the simulated vehicle moves south.
    let (mail, ok) = read_until(&w, Duration::from_secs(30), |all| {
        let moving = all
            .iter()
            .filter(|m| m.key == "NAV_Y")
            .any(|m| m.dval < -30.0);
        let desired = from(all, "DESIRED_SPEED", name)
            .iter()
            .any(|m| m.dval > 0.0);
        moving && desired
    });
    assert!(
        ok,
        "the helm did not drive the vehicle\n{}",
        b.output("helm")
    );
    assert!(
        from(&mail, "IVPHELM_STATE", name)
            .iter()
            .any(|m| m.string() == "DRIVE"),
        "no IVPHELM_STATE=DRIVE from {name}"
    );
    assert!(from(&mail, "DESIRED_SPEED", "pHelmIvP").is_empty());
    // Registrations repeat (helm.md §4.1): a helm variable at connection and at the end
    // of start-up; a behavior's variable at the end of start-up and the first decision;
    // NAV_X is both (the waypoint reads it too).
    let regs = |var: &str| {
        from(&mail, "IVPHELM_REGISTER", name)
            .iter()
            .filter(|m| m.string() == var)
            .count()
    };
    assert_eq!(regs("DB_CLIENTS"), 2, "DB_CLIENTS registrations");
    assert_eq!(regs("SURVEY_UPDATE"), 2, "SURVEY_UPDATE registrations");
    assert_eq!(regs("NAV_X"), 3, "NAV_X registrations");
    assert!(
        regs("APPCAST_REQ") == 0,
        "the base's variables are not announced"
    );

    b.signal(h, "TERM");
    let code = b.wait_exit(h, Duration::from_secs(5));
    assert_eq!(code, Some(0), "SIGTERM: clean exit\n{}", b.output("helm"));

    // SIGINT as well (Ctrl-C in a pAntler console).
    let h2 = b.spawn(&[&mission, name, "--verbose=quiet"], "helm2");
    let (_, ok) = read_until(&w, Duration::from_secs(20), |all| {
        all.iter()
            .any(|m| m.key == "IVPHELM_STATE" && m.source == name && m.time > 0.0)
    });
    assert!(ok, "second helm did not start\n{}", b.output("helm2"));
    b.signal(h2, "INT");
    assert_eq!(b.wait_exit(h2, Duration::from_secs(5)), Some(0));
    let out = b.output("helm2");
    assert!(
        !out.contains('$') && !out.contains("final:"),
        "quiet: {out}"
    );
}

#[test]
fn appcast_request_gets_the_report_with_state_behaviors_and_warnings() {
    let name = "pHelmIvP";
    let mut b = Bench::new("appcast", 4.0, &block(name, ""));
    let w = b.watcher("uMAC_test", &["APPCAST", "IVPHELM_STATE"]);
    let mission = b.mission.display().to_string();
    let h = b.spawn(&[&mission, "--verbose=terse"], "helm");
    let (_, ok) = read_until(&w, Duration::from_secs(20), |all| {
        from(all, "IVPHELM_STATE", name)
            .iter()
            .any(|m| m.string() == "DRIVE")
    });
    assert!(ok, "helm did not start\n{}", b.output("helm"));
    // A bad update string: the behavior posts a BHV_WARNING, a run warning.
    w.notify_string("SURVEY_UPDATE", "no_such_param=3", None)
        .expect("post");
    std::thread::sleep(Duration::from_millis(500));
    w.notify_string(
        "APPCAST_REQ",
        "node=all,app=pHelmIvP,duration=3.0,key=uMAC_test,thresh=any",
        None,
    )
    .expect("post");
    let (mail, ok) = read_until(&w, Duration::from_secs(10), |all| {
        from(all, "APPCAST", name)
            .iter()
            .any(|m| m.string().contains("run_warnings="))
    });
    assert!(ok, "no APPCAST with run warnings\n{}", b.output("helm"));
    let cast = from(&mail, "APPCAST", name)
        .last()
        .map(|m| m.string().into_owned())
        .expect("an appcast");
    assert!(cast.starts_with("proc=pHelmIvP!@#iter="), "{cast}");
    assert!(cast.contains("!@#node=alpha!@#"), "{cast}");
    assert!(cast.contains("Helm State:      DRIVE"), "{cast}");
    assert!(
        cast.contains("Behaviors Active: ---------- (1)!@  waypt_survey ["),
        "{cast}"
    );
    assert!(
        cast.contains("Helm Decision: [speed,0,4,41] [course,0,359,360]"),
        "{cast}"
    );
    assert!(
        cast.contains(":BHV_WARNING: Faulty update for behavior: waypt_survey"),
        "{cast}"
    );
    assert!(
        cast.contains("!@Variable ") && cast.contains("!@WPT_STAT "),
        "{cast}"
    );
    // Terse on the terminal: `$` per iteration, no report.
    b.signal(h, "TERM");
    assert_eq!(b.wait_exit(h, Duration::from_secs(5)), Some(0));
    let out = b.output("helm");
    assert!(out.contains("$$$"), "{out}");
    assert!(!out.contains("Helm Iteration:"), "{out}");
}

#[test]
fn verbose_mode_prints_the_report_and_helm_verbose_selects_terse() {
    // Not a terminal here: `TERM_REPORTING = true` asks for the report anyway.
    let mut b = Bench::new("verbose", 4.0, &block("pHelmIvP", ""));
    let text = std::fs::read_to_string(&b.mission).expect("read mission");
    std::fs::write(&b.mission, format!("TERM_REPORTING = true\n{text}")).expect("write");
    let w = b.watcher("watcher", &["IVPHELM_STATE"]);
    let mission = b.mission.display().to_string();
    let h = b.spawn(&[&mission], "verbose");
    let (_, ok) = read_until(&w, Duration::from_secs(20), |all| {
        from(all, "IVPHELM_STATE", "pHelmIvP")
            .iter()
            .filter(|m| m.string() == "DRIVE")
            .count()
            > 8
    });
    assert!(ok, "helm did not drive\n{}", b.output("verbose"));
    b.signal(h, "TERM");
    assert_eq!(b.wait_exit(h, Duration::from_secs(5)), Some(0));
    let out = b.output("verbose");
    let rule = "=".repeat(62);
    assert!(out.contains(&format!("{rule}\npHelmIvP alpha")), "{out}");
    assert!(out.contains("  Helm Iteration:  "), "{out}");
    assert!(out.contains("Behaviors Active: ----------"), "{out}");
    assert!(!out.contains("$$"), "{out}");

    // HELM_VERBOSE=terse: the heartbeat instead.
    let out_f = std::fs::File::create(b.dir.join("terse.out")).expect("out");
    let child = Command::new(HELM)
        .arg(&mission)
        .env("HELM_VERBOSE", "terse")
        .current_dir(&b.dir)
        .stdin(Stdio::null())
        .stdout(out_f)
        .stderr(Stdio::null())
        .spawn()
        .expect("start helm");
    b.children.push(child);
    let h2 = b.children.len() - 1;
    std::thread::sleep(Duration::from_secs(3));
    b.signal(h2, "TERM");
    assert_eq!(b.wait_exit(h2, Duration::from_secs(5)), Some(0));
    let out = b.output("terse");
    assert!(
        out.contains("$$$") && !out.contains("Helm Iteration"),
        "{out}"
    );
}

fn run_flag(args: &[&str]) -> Output {
    Command::new(HELM)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .expect("run helm")
}

#[test]
fn phelmivp_flags() {
    let text = |o: &Output| String::from_utf8_lossy(&o.stdout).into_owned();
    for v in ["-v", "--version", "-version"] {
        let o = run_flag(&["x.moos", v]);
        assert!(o.status.success() && text(&o).contains("pHelmIvP"), "{v}");
    }
    let o = run_flag(&["-i"]);
    assert!(o.status.success());
    assert!(text(&o).contains("SUBSCRIPTIONS:") && text(&o).contains("DESIRED_HEADING"));
    for h in ["-h", "--help", "-help"] {
        let o = run_flag(&["alpha.moos", h]);
        assert!(o.status.success(), "{h}");
        assert!(
            text(&o).contains("helm MISSION.moos [FILE.bhv]... [NAME]"),
            "{h}"
        );
    }
    let o = run_flag(&["alpha.moos", "--verbose=loud"]);
    assert!(!o.status.success());
    assert_eq!(text(&o).trim(), "Illegal verbose setting. Exiting now.");

    // `-e`: a block `helm check` accepts, in a mission with the globals it needs.
    let o = run_flag(&["-e"]);
    assert!(o.status.success());
    let dir = temp_dir("example");
    let mission = format!(
        "Community = alpha\nLatOrigin = 43.8\nLongOrigin = -70.3\n{}",
        text(&o)
    );
    std::fs::write(dir.join("m.moos"), mission).expect("write");
    std::fs::write(dir.join("alpha.bhv"), BHV).expect("write");
    let c = run_flag(&["check", &dir.join("m.moos").display().to_string()]);
    let out = text(&c);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(c.status.success(), "{out}");
    assert!(out.contains("ok: 1 behavior(s)"), "{out}");
}

/// Primary `pHelmIvP` and standby `pHelmIvP_Standby` (standby = 2 MOOS s) as two
/// processes; returns the bench and both child indexes once the standby listens.
fn two_helms(tag: &str) -> (Bench, usize, usize, Client) {
    let blocks = format!(
        "{}\n{}",
        block("pHelmIvP", ""),
        block("pHelmIvP_Standby", "  standby = 2\n")
    );
    let mut b = Bench::new(tag, 4.0, &blocks);
    let w = b.watcher(
        "watcher",
        &[
            "IVPHELM_STATE",
            "DESIRED_SPEED",
            "DESIRED_HEADING",
            "IVPHELM_ALLSTOP",
        ],
    );
    let mission = b.mission.display().to_string();
    let p = b.spawn(&[&mission, "pHelmIvP"], "primary");
    let s = b.spawn(&[&mission, "pHelmIvP_Standby"], "standby");
    let (_, ok) = read_until(&w, Duration::from_secs(20), |all| {
        let primary = from(all, "DESIRED_SPEED", "pHelmIvP")
            .iter()
            .any(|m| m.dval > 0.0);
        let standby = from(all, "IVPHELM_STATE", "pHelmIvP_Standby")
            .iter()
            .any(|m| m.string() == "STANDBY");
        primary && standby
    });
    assert!(
        ok,
        "primary driving and standby waiting\n{}\n{}",
        b.output("primary"),
        b.output("standby")
    );
    (b, p, s, w)
}

#[test]
fn standby_process_takes_over_from_a_killed_primary() {
    let (mut b, p, _s, w) = two_helms("standby-kill");
    b.signal(p, "KILL");
    let _ = b.wait_exit(p, Duration::from_secs(2));
    let killed = Instant::now();
    let (_, ok) = read_until(&w, Duration::from_secs(10), |all| {
        from(all, "DESIRED_SPEED", "pHelmIvP_Standby")
            .iter()
            .any(|m| m.dval > 0.0)
    });
    assert!(ok, "the standby never drove\n{}", b.output("standby"));
    // standby = 2 MOOS s at warp 4 is 0.5 s; allow for the DB noticing and mail delay.
    assert!(
        killed.elapsed() < Duration::from_secs(3),
        "took {:?}",
        killed.elapsed()
    );
}

#[test]
fn frozen_primary_is_disabled_after_the_standby_took_over() {
    let (b, p, _s, w) = two_helms("standby-stop");
    b.signal(p, "STOP");
    let (_, ok) = read_until(&w, Duration::from_secs(10), |all| {
        from(all, "DESIRED_SPEED", "pHelmIvP_Standby")
            .iter()
            .any(|m| m.dval > 0.0)
    });
    assert!(ok, "the standby never drove\n{}", b.output("standby"));
    // Resume the primary well within the DB's client timeout.
    std::thread::sleep(Duration::from_millis(500));
    // Stamped before the signal: a frozen process posts nothing.
    let resumed = w.moos_time();
    b.signal(p, "CONT");
    let (mail, _) = read_until(&w, Duration::from_secs(4), |_| false);
    let after: Vec<&Message> = mail
        .iter()
        .filter(|m| m.source == "pHelmIvP" && m.time >= resumed)
        .collect();
    assert!(
        after
            .iter()
            .any(|m| m.key == "IVPHELM_STATE" && m.string() == "DISABLED"),
        "primary not DISABLED: {after:?}\n{}",
        b.output("primary")
    );
    let allstops: Vec<&&Message> = after
        .iter()
        .filter(|m| m.key == "IVPHELM_ALLSTOP")
        .collect();
    assert_eq!(allstops.len(), 1, "{allstops:?}");
    assert_eq!(allstops[0].string(), "DisabledByStandbyHelm");
    let desired: Vec<&&Message> = after
        .iter()
        .filter(|m| m.key.starts_with("DESIRED_"))
        .collect();
    assert!(
        desired.iter().all(|m| m.dval == 0.0),
        "the disabled primary drove: {desired:?}"
    );
    // And the standby keeps driving.
    assert!(from(&mail, "DESIRED_SPEED", "pHelmIvP_Standby")
        .iter()
        .any(|m| m.dval > 0.0));
}
