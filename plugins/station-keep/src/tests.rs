//! StationKeep tests against the worked examples of behaviors-plugins.md §6.4–§6.6.

use super::*;
use behavior_api::ivp::function::RawFunction;
use behavior_api::testing::MockHelm as MockHost;
use ivp_solver::Solver;

const HELM: &str = "course,0,359,360:speed,0,2,21";

fn bhv(params: &[(&str, &str)]) -> (StationKeep, MockHost) {
    let mut b = StationKeep::new(&HelmDomain::new(HELM));
    let mut host = MockHost::new("skeep");
    for (p, v) in params {
        assert!(host.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
    }
    (b, host)
}

/// The helm's decision (course, speed) for this function alone.
fn decide(f: &FunctionData) -> (f64, f64) {
    let dom = ivp::Domain::parse("course:0:359:360,speed:0:2:21")
        .or_else(|_| {
            let mut d = ivp::Domain::new();
            d.add_var("course", 0.0, 359.0, 360)?;
            d.add_var("speed", 0.0, 2.0, 21)?;
            Ok::<_, ivp::error::IvpError>(d)
        })
        .unwrap();
    let g = ivp::IvpFunction::from_raw_parts(RawFunction {
        vars: dom.vars().to_vec(),
        bounds: f.bounds.to_vec(),
        weights: f.weights.to_vec(),
        pwt: f.pwt,
        context: String::new(),
        gelbox: f.gelbox.to_vec(),
        grid: f.grid.to_vec(),
    })
    .unwrap();
    let d = Solver::new().solve(&dom, &[&g]).unwrap().unwrap();
    (d.values[0].unwrap(), d.values[1].unwrap())
}

fn step(b: &mut StationKeep, host: &mut MockHost, x: f64, y: f64, h: f64) -> Option<(f64, f64)> {
    host.set("NAV_X", x);
    host.set("NAV_Y", y);
    host.set("NAV_HEADING", h);
    host.set("NAV_SPEED", 0.0);
    let r = host.with(|ctx| b.on_run(ctx)).map(|f| decide(&f));
    host.time += 1.0;
    r
}

fn near(a: (f64, f64), b: (f64, f64)) -> bool {
    (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9
}

#[test]
fn domain_name_and_defaults() {
    let (b, _) = bhv(&[]);
    assert_eq!(b.domain(), "course,0,359,360:speed,0,2,21");
    assert_eq!(b.default_name(), "station_keep");
    assert_eq!(
        StationKeep::new(&HelmDomain::new("course,0,359,360")).domain(),
        ""
    );
    assert_eq!(
        b.settings("skeep"),
        "type=BHV_StationKeep,name=skeep,x=0.00,y=0.00,inner_radius=4.0,outer_radius=15.0,hibernation_radius=-1.0,outer_speed=1.2,center_activate=false"
    );
}

#[test]
fn point_strings() {
    assert_eq!(parse_station_point("50,-40"), Some((50.0, -40.0)));
    assert_eq!(parse_station_point(" 3 : 4 "), Some((3.0, 4.0)));
    assert_eq!(parse_station_point("x=1.5,y=-2,label=a"), Some((1.5, -2.0)));
    assert_eq!(parse_station_point("x=abc,y=2"), Some((0.0, 2.0)));
    assert_eq!(
        parse_station_point("x=1,y=2,shiftx=10,shifty=-1"),
        Some((11.0, 1.0))
    );
    assert_eq!(parse_station_point("1,2,3"), Some((1.0, 2.0)));
    assert_eq!(parse_station_point("7,8:label,bar"), Some((7.0, 8.0)));
    assert_eq!(parse_station_point("present_position"), None);
    assert_eq!(parse_station_point("x=1"), None);
    assert_eq!(parse_station_point(""), None);
}

#[test]
fn parameter_rules() {
    let (mut b, mut host) = bhv(&[]);
    host.with(|ctx| {
        assert!(b.set_param(ctx, "Station_PT", " 1,2 "));
        assert!(b.pending && b.static_defined);
        assert!(!b.set_param(ctx, "station_pt", "present_position"));
        assert!(b.set_param(ctx, "center_activate", "TRUE"));
        assert!(!b.set_param(ctx, "center_activate", "yes"));
        assert!(b.set_param(ctx, "hibernation_radius", "30"));
        assert_eq!(b.mode, Mode::Hibernating);
        assert!(b.set_param(ctx, "hibernation_radius", "OFF"));
        assert_eq!((b.mode, b.hibernation_radius), (Mode::Disabled, -1.0));
        assert!(b.set_param(ctx, "hibernation_radius", "-1"));
        for bad in ["0", "-2", "-1.0", "far"] {
            assert!(!b.set_param(ctx, "hibernation_radius", bad), "{bad}");
        }
        assert!(!b.set_param(ctx, "outer_radius", "0"));
        assert!(!b.set_param(ctx, "inner_radius", "-1"));
        assert!(b.set_param(ctx, "extra_speed", "1.0"));
        assert!(b.set_param(ctx, "outer_speed", "1.5"));
        assert_eq!(b.extra_speed, 1.5);
        assert!(b.set_param(ctx, "transit_speed", "1.0"));
        assert_eq!(b.extra_speed, 1.0);
        assert!(b.set_param(ctx, "swing_time", "100"));
        assert_eq!(b.swing_time, 60.0);
        assert!(b.set_param(ctx, "swing_time", "-3"));
        assert_eq!(b.swing_time, 0.0);
        assert!(b.set_param(
            ctx,
            "visual_hints",
            "edge_color=green, vertex_size=3, bogus=1, label_color=notacolor"
        ));
        assert_eq!(
            (b.edge_color.as_str(), b.vertex_size, b.label_color.as_str()),
            ("green", 3.0, "white")
        );
        assert!(!b.set_param(ctx, "speed", "1"));
    });
}

/// (station, ownship x, y, hdg, it.1 decision, it.2 distance, it.2 decision)
type StepCase = (&'static str, f64, f64, f64, (f64, f64), f64, (f64, f64));

#[test]
fn single_step_examples() {
    let cases: &[StepCase] = &[
        ("0,0", 10.0, 0.0, 90.0, (270.0, 0.0), 10.0, (270.0, 0.7)),
        ("0,0", 9.5, 0.0, 90.0, (270.0, 0.0), 9.5, (270.0, 0.6)),
        ("0,0", 7.0, 7.0, 90.0, (225.0, 0.0), 9.899495, (225.0, 0.6)),
        (
            "100,50",
            0.0,
            0.0,
            90.0,
            (63.0, 0.0),
            111.803399,
            (63.0, 2.0),
        ),
        ("0,0", 1.0, 0.0, 0.0, (270.0, 0.0), 1.0, (270.0, 0.0)),
    ];
    for &(st, x, y, h, d1, dist, d2) in cases {
        let (mut b, mut host) = bhv(&[("station_pt", st)]);
        let got = step(&mut b, &mut host, x, y, h).unwrap();
        assert!(near(got, (d1.0, 0.1 * (d1.1 * 10.0))), "{st} it.1 {got:?}");
        assert_eq!(host.posted("DIST_TO_STATION"), vec!["-1"]);
        assert_eq!(host.posted("PSKEEP_MODE"), vec!["HIBERNATING"]);
        host.clear();
        let got = step(&mut b, &mut host, x, y, h).unwrap();
        assert!(
            (got.0 - d2.0).abs() < 1e-9 && (got.1 - d2.1).abs() < 1e-9,
            "{st} it.2 {got:?}"
        );
        assert!((b.dist - dist).abs() < 1e-6);
        assert_eq!(host.posted("PSKEEP_MODE"), vec!["SEEKING_STATION"]);
    }
    let (mut b, mut host) = bhv(&[("station_pt", "0,0"), ("inner_radius", "1")]);
    step(&mut b, &mut host, -3.0, -2.0, 10.0);
    let got = step(&mut b, &mut host, -3.0, -2.0, 10.0).unwrap();
    assert!(
        (got.0 - 56.0).abs() < 1e-9 && (got.1 - 0.2).abs() < 1e-9,
        "{got:?}"
    );
}

#[test]
fn hibernation_sequence() {
    let (mut b, mut host) = bhv(&[
        ("station_pt", "x=0,y=0"),
        ("hibernation_radius", "30"),
        ("outer_speed", "1.5"),
        ("transit_speed", "1.9"),
    ]);
    host.time = 1001.0;
    let mut xs = vec![20.0, 20.0, 20.0, 35.0];
    xs.extend((0..12).map(|i| 33.0 - 2.0 * f64::from(i))); // 33 .. 11
    xs.extend((12..=21).map(f64::from));
    let mut modes = Vec::new();
    let mut speeds = Vec::new();
    for x in &xs {
        host.clear();
        let d = step(&mut b, &mut host, *x, 0.0, 0.0).unwrap();
        modes.push(host.last("PSKEEP_MODE").unwrap());
        speeds.push(d.1);
    }
    let t = |time: usize| time - 1001;
    assert_eq!(modes[t(1001)], "HIBERNATING");
    assert_eq!(
        (modes[t(1003)].as_str(), speeds[t(1003)]),
        ("HIBERNATING", 0.0)
    );
    assert_eq!(modes[t(1004)], "SEEKING_STATION");
    assert!((speeds[t(1004)] - 1.9).abs() < 1e-9);
    assert_eq!(b.mode, Mode::Hibernating);
    for (time, v) in [
        (1015, 1.2),
        (1016, 1.0),
        (1017, 1.1),
        (1018, 1.2),
        (1019, 1.4),
        (1020, 1.9),
    ] {
        assert!(
            (speeds[t(time)] - v).abs() < 1e-9,
            "t={time} {}",
            speeds[t(time)]
        );
        assert_eq!(modes[t(time)], "SEEKING_STATION");
    }
    assert_eq!(modes[t(1022)], "SEEKING_STATION");
    assert_eq!(modes[t(1023)], "HIBERNATING");
    assert_eq!(speeds[t(1023)], 0.0);
    assert_eq!(*modes.last().unwrap(), "HIBERNATING");
}

#[test]
fn center_activate_with_swing_time() {
    let (mut b, mut host) = bhv(&[("center_activate", "true"), ("swing_time", "2")]);
    host.time = 1001.0;
    let mut out = Vec::new();
    for x in [0.0, 1.0, 2.0, 3.0, 30.0] {
        host.clear();
        let d = step(&mut b, &mut host, x, 0.0, 45.0).unwrap();
        out.push((
            d,
            host.last("DIST_TO_STATION").unwrap(),
            host.last("PSKEEP_MODE").unwrap(),
        ));
    }
    let want = [
        ((45.0, 0.0), "-1", "HIBERNATING"),
        ((45.0, 0.0), "-1", "HIBERNATING"),
        ((0.0, 0.0), "-1", "HIBERNATING"),
        ((270.0, 0.0), "1", "SEEKING_STATION"),
        ((270.0, 2.0), "28", "SEEKING_STATION"),
    ];
    for (i, (g, w)) in out.iter().zip(want).enumerate() {
        assert!(near(g.0, w.0), "{i}: {g:?}");
        assert_eq!((g.1.as_str(), g.2.as_str()), (w.1, w.2), "{i}");
    }
    // Condition false at 1006: run→idle; back at 1007 with the stale distance.
    host.clear();
    host.with(|ctx| b.on_run_to_idle(ctx));
    assert_eq!(host.posted("VIEW_POLYGON").len(), 3);
    assert!(host
        .posted("VIEW_POLYGON")
        .iter()
        .all(|s| s.ends_with(",active=false")));
    host.time = 1007.0;
    host.clear();
    let d = step(&mut b, &mut host, 100.0, 0.0, 45.0).unwrap();
    assert!(near(d, (45.0, 2.0)), "{d:?}");
    assert_eq!(host.last("DIST_TO_STATION").unwrap(), "28");
    assert_eq!(host.last("PSKEEP_MODE").unwrap(), "SEEKING_STATION");
    let d = step(&mut b, &mut host, 100.0, 0.0, 45.0).unwrap();
    assert!(near(d, (45.0, 2.0)), "{d:?}");
}

#[test]
fn course_summit_ties_in_swing_window() {
    for (h, want) in [(45.5, 45.0), (180.5, 180.0), (359.5, 359.0), (0.5, 1.0)] {
        let (mut b, mut host) = bhv(&[("center_activate", "true"), ("swing_time", "5")]);
        let d = step(&mut b, &mut host, 0.0, 0.0, h).unwrap();
        assert_eq!(d, (want, 0.0), "heading {h}");
    }
}

#[test]
fn no_station_and_missing_nav() {
    let (mut b, mut host) = bhv(&[]);
    assert!(step(&mut b, &mut host, 3.0, 4.0, 0.0).is_none());
    assert_eq!(host.posted("DIST_TO_STATION"), vec!["5"]);
    assert_eq!(
        host.posted("BHV_WARNING"),
        vec!["skeep: STATION_POINT_NOT_SET"]
    );
    assert_eq!(host.posted("VIEW_POLYGON").len(), 3);
    host.clear();
    host.unset("NAV_X");
    assert!(host.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(
        host.posted("BHV_ERROR"),
        vec!["skeep: No ownship X/Y info in info_buffer."]
    );
    host.clear();
    host.set("NAV_X", 0.0);
    host.unset("NAV_HEADING");
    assert!(host.with(|ctx| b.on_run(ctx)).is_none());
    assert_eq!(
        host.posted("BHV_ERROR"),
        vec!["skeep: No ownship heading info in info_buffer."]
    );
    host.clear();
    host.set("NAV_HEADING", 0.0);
    host.unset("NAV_SPEED");
    b.set_param_for_test("station_pt", "0,0");
    assert!(host.with(|ctx| b.on_run(ctx)).is_some());
    assert_eq!(
        host.posted("BHV_WARNING"),
        vec!["skeep: NAV_SPEED dbl info not found in helm info_buffer"]
    );
}

#[test]
fn visuals() {
    let (mut b, mut host) = bhv(&[("station_pt", "0,-50")]);
    step(&mut b, &mut host, 0.0, 0.0, 0.0);
    let v = host.posted("VIEW_POLYGON");
    assert_eq!(v.len(), 2);
    assert_eq!(
        v[0],
        "radial:: x=0.0,y=-50.0,source=abe:skeep,pts=32,edge_size=1,vertex_size=1,edge_color=light_blue,label_color=white,vertex_color=red,label=abe:station-keep-out,radius=15.0"
    );
    assert!(v[1].ends_with("label=abe:station-keep-in,radius=4.0"));
    let keys: Vec<&str> = host
        .posts
        .iter()
        .filter(|p| p.0 == "VIEW_POLYGON")
        .map(|p| p.2.as_str())
        .collect();
    assert_eq!(keys, vec!["outer", "inner"]);
    host.clear();
    host.with(|ctx| assert!(b.set_param(ctx, "hibernation_radius", "20")));
    step(&mut b, &mut host, 0.0, 0.0, 0.0);
    assert_eq!(host.posted("VIEW_POLYGON").len(), 3);
    host.clear();
    host.with(|ctx| b.on_complete(ctx));
    let v = host.posted("VIEW_POLYGON");
    assert!(v[2].ends_with("label=abe:station-keep-hiber,radius=20.0,active=false"));
}

#[test]
fn settings_posted_by_hooks() {
    let (mut b, mut host) = bhv(&[("station_pt", "50,-40"), ("outer_radius", "14")]);
    host.with(|ctx| b.on_params_complete(ctx));
    host.with(|ctx| b.on_idle_to_run(ctx));
    assert_eq!(host.posted("BHV_SETTINGS").len(), 2);
    assert_eq!(
        host.last("BHV_SETTINGS").unwrap(),
        "type=BHV_StationKeep,name=skeep,x=50.00,y=-40.00,inner_radius=4.0,outer_radius=14.0,hibernation_radius=-1.0,outer_speed=1.2,center_activate=false"
    );
}

impl StationKeep {
    fn set_param_for_test(&mut self, p: &str, v: &str) {
        let mut host = MockHost::new("skeep");
        assert!(host.with(|ctx| self.set_param(ctx, p, v)));
    }
}

/// The function §5.6 describes, built afresh with the separate ZAIC setters and the
/// coupler, every time.
fn fresh(dom: &ivp::Domain, course: f64, speed: f64) -> Option<ivp::IvpFunction> {
    use behavior_api::ivp::{coupler::couple, zaic::ZaicPeak};
    let mut zs = ZaicPeak::new(dom, "speed").ok()?;
    zs.set_summit(speed, 0);
    zs.set_base_width(0.4, 0);
    zs.set_peak_width(0.0, 0);
    zs.set_summit_delta(0.0, 0);
    zs.set_min_max_util(0.0, 25.0, 0);
    let mut zc = ZaicPeak::new(dom, "course").ok()?;
    zc.set_summit(course, 0);
    zc.set_base_width(180.0, 0);
    zc.set_peak_width(0.0, 0);
    zc.set_summit_delta(0.0, 0);
    zc.set_value_wrap(true);
    couple(zc.extract(true)?, zs.extract(true)?, 50.0, 50.0, true)
}

/// The kept speed function and course builder give the fresh function bit for bit,
/// over summits that repeat (a vehicle inside the inner radius) and change.
#[test]
fn kept_build_is_the_fresh_build() {
    use behavior_api::testing::function_bits;
    let (mut b, _) = bhv(&[("station_pt", "0,0")]);
    let dom = b.ivp_domain.clone().unwrap();
    let speeds = [0.0, 0.0, 0.7, 1.2, 1.2, 2.5, 0.0, f64::NAN, 0.35];
    for (i, &speed) in speeds.iter().cycle().take(60).enumerate() {
        let course = (i as f64 * 37.3) % 400.0 - 20.0;
        let want = fresh(&dom, course, speed).map(|f| function_bits(&f));
        let got = b.build(course, speed).map(|f| function_bits(&f));
        assert_eq!(want, got, "course {course} speed {speed}");
    }
}
