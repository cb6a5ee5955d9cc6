//! BHV_Loiter behavior tests with a mock host.

use super::*;
use behavior_api::testing::MockHelm as MockHost;

fn behavior(h: &mut MockHost, params: &[(&str, &str)]) -> BhvLoiter {
    let helm = HelmDomain::new("course,0,359,360:speed,0,2,21");
    let mut b = BhvLoiter::new(&helm);
    for (p, v) in params {
        assert!(h.with(|c| b.set_param(c, p, v)), "{p} = {v}");
    }
    h.with(|c| b.on_params_complete(c));
    b
}

#[test]
fn spec_example_first_run() {
    let mut h = MockHost::new("wpt");
    h.name = "loiter".into();
    let mut b = behavior(
        &mut h,
        &[
            (
                "polygon",
                "format=radial, x=50, y=-80, radius=20, pts=8, snap=1",
            ),
            ("clockwise", "false"),
            ("speed", "1.5"),
        ],
    );
    assert_eq!(
        geometry::pts_spec(b.engine.points(), 1),
        "pts={42,-62:32,-72:32,-88:42,-98:58,-98:68,-88:68,-72:58,-62}"
    );
    assert!(h.last("BHV_SETTINGS").unwrap().starts_with(
        "type=BHV_Loiter,name=loiter,x=50.00,y=-80.00,clockwise=false,dynamic_clockwise=false,center_activate=false,desired_speed=1.5,polygon=\"pts={42,-62"
    ));
    h.clear();
    h.nav(0.0, -20.0, 0.0, 0.0);
    let f = h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(f.piece_count(), Some(12));
    assert_eq!(h.last("LOITER_MODE").unwrap(), "acquiring_external");
    assert_eq!(h.last("LOITER_INDEX").unwrap(), "2");
    assert_eq!(h.last("LOITER_DIST_TO_POLY").unwrap(), "59");
    assert_eq!(h.last("LOITER_ACQUIRE").unwrap(), "1");
    assert_eq!(
        h.last("LOITER_REPORT").unwrap(),
        "index=2,capture_hits=0,nonmono_hits=0,acquire_mode=true"
    );
    let mut d = ivp::Domain::new();
    d.add_var("course", 0.0, 359.0, 360).unwrap();
    d.add_var("speed", 0.0, 2.0, 21).unwrap();
    let g =
        ivp::IvpFunction::from_flat(d, f.bounds.to_vec(), f.weights.to_vec(), f.gelbox.to_vec())
            .unwrap();
    let (c, s, v) = crate::waypoint::ipf::tests::argmax(&g);
    assert_eq!((c, s), (155, 15));
    assert!((v - 100.0).abs() < 1e-9);
}

#[test]
fn parameters_and_macros() {
    let mut h = MockHost::new("wpt");
    let mut b = behavior(&mut h, &[("polygon", "pts={0,0:0,10:10,10:10,0}")]);
    for (p, v) in [
        ("polygon", "0,0 : 5,2 : 10,0 : 5,10"),
        ("clockwise", "sometimes"),
        ("patience", "0"),
        ("speed", "-1"),
        ("center_assign", "nowhere"),
        ("post_suffix", "a b"),
        ("bogus", "1"),
    ] {
        assert!(!h.with(|c| b.set_param(c, p, v)), "{p} = {v}");
    }
    assert!(h.with(|c| b.set_param(c, "clockwise", "best")));
    assert!(h.with(|c| b.set_param(c, "post_suffix", "east")));
    assert_eq!(b.suffix, "_EAST");
    assert!(h.with(|c| b.set_param(c, "center_assign", "100,50")));
    assert_eq!(b.poly.center(), (100.0, 50.0));
    assert!(h.with(|c| b.set_param(c, "xcenter_assign", "20")));
    assert!(h.with(|c| b.set_param(c, "visual_hints", "vertex_size=7,edge_color=nope")));
    assert_eq!(b.hints.vertex_size, 7.0);
    assert_eq!(b.hints.edge_color, "white");
    let m = b
        .expand_macros("$[PTS] $[CX] $(CY) $[CENTER] $[CWISE]")
        .unwrap();
    assert_eq!(m, "4 100 50 x=100,y=50 true");
    h.nav(0.0, 0.0, 90.0, 1.0);
    h.with(|c| b.on_run(c)).expect("function");
    assert_eq!(b.poly.center(), (20.0, 50.0));
    assert!(h.last("LOITER_MODE_EAST").is_some());
}

#[test]
fn slingshot_completes() {
    let mut h = MockHost::new("wpt");
    let mut b = behavior(
        &mut h,
        &[
            ("polygon", "format=radial, x=0, y=0, radius=20, pts=8"),
            ("slingshot", "100"),
            ("acquire_dist", "10"),
        ],
    );
    for k in 0..8 {
        let (x, y) = geometry::project_point(f64::from(k) * 45.0, 20.0, 0.0, 0.0);
        h.nav(x, y, 90.0, 1.0);
        h.with(|c| b.on_run(c));
    }
    assert!(h.completes >= 1);
    h.clear();
    h.with(|c| b.on_complete(c));
    assert_eq!(h.last("LOITER_COMPLETE").unwrap(), "true");
    assert_eq!(b.bng_total, 0.0);
}

/// Loiter polygons written in the generator formats: the loaded polygon is the parsed
/// one after the loiter's 0.1 m snap, and the first run steers for the vertex the
/// loiter picked.
fn loiter_on(polygon: &str, nav: (f64, f64)) -> (BhvLoiter, MockHost, (u32, u32)) {
    let mut h = MockHost::new("wpt");
    h.name = "loiter".into();
    let mut b = behavior(&mut h, &[("polygon", polygon), ("speed", "1.5")]);
    let mut expected = geometry::parse_polygon(polygon).unwrap();
    expected.apply_snap(0.1);
    let mut got: Vec<(u64, u64)> = b
        .engine
        .points()
        .iter()
        .map(|v| (v.x.to_bits(), v.y.to_bits()))
        .collect();
    let mut want: Vec<(u64, u64)> = expected
        .vertices()
        .iter()
        .map(|v| (v.x.to_bits(), v.y.to_bits()))
        .collect();
    got.sort_unstable();
    want.sort_unstable();
    assert_eq!(got, want, "{polygon}");
    h.clear();
    h.nav(nav.0, nav.1, 0.0, 0.0);
    let f = h.with(|c| b.on_run(c)).expect("function");
    let mut d = ivp::Domain::new();
    d.add_var("course", 0.0, 359.0, 360).unwrap();
    d.add_var("speed", 0.0, 2.0, 21).unwrap();
    let g =
        ivp::IvpFunction::from_flat(d, f.bounds.to_vec(), f.weights.to_vec(), f.gelbox.to_vec())
            .unwrap();
    let (c, s, _) = crate::waypoint::ipf::tests::argmax(&g);
    (b, h, (c, s))
}

#[test]
fn radial_and_ellipse_polygons() {
    for (polygon, n) in [
        (
            "radial:: x=110, y=-50, radius=20, pts=8, snap=1, label=HENRY_LOITER",
            8,
        ),
        (
            "format=ellipse, x=60, y=-50, degs=90, minor=35, major=125, pts=16",
            16,
        ),
    ] {
        let (b, h, (course, speed)) = loiter_on(polygon, (0.0, -150.0));
        assert_eq!(b.engine.points().len(), n, "{polygon}");
        assert_eq!(h.last("LOITER_MODE").unwrap(), "acquiring_external");
        let ix: usize = h.last("LOITER_INDEX").unwrap().parse().unwrap();
        let target = b.engine.points()[ix];
        let bearing = geometry::rel_ang(0.0, -150.0, target.x, target.y);
        let course = f64::from(course);
        assert!(
            (course - bearing).abs() <= 1.0,
            "{polygon}: vertex {ix}: {course} vs {bearing}"
        );
        assert_eq!(speed, 15, "1.5 m/s");
    }
    // §8.3: snap=0 makes a keyed radial invalid; an erase (inactive) polygon and a
    // non-convex abbreviated one are not loiter regions either.
    let mut h = MockHost::new("wpt");
    let mut b = behavior(&mut h, &[("polygon", "radial: 0, 0, 10, 4")]);
    for bad in [
        "format=radial, x=0, y=-75, radius=20, pts=8, snap=0",
        "format=radial, x=0, y=-75, radius=-1, pts=8, active=false",
        "0,0 : 5,2 : 10,0 : 5,10",
        "format=rangewedge, x=0, y=0, lang=0, rang=90, range_max=10, pts=2",
    ] {
        assert!(!h.with(|c| b.set_param(c, "polygon", bad)), "{bad}");
    }
    for good in [
        "format=wedge, x=0, y=0, lang=0, rang=90, range=10, pts=3",
        "oval: x=5.72,y=-47.09, rad=15, len=140, ang=64",
        "pylon: x1=0, y1=0, x2=0, y2=10, axis_pad=2, perp_pad=3",
    ] {
        assert!(h.with(|c| b.set_param(c, "polygon", good)), "{good}");
    }
}
