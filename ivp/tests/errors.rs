//! Bad parameters give typed errors that name the parameter.

use ivp::{couple, Domain, IvpError, IvpFunction, ZaicHeq, ZaicLeq, ZaicPeak, ZaicSpd, ZaicVector};
use ivp_solver::Solver;

fn dom() -> Domain {
    Domain::parse("course:0:359:360,speed:0:4:41").unwrap()
}

#[test]
fn domain_errors() {
    let mut d = Domain::new();
    let e = d.add_var("speed", 0.0, 4.0, 0).unwrap_err();
    assert!(
        matches!(e, IvpError::PointsTooFew { ref var, points: 0 } if var == "speed"),
        "{e}"
    );
    assert!(e.to_string().contains("points"));
    let e = d.add_var("speed", 5.0, 4.0, 3).unwrap_err();
    assert!(
        matches!(e, IvpError::LowAboveHigh { .. }) && e.to_string().contains("low"),
        "{e}"
    );
    let e = d.add_var("depth", f64::NAN, 4.0, 3).unwrap_err();
    assert!(
        matches!(e, IvpError::NotFinite { ref param, .. } if param == "depth.low"),
        "{e}"
    );
    let e = Domain::parse_var("speed:0:4:x").unwrap_err();
    assert!(e.to_string().contains("points"), "{e}");
}

#[test]
fn zaic_errors() {
    let d = dom();
    assert!(matches!(ZaicPeak::new(&d, "depth"), Err(IvpError::UnknownVar(ref v)) if v == "depth"));

    let mut p = ZaicPeak::new(&d, "speed").unwrap();
    assert!(!p.set_min_max_util(50.0, 50.0, 0));
    assert!(matches!(
        p.try_extract(true),
        Err(IvpError::MinNotBelowMax { .. })
    ));
    assert!(p.extract(true).is_none());

    let mut p = ZaicPeak::new(&d, "speed").unwrap();
    assert!(!p.set_summit(f64::NAN, 0));
    let e = p.try_extract(true).unwrap_err();
    assert!(
        matches!(e, IvpError::NotFinite { ref param, .. } if param == "summit"),
        "{e}"
    );

    let mut p = ZaicPeak::new(&d, "speed").unwrap();
    assert!(!p.set_summit(1.0, 3));
    assert!(matches!(
        p.try_extract(true),
        Err(IvpError::BadComponent { index: 3, count: 1 })
    ));

    let mut h = ZaicHeq::new(&d, "speed").unwrap();
    assert!(!h.set_base_width(-1.0));
    let e = h.try_extract().unwrap_err();
    assert!(
        matches!(e, IvpError::Negative { ref param, .. } if param == "basewidth"),
        "{e}"
    );

    let mut l = ZaicLeq::new(&d, "speed").unwrap();
    assert!(!l.set_summit_delta(-2.0));
    assert!(
        matches!(l.try_extract(), Err(IvpError::Negative { ref param, .. }) if param == "summit_delta")
    );

    let one = Domain::parse("speed:2:2:1").unwrap();
    let mut h = ZaicHeq::new(&one, "speed").unwrap();
    assert!(matches!(h.try_extract(), Err(IvpError::ZeroDelta(_))));

    let mut s = ZaicSpd::new(&d, "speed").unwrap();
    assert!(!s.set_med_speed(f64::INFINITY));
    assert!(
        matches!(s.try_extract(), Err(IvpError::NotFinite { ref param, .. }) if param == "med_spd")
    );

    let mut v = ZaicVector::new(&d, "speed").unwrap();
    v.set_domain_vals(&[1.0, 2.0]);
    v.set_range_vals(&[1.0]);
    assert!(
        matches!(v.try_extract(), Err(IvpError::Invalid { ref param, .. }) if param == "range_vals")
    );
}

#[test]
fn function_and_solver_errors() {
    let d = Domain::parse("speed:0:4:41").unwrap();
    let e = IvpFunction::from_pieces(d.clone(), &[(vec![(0, 41)], vec![0.0, 1.0])]).unwrap_err();
    assert!(matches!(e, IvpError::BadPiece { piece: 0, .. }), "{e}");
    let e = IvpFunction::from_pieces(d.clone(), &[(vec![(0, 40)], vec![0.0])]).unwrap_err();
    assert!(matches!(e, IvpError::BadPiece { .. }), "{e}");

    let f = IvpFunction::from_pieces(
        Domain::parse("depth:0:10:11").unwrap(),
        &[(vec![(0, 10)], vec![1.0, 0.0])],
    )
    .unwrap();
    let e = Solver::new().solve(&dom(), &[&f]).unwrap_err();
    assert_eq!(e.to_string(), "DomainVar depth not recognized");

    let g = IvpFunction::from_pieces(d.clone(), &[(vec![(0, 40)], vec![1.0, 0.0])]).unwrap();
    assert!(couple(g.clone(), g.clone(), 50.0, 50.0, true).is_none());
    assert!(
        matches!(ivp::try_couple(g.clone(), g, 0.0, 50.0, true), Err(IvpError::Invalid { ref param, .. }) if param == "w1")
    );
}

#[test]
fn raw_parts_round_trip_moves_buffers() {
    let mut z = ZaicPeak::new(&dom(), "speed").unwrap();
    z.set_params(2.0, 1.0, 1.6, 20.0, 0.0, 100.0, 0);
    let f = z.extract(true).unwrap();
    let ptr = f.weights().as_ptr();
    let raw = f.clone().into_raw_parts();
    let back = IvpFunction::from_raw_parts(raw).unwrap();
    assert_eq!(back, f);
    let raw = f.into_raw_parts();
    let wptr = raw.weights.as_ptr();
    let back2 = IvpFunction::from_raw_parts(raw).unwrap();
    assert_eq!(
        back2.weights().as_ptr(),
        wptr,
        "buffers are moved, not copied"
    );
    let _ = ptr;
}
