//! The three entry points: a polygon, a seglist or a point from a string, in every
//! format a MOOS-IvP mission writes (geometry-formats.md §4–§6). `None` means the real
//! parser's object would be unusable ("invalid"); an empty *inactive* object is valid
//! (the erase form).

use crate::formats::{
    abbreviated, bowtie, ellipse, lawnmower, oval, point, pylon, radial, standard, wedge, zigzag,
};
use crate::polygon::Polygon;
use crate::text::{nowhite, trim};

pub use crate::objects::{Point, Seglist};

/// A polygon generator: the text of one format to a polygon, `None` if invalid.
type PolygonFormat = fn(&str) -> Option<Polygon>;

fn polygon_is_valid(p: &Polygon) -> bool {
    !p.is_empty() || p.attrs.active == Some(false)
}

/// A polygon from a string (`string2Poly`, §4.1). `None` if invalid. A valid polygon
/// may still be non-convex (abbreviated form) or empty and inactive (erase form);
/// behaviors that need a region check [`Polygon::is_convex`].
pub fn parse_polygon(input: &str) -> Option<Polygon> {
    let s = trim(input);
    if let Some(p) = standard::polygon(s) {
        return Some(p);
    }
    if s.contains("format") {
        let w = nowhite(s);
        let mut generator: Option<PolygonFormat> = None;
        if w.contains("format=radial") {
            generator = Some(radial::keyed);
        } else if w.contains("format=ellipse") {
            generator = Some(ellipse::polygon);
        } else if w.contains("format=wedge") || w.contains("format=piewedge") {
            generator = Some(wedge::pie);
        }
        if w.contains("format=rangewedge") {
            generator = Some(wedge::range);
        } else if w.contains("format=pylon") {
            generator = Some(pylon::polygon);
        } else if w.contains("format=oval") {
            generator = Some(oval::polygon);
        }
        if let Some(p) = generator.and_then(|g| g(s)).filter(polygon_is_valid) {
            return Some(p);
        }
    }
    let prefixes: [(&str, PolygonFormat); 9] = [
        ("radial::", radial::keyed),
        ("radial:", radial::short),
        ("ellipse::", ellipse::polygon),
        ("ellipse:", ellipse::polygon),
        ("wedge:", wedge::pie),
        ("piewedge:", wedge::pie),
        ("rangewedge:", wedge::range),
        ("pylon:", pylon::polygon),
        ("oval:", oval::polygon),
    ];
    for (prefix, generator) in prefixes {
        if let Some(rest) = s.strip_prefix(prefix) {
            return generator(rest).filter(polygon_is_valid);
        }
    }
    abbreviated::seglist(s)
        .filter(Seglist::is_valid)
        .map(Seglist::into_polygon)
}

/// A seglist from a string (`string2SegList`, §5.1). `None` if invalid (no vertex and
/// active). BHV_Waypoint falls back to [`parse_polygon`] when this yields no vertex.
pub fn parse_seglist(input: &str) -> Option<Seglist> {
    if let Some(sl) = standard::seglist(input).filter(Seglist::is_valid) {
        return Some(sl);
    }
    if input.contains("format") {
        let w = nowhite(input);
        let generated = if w.contains("format=zigzag") {
            zigzag::seglist(input)
        } else if w.contains("format=lawnmower") {
            lawnmower::seglist(input)
        } else if w.contains("format=bowtie") {
            bowtie::seglist(input)
        } else {
            None
        };
        if let Some(sl) = generated.filter(Seglist::is_valid) {
            return Some(sl);
        }
    }
    if let Some(rest) = input.strip_prefix("zigzag:") {
        return zigzag::seglist(rest).filter(Seglist::is_valid);
    }
    if let Some(rest) = input.strip_prefix("lawnmower:") {
        return lawnmower::seglist(rest).filter(Seglist::is_valid);
    }
    let body = input
        .strip_prefix("pts:")
        .or_else(|| input.strip_prefix("points:"))
        .unwrap_or(input);
    abbreviated::seglist(body).filter(Seglist::is_valid)
}

/// A point from a string (`string2Point`, §6.1). `None` if no vertex was set.
pub fn parse_point(input: &str) -> Option<Point> {
    point::parse(input)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::Vertex;

    #[test]
    fn short_radial_counts_that_loop_forever_in_cplusplus_are_invalid() {
        for n in ["-4", "inf", "-inf", "nan", "0"] {
            assert!(
                parse_polygon(&format!("radial: 0, 0, 10, {n}")).is_none(),
                "{n}"
            );
        }
        assert_eq!(parse_polygon("radial: 0, 0, 10, 8.5").unwrap().size(), 8);
    }

    #[test]
    fn counts_that_would_hang_are_invalid() {
        for s in [
            "format=radial, x=0, y=0, radius=10, pts=9223372036854775807",
            "radial: 0, 0, 10, 1e300",
            "format=ellipse, x=0, y=0, degs=0, major=4, minor=2, pts=1000000",
            "format=wedge, x=0, y=0, lang=0, rang=90, range=10, pts=1000000000",
            "format=rangewedge, x=0, y=0, lang=0, rang=90, range_min=1, range_max=10, pts=99999999",
        ] {
            assert!(parse_polygon(s).is_none(), "{s}");
        }
        for s in [
            "zigzag: 0, 0, 90, 100000000000000000000, 1, 1",
            "lawnmower: x=0, y=0, height=10, width=100000000, lane_width=0.001, rows=ns",
        ] {
            assert!(parse_seglist(s).is_none(), "{s}");
        }
        let big = parse_polygon("format=radial, x=0, y=0, radius=1000, pts=2000").unwrap();
        assert_eq!(big.size(), 2000);
    }

    #[test]
    fn seglist_prefixes_and_fallbacks() {
        let s = parse_seglist("points: 1,2 : 3,4").unwrap();
        assert_eq!(s.pts.len(), 2);
        assert!(parse_seglist(" zigzag: 0,0,90,100,20,10").is_none());
        assert_eq!(
            parse_seglist("zigzag: 0,0,90,100,20,10").unwrap().pts.len(),
            11
        );
        // Tags printed by a lawnmower do not survive a re-parse.
        let mower =
            parse_seglist("lawnmower: x=0, y=0, height=20, width=20, lane_width=10, rows=ns")
                .unwrap();
        assert_eq!(mower.tags.len(), mower.pts.len() / 2);
        let again = parse_seglist(&mower.spec(3)).unwrap();
        assert_eq!(again.pts, mower.pts);
        assert!(again.tags.is_empty());
        // The erase form is valid and prints only its attributes.
        let erase = parse_seglist("label=foo,msg=m,edge_color=red,active=false").unwrap();
        assert!(erase.pts.is_empty());
        assert_eq!(erase.spec(1), "active=false,label=foo,msg=m,edge_color=red");
    }

    #[test]
    fn properties_survive_polygon_operations() {
        let mut p = parse_polygon("pts={0,0,1,a:10,0:5,5,0,c}").unwrap();
        assert_eq!(p.spec(1), "pts={0,0,1,a:10,0:5,5,0,c}");
        p.reverse();
        assert_eq!(
            p.props(),
            &["c".to_string(), String::new(), "a".to_string()]
        );
        let mut s = Seglist::default();
        s.push(Vertex::new(1.0, 2.0), "");
        s.push(Vertex::new(3.0, 4.0), "p");
        assert_eq!(s.props, vec![String::new(), "p".to_string()]);
    }

    #[test]
    fn points() {
        let p = parse_point("x=1,y=2,shiftx=10,shifty=-5,shiftz=2").unwrap();
        assert_eq!((p.x, p.y, p.z), (11.0, -3.0, Some(2.0)));
        assert_eq!(p.spec(), "x=11,y=-3,z=2");
        assert!(parse_point("present_position").is_none());
        assert_eq!(parse_point("7,8:9,10").unwrap().x, 9.0);
    }
}
