//! The `contactmgr` binary against our `moosdb` binary, on a free port: a mission with
//! an alert in its block; a test client plays ownship (NAV_*) and a contact
//! (NODE_REPORT). Checked: the alert's on-flag names the contact when it comes inside
//! the ranges, the off-flag (resolution) follows when its reports stop and it goes
//! stale, a `BCM_ALERT_REQUEST` posted at run time fires for a second contact, a
//! refused request and a bad block line show up in the APPCAST, and the bad line is
//! reported on stderr with file and line.

use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use moos::client::{Client, ClientConfig};
use moos::Message;
use test_support::{free_port, moosdb_beside, wait_for, Proc};

/// The `moosdb` next to `contactmgr` (see [`test_support::moosdb_beside`]).
fn moosdb_path() -> PathBuf {
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_contactmgr"));
    moosdb_beside(&exe, env!("CARGO_MANIFEST_DIR"), "contactmgr-test-moosdb")
}

/// Every message of `var` seen so far.
fn seen<'a>(log: &'a [Message], var: &str) -> Vec<&'a Message> {
    log.iter().filter(|m| m.key == var).collect()
}

fn report(c: &Client, name: &str, x: f64, y: f64, hdg: f64, spd: f64) {
    let t = c.moos_time();
    let r = format!("NAME={name},X={x},Y={y},HDG={hdg},SPD={spd},TIME={t},TYPE=kayak");
    c.notify_string("NODE_REPORT", &r, None)
        .expect("post report");
}

#[test]
fn contactmgr_alerts_resolves_and_takes_requests_over_moosdb() {
    let port = free_port();
    let dir = std::env::temp_dir().join(format!("contactmgr-app-{}-{port}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let mission = dir.join("alpha.moos");
    let text = format!(
        "ServerHost = localhost\nServerPort = {port}\nCommunity  = alpha\nMOOSTimeWarp = 1\n\n\
         ProcessConfig = pContactMgrV20\n{{\n  AppTick = 10\n  CommsTick = 10\n\
         \n  alert = id=avd, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME]\n\
         \x20 alert = id=avd, off_flag=CONTACT_RESOLVED=$[VNAME], alert_range=50, cpa_range=75\n\
         \x20 contact_max_age = 3\n  alert_verbose = true\n  colour = red\n}}\n"
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
    let stderr_path = dir.join("contactmgr.err");
    let app = Proc(
        Command::new(env!("CARGO_BIN_EXE_contactmgr"))
            .arg(&mission)
            .arg("pContactMgrV20")
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&stderr_path).expect("stderr file"))
            .spawn()
            .expect("start contactmgr"),
    );

    let c = Client::connect(ClientConfig::new("127.0.0.1", port, "tester")).expect("connect");
    for v in [
        "CONTACT_INFO",
        "CONTACT_RESOLVED",
        "ALERT_VERBOSE",
        "CONTACTS_RETIRED",
        "PCONTACTMGRV20_PID",
        "RUNTIME_ALERT",
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
    wait_for("PCONTACTMGRV20_PID", limit, || {
        pump(&mut log);
        !seen(&log, "PCONTACTMGRV20_PID").is_empty()
    });
    let pid = seen(&log, "PCONTACTMGRV20_PID")[0].dval;
    assert_eq!(pid, f64::from(app.0.id()));

    // Ownship stopped at the origin. Bob 100 m north (outside 75 m), then 60 m north
    // heading south at 2 m/s: inside the CPA range on a collision course.
    for (v, x) in [
        ("NAV_X", 0.0),
        ("NAV_Y", 0.0),
        ("NAV_HEADING", 0.0),
        ("NAV_SPEED", 0.0),
    ] {
        c.notify_double(v, x, None).expect("nav");
    }
    report(&c, "bob", 0.0, 100.0, 180.0, 2.0);
    std::thread::sleep(Duration::from_millis(300));
    pump(&mut log);
    assert!(seen(&log, "CONTACT_INFO").is_empty(), "alert at 100 m");
    wait_for("the on-flag", limit, || {
        report(&c, "bob", 0.0, 60.0, 180.0, 2.0);
        std::thread::sleep(Duration::from_millis(100));
        pump(&mut log);
        !seen(&log, "CONTACT_INFO").is_empty()
    });
    let on = seen(&log, "CONTACT_INFO");
    assert_eq!(on[0].string(), "name=bob # contact=bob");
    assert!(seen(&log, "ALERT_VERBOSE").iter().any(|m| m
        .string()
        .starts_with("contact=bob,alert_id=avd,off-->alerted,")));

    // Bob's reports stop: once stale (3 s) the alert resolves and bob retires.
    wait_for("the off-flag", limit, || {
        pump(&mut log);
        !seen(&log, "CONTACT_RESOLVED").is_empty()
    });
    assert_eq!(seen(&log, "CONTACT_RESOLVED")[0].string(), "bob");
    wait_for("CONTACTS_RETIRED", limit, || {
        pump(&mut log);
        seen(&log, "CONTACTS_RETIRED")
            .iter()
            .any(|m| m.string() == "bob")
    });
    let pos = |var: &str| log.iter().position(|m| m.key == var).expect(var);
    assert!(pos("CONTACT_INFO") < pos("CONTACT_RESOLVED"));
    assert_eq!(
        seen(&log, "CONTACT_INFO").len(),
        1,
        "one on-flag per approach"
    );

    // A run-time alert request (and a refused one), then cal 20 m east, closing.
    c.notify_string(
        "BCM_ALERT_REQUEST",
        "id=rt, on_flag=RUNTIME_ALERT=$[VNAME] seen, alert_range=30",
        None,
    )
    .expect("request");
    c.notify_string("BCM_ALERT_REQUEST", "id=bad, colour=red", None)
        .expect("request");
    wait_for("the run-time alert", limit, || {
        report(&c, "cal", 20.0, 0.0, 270.0, 1.0);
        std::thread::sleep(Duration::from_millis(100));
        pump(&mut log);
        !seen(&log, "RUNTIME_ALERT").is_empty()
    });
    assert_eq!(seen(&log, "RUNTIME_ALERT")[0].string(), "cal seen");
    assert!(seen(&log, "CONTACT_INFO")
        .iter()
        .any(|m| m.string() == "name=cal # contact=cal"));

    // The appcast on request: the bad block line and the refused request are in it.
    c.notify_string(
        "APPCAST_REQ",
        "node=all,app=pContactMgrV20,duration=3,key=tester,thresh=any",
        None,
    )
    .expect("appcast request");
    wait_for("an APPCAST naming the problems", limit, || {
        pump(&mut log);
        seen(&log, "APPCAST").iter().any(|m| {
            let s = m.string();
            s.contains("Unhandled Alert Request: id=bad, colour=red")
                && s.contains("alpha.moos:15: unknown parameter: colour")
        })
    });
    assert!(seen(&log, "APPCAST")[0]
        .string()
        .starts_with("proc=pContactMgrV20!@#iter="));
    drop(app);
    drop(db);
    let err = std::fs::read_to_string(&stderr_path).unwrap_or_default();
    assert!(
        err.contains("alpha.moos:15: unknown parameter: colour"),
        "stderr: {err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
