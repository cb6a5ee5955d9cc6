//! The `obstaclemgr` binary against our `moosdb` binary, on a free port: a mission
//! with a pObstacleMgr block; a test client plays ownship (NAV_*), the helm's V24
//! template (OBM_ALERT_REQUEST) and the shoreside (GIVEN_OBSTACLE, TRACKED_FEATURE).
//! Checked: OBM_CONNECT at start; the alert for a given obstacle in range, in the exact
//! format the helm's spawn reads; its resolution when its duration runs out; a cluster
//! of tracked points alerted with its hull and resolved when its points age out; the
//! new-obstacle flag; a bad block line in the APPCAST and on stderr with file and line.
//! Nothing is asserted on timing: every wait polls with a generous limit.

use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use moos::client::{Client, ClientConfig};
use moos::Message;
use test_support::{free_port, moosdb_beside, wait_for, Proc};

/// The `moosdb` next to `obstaclemgr` (see [`test_support::moosdb_beside`]).
fn moosdb_path() -> PathBuf {
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_obstaclemgr"));
    moosdb_beside(&exe, env!("CARGO_MANIFEST_DIR"), "obstaclemgr-test-moosdb")
}

/// Every message of `var` seen so far.
fn seen<'a>(log: &'a [Message], var: &str) -> Vec<&'a Message> {
    log.iter().filter(|m| m.key == var).collect()
}

fn pos(log: &[Message], var: &str, val: &str) -> usize {
    log.iter()
        .position(|m| m.key == var && m.string() == val)
        .unwrap_or_else(|| panic!("no {var} = {val}"))
}

const ALERT_A: &str = "name=avd_ob_oba#poly=pts={60,-12:60,6:80,6:80,-12},label=oba#id=oba";
const ALERT_P: &str =
    "name=avd_ob_pa#poly=pts={60,-4:63,5:70,3:66,-6},label=pa,vsource=lidar#id=pa";

#[test]
fn obstaclemgr_alerts_and_resolves_over_moosdb() {
    let port = free_port();
    let dir = std::env::temp_dir().join(format!("obstaclemgr-app-{}-{port}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let mission = dir.join("alpha.moos");
    let text = format!(
        "ServerHost = localhost\nServerPort = {port}\nCommunity  = alpha\nMOOSTimeWarp = 1\n\n\
         ProcessConfig = pObstacleMgr\n{{\n  AppTick = 10\n  CommsTick = 10\n\
         \x20 point_var = TRACKED_FEATURE\n  max_age_per_point = 3\n\
         \x20 new_obs_flag = NEWOBS=now:$[OBS_NOW],ever:$[OBS_EVER]\n  colour = red\n}}\n"
    );
    std::fs::write(&mission, text).expect("write mission");

    let db = Proc(
        Command::new(moosdb_path())
            .arg(format!("--moos_port={port}"))
            .arg("--bind=127.0.0.1")
            .arg("--moos_community=alpha")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start moosdb"),
    );
    wait_for("moosdb to listen", Duration::from_secs(20), || {
        TcpStream::connect(("127.0.0.1", port)).is_ok()
    });
    let stderr_path = dir.join("obstaclemgr.err");
    let app = Proc(
        Command::new(env!("CARGO_BIN_EXE_obstaclemgr"))
            .arg(&mission)
            .arg("pObstacleMgr")
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&stderr_path).expect("stderr file"))
            .spawn()
            .expect("start obstaclemgr"),
    );

    let c = Client::connect(ClientConfig::new("127.0.0.1", port, "tester")).expect("connect");
    for v in [
        "OBSTACLE_ALERT",
        "OBM_RESOLVED",
        "OBM_CONNECT",
        "NEWOBS",
        "POBSTACLEMGR_PID",
        "APPCAST",
    ] {
        c.register(v, 0.0).expect("register");
    }
    let mut log: Vec<Message> = Vec::new();
    let pump = |log: &mut Vec<Message>| {
        let mut m = Vec::new();
        c.fetch(&mut m);
        log.extend(m);
    };
    let limit = Duration::from_secs(30);
    // The app is up (and subscribed: it registers before posting its PID).
    wait_for("POBSTACLEMGR_PID", limit, || {
        pump(&mut log);
        !seen(&log, "POBSTACLEMGR_PID").is_empty()
    });
    assert_eq!(
        seen(&log, "POBSTACLEMGR_PID")[0].dval,
        f64::from(app.0.id())
    );
    wait_for("OBM_CONNECT", limit, || {
        pump(&mut log);
        !seen(&log, "OBM_CONNECT").is_empty()
    });
    assert_eq!(seen(&log, "OBM_CONNECT")[0].string(), "true");

    // Ownship 14 m short of the obstacle; the template's request; the obstacle, given
    // for 3 s (default given_max_duration 60).
    c.notify_double("NAV_X", 46.0, None).expect("nav");
    c.notify_double("NAV_Y", 0.0, None).expect("nav");
    c.notify_string(
        "OBM_ALERT_REQUEST",
        "name=avd_ob_,update_var=OBSTACLE_ALERT,alert_range=15",
        None,
    )
    .expect("request");
    c.notify_string(
        "GIVEN_OBSTACLE",
        "pts={60,-12:60,6:80,6:80,-12},label=oba,duration=3",
        None,
    )
    .expect("given");
    wait_for("the alert for oba", limit, || {
        pump(&mut log);
        seen(&log, "OBSTACLE_ALERT")
            .iter()
            .any(|m| m.string() == ALERT_A)
    });
    assert_eq!(seen(&log, "NEWOBS")[0].string(), "now:1,ever:1");
    wait_for("oba resolved", limit, || {
        pump(&mut log);
        seen(&log, "OBM_RESOLVED")
            .iter()
            .any(|m| m.string() == "oba")
    });
    assert!(pos(&log, "OBSTACLE_ALERT", ALERT_A) < pos(&log, "OBM_RESOLVED", "oba"));
    assert_eq!(
        seen(&log, "OBSTACLE_ALERT").len(),
        1,
        "one alert for a given obstacle that did not change"
    );

    // Tracked points of cluster pa (run R3's), once each: the last alert carries the
    // hull of all four; once the points are 3 s old, pa resolves.
    for (x, y) in [(60, -4), (66, -6), (70, 3), (63, 5)] {
        c.notify_string(
            "TRACKED_FEATURE",
            &format!("x={x},y={y},key=pa,vsource=lidar"),
            None,
        )
        .expect("point");
    }
    wait_for("the alert for pa's hull", limit, || {
        pump(&mut log);
        seen(&log, "OBSTACLE_ALERT")
            .iter()
            .any(|m| m.string() == ALERT_P)
    });
    wait_for("pa resolved", limit, || {
        pump(&mut log);
        seen(&log, "OBM_RESOLVED")
            .iter()
            .any(|m| m.string() == "pa")
    });
    assert!(pos(&log, "OBSTACLE_ALERT", ALERT_P) < pos(&log, "OBM_RESOLVED", "pa"));
    assert!(seen(&log, "OBSTACLE_ALERT")
        .iter()
        .all(|m| m.string().starts_with("name=avd_ob_")));

    // The appcast on request: the bad block line is in it.
    c.notify_string(
        "APPCAST_REQ",
        "node=all,app=pObstacleMgr,duration=3,key=tester,thresh=any",
        None,
    )
    .expect("appcast request");
    wait_for("an APPCAST naming the bad line", limit, || {
        pump(&mut log);
        seen(&log, "APPCAST").iter().any(|m| {
            let s = m.string();
            s.contains("alpha.moos:13: unknown parameter: colour") && s.contains("Obstacles: ")
        })
    });
    assert!(seen(&log, "APPCAST")[0]
        .string()
        .starts_with("proc=pObstacleMgr!@#iter="));
    drop(app);
    drop(db);
    let err = std::fs::read_to_string(&stderr_path).unwrap_or_default();
    assert!(
        err.contains("alpha.moos:13: unknown parameter: colour"),
        "stderr: {err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
