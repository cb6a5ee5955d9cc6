//! Worked examples of ivp-solver.md §10.

use ivp::{couple, Domain, ZaicPeak, ZaicSpd};
use ivp_ipf::ipf_packets;
use ivp_solver::Solver;

fn waypoint(dom: &Domain, bearing: f64, heading: f64, cruise: f64) -> ivp::IvpFunction {
    let mut s = ZaicPeak::new(dom, "speed").unwrap();
    s.set_params(cruise, cruise / 2.0, 1.6, 20.0, 0.0, 100.0, 0);
    let mut c = ZaicPeak::new(dom, "course").unwrap();
    c.set_value_wrap(true);
    c.set_params(bearing, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
    let k = c.add_component();
    c.set_params(heading, 30.0, 180.0, 5.0, 0.0, 20.0, k);
    couple(
        c.extract(false).unwrap(),
        s.extract(true).unwrap(),
        50.0,
        50.0,
        true,
    )
    .unwrap()
}

#[test]
fn example_a_waypoint() {
    let dom = Domain::parse("course:0:359:360,speed:0:2:21").unwrap();
    let bearing = geometry::rel_ang(0.0, 0.0, 100.0, 50.0);
    assert!((bearing - 63.4349488229).abs() < 1e-9);
    let mut f = waypoint(&dom, bearing, 90.0, 2.0);
    assert_eq!(f.piece_count(), 14);
    f.set_pwt(100.0);
    f.set_context("1:waypt");
    assert!(ivp_ipf::encode(&f).starts_with("H,7,1:waypt,2,14,1,100,D,course;0;359;360:speed;0;2;21,G,359,20,F,0,60,0,10,0.2894,3.5714,31.6102,0,60,11,20,"));
    let d = Solver::new().solve(&dom, &[&f]).unwrap().unwrap();
    assert_eq!(d.values, vec![Some(64.0), Some(2.0)]);
    assert!((d.utility - 10000.0).abs() < 1e-6);
    let pk = ipf_packets("waypt^1", &ivp_ipf::encode(&f));
    assert_eq!(pk.len(), 1);
    assert!(pk[0].starts_with("P,waypt^1,1,1,H,7,"));
}

#[test]
fn example_table_waypoints() {
    let cases = [
        (
            (0.0, 0.0, 90.0),
            (100.0, 50.0),
            1.2,
            "speed:0:2:21",
            28,
            (64.0, 1.2),
        ),
        (
            (0.0, 0.0, 10.0),
            (-50.0, 80.0),
            1.5,
            "speed:0:4:41",
            35,
            (328.0, 1.5),
        ),
        (
            (0.0, 0.0, 200.0),
            (30.0, -70.0),
            0.5,
            "speed:0:2:21",
            28,
            (157.0, 0.5),
        ),
        (
            (0.0, 0.0, 45.5),
            (100.0, 100.0),
            2.0,
            "speed:0:2:21",
            10,
            (45.0, 2.0),
        ),
        (
            (0.0, 0.0, 0.0),
            (0.0, 100.0),
            1.0,
            "speed:0:2:21",
            16,
            (0.0, 1.0),
        ),
    ];
    for ((ox, oy, h), (tx, ty), cruise, spd, pieces, (dc, ds)) in cases {
        let dom = Domain::parse(&format!("course:0:359:360,{spd}")).unwrap();
        let mut f = waypoint(&dom, geometry::rel_ang(ox, oy, tx, ty), h, cruise);
        assert_eq!(f.piece_count(), pieces);
        f.set_pwt(100.0);
        let d = Solver::new().solve(&dom, &[&f]).unwrap().unwrap();
        assert_eq!(d.values[0], Some(dc));
        assert!((d.values[1].unwrap() - ds).abs() < 1e-12);
    }
}

#[test]
fn example_d_zaic_spd() {
    let dom = Domain::parse("speed:0:2:21").unwrap();
    let mut z = ZaicSpd::new(&dom, "speed").unwrap();
    z.set_params(1.5, 0.1, 1.9, 70.0, 20.0, 0.0, 0.0, 100.0);
    let f = z.extract().unwrap();
    let b: Vec<(i32, i32)> = f.pieces().map(|p| (p.lo(0), p.hi(0))).collect();
    assert_eq!(b, vec![(0, 1), (2, 15), (16, 19), (20, 20)]);
}

#[test]
fn solver_reuse_and_inputs_untouched() {
    let dom = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
    let mut a = waypoint(&dom, 30.0, 10.0, 2.0);
    a.set_pwt(100.0);
    let mut b = waypoint(&dom, 200.0, 10.0, 1.0);
    b.set_pwt(300.0);
    let (a0, b0) = (a.clone(), b.clone());
    let mut s = Solver::new();
    let d1 = s.solve(&dom, &[&a, &b]).unwrap().unwrap();
    let d2 = s.solve(&dom, &[&a, &b]).unwrap().unwrap();
    assert_eq!(d1, d2);
    assert_eq!((a, b), (a0, b0));
}
