//! BHV_Waypoint behavior-level tests with a mock host.

use super::*;
use behavior_api::testing::MockHelm as MockHost;

fn helm() -> HelmDomain {
    HelmDomain::new("course,0,359,360:speed,0,2,21")
}

fn configure(h: &mut MockHost, b: &mut BhvWaypoint, params: &[(&str, &str)]) {
    for (p, v) in params {
        assert!(h.with(|c| b.set_param(c, p, v)), "{p} = {v}");
    }
    h.with(|c| b.on_params_complete(c));
}

/// Best (course, speed index) of a function handed to the host.
fn decision(f: &FunctionData) -> (u32, u32) {
    let mut d = ivp::Domain::new();
    d.add_var("course", 0.0, 359.0, 360).unwrap();
    d.add_var("speed", 0.0, 2.0, 21).unwrap();
    let f =
        ivp::IvpFunction::from_flat(d, f.bounds.to_vec(), f.weights.to_vec(), f.gelbox.to_vec())
            .unwrap();
    let (c, s, _) = ipf::tests::argmax(&f);
    (c, s)
}

#[test]
fn parameter_validation() {
    let mut b = BhvWaypoint::new(&helm());
    let mut h = MockHost::new("wpt");
    let bad = [
        ("speed", "-1"),
        ("speed", "fast"),
        ("lead", "abc"),
        ("lead_damper", "0"),
        ("lead_damper", "-2"),
        ("order", "Reverse"),
        ("repeat", "-1"),
        ("repeat", "often"),
        ("radius", "0"),
        ("slip_radius", "-1"),
        ("capture_line", "maybe"),
        ("crs_spd_zaic_ratio", "0"),
        ("patience", "100"),
        ("efficiency_measure", "some"),
        ("visual_hints", "vertex_color=notacolor"),
        ("end_spd", "slow_dist=0"),
        ("points", "1,2 : 3,x"),
        ("points", ""),
        ("point", "abc"),
        ("wpt_status", "A B"),
        ("post_suffix", "a b"),
        ("lead_condition", "BAD"),
        ("reset_on_idle", "sure"),
        ("xpoints", "1,2"),
        ("_speed", "1"),
        ("bogus", "1"),
    ];
    for (p, v) in bad {
        assert!(
            !h.with(|c| b.set_param(c, p, v)),
            "{p} = {v} should be rejected"
        );
    }
    let good = [
        ("speed", "5"),
        ("ipf_type", "whatever"),
        ("use_alt_speed", "perhaps"),
        ("currix", "abc"),
        ("points", "empty"),
        ("capture_line", "absolute"),
        ("repeat", "2.7"),
        ("lead_condition", "LEAD_OK,true"),
        ("post_suffix", "A"),
        ("wptflag", "HIT = $[NI]"),
    ];
    for (p, v) in good {
        assert!(
            h.with(|c| b.set_param(c, p, v)),
            "{p} = {v} should be accepted"
        );
    }
    // speed clipped to the domain's high value
    assert_eq!(b.cruise_speed, 2.0);
    assert_eq!(b.ipf_type, "zaic");
    assert_eq!(b.engine.repeats(), 2);
    assert!(h.perpetual, "repeat > 0 makes the behavior perpetual");
    assert_eq!(b.engine.capture_radius(), 0.0);
    assert_eq!(b.post_suffix, "_A");
    assert_eq!(b.lead_conditions, vec!["LEAD_OK=true".to_string()]);
}

#[test]
fn survey_run_like_spec_example() {
    let mut b = BhvWaypoint::new(&helm());
    let mut h = MockHost::new("wpt");
    configure(
        &mut h,
        &mut b,
        &[
            ("wptflag", "HIT = $[NI]"),
            ("speed", "2"),
            ("capture_radius", "5.0"),
            ("slip_radius", "15.0"),
            ("points", "0,-40 : 60,-40 : 60,-80"),
        ],
    );
    assert!(h
        .last("BHV_SETTINGS")
        .unwrap()
        .starts_with("type=BHV_Waypoint,name=wpt,points=pts={0,-40:60,-40:60,-80},speed=2"));
    assert_eq!(
        h.last("BHV_WARNING").unwrap(),
        "wpt: No waypts given. Set val to empty if intentional"
    );
    h.clear();
    h.nav(0.0, -20.0, 0.0, 0.0);
    let f = h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(f.piece_count(), Some(8));
    assert_eq!(decision(&f), (180, 20));
    assert_eq!(
        h.last("WPT_STAT").unwrap(),
        "vname=abe,behavior-name=wpt,index=0,hits=0/0,cycles=0,dist=20,eta=inf"
    );
    assert_eq!(h.posted("WPT_INDEX"), vec!["0"]);
    assert!(h.flags.is_empty());
    assert_eq!(h.platform, (0.0, -20.0, 0.0, 0.0));

    h.clear();
    h.nav(0.0, -30.0, 180.0, 2.0);
    h.with(|c| b.on_run(c)).expect("function");
    assert!(h.last("WPT_STAT").unwrap().ends_with("dist=10,eta=5"));
    assert!(h.posted("WPT_INDEX").is_empty(), "index unchanged");

    h.clear();
    h.nav(0.0, -40.0, 180.0, 2.0);
    let f = h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(h.flags, vec![("HIT = 1".to_string(), false)]);
    assert_eq!(h.posted("WPT_INDEX"), vec!["1"]);
    assert!(h
        .last("WPT_STAT")
        .unwrap()
        .contains("index=1,hits=1/1,cycles=0,dist=60,eta=30"));
    assert_eq!(decision(&f).0, 90);

    h.clear();
    h.nav(60.0, -40.0, 90.0, 2.0);
    h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(h.flags, vec![("HIT = 2".to_string(), false)]);

    h.clear();
    h.nav(60.0, -80.0, 180.0, 2.0);
    assert!(h.with(|c| b.on_run(c)).is_none());
    assert_eq!(h.completes, 1);
    assert_eq!(h.posted("WPT_STAT"), vec!["behavior-name=wpt,completed"]);
    assert_eq!(h.flags, vec![("HIT = 0".to_string(), false)]);
    assert_eq!(h.posted("CYCLE_INDEX"), vec!["1"]);
}

#[test]
fn reverse_repeat_flags_and_macros() {
    let mut b = BhvWaypoint::new(&helm());
    let mut h = MockHost::new("wpt");
    configure(
        &mut h,
        &mut b,
        &[
            ("cycleflag", "CYC = $[CYCLES]"),
            ("wptflag", "HIT_PREV = $[PX],$[PY]"),
            ("wptflag", "HIT_NEXT = $(NX),$(NY)"),
            ("speed", "2.5"),
            ("capture_radius", "3"),
            ("slip_radius", "8"),
            ("capture_line", "true"),
            ("order", "reverse"),
            ("repeat", "1"),
            ("points", "20,-20 : 50,-20 : 50,-50 : 20,-50"),
        ],
    );
    assert!(h.perpetual);
    let route = [(20.0, -50.0), (50.0, -50.0), (50.0, -20.0), (20.0, -20.0)];
    h.nav(10.0, -40.0, 0.0, 2.5);
    h.with(|c| b.on_run(c)).expect("function");
    for cycle in 1..=2 {
        for (k, &(x, y)) in route.iter().enumerate() {
            h.clear();
            h.nav(x, y, 0.0, 2.5);
            let f = h.with(|c| b.on_run(c));
            let flags: Vec<&str> = h.flags.iter().map(|f| f.0.as_str()).collect();
            let prev = format!("HIT_PREV = {},{}", x, y);
            if k < 3 {
                assert!(f.is_some());
                let (nx, ny) = route[k + 1];
                assert_eq!(flags, vec![prev, format!("HIT_NEXT = {nx},{ny}")]);
            } else {
                // cycled: next point is the first again; completed: the next point
                // macro keeps the last next point
                assert_eq!(flags[0], format!("CYC = {cycle}"));
                assert_eq!(flags[1], prev);
                let (nx, ny) = if cycle == 1 { route[0] } else { (x, y) };
                assert_eq!(flags[2], format!("HIT_NEXT = {nx},{ny}"));
                assert_eq!(h.posted("CYCLE_INDEX"), vec![cycle.to_string()]);
                if cycle == 1 {
                    assert_eq!(h.posted("WPT_STAT")[0], "behavior-name=wpt,cycled");
                    assert_eq!(h.completes, 0);
                } else {
                    assert!(f.is_none());
                    assert_eq!(h.completes, 1);
                    assert_eq!(h.posted("WPT_STAT")[0], "behavior-name=wpt,completed");
                }
            }
        }
    }
    let m = b.expand_type_macros("$[ORDER] $[WPTS] $[NI] $[IX] $[UNKNOWN] $[LEAD_TO_START]");
    assert_eq!(m, "reverse 4 0 0 $[UNKNOWN] 0");
}

#[test]
fn lead_track_point_and_lead_condition() {
    let mut b = BhvWaypoint::new(&helm());
    let mut h = MockHost::new("wpt");
    configure(
        &mut h,
        &mut b,
        &[
            ("speed", "2"),
            ("lead", "8"),
            ("lead_condition", "LEAD = on"),
            ("points", "0,0 : 100,0"),
        ],
    );
    h.strs.insert("LEAD".into(), "on".into());
    h.nav(0.0, 1.0, 90.0, 2.0);
    h.with(|c| b.on_run(c)).expect("function"); // captures wpt 0
    h.nav(20.0, 10.0, 90.0, 2.0);
    h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(b.trackpt, (28.0, 0.0));
    // damper: within 12 m of the track line the lead grows
    b.lead_damper = 20.0;
    h.with(|c| b.on_run(c)).expect("function");
    let f = 1.0 + 2.0 * (1.0 - 10.0 / 20.0);
    assert!((b.trackpt.0 - (20.0 + 8.0 * f)).abs() < 1e-9);
    // lead condition false: steer at the waypoint itself
    h.strs.insert("LEAD".into(), "off".into());
    h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(b.trackpt, (100.0, 0.0));
}

#[test]
fn missing_nav_and_idle_transitions() {
    let mut b = BhvWaypoint::new(&helm());
    let mut h = MockHost::new("wpt");
    configure(
        &mut h,
        &mut b,
        &[("points", "0,10"), ("wpt_dist_to_next", "DNEXT")],
    );
    h.clear();
    assert!(h.with(|c| b.on_run(c)).is_none());
    assert!(h
        .posted("BHV_ERROR")
        .contains(&"wpt: No ownship X/Y info in info_buffer.".to_string()));
    assert!(h.last("VIEW_POINT").unwrap().contains("active=false"));
    h.nav(0.0, 0.0, 0.0, 1.0);
    h.clear();
    h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(h.posted("DNEXT"), vec!["10"]);
    h.clear();
    h.with(|c| b.on_run_to_idle(c));
    assert_eq!(h.posted("DNEXT"), vec!["-1"]);
    assert_eq!(h.posted("VIEW_POINT").len(), 2);
    // no points: no function, no posting
    let mut e = BhvWaypoint::new(&helm());
    h.clear();
    assert!(h.with(|c| e.on_run(c)).is_none());
    assert!(h.posts.is_empty());
    // points = start: the single point becomes the ownship position
    assert!(h.with(|c| e.set_param(c, "point", "start")));
    h.nav(1.23456, -7.0, 0.0, 0.0);
    h.with(|c| e.on_every_state(c));
    assert_eq!(e.engine.points(), &[Vertex::new(1.235, -7.0)]);
}

/// A mission lawnmower (s1_alpha_msurvey, geometry-formats.md SL-04): 18 east-west
/// lanes entered at the end nearest (0,0); the lanes' edge tags are posted back.
#[test]
fn lawnmower_survey() {
    let mut b = BhvWaypoint::new(&helm());
    let mut h = MockHost::new("wpt");
    configure(
        &mut h,
        &mut b,
        &[
            ("speed", "2"),
            ("capture_radius", "3"),
            (
                "points",
                "format=lawnmower, label=survey, x=50, y=-90, height=200, width=100, lane_width=12, degs=90",
            ),
        ],
    );
    let pts = b.engine.points().to_vec();
    assert_eq!(pts.len(), 36);
    assert_eq!((pts[0].x, pts[0].y), (-54.00000000000001, -40.0));
    assert_eq!((pts[1].x, pts[1].y), (-54.00000000000001, -140.0));
    assert_eq!((pts[35].x, pts[35].y), (150.0, -40.0));
    h.nav(0.0, 0.0, 0.0, 0.0);
    let f = h.with(|c| b.on_run(c)).expect("function");
    // Toward the first vertex (bearing 233.47; the function's peak is a 1-degree piece).
    let to_first = geometry::rel_ang(0.0, 0.0, pts[0].x, pts[0].y);
    let course = f64::from(decision(&f).0);
    assert!((course - to_first).abs() <= 1.0, "{course} vs {to_first}");
    let seg = h.last("VIEW_SEGLIST").unwrap();
    assert!(seg.starts_with("pts={-54,-40:-54,-140:-42,-140:"), "{seg}");
    assert!(seg.contains(",tags={0:1:lane#2:3:lane#"), "{seg}");
    assert!(seg.contains("#34:35:lane},label=abe_wpt"), "{seg}");
    // At the first lane's north end: down the lane (south).
    h.clear();
    h.nav(-54.0, -40.0, 180.0, 2.0);
    let f = h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(h.posted("WPT_INDEX"), vec!["1"]);
    assert_eq!(decision(&f).0, 180);
    // A plain point list replaces the path and its tags.
    assert!(h.with(|c| b.set_param(c, "points", "0,0 : 10,0")));
    h.clear();
    h.with(|c| b.on_run(c)).expect("function");
    assert!(!h.last("VIEW_SEGLIST").unwrap().contains("tags="));
}

/// Every seglist and polygon format is a waypoint list; invalid ones are rejected.
#[test]
fn geometry_formats_as_points() {
    let mut h = MockHost::new("wpt");
    for (value, n) in [
        (
            "format=bowtie, x=0, y=0, height=40, wid1=10, wid2=30, wid3=40",
            10,
        ),
        ("zigzag: 0, 0, 90, 100, 20, 10", 11),
        ("radial:: x=0, y=-75, radius=20, pts=6, snap=1", 6),
        (
            "format=ellipse, x=0, y=0, degs=0, major=40, minor=20, pts=12",
            12,
        ),
        ("-40,-40,160", 1),
    ] {
        let mut b = BhvWaypoint::new(&helm());
        assert!(h.with(|c| b.set_param(c, "points", value)), "{value}");
        assert_eq!(b.engine.size(), n, "{value}");
    }
    let mut b = BhvWaypoint::new(&helm());
    for bad in [
        "format=radial, x=0, y=-75, radius=20, pts=6, snap=0",
        "format=zigzag, 0, 0, 90, 100, 20, 10",
        "format=lawnmower, x=0, y=0, height=100",
        "label=foo,active=false",
    ] {
        assert!(!h.with(|c| b.set_param(c, "points", bad)), "{bad}");
    }
    assert!(h.with(|c| b.set_param(c, "point", "x=12,y=-92,heading=97")));
    assert_eq!(b.engine.points(), &[Vertex::new(12.0, -92.0)]);
}
