use super::*;
use crate::{Config, MailValue, ObstacleManager, Value};

const FILE: &str = "region = pts={0,-60:0,60:200,60:200,-60}\nmin_range = 2\n\
                    poly = pts={60,-12:60,6:80,6:80,-12},label=ob_0\n\
                    poly = pts={120,0:120,10:130,10:130,0},label=ob_1,vsource=sim\n";

fn sim(lines: &[(&str, &str)]) -> ObstacleSim {
    let mut c = SimConfig::default();
    for (p, v) in lines {
        c.set(p, v).unwrap_or_else(|e| panic!("{p}: {e}"));
    }
    ObstacleSim::new(
        c,
        ObstacleFile::parse(FILE, "obstacles.txt").unwrap(),
        || 0.25,
    )
}

fn v(name: &str, x: f64, y: f64) -> SimVehicle<'_> {
    SimVehicle {
        name,
        x,
        y,
        color: None,
    }
}

fn vals(p: &[Posting], var: &str) -> Vec<String> {
    p.iter()
        .filter(|p| p.var == var)
        .map(|p| p.val.to_string())
        .collect()
}

#[test]
fn startup_then_a_refresh_per_new_vehicle() {
    let mut s = sim(&[]);
    let p = s.step(0.0, &[], &mut || 0.5).to_vec();
    assert_eq!(
        vals(&p, "PLOGGER_CMD"),
        ["COPY_FILE_REQUEST = obstacles.txt"]
    );
    assert_eq!(
        p.iter().find(|p| p.var == "UFOS_MIN_RNG").map(|p| &p.val),
        Some(&Value::Num(2.0))
    );
    assert!(
        vals(&p, "GIVEN_OBSTACLE").is_empty(),
        "no vehicle, no viewer: no refresh"
    );
    let p = s.step(1.0, &[v("abe", 0.0, 0.0)], &mut || 0.5).to_vec();
    assert_eq!(
        vals(&p, "GIVEN_OBSTACLE"),
        [
            "pts={60,-12:60,6:80,6:80,-12},label=ob_0",
            "pts={120,0:120,10:130,10:130,0},label=ob_1,vsource=sim"
        ]
    );
    assert_eq!(vals(&p, "KNOWN_OBSTACLE"), vals(&p, "GIVEN_OBSTACLE"));
    assert_eq!(
        vals(&p, "VIEW_POLYGON"),
        [
            "pts={60,-12:60,6:80,6:80,-12},label=ob_0,label_color=invisible,edge_color=gray50,vertex_color=gray50,fill_color=white,vertex_size=1,edge_size=1,fill_transparency=0.15",
            "pts={120,0:120,10:130,10:130,0},label=ob_1,vsource=sim,label_color=invisible,edge_color=gray50,vertex_color=gray50,fill_color=white,vertex_size=1,edge_size=1,fill_transparency=0.15",
            "pts={0,-60:0,60:200,60:200,-60},label=obs_region,edge_color=gray50,vertex_color=white"
        ]
    );
    // The same vehicle again: nothing; a second vehicle, then a viewer: a refresh each.
    assert!(s.step(2.0, &[v("abe", 1.0, 0.0)], &mut || 0.5).is_empty());
    assert_eq!(
        vals(
            s.step(3.0, &[v("abe", 1.0, 0.0), v("ben", 0.0, 5.0)], &mut || 0.5),
            "KNOWN_OBSTACLE"
        )
        .len(),
        2
    );
    s.pmv_connect();
    assert_eq!(
        vals(s.step(4.0, &[], &mut || 0.5), "KNOWN_OBSTACLE").len(),
        2
    );
    assert_eq!(s.refreshes(), 3);
}

#[test]
fn durations_and_the_refresh_interval() {
    let mut s = sim(&[
        ("min_duration", "400"),
        ("max_duration", "500"),
        ("refresh_interval", "200"),
        ("post_visuals", "false"),
        ("draw_region", "false"),
    ]);
    assert!(s.obstacles().iter().all(|o| o.duration == 425.0));
    let p = s.step(0.0, &[], &mut || 0.5).to_vec();
    assert_eq!(
        vals(&p, "GIVEN_OBSTACLE")[0],
        "pts={60,-12:60,6:80,6:80,-12},label=ob_0,duration=425"
    );
    assert!(vals(&p, "VIEW_POLYGON").is_empty());
    let refreshed: Vec<u32> = (1..=450)
        .filter(|&t| !s.step(f64::from(t), &[], &mut || 0.5).is_empty())
        .collect();
    assert_eq!(
        refreshed,
        [201, 402],
        "every interval (strictly more than 200 s)"
    );
    // The manager keeps a given obstacle alive across refreshes within its duration.
    let mut mcfg = Config::default();
    mcfg.set("given_max_duration", "1000").unwrap();
    let mut m = ObstacleManager::new(mcfg, 0.0);
    let given = vals(&p, "GIVEN_OBSTACLE");
    let mail: Vec<(&str, MailValue<'_>)> = given
        .iter()
        .map(|g| ("GIVEN_OBSTACLE", MailValue::Str(g)))
        .collect();
    m.handle_mail(0.0, &mail);
    assert_eq!(m.obstacles().count(), 2);
    assert!(
        vals(m.iterate(426.0), "OBM_RESOLVED").len() == 2,
        "not re-given: gone"
    );
}

#[test]
fn point_mode_feeds_the_manager() {
    let mut s = sim(&[
        ("post_points", "true"),
        ("rate_points", "4"),
        ("sensor_range", "30"),
    ]);
    let mut r = 0.0;
    let mut rng = || {
        r = (r + 0.37) % 1.0;
        r
    };
    let red = SimVehicle {
        name: "abe",
        x: 40.0,
        y: 0.0,
        color: Some("red"),
    };
    let p = s.step(0.0, &[red], &mut rng).to_vec();
    let pts = vals(&p, "TRACKED_FEATURE_ABE");
    assert_eq!(pts.len(), 4, "ob_0 is 20 m away, ob_1 80 m: {pts:?}");
    assert!(
        vals(&p, "GIVEN_OBSTACLE").is_empty(),
        "point mode gives no polygons"
    );
    assert_eq!(vals(&p, "KNOWN_OBSTACLE").len(), 2);
    let views = vals(&p, "VIEW_POINT");
    assert!(
        views[3].contains(
            ",label=abe:ob_0:4,label_color=invisible,vertex_color=red,duration=10,vertex_size=2"
        ),
        "{views:?}"
    );
    let mut m = ObstacleManager::new(Config::default(), 0.0);
    let mail: Vec<(&str, MailValue<'_>)> = pts
        .iter()
        .map(|v| ("TRACKED_FEATURE", MailValue::Str(v)))
        .collect();
    m.handle_mail(0.0, &mail);
    m.iterate(0.0);
    let (key, o) = m.obstacles().next().unwrap();
    assert_eq!(key, "ob_0");
    // The points are on ob_0's west edge, seen from the west.
    assert!(o
        .points
        .iter()
        .all(|p| (p.0 - 60.0).abs() < 1e-6 && (-12.0..=6.0).contains(&p.1)));
}
