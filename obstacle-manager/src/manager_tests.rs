use super::*;
use contact_manager::MailValue::{Num, Str};
use contact_manager::Value;

fn cfg(lines: &[(&str, &str)]) -> Config {
    let mut c = Config::default();
    for (p, v) in lines {
        c.set(p, v).unwrap_or_else(|e| panic!("{p}: {e}"));
    }
    c
}

fn strs(p: &[Posting], var: &str) -> Vec<String> {
    p.iter()
        .filter(|p| p.var == var)
        .map(|p| p.val.to_string())
        .collect()
}

fn nav(m: &mut ObstacleManager, now: f64, x: f64, y: f64) {
    m.handle_mail(now, &[("NAV_X", Num(x)), ("NAV_Y", Num(y))]);
}

const R1_REQUEST: &str = "name=avd_obstacles_,update_var=OBSTACLE_ALERT,alert_range=30";

/// Run R1 of obstacles.md §6: a configured obstacle, the flag, three mailed ones.
#[test]
fn given_obstacles_as_in_run_r1() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("given_obstacle", "pts={60,-12:60,6:80,6:80,-12},label=oba"),
            ("new_obs_flag", "NEWOBS=now:$[OBS_NOW],ever:$[OBS_EVER]"),
        ]),
        0.0,
    );
    m.handle_mail(0.0, &[("OBM_ALERT_REQUEST", Str(R1_REQUEST))]);
    nav(&mut m, 0.0, 0.0, 0.0);
    let p = m.iterate(0.0).to_vec();
    assert_eq!(strs(&p, "NEWOBS"), ["now:1,ever:1"]);
    assert_eq!(strs(&p, "OBM_CONNECT"), ["true"]);
    assert!(strs(&p, "OBSTACLE_ALERT").is_empty(), "60 m away");
    assert!(strs(&p, "OBM_DIST_TO_OBJ").is_empty());
    // Ownship comes within 30 m: the (changed-marked) obstacle is not re-sent, it
    // enters the range.
    nav(&mut m, 1.0, 30.6, 0.0);
    let p = m.iterate(1.0).to_vec();
    assert_eq!(
        strs(&p, "OBSTACLE_ALERT"),
        ["name=avd_obstacles_oba#poly=pts={60,-12:60,6:80,6:80,-12},label=oba#id=oba"]
    );
    assert_eq!(strs(&p, "OBM_DIST_TO_OBJ"), ["OBA,29.4"]);
    let p = m.iterate(2.0).to_vec();
    assert!(strs(&p, "OBSTACLE_ALERT").is_empty(), "sent once");
    assert_eq!(strs(&p, "OBM_DIST_TO_OBJ"), ["OBA,29.4"]);
    // No duration, too long a duration: refused with the reference's warnings.
    m.handle_mail(
        3.0,
        &[
            ("GIVEN_OBSTACLE", Str("pts={0,0:9,0:0,9},label=obc")),
            (
                "GIVEN_OBSTACLE",
                Str("pts={0,0:9,0:0,9},label=obd,duration=5000"),
            ),
            (
                "GIVEN_OBSTACLE",
                Str("pts={0,0:9,0:0,9},label=obe,duration=20"),
            ),
        ],
    );
    let p = m.iterate(3.0).to_vec();
    assert_eq!(strs(&p, "NEWOBS"), ["now:2,ever:2"]);
    let w: Vec<(&str, u64)> = m.warnings().run_warnings().collect();
    for text in [
        "Incoming GIVEN_OBSTACLE has missing duration",
        "Incoming GIVEN_OBSTACLE has duration exceeding max duration",
        "Unhandled Mail: GIVEN_OBSTACLE",
    ] {
        assert!(w.iter().any(|(t, _)| *t == text), "{text}: {w:?}");
    }
    assert_eq!(
        m.obstacles().map(|(k, _)| k).collect::<Vec<_>>(),
        ["oba", "obe"]
    );
    // obe resolves 20 s after it was given: erased, then OBM_RESOLVED.
    let p = m.iterate(23.0).to_vec();
    assert!(strs(&p, "OBM_RESOLVED").is_empty());
    let p = m.iterate(23.5).to_vec();
    let order: Vec<(&str, String)> = p
        .iter()
        .filter(|p| p.var == "VIEW_POLYGON" || p.var == "OBM_RESOLVED")
        .map(|p| (p.var.as_str(), p.val.to_string()))
        .collect();
    assert_eq!(
        order,
        [
            (
                "VIEW_POLYGON",
                "pts={0,0:9,0:0,9},active=false,label=obe".to_string()
            ),
            ("OBM_RESOLVED", "obe".to_string())
        ]
    );
    assert_eq!(m.counts().resolved, 1);
}

/// Run R3: clusters of tracked points, their hulls and drawings, the general alert.
#[test]
fn tracked_points_as_in_run_r3() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("general_alert", "update_var=GEN_ALERT, alert_range=40000"),
            (
                "given_obstacle",
                "pts={300,300:300,310:310,310:310,300},label=far",
            ),
        ]),
        0.0,
    );
    m.handle_mail(0.0, &[("OBM_ALERT_REQUEST", Str(R1_REQUEST))]);
    nav(&mut m, 0.0, 40.0, 0.0);
    let p = m.iterate(0.0).to_vec();
    assert_eq!(
        strs(&p, "GEN_ALERT"),
        ["name=gen_alert_far#poly=pts={300,300:300,310:310,310:310,300},label=far#id=far"]
    );
    let mut hulls = Vec::new();
    let mut alerts = Vec::new();
    for (k, (x, y)) in [(60, -4), (66, -6), (70, 3), (63, 5)]
        .into_iter()
        .enumerate()
    {
        let pt = format!("x={x},y={y},key=pa");
        m.handle_mail(1.0 + k as f64, &[("TRACKED_FEATURE", Str(&pt))]);
        let p = m.iterate(1.0 + k as f64).to_vec();
        hulls.extend(strs(&p, "VIEW_POLYGON"));
        alerts.extend(strs(&p, "OBSTACLE_ALERT"));
    }
    assert_eq!(
        hulls[3],
        "pts={60,-4:63,5:70,3:66,-6},label=obmgr_pa,edge_color=blue,vertex_color=blue,fill_color=blue,vertex_size=3,edge_size=1,fill_transparency=0.15"
    );
    assert!(hulls[0].starts_with("pts={60.05,-3.9134:60.05,-4.0866:59.9,-4},label=obmgr_pa,"));
    assert_eq!(alerts.len(), 4, "every new point re-sends: {alerts:?}");
    assert_eq!(
        alerts[3],
        "name=avd_obstacles_pa#poly=pts={60,-4:63,5:70,3:66,-6},label=pa#id=pa"
    );
    // A point without a key; a point of pb far away (outside 30 m, but inside the
    // general alert's range).
    m.handle_mail(
        5.0,
        &[
            ("TRACKED_FEATURE", Str("x=1,y=2")),
            ("TRACKED_FEATURE", Str("x=120,y=40,key=pb,vsource=lidar")),
            ("TRACKED_FEATURE", Str("x=130,y=40,key=pb,vsource=lidar")),
        ],
    );
    let p = m.iterate(5.0).to_vec();
    assert!(strs(&p, "OBSTACLE_ALERT").is_empty());
    assert_eq!(
        strs(&p, "GEN_ALERT"),
        ["name=gen_alert_pb#poly=pts={120,39:120,41:130,41:130,39},label=pb,vsource=lidar#id=pb"]
    );
    assert_eq!(m.counts().points_invalid, 1);
    assert!(m
        .warnings()
        .run_warnings()
        .any(|(t, _)| t == "Invalid point:x=1,y=2"));
    // Points live 20 s: pa's go one by one (each changes the hull), then pa resolves.
    let p = m.iterate(21.5).to_vec();
    assert_eq!(strs(&p, "OBSTACLE_ALERT").len(), 1, "hull of 3 points");
    let p = m.iterate(24.5).to_vec();
    assert_eq!(strs(&p, "OBM_RESOLVED"), ["pa"]);
    assert_eq!(
        strs(&p, "VIEW_POLYGON"),
        ["pts={0,0:9,0:0,9},active=false,label=obmgr_pa"]
    );
    let p = m.iterate(25.5).to_vec();
    assert_eq!(strs(&p, "OBM_RESOLVED"), ["pb"]);
}

#[test]
fn changes_outside_the_range_wait_until_it_is_entered() {
    let mut m = ObstacleManager::new(Config::default(), 0.0);
    m.handle_mail(
        0.0,
        &[(
            "OBM_ALERT_REQUEST",
            Str("name=a_,update_var=AL,alert_range=10"),
        )],
    );
    nav(&mut m, 0.0, 0.0, 0.0);
    m.handle_mail(0.0, &[("TRACKED_FEATURE", Str("x=50,y=0,key=k"))]);
    assert!(strs(m.iterate(0.0), "AL").is_empty());
    assert!(
        m.obstacles().all(|(_, o)| !o.changed),
        "mark cleared outside"
    );
    nav(&mut m, 1.0, 45.0, 0.0);
    assert_eq!(strs(m.iterate(1.0), "AL").len(), 1, "entering re-sends");
    assert!(strs(m.iterate(2.0), "AL").is_empty());
    // A new request (another template) re-sends every obstacle in range.
    m.handle_mail(
        3.0,
        &[(
            "OBM_ALERT_REQUEST",
            Str("name=b_,update_var=BL,alert_range=8"),
        )],
    );
    assert_eq!(
        strs(m.iterate(3.0), "BL"),
        ["name=b_k#poly=pts={50.05,0.0866:50.05,-0.0866:49.9,0},label=k#id=k"]
    );
    // Refused requests change nothing.
    m.handle_mail(4.0, &[("OBM_ALERT_REQUEST", Str("name=c_,update_var=CL"))]);
    assert_eq!(m.request().map(|r| r.name.as_str()), Some("b_"));
    assert!(m
        .warnings()
        .run_warnings()
        .any(|(t, _)| t == "Unhandled Mail: OBM_ALERT_REQUEST"));
}

#[test]
fn no_alerts_before_a_request_and_dist_policies() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("given_obstacle", "pts={10,0:10,5:15,5:15,0},label=a"),
            ("given_obstacle", "pts={100,0:100,5:105,5:105,0},label=b"),
            ("post_dist_to_polys", "true"),
        ]),
        0.0,
    );
    let p = m.iterate(0.0).to_vec();
    assert!(strs(&p, "OBM_DIST_TO_OBJ").is_empty());
    assert_eq!(p.iter().filter(|p| p.var == "OBM_MIN_DIST_EVER").count(), 1);
    m.handle_mail(
        1.0,
        &[(
            "OBM_ALERT_REQUEST",
            Str("name=a_,update_var=AL,alert_range=20"),
        )],
    );
    let p = m.iterate(1.0).to_vec();
    assert_eq!(strs(&p, "OBM_DIST_TO_OBJ"), ["A,10.0", "B,100.0"]);
    assert_eq!(strs(&p, "AL").len(), 1);
}

#[test]
fn relays_expunge_and_refusals() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("disable_var", "OBM_DISABLE"),
            ("expunge_var", "OBM_EXPUNGE"),
            (
                "new_obs_flag",
                "LAST_DIS=$[RECENT_DISABLED] of $[TOTAL_DISABLED]",
            ),
            ("ignore_range", "100"),
        ]),
        0.0,
    );
    m.handle_mail(
        0.0,
        &[
            ("TRACKED_FEATURE", Str("x=1,y=1,key=p")),
            ("TRACKED_FEATURE", Str("x=500,y=1,key=q")),
            ("OBM_DISABLE", Str("obstacle_id=p")),
            ("OBM_DISABLE", Str("bare")),
            (
                "GIVEN_OBSTACLE",
                Str("pts={0,0:9,0:0,9},label=p,duration=5"),
            ),
            (
                "GIVEN_OBSTACLE",
                Str("pts={0,0:9,0:0,9},label=g,duration=5"),
            ),
            ("OBM_EXPUNGE", Str("obstacle_id=g")),
            ("OBM_EXPUNGE", Str("colour=red")),
        ],
    );
    let p = m.iterate(0.0).to_vec();
    assert_eq!(
        strs(&p, "BHV_ABLE_FILTER"),
        [
            "obstacle_id=p,action=disable",
            "obstacle_id=bare,action=disable",
            "obstacle_id=g,action=expunge"
        ]
    );
    assert_eq!(strs(&p, "LAST_DIS"), ["p of 1"]);
    assert!(strs(&p, "OBM_RESOLVED").is_empty(), "expunged silently");
    assert_eq!(m.obstacles().map(|(k, _)| k).collect::<Vec<_>>(), ["p"]);
    assert_eq!(m.counts().points_ignored, 1);
    assert_eq!(m.able_lists().disabled, ["p"]);
    let w: Vec<&str> = m.warnings().run_warnings().map(|(t, _)| t).collect();
    assert!(w.contains(&"Reject given obst: already known as data obstacle"));
    assert!(w.contains(&"Unhandled Mail: OBM_EXPUNGE"));
}

#[test]
fn mail_flags_count_mail() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("mailflag", "NAV_X # SEEN_X=$[CNT]/$[MCNT]"),
            ("mailflag", "ANY # OTHER=$[CNT]"),
        ]),
        0.0,
    );
    assert!(m.subscriptions().contains(&"ANY".to_string()));
    m.handle_mail(
        0.0,
        &[("NAV_X", Num(1.0)), ("NAV_X", Num(2.0)), ("FOO", Str("x"))],
    );
    let p = m.iterate(0.0).to_vec();
    assert_eq!(strs(&p, "SEEN_X"), ["1/1", "2/2"]);
    assert_eq!(strs(&p, "OTHER"), ["1"]);
    // FOO is served by the ANY flag, so it is not unhandled.
    assert!(!m.warnings().run_warnings().any(|(t, _)| t.contains("FOO")));
    assert_eq!(
        p.iter().find(|p| p.var == "OBM_CONNECT").map(|p| &p.val),
        Some(&Value::Str("true".into()))
    );
}

#[test]
fn lasso_hulls() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("lasso", "true"),
            ("lasso_radius", "6"),
            ("lasso_points", "8"),
        ]),
        0.0,
    );
    m.handle_mail(
        0.0,
        &[
            ("TRACKED_FEATURE", Str("x=0,y=0,label=a")),
            ("TRACKED_FEATURE", Str("x=10,y=0,label=a")),
        ],
    );
    m.iterate(0.0);
    let (_, o) = m.obstacles().next().unwrap();
    assert_eq!(o.poly.size(), 8);
    assert!(o.poly.contains(5.0, 0.0));
    assert_eq!(o.poly.attrs.label, "obmgr_a");
}

#[test]
fn point_limit_and_drawing_thresholds() {
    let mut m = ObstacleManager::new(
        cfg(&[
            ("max_pts_per_cluster", "3"),
            ("poly_label_thresh", "1"),
            ("obstacles_color", "yellow"),
        ]),
        0.0,
    );
    for (k, x) in [0.0, 10.0, 20.0, 30.0, 40.0].into_iter().enumerate() {
        let pt = format!("x={x},y={},key=a", k % 2);
        m.handle_mail(0.0, &[("TRACKED_FEATURE", Str(&pt))]);
    }
    let p = m.iterate(0.0).to_vec();
    let (_, o) = m.obstacles().next().unwrap();
    let xs: Vec<f64> = o.points.iter().map(|p| p.0).collect();
    assert_eq!(
        xs,
        [40.0, 30.0, 20.0],
        "the three most recent, newest first"
    );
    assert!(!strs(&p, "VIEW_POLYGON")[0].contains("label_color"));
    // A second obstacle crosses the label threshold (2 > 1): every point obstacle is
    // drawn again, labels hidden.
    m.handle_mail(1.0, &[("TRACKED_FEATURE", Str("x=100,y=0,key=b"))]);
    let p = m.iterate(1.0).to_vec();
    let views = strs(&p, "VIEW_POLYGON");
    assert_eq!(views.len(), 2, "{views:?}");
    assert!(views
        .iter()
        .all(|v| v.contains("label_color=invisible,edge_color=yellow")));
    // No change, no crossing: nothing drawn (before any request the marks stay set, so
    // point obstacles are drawn every iteration, as the reference does).
    let p = m.iterate(2.0).to_vec();
    assert_eq!(strs(&p, "VIEW_POLYGON").len(), 2);
    m.handle_mail(
        3.0,
        &[(
            "OBM_ALERT_REQUEST",
            Str("name=a_,update_var=AL,alert_range=5"),
        )],
    );
    m.iterate(3.0);
    assert!(strs(m.iterate(4.0), "VIEW_POLYGON").is_empty());
}
