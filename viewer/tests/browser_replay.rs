//! `helm view` on `.alog` files, looked at in a real (headless) Chromium: the vehicle is
//! drawn where the log puts it at the slider's time, a polygon appears and disappears
//! with time, labels that look like markup stay text, a folder of runs shows its table,
//! a fleet's Monte Carlo (`helm sim --runs N --alogs`) plays each run's vehicles together.
//! Screenshots: `target/viewer-artifacts/replay-*.png`.

mod common;

use std::fmt::Write as _;
use std::time::Duration;

use common::cdp::Browser;
use common::{artifacts, helm_bin, helm_view, temp_dir, workspace};

const LIMIT: Duration = Duration::from_secs(60);

/// Two vehicles: abe goes east 2 m/s from (0,0), bob north 1 m/s from (50,-50), one
/// report every 0.5 s for 60 s; a polygon shown from 10 s to 20 s; a point whose label
/// is markup.
fn log(shift: f64) -> String {
    let mut s = String::from("%%%%\n%% LOGSTART 1700000000.00\n%%%%\n");
    for i in 0..=120 {
        let t = f64::from(i) * 0.5;
        let _ = writeln!(
            s,
            "{t:.3} NODE_REPORT pNodeReporter NAME=abe,X={},Y={shift},SPD=2,HDG=90,TYPE=kayak,COLOR=yellow",
            2.0 * t
        );
        let _ = writeln!(
            s,
            "{t:.3} NODE_REPORT pNodeReporter NAME=bob,X=50,Y={},SPD=1,HDG=0,TYPE=ship,COLOR=orange",
            -50.0 + t
        );
        if i == 20 {
            s.push_str("10.000 VIEW_POLYGON pHelmIvP pts={20,20:60,20:60,60:20,60},label=zone,edge_color=red,fill_color=pink\n");
            s.push_str(
                "10.000 VIEW_POINT pHelmIvP x=30,y=-20,label=<script>window.__pwned=1</script>\n",
            );
            s.push_str("10.000 VIEW_POINT pHelmIvP x=40,y=-30,label=<img src=x onerror=\"window.__pwned=2\">\n");
            // Two more points on the first one's spot: their labels must not cover each other.
            s.push_str("10.000 VIEW_POINT pHelmIvP x=30,y=-20,label=twin_one\n");
            s.push_str("10.000 VIEW_POINT pHelmIvP x=30,y=-20,label=twin_two\n");
            // Where abe is at 12 s: its label and the vehicle's must not cover each other.
            s.push_str("10.000 VIEW_POINT pHelmIvP x=24,y=0,label=abe_wpt\n");
            s.push_str("10.000 VIEW_POLYGON pHelmIvP pts={garbled\n");
        }
        if i == 40 {
            s.push_str("20.000 VIEW_POLYGON pHelmIvP pts={0,0:9,0:0,9},active=false,label=zone\n");
        }
    }
    s
}

fn set_time(b: &mut Browser, t: f64) {
    b.eval(&format!(
        "(() => {{ const s = document.getElementById('slider'); s.value = {t}; s.dispatchEvent(new Event('input')); }})()"
    ));
    b.wait_for(&format!("document.body.dataset.drawn === '{t}'"), LIMIT);
}

/// Each vehicle as drawn: name, data position, and how far the hull's centre is from
/// where the page's own map transform puts that position (pixels).
fn vehicles(b: &mut Browser) -> Vec<(String, f64, f64, f64)> {
    let v = b.eval(
        "[...document.querySelectorAll('#vehicles g.vehicle')].map(g => {
            const bb = g.querySelector('polygon').getBBox();
            const [sx, sy] = toScreen(+g.dataset.x, +g.dataset.y);
            const off = Math.hypot(bb.x + bb.width / 2 - sx, bb.y + bb.height / 2 - sy);
            return [g.dataset.name, +g.dataset.x, +g.dataset.y, off, bb.width];
        })",
    );
    v.as_array()
        .expect("array")
        .iter()
        .map(|r| {
            (
                r[0].as_str().unwrap_or_default().to_owned(),
                r[1].as_f64().unwrap_or(f64::NAN),
                r[2].as_f64().unwrap_or(f64::NAN),
                r[3].as_f64().unwrap_or(f64::NAN),
            )
        })
        .collect()
}

#[test]
fn replay_in_a_real_browser() {
    let dir = temp_dir("viewer-replay");
    let file = dir.join("two.alog");
    std::fs::write(&file, log(0.0)).expect("write log");
    let (_view, url) = helm_view(&[file.to_str().expect("utf-8 path")]);
    let mut b = Browser::start();
    b.goto(&url);
    b.wait_for("document.body.dataset.frames", LIMIT);

    // The slider at 12.3 s: abe's last report is at 12.0 s (x = 24), bob's at y = -38.
    set_time(&mut b, 12.3);
    let v = vehicles(&mut b);
    assert_eq!(v.len(), 2, "{v:?}");
    assert_eq!((v[0].0.as_str(), v[0].1, v[0].2), ("abe", 24.0, 0.0));
    assert_eq!((v[1].0.as_str(), v[1].1, v[1].2), ("bob", 50.0, -38.0));
    // The hull is drawn there, not elsewhere (its box centre within 3 px of the spot;
    // the bow makes it a little off-centre).
    for (name, _, _, off) in &v {
        assert!(*off < 3.0, "{name}'s hull is {off} px from its position");
    }
    // The polygon stands between 10 s and 20 s.
    let zone = "document.querySelectorAll('#shapes [data-key=\"polygon:zone\"]').length";
    assert_eq!(b.eval(zone), 1);
    // Labels that are markup show as text, and nothing of them ran.
    let labels = b.eval("[...document.querySelectorAll('#shapes text')].map(t => t.textContent)");
    let labels: Vec<&str> = labels
        .as_array()
        .expect("labels")
        .iter()
        .filter_map(|l| l.as_str())
        .collect();
    assert!(
        labels.contains(&"<script>window.__pwned=1</script>"),
        "{labels:?}"
    );
    assert!(
        labels.contains(&"<img src=x onerror=\"window.__pwned=2\">"),
        "{labels:?}"
    );
    assert_eq!(
        b.eval("document.querySelectorAll('#map script, #map img, aside img').length"),
        0
    );
    assert_eq!(b.eval("window.__pwned === undefined"), true);
    // Labels sharing a spot, shapes' and vehicles', are stacked, not drawn over one another.
    let overlaps = b.eval(
        "(() => { const r = [...document.querySelectorAll('#shapes text, #vehicles text')].map(t => t.getBBox()); let n = 0;
           for (let i = 0; i < r.length; i++) for (let j = i + 1; j < r.length; j++)
             if (r[i].x < r[j].x + r[j].width && r[j].x < r[i].x + r[i].width &&
                 r[i].y < r[j].y + r[j].height && r[j].y < r[i].y + r[i].height) n++;
           return n; })()",
    );
    assert_eq!(overlaps, 0, "labels overlap");
    assert_eq!(
        b.eval("document.querySelectorAll('#shapes text').length"),
        6,
        "zone, two markup labels, two twins, abe's waypoint"
    );
    assert_eq!(
        b.eval("document.querySelectorAll('#vehicles text').length"),
        2
    );
    // The garbled polygon was counted, and the page says so.
    let skipped = b.eval("document.getElementById('skipped').textContent");
    assert!(
        skipped
            .as_str()
            .is_some_and(|s| s.contains("1 malformed VIEW_POLYGON")),
        "{skipped}"
    );
    b.screenshot(&artifacts().join("replay-12s.png"));

    set_time(&mut b, 25.0);
    assert_eq!(b.eval(zone), 0, "the polygon was erased at 20 s");
    let v = vehicles(&mut b);
    assert_eq!((v[0].1, v[1].2), (50.0, -25.0));
    b.screenshot(&artifacts().join("replay-25s.png"));

    // Zoom (wheel) and pan (drag) move the map, not the data.
    let before = b.eval("[S.view.s, S.view.cx, S.view.cy]");
    b.eval(
        "(() => { const m = document.getElementById('map');
          m.dispatchEvent(new WheelEvent('wheel', {deltaY: -300, clientX: 400, clientY: 300, bubbles: true, cancelable: true}));
          const p = (type, x) => m.dispatchEvent(new PointerEvent(type, {clientX: x, clientY: 300, pointerId: 1, bubbles: true}));
          p('pointerdown', 400); p('pointermove', 500); p('pointerup', 500); })()",
    );
    let after = b.eval("[S.view.s, S.view.cx, S.view.cy]");
    let f = |v: &serde_json::Value, i: usize| v[i].as_f64().unwrap_or(f64::NAN);
    assert!(
        f(&after, 0) > 1.3 * f(&before, 0),
        "zoomed in: {before} -> {after}"
    );
    assert!(
        f(&after, 1) < f(&before, 1),
        "dragged right, so the centre moved west"
    );
    let v = vehicles(&mut b);
    assert_eq!((v[0].1, v[0].2), (50.0, 0.0), "data unchanged by the view");
    b.wait_for("document.querySelector('#grid text')", LIMIT);
    b.screenshot(&artifacts().join("replay-zoomed.png"));

    // Play runs the clock forward.
    b.eval("document.getElementById('play').click()");
    b.wait_for("+document.body.dataset.t > 26", LIMIT);
}

#[test]
fn a_folder_of_runs_shows_the_table_and_a_click_shows_that_run() {
    let dir = temp_dir("viewer-mc");
    for (i, shift) in [0.0, 30.0, 60.0].iter().enumerate() {
        std::fs::write(dir.join(format!("run-{i}.alog")), log(*shift)).expect("write log");
    }
    std::fs::write(
        dir.join("runs.csv"),
        "run,seed,end_reason\n0,1,ok\n1,2,ok\n2,3,timeout\n",
    )
    .expect("csv");
    let (_view, url) = helm_view(&[dir.to_str().expect("utf-8 path")]);
    let mut b = Browser::start();
    b.goto(&url);
    b.wait_for(
        "document.querySelectorAll('#runs tbody tr').length === 3",
        LIMIT,
    );
    b.wait_for(
        "document.querySelectorAll('#alltracks polyline').length === 6",
        LIMIT,
    );
    let cell =
        b.eval("document.querySelector('#runs tbody tr:nth-child(3) td:nth-child(3)').textContent");
    assert_eq!(cell, "timeout");
    // Run 2's abe is at y = 60.
    b.eval("document.querySelector('#runs tbody tr:nth-child(3)').click()");
    b.wait_for(
        "[...document.querySelectorAll('#vehicles g.vehicle')].some(g => g.dataset.name === 'abe' && g.dataset.y === '60')",
        LIMIT,
    );
    assert_eq!(
        b.eval("document.querySelector('#runs tr.sel').dataset.run"),
        "2"
    );
    b.screenshot(&artifacts().join("replay-runs.png"));
}

/// Two vehicles crossing within each other's comms range (so each log also reports the
/// other as a contact): missions/encounter's, with only their transits (the avoidance
/// behavior is a plugin library, which a debug test build does not have).
const CROSSING: &str = r#"
[[vehicle]]
name    = "abe"
mission = "encounter.moos"
bhv     = ["abe.bhv"]
x       = 0
y       = -40
heading = 0
color   = "dodger_blue"

[[vehicle]]
name    = "ben"
mission = "encounter.moos"
bhv     = ["ben.bhv"]
x       = 40
y       = 0
heading = 270
color   = "orange_red"

[comms]
range = 100
"#;

/// A vehicle's last `NODE_REPORT_LOCAL` position at or before `t` in its own log.
fn own_position(log: &std::path::Path, t: f64) -> (f64, f64) {
    let text = std::fs::read_to_string(log).expect("read log");
    let mut at = (f64::NAN, f64::NAN);
    for l in text.lines() {
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() < 4 || f[1] != "NODE_REPORT_LOCAL" || f[0].parse::<f64>().map_or(true, |x| x > t)
        {
            continue;
        }
        let num = |k: &str| {
            f[3].split(',')
                .find_map(|kv| kv.strip_prefix(k))
                .and_then(|v| v.parse().ok())
                .unwrap_or(f64::NAN)
        };
        at = (num("X="), num("Y="));
    }
    at
}

#[test]
fn a_fleets_runs_play_all_their_vehicles_together() {
    let mission = temp_dir("viewer-fleet-mission");
    let src = workspace().join("missions/encounter");
    for f in ["encounter.moos", "abe.bhv", "ben.bhv"] {
        std::fs::copy(src.join(f), mission.join(f)).expect("copy mission file");
    }
    std::fs::write(mission.join("encounter.bhv"), "initialize DEPLOY = true\n").expect("bhv");
    std::fs::write(mission.join("scenario.toml"), CROSSING).expect("scenario");
    let out = temp_dir("viewer-fleet-runs");
    let sim = std::process::Command::new(helm_bin())
        .arg("sim")
        .arg(&mission)
        .args([
            "--runs",
            "2",
            "--alogs",
            "--jitter",
            "x=5,y=5,heading=10",
            "--max-time",
            "20",
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run helm sim");
    assert!(
        sim.status.success(),
        "{}",
        String::from_utf8_lossy(&sim.stderr)
    );
    assert!(out.join("run-0001/ben.alog").is_file());

    let (_view, url) = helm_view(&[out.to_str().expect("utf-8 path")]);
    let mut b = Browser::start();
    b.goto(&url);
    // One row per run (runs.csv), not one per vehicle log.
    b.wait_for(
        "document.querySelectorAll('#runs tbody tr').length === 2",
        LIMIT,
    );
    assert_eq!(
        b.eval("document.querySelectorAll('#runs tbody tr').length"),
        2
    );
    let cols = b.eval("[...document.querySelectorAll('#runs thead th')].map(h => h.textContent)");
    assert!(
        cols.as_array()
            .is_some_and(|c| c.iter().any(|c| c == "cpa_abe_ben")),
        "{cols}"
    );
    // Both vehicles' tracks of both runs in the overview.
    b.wait_for(
        "document.querySelectorAll('#alltracks polyline').length === 4",
        LIMIT,
    );

    b.eval("document.querySelector('#runs tbody tr:nth-child(2)').click()");
    b.wait_for("document.querySelector('#runs tr.sel') && document.querySelector('#runs tr.sel').dataset.run === '1'", LIMIT);
    set_time(&mut b, 10.0);
    let v = vehicles(&mut b);
    let names: Vec<&str> = v.iter().map(|v| v.0.as_str()).collect();
    assert_eq!(names, ["abe", "ben"], "each vehicle drawn once: {v:?}");
    // Each where its own log of run 1 puts it, its hull drawn there.
    for (name, x, y, off) in &v {
        let own = own_position(&out.join(format!("run-0001/{name}.alog")), 10.0);
        assert_eq!((*x, *y), own, "{name}");
        assert!(*off < 3.0, "{name}'s hull is {off} px from its position");
    }
    let trails =
        b.eval("[...document.querySelectorAll('#trails polyline')].map(p => p.dataset.name)");
    assert_eq!(trails, serde_json::json!(["abe", "ben"]));
    b.screenshot(&artifacts().join("replay-fleet.png"));
    // A closer look: the map centred on the two vehicles, drawn at the next paint.
    b.eval(
        "(() => { const [a, c] = [...S.vehicles.values()];
          S.view.cx = (a.x + c.x) / 2; S.view.cy = (a.y + c.y) / 2; S.view.s = 10; S.dirty = true;
          return new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r))); })()",
    );
    b.screenshot(&artifacts().join("replay-fleet-zoomed.png"));
}
