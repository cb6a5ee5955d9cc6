//! The helm survives its MOOSDB and its simulator (issue 10, point 3), with the real
//! binaries: the `helm` binary (not embedded) and the `moosdb` binary on a free port
//! of 127.0.0.1, the alpha mission at MOOSTimeWarp 20, and the `uSimMarine` simulator of
//! `helm run --embedded` running in this test process as a separate MOOS client (so it
//! can be killed and restarted on its own). An observer client records what reaches
//! the DB.
//!
//! 1. Mid-survey the `moosdb` process is killed (SIGKILL) and, 3 s later, a new one is
//!    started on the same port.
//! 2. Later the simulator is stopped for 2 s and restarted where the vehicle was.
//! 3. The mission must complete (`MISSION = complete`, the return behavior's endflag).
//!
//! A second test freezes the DB instead (SIGSTOP: the process is there, its sockets stay
//! open, it answers nothing) for 8 s: the helm's client gives up on it after 5 s of
//! silence (`silence_timeout`), so the helm stops posting into a DB that does not read;
//! after SIGCONT it reconnects and drives again.
//!
//! A third starts a second helm with the same MOOS name: refused by the DB, it exits
//! non-zero saying so, and the first keeps its connection.
//!
//! What the helm does while its DB is gone, as chosen from the specs: helm.md has no
//! staleness rule for navigation (its only nav rule is the start-up hold until every
//! NAV_* was received once) and moos-wire.md §5.6 says a MOOS app notices a dead DB by
//! the socket and reconnects; like CMOOSApp, the helm does not iterate while
//! disconnected. So it *holds*: no iteration and no posting while there is no DB (so
//! nothing is posted that cannot be delivered: the helm's alog, which records every
//! posting, has none in the outage, and it never logs `not posted`), then it
//! reconnects to the new DB, its client re-registers every variable (it gets NAV_* again
//! and finishes the mission) and it drives on. While the simulator is gone the DB is
//! there, so the helm keeps iterating on the last navigation it has (no all-stop: the
//! spec has none for stale navigation) and its DESIRED_* keep arriving.

use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::{free_port, ALPHA_BHV, ALPHA_MOOS};
use moos::client::{Client, ClientConfig};
use moos::mission::MissionFile;
use moos::wire::Message;

mod common;

const WARP: f64 = 20.0;

/// The alpha mission with `port`, the warp, and the simulator starting at `start`.
fn mission_text(port: u16, start: (f64, f64, f64, f64)) -> String {
    common::with_params(
        ALPHA_MOOS,
        &[
            ("ServerPort", port.to_string()),
            ("MOOSTimeWarp", WARP.to_string()),
            ("start_x", start.0.to_string()),
            ("start_y", start.1.to_string()),
            ("start_heading", start.2.to_string()),
            ("start_speed", start.3.to_string()),
        ],
    )
}

/// The `moosdb` built next to the `helm` binary (`cargo test --workspace` builds both).
fn moosdb_path() -> PathBuf {
    let helm = Path::new(env!("CARGO_BIN_EXE_helm"));
    helm.with_file_name(format!("moosdb{}", std::env::consts::EXE_SUFFIX))
}

/// A `moosdb` process, killed on drop.
struct MoosDb {
    child: Child,
    log: PathBuf,
}

impl MoosDb {
    fn start(mission: &Path, log: PathBuf) -> MoosDb {
        let out = std::fs::File::create(&log).expect("db log");
        let err = out.try_clone().expect("db log");
        let child = Command::new(moosdb_path())
            .arg(mission)
            .arg("--bind=127.0.0.1")
            .env("RUST_LOG", "info")
            .env("NO_COLOR", "1")
            .stdout(Stdio::from(out))
            .stderr(Stdio::from(err))
            .spawn()
            .unwrap_or_else(|e| {
                panic!(
                    "cannot start {}: {e} (build it: cargo build -p moosdb)",
                    moosdb_path().display()
                )
            });
        MoosDb { child, log }
    }

    fn wait_listening(&self, port: u16) {
        let t0 = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                t0.elapsed() < Duration::from_secs(10),
                "moosdb not listening"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }

    fn log(&self) -> String {
        std::fs::read_to_string(&self.log).unwrap_or_default()
    }
}

impl Drop for MoosDb {
    fn drop(&mut self) {
        self.kill();
    }
}

/// The helm process, interrupted (then killed) on drop.
struct Helm(Child);

impl Drop for Helm {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Everything the observer received, with its MOOS receive time.
struct Observer {
    c: Client,
    seen: Vec<(f64, Message)>,
}

impl Observer {
    fn new(port: u16) -> Observer {
        let mut cfg = ClientConfig::new("127.0.0.1", port, "observer");
        cfg.time_warp = WARP;
        let c = Client::connect(cfg).expect("observer connects");
        for v in [
            "DESIRED_SPEED",
            "DESIRED_HEADING",
            "NAV_X",
            "NAV_Y",
            "NAV_HEADING",
            "NAV_SPEED",
            "MISSION",
            "IVPHELM_STATE",
            "IVPHELM_ALLSTOP",
        ] {
            c.register(v, 0.0).expect("register");
        }
        Observer {
            c,
            seen: Vec::new(),
        }
    }

    fn poll(&mut self) {
        let mut v = Vec::new();
        self.c.wait_for_mail(Duration::from_millis(50));
        self.c.fetch(&mut v);
        let now = self.c.moos_time();
        self.seen.extend(v.into_iter().map(|m| (now, m)));
    }

    /// Poll until `pred` holds for a message received after `since` (MOOS time).
    fn wait_for(
        &mut self,
        what: &str,
        since: f64,
        limit: Duration,
        pred: impl Fn(&Message) -> bool,
    ) {
        let t0 = Instant::now();
        loop {
            // Received and stamped after `since` (mail queued before is not news).
            if self
                .seen
                .iter()
                .any(|(t, m)| *t >= since && m.time >= since && pred(m))
            {
                return;
            }
            assert!(t0.elapsed() < limit, "{what}: not seen within {limit:?}");
            self.poll();
        }
    }

    fn last(&self, key: &str) -> Option<f64> {
        self.seen
            .iter()
            .rev()
            .find(|(_, m)| m.key == key)
            .map(|(_, m)| m.dval)
    }

    fn count_after(&self, key: &str, since: f64) -> usize {
        self.seen
            .iter()
            .filter(|(t, m)| *t >= since && m.key == key)
            .count()
    }

    fn now(&self) -> f64 {
        self.c.moos_time()
    }

    fn pause(&mut self, real: Duration) {
        let t0 = Instant::now();
        while t0.elapsed() < real {
            self.poll();
        }
    }
}

/// One of these tests at a time: each runs a helm, a DB and a simulator against the clock.
fn serial() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LOCK.lock().unwrap_or_else(|p| p.into_inner())
}

/// `helm run MISSION --alog ALOG` (not embedded), warnings to `dir/helm.err`.
fn spawn_helm(moos_path: &Path, alog: &Path, dir: &Path) -> Helm {
    Helm(
        Command::new(env!("CARGO_BIN_EXE_helm"))
            .arg("run")
            .arg(moos_path)
            .args(["--duration", "3000", "--quiet", "--alog"])
            .arg(alog)
            .env("RUST_LOG", "warn")
            .env("NO_COLOR", "1")
            .stdout(Stdio::from(
                std::fs::File::create(dir.join("helm.out")).expect("out"),
            ))
            .stderr(Stdio::from(
                std::fs::File::create(dir.join("helm.err")).expect("err"),
            ))
            .spawn()
            .expect("start helm"),
    )
}

/// End the helm cleanly (SIGINT: final line, alog flushed); its (stdout, stderr).
fn interrupt(helm: &mut Helm, dir: &Path) -> (String, String) {
    let pid = helm.0.id().to_string();
    let _ = Command::new("kill").args(["-INT", &pid]).status();
    let t0 = Instant::now();
    while helm.0.try_wait().expect("wait").is_none() {
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "helm did not stop on SIGINT"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    (
        std::fs::read_to_string(dir.join("helm.out")).unwrap_or_default(),
        std::fs::read_to_string(dir.join("helm.err")).unwrap_or_default(),
    )
}

/// MOOS times of the helm's own postings, from its alog.
fn helm_post_times(alog: &Path) -> Vec<f64> {
    let f = std::fs::File::open(alog).expect("alog written");
    let log = moos::alog::read(std::io::BufReader::new(f)).expect("alog parses");
    let start = log.log_start.expect("LOGSTART");
    log.entries
        .iter()
        .filter(|e| e.source == "pHelmIvP")
        .map(|e| start + e.time)
        .collect()
}

fn scratch(tag: &str) -> PathBuf {
    common::temp_dir(&format!("helm-{tag}"))
}

/// The alpha mission written into `dir` for a DB on a free port, the vehicle at its
/// usual start, and that DB started (its log `dir/db_log`) and listening: (the mission
/// file, the port, the DB).
fn alpha_with_db(dir: &Path, db_log: &str) -> (PathBuf, u16, MoosDb) {
    let port = free_port();
    let moos_path = dir.join("alpha.moos");
    std::fs::write(&moos_path, mission_text(port, (0.0, -20.0, 180.0, 0.0))).expect("mission");
    std::fs::write(dir.join("alpha.bhv"), ALPHA_BHV).expect("bhv");
    let db = MoosDb::start(&moos_path, dir.join(db_log));
    db.wait_listening(port);
    (moos_path, port, db)
}

#[test]
fn helm_survives_moosdb_death_and_simulator_restart() {
    let _serial = serial();
    let dir = scratch("db-death");
    let (moos_path, port, mut db) = alpha_with_db(&dir, "db1.log");
    let alog = dir.join("helm.alog");

    let mission = MissionFile::read(&moos_path).expect("mission parses");
    let mut sim = Some(helm_app::embedded_sim::Sim::start(&mission).expect("simulator connects"));
    let mut obs = Observer::new(port);
    let mut helm = spawn_helm(&moos_path, &alog, &dir);

    // Driving: the helm commands speed and the vehicle moves east towards 60,-40.
    obs.wait_for("driving", 0.0, Duration::from_secs(30), |m| {
        m.key == "NAV_X" && m.dval > 15.0
    });

    // 1. The DB dies.
    let killed = obs.now();
    db.kill();
    obs.pause(Duration::from_secs(3));
    let restarted = obs.now();
    let db = MoosDb::start(&moos_path, dir.join("db2.log"));
    db.wait_listening(port);
    obs.wait_for(
        "helm drives again",
        restarted,
        Duration::from_secs(20),
        |m| m.key == "DESIRED_SPEED" && m.dval > 0.0,
    );
    obs.wait_for(
        "vehicle moves again",
        restarted,
        Duration::from_secs(20),
        |m| m.key == "NAV_X",
    );
    assert!(
        db.log().contains("pHelmIvP"),
        "the helm did not connect to the new DB:\n{}",
        db.log()
    );

    // 2. The simulator dies, and comes back where the vehicle was.
    obs.pause(Duration::from_secs(2));
    if let Some(s) = sim.take() {
        s.stop();
    }
    let sim_gone = obs.now();
    let at = (
        obs.last("NAV_X").expect("x"),
        obs.last("NAV_Y").expect("y"),
        obs.last("NAV_HEADING").expect("heading"),
        obs.last("NAV_SPEED").expect("speed"),
    );
    obs.pause(Duration::from_secs(2));
    let sim_back = obs.now();
    // With the DB up the helm keeps deciding on its last navigation (no staleness rule).
    assert!(
        obs.count_after("DESIRED_HEADING", sim_gone + 2.0) > 10,
        "the helm stopped posting while the simulator was gone"
    );
    assert_eq!(
        obs.count_after("NAV_X", sim_gone + 2.0),
        0,
        "the simulator still posts"
    );
    let restart_text = mission_text(port, at);
    let restart_mission =
        MissionFile::parse(&restart_text, &moos_path).expect("restart mission parses");
    let _sim = helm_app::embedded_sim::Sim::start(&restart_mission).expect("simulator reconnects");

    // 3. The mission completes.
    obs.wait_for("mission complete", sim_back, Duration::from_secs(90), |m| {
        m.key == "MISSION" && m.string() == "complete"
    });

    let (out, err) = interrupt(&mut helm, &dir);
    assert!(
        err.contains("lost the MOOSDB"),
        "no disconnect warning:\n{err}"
    );
    assert!(
        !err.contains("not posted"),
        "the helm tried to post without a DB:\n{err}"
    );
    assert!(out.contains("final:"), "{out}\n{err}");

    // The helm's alog: postings before the kill, none during the outage, many after.
    // The client sees the socket close within milliseconds: 0.25 s real of grace.
    let grace = 0.25 * WARP;
    let helm_posts = helm_post_times(&alog);
    let during: Vec<f64> = helm_posts
        .iter()
        .copied()
        .filter(|t| *t > killed + grace && *t < restarted)
        .collect();
    assert!(
        during.is_empty(),
        "{} postings while the DB was dead (killed {killed:.1}, restarted {restarted:.1}): {:?}",
        during.len(),
        &during[..during.len().min(5)]
    );
    println!(
        "helm postings: {} before the kill, {} in the outage, {} after the new DB (outage {:.1} MOOS s)",
        helm_posts.iter().filter(|t| **t < killed).count(),
        during.len(),
        helm_posts.iter().filter(|t| **t > restarted).count(),
        restarted - killed
    );
    assert!(
        helm_posts.iter().any(|t| *t < killed),
        "nothing posted before the kill"
    );
    assert!(
        helm_posts.iter().filter(|t| **t > restarted).count() > 100,
        "too few postings after the DB came back"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn signal(pid: u32, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &pid.to_string()])
        .status()
        .is_ok_and(|s| s.success());
    assert!(ok, "kill {sig} {pid} failed");
}

#[test]
fn helm_gives_up_on_a_frozen_moosdb_and_comes_back() {
    let _serial = serial();
    let dir = scratch("db-frozen");
    let (moos_path, port, db) = alpha_with_db(&dir, "db.log");
    let alog = dir.join("helm.alog");
    let mission = MissionFile::read(&moos_path).expect("mission parses");
    let _sim = helm_app::embedded_sim::Sim::start(&mission).expect("simulator connects");
    let mut obs = Observer::new(port);
    let mut helm = spawn_helm(&moos_path, &alog, &dir);
    obs.wait_for("driving", 0.0, Duration::from_secs(30), |m| {
        m.key == "NAV_X" && m.dval > 15.0
    });

    // Frozen for 8 s real (160 MOOS s).
    let frozen = obs.now();
    signal(db.child.id(), "-STOP");
    obs.pause(Duration::from_secs(8));
    let thawed = moos::time::local_time(WARP);
    signal(db.child.id(), "-CONT");
    obs.wait_for("helm drives again", thawed, Duration::from_secs(30), |m| {
        m.key == "DESIRED_SPEED" && m.dval > 0.0
    });
    let (out, err) = interrupt(&mut helm, &dir);
    assert!(out.contains("final:"), "{out}\n{err}");
    assert!(
        err.contains("nothing from the DB"),
        "the helm's client did not give up on the frozen DB:\n{err}"
    );
    assert!(err.contains("lost the MOOSDB"), "{err}");
    // Posting stops once the client gives up (5 s of silence, and up to the 250 ms
    // read tick): from 6 s real after the freeze to the thaw, nothing.
    let posts = helm_post_times(&alog);
    let quiet_from = frozen + 6.0 * WARP;
    let during = posts
        .iter()
        .filter(|t| **t > quiet_from && **t < thawed)
        .count();
    let before = posts.iter().filter(|t| **t < frozen).count();
    let after = posts.iter().filter(|t| **t > thawed).count();
    println!("helm postings: {before} before the freeze, {during} from 6 s in to the thaw, {after} after");
    assert_eq!(during, 0, "the helm kept posting into a frozen DB");
    assert!(before > 0 && after > 0, "{before} / {after}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A second helm with the same MOOS name: the DB refuses it, it says so and exits
/// non-zero; the first helm keeps its connection.
#[test]
fn a_second_helm_with_the_same_name_is_refused() {
    let _serial = serial();
    let dir = scratch("db-clash");
    let (moos_path, _, db) = alpha_with_db(&dir, "db.log");
    let first_dir = dir.join("first");
    std::fs::create_dir_all(&first_dir).expect("dir");
    let mut first = spawn_helm(&moos_path, &first_dir.join("helm.alog"), &first_dir);
    let t0 = Instant::now();
    while !db.log().contains("client connected client=pHelmIvP") {
        assert!(
            t0.elapsed() < Duration::from_secs(20),
            "first helm never connected"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = Command::new(env!("CARGO_BIN_EXE_helm"))
        .arg("run")
        .arg(&moos_path)
        .args(["--duration", "30", "--quiet"])
        .output()
        .expect("second helm");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "second helm ran:\n{err}");
    assert!(err.contains("already exists"), "{err}");
    assert!(
        first.0.try_wait().expect("wait").is_none(),
        "first helm died"
    );
    assert!(
        !db.log().contains("client disconnected client=pHelmIvP"),
        "{}",
        db.log()
    );
    let (out, _) = interrupt(&mut first, &first_dir);
    assert!(out.contains("final:"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}
