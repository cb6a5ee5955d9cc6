//! Fuzz harnesses (fuzzkit, bounded by `FUZZ_CASES` / `FUZZ_SECS`) of what the obstacle
//! side reads from outside: obstacle strings (`GIVEN_OBSTACLE`, `KNOWN_OBSTACLE`, the
//! alert updates of the golden cases), obstacle-file lines, alert requests, tracked
//! points, relay values and configuration lines, through the parsers and through a
//! running manager, simulator and collision counter.
//!
//! Invariants: no panic, no hang, bounded memory; every refusal is a typed error; a
//! refused configuration line changes nothing; a refused obstacle file names only
//! lines it has; every posting has a variable name; every obstacle with a polygon
//! has a convex one (what the helm's spawn needs).

use std::path::Path;

use obstacle_manager::{
    AlertRequest, CollisionConfig, CollisionDetector, Config, Given, MailValue, ObstacleFile,
    ObstacleFileError, ObstacleManager, ObstacleSim, SimConfig, SimVehicle, TrackedPoint,
};

/// String values of `vars` in the golden cases.
fn case_strings(vars: &[&str]) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../conformance/helm");
    let mut out = Vec::new();
    for text in fuzzkit::seed_files(&dir, "toml") {
        let text = String::from_utf8_lossy(&text);
        for line in text.lines() {
            for var in vars {
                for pat in [format!("[\"{var}\", \""), format!("{var} = \"")] {
                    let mut rest = line;
                    while let Some(i) = rest.find(&pat) {
                        rest = &rest[i + pat.len()..];
                        if let Some(j) = rest.find('"') {
                            out.push(rest.as_bytes()[..j].to_vec());
                        }
                    }
                }
            }
        }
    }
    out.sort();
    out.dedup();
    out
}

fn seeds() -> Vec<Vec<u8>> {
    let mut v = case_strings(&["OBSTACLE_ALERT", "OBM_ALERT_REQUEST"]);
    assert!(v.len() >= 2, "no obstacle seeds in the golden cases");
    for s in [
        "pts={60,-12:60,6:80,6:80,-12},label=oba,duration=20",
        "pts={0,0:9,0:0,9},active=false,label=ob_3,duration=0",
        "format=radial, x=50, y=-100, radius=8, pts=8, label=ob_1, vsource=lidar",
        "name=avd_obstacles_,update_var=OBSTACLE_ALERT,alert_range=30",
        "update_var=GEN_ALERT, alert_range=40000",
        "x=5,y=8,key=ob_3,vsource=lidar",
        "x=60, y=-4, label=TEST_12, color=1, size=2",
        "obstacle_id=ob_2",
        "vsource=lidar",
        "# obstacles\nregion = pts={30,-20:30,-140:120,-140:120,-20}\nmin_range = 20\n\
         min_size = 6\nmax_size = 10\npoly = pts={45,-40:48,-36:52,-35:55,-36:58,-40:58,-44:55,-47:52,-48},label=ob_0\n",
        "lasso = true\nlasso_points = 8\nlasso_radius = 6\nmax_pts_per_cluster = 3\n",
        "new_obs_flag = NEWOBS=now:$[OBS_NOW],ever:$[OBS_EVER]\nmailflag = NAV_X # N=$[CNT]",
        "encounter_flag = OB_ENCOUNTER = $DIST\ncollision_flag = C=vname=$VNAME,ob=$ID,dist=$DIST",
        "post_points = true\nrate_points = 3\nsensor_range = 80\npoly = pts={20,-70:20,-50:40,-50:40,-70},label=ob_9",
    ] {
        v.push(s.as_bytes().to_vec());
    }
    v
}

const DICT: &[&[u8]] = &[
    b",",
    b"=",
    b"#",
    b"{",
    b"}",
    b":",
    b"\n",
    b"pts={",
    b"label=",
    b"duration=",
    b"active=false",
    b"format=radial,",
    b"radius=",
    b"name=",
    b"update_var=",
    b"alert_range=",
    b"x=",
    b"y=",
    b"key=",
    b"vsource=",
    b"poly = ",
    b"region = ",
    b"min_range = ",
    b"obstacle_id=",
    b"$[OBS_NOW]",
    b"nan",
    b"inf",
    b"-1",
    b"0",
    b"1e308",
    b"-1e308",
    b"99999999999999999999",
    b"\xff",
];

const PARAMS: &[&str] = &[
    "given_obstacle",
    "alert_range",
    "ignore_range",
    "max_pts_per_cluster",
    "max_age_per_point",
    "general_alert",
    "new_obs_flag",
    "mailflag",
    "lasso",
    "lasso_points",
    "lasso_radius",
    "post_dist_to_polys",
];

/// The input, then its lines (when it has more than one).
fn units(text: &str) -> impl Iterator<Item = &str> {
    let several = text.trim_end().contains('\n');
    std::iter::once(text).chain(text.lines().filter(move |_| several))
}

/// Inputs longer than this go through the parsers only: a polygon of ten thousand
/// vertices costs a quadratic convexity check per parse (a second in a debug build),
/// and the running paths below parse each line many times.
const RUN_LIMIT: usize = 8 << 10;

fn parsers(text: &str) {
    for line in units(text) {
        if let Ok(g) = Given::parse(line) {
            assert!(g.poly.is_convex());
        }
        if let Ok(p) = TrackedPoint::parse(line) {
            assert!(p.x.is_finite() && p.y.is_finite() && !p.key.is_empty());
        }
        if let Ok(r) = AlertRequest::parse(line) {
            assert!(r.range > 0.0 && !r.name.is_empty() && !r.update_var.is_empty());
        }
        let _ = AlertRequest::parse_general(line);
    }
    match ObstacleFile::parse(text, "f.txt") {
        Ok(f) => assert!(f.obstacles.iter().all(|p| p.is_convex())),
        Err(ObstacleFileError::Lines { lines, .. }) => {
            let n = text.lines().count();
            assert!(!lines.is_empty());
            assert!(lines.iter().all(|(l, _)| (1..=n).contains(l)));
        }
        Err(e) => panic!("in-memory parse gave {e}"),
    }
}

fn config(text: &str) -> Config {
    let mut cfg = Config::default();
    cfg.set("disable_var", "OBM_DISABLE").expect("seed config");
    cfg.set("expunge_var", "OBM_EXPUNGE").expect("seed config");
    for p in PARAMS {
        let before = cfg.clone();
        if cfg.set(p, text).is_err() {
            assert_eq!(cfg, before, "a refused {p} line changed the config");
        }
    }
    for line in text.lines() {
        if let Some((p, v)) = line.split_once('=') {
            let _ = cfg.set(p, v);
        }
    }
    cfg
}

fn manager(cfg: Config, text: &str) {
    let mut m = ObstacleManager::new(cfg, 1000.0);
    let vars = [
        "OBM_ALERT_REQUEST",
        "GIVEN_OBSTACLE",
        "TRACKED_FEATURE",
        "OBM_DISABLE",
        "OBM_EXPUNGE",
    ];
    m.handle_mail(
        1000.0,
        &[(
            "OBM_ALERT_REQUEST",
            MailValue::Str("name=avd_,update_var=OBSTACLE_ALERT,alert_range=50"),
        )],
    );
    for (k, line) in units(text).enumerate() {
        let now = 1000.0 + k as f64;
        let mail: Vec<(&str, MailValue<'_>)> =
            vars.iter().map(|v| (*v, MailValue::Str(line))).collect();
        m.handle_mail(now, &mail);
        m.handle_mail(
            now,
            &[
                ("NAV_X", MailValue::Num(f64::NAN)),
                ("NAV_Y", MailValue::Str(line)),
            ],
        );
        for p in m.iterate(now) {
            assert!(!p.var.is_empty());
        }
        for (_, o) in m.obstacles() {
            assert!(o.poly.is_empty() || o.poly.is_convex(), "{:?}", o.poly);
        }
        if k > 40 {
            break;
        }
    }
    let _ = obstacle_manager::appcast::body(&m);
}

fn shoreside(text: &str) {
    let mut sc = SimConfig::default();
    let mut cc = CollisionConfig::default();
    for line in text.lines() {
        if let Some((p, v)) = line.split_once('=') {
            let _ = sc.set(p, v);
            let _ = cc.set(p, v);
        }
    }
    let _ = cc.finish();
    let Ok(file) = ObstacleFile::parse(text, "f.txt") else {
        return;
    };
    let mut sim = ObstacleSim::new(sc, file, || 0.37);
    let mut det = CollisionDetector::new(cc);
    for k in 0..5 {
        let now = f64::from(k);
        let (x, y) = (f64::from(k) * 20.0, -60.0);
        let seen = [
            SimVehicle {
                name: "abe",
                x,
                y,
                color: Some("red"),
            },
            SimVehicle {
                name: "ben",
                x: f64::NAN,
                y: 0.0,
                color: None,
            },
        ];
        let out = sim.step(now, &seen, &mut || 0.61).to_vec();
        for p in &out {
            if p.var == "KNOWN_OBSTACLE" {
                let v = p.val.as_str().unwrap_or_default();
                let _ = det.known_obstacle(v, now);
            }
        }
        for line in text.lines().take(3) {
            let _ = det.known_obstacle(line, now);
        }
        det.step(
            now,
            &[("abe", f64::from(k) * 20.0, -60.0), ("ben", f64::NAN, 0.0)],
        );
    }
}

fn check(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let text = text.as_ref();
    parsers(text);
    if text.len() <= RUN_LIMIT {
        manager(config(text), text);
        shoreside(text);
    }
}

#[test]
fn fuzz_obstacle_inputs() {
    fuzzkit::fuzz("obstacle_manager", 1500, &seeds(), DICT, check);
}
