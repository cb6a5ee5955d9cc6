//! A plugin depends on `behavior-api` alone: numbers, colours, geometry and the VIEW_*
//! strings come through its re-exports, and they are the helm's own rules.

use behavior_api::geometry::spec::{point_spec, Attrs};
use behavior_api::{atof, compact, is_color, is_number, parse_color, parse_number, Color};

#[test]
fn numbers_are_the_helms() {
    assert!(is_number(" +2.5 "));
    assert!(!is_number("1e3"));
    assert_eq!(atof("12.5abc"), 12.5);
    assert_eq!(parse_number("-.5"), Some(-0.5));
    assert_eq!(parse_number("0x10"), None);
    // One compact formatter: the geometry's name is the same function.
    for (v, d) in [
        (3.0, 2),
        (2.5, 6),
        (-0.0001, 2),
        (63.43494882, 3),
        (1e20, 1),
    ] {
        assert_eq!(compact(v, d), behavior_api::geometry::spec::fmt_x(v, d));
    }
    assert_eq!(compact(63.43494882, 3), "63.435");
}

#[test]
fn view_attributes_use_the_one_colour_parser() {
    let mut a = Attrs::default();
    assert!(a.set("label_color", "gray70"));
    assert!(a.set("vertex_color", "Dodger_Blue"));
    assert!(a.set("edge_color", "0,0,0"));
    assert!(a.set("fill_color", "hex:00,00,00"));
    assert_eq!(a.label_color, "gray70");
    assert_eq!(a.vertex_color, "Dodger_Blue");
    // Pure black from a triple is not a colour: dropped, as the real parser does.
    assert!(a.edge_color.is_empty());
    assert!(a.fill_color.is_empty());
    assert!(a.set("edge_color", "0.5%0.5%0.5"));
    assert_eq!(
        point_spec(1.0, 2.0, None, &a),
        "x=1,y=2,label_color=gray70,edge_color=0.5%0.5%0.5,vertex_color=Dodger_Blue"
    );
    assert!(is_color("tomatao") && is_color("tomato") && is_color("off"));
    assert_eq!(parse_color("grey_50"), Some(Color::Named("grey50")));
    assert!(behavior_api::geometry::is_color("Gray70"));
    assert!(!behavior_api::geometry::is_color("0:0:0"));
}

/// The reflector lives in its own crate (ivp-reflector) but behaviors reach it where they
/// always did, beside ivp's own items: `ivp::Reflector`, `ivp::Aof`, `ivp::reflector::…`.
#[test]
fn the_reflector_is_reached_through_ivp() {
    use behavior_api::ivp::reflector::{box_subtract, eval_grid_pointwise, intersects, IndexBox};
    use behavior_api::ivp::{couple, Aof, Domain, IvpFunction, Reflector, ZaicPeak};

    struct Flat;
    impl Aof for Flat {
        fn eval(&self, _: &Domain, index: &[u32]) -> f64 {
            f64::from(index[0])
        }
    }
    let dom = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
    let mut out = [0.0; 2];
    eval_grid_pointwise(&Flat, &dom, &[&[3, 4], &[0]], &mut out);
    assert_eq!(out, [3.0, 4.0]);
    let mut r = Reflector::new(&dom, &Flat);
    assert!(r.set_param("uniform_piece", "discrete@course:10,speed:41"));
    r.create(None, None);
    let f: IvpFunction = r.extract(true).unwrap();
    assert_eq!(f.domain().size(), 2);
    let mut crs = ZaicPeak::new(&dom, "course").unwrap();
    crs.set_params(90.0, 0.0, 180.0, 50.0, 0.0, 100.0, 0);
    let mut spd = ZaicPeak::new(&dom, "speed").unwrap();
    spd.set_params(2.0, 1.0, 1.6, 20.0, 0.0, 100.0, 0);
    let (c, s) = (crs.extract(true).unwrap(), spd.extract(true).unwrap());
    assert!(couple(c, s, 50.0, 50.0, true).is_some());
    let whole: IndexBox = vec![(0, 9)];
    assert!(intersects(&whole, &[(5, 5)]));
    assert_eq!(box_subtract(&whole, &[(5, 5)]).len(), 2);
}
