//! Parsers for point, seglist and polygon strings (behaviors-std.md §1.4).

use crate::points::project_point;
use crate::polygon::Polygon;
use crate::spec::{Attrs, Vertex};

/// A parsed seglist: vertices plus visual attributes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Seglist {
    pub pts: Vec<Vertex>,
    pub attrs: Attrs,
}

/// A parsed point.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub z: Option<f64>,
    pub attrs: Attrs,
}

fn num(s: &str) -> Option<f64> {
    let t = s.trim();
    if t.is_empty() {
        return None;
    }
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Split at commas that are not inside `{}` or double quotes.
fn split_top(s: &str, sep: char) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut depth = 0i32;
    let mut quoted = false;
    for c in s.chars() {
        match c {
            '"' => quoted = !quoted,
            '{' if !quoted => depth += 1,
            '}' if !quoted => depth -= 1,
            _ => {}
        }
        if c == sep && depth <= 0 && !quoted {
            out.push(std::mem::take(&mut cur));
        } else {
            cur.push(c);
        }
    }
    out.push(cur);
    out
}

fn key_val(s: &str) -> Option<(String, String)> {
    let (k, v) = s.split_once('=')?;
    Some((k.trim().to_ascii_lowercase(), v.trim().to_string()))
}

/// One vertex `x,y[,z]` or `x=..,y=..[,z=..]`.
fn parse_vertex(s: &str) -> Option<Vertex> {
    let f: Vec<&str> = s.split(',').map(str::trim).collect();
    if f.iter().all(|x| !x.contains('=')) {
        return match f.len() {
            2 => Some(Vertex::new(num(f[0])?, num(f[1])?)),
            3 => Some(Vertex {
                x: num(f[0])?,
                y: num(f[1])?,
                z: Some(num(f[2])?),
            }),
            _ => None,
        };
    }
    let (mut x, mut y, mut z) = (None, None, None);
    for part in f {
        let (k, v) = key_val(part)?;
        match k.as_str() {
            "x" => x = Some(num(&v)?),
            "y" => y = Some(num(&v)?),
            "z" => z = Some(num(&v)?),
            _ => return None,
        }
    }
    Some(Vertex { x: x?, y: y?, z })
}

/// The standard form `pts={...}` with extra `key=value` fields.
fn parse_standard(s: &str) -> Option<Seglist> {
    let mut out = Seglist::default();
    let mut found = false;
    for field in split_top(s, ',') {
        let field = field.trim();
        if field.is_empty() {
            continue;
        }
        let (k, v) = key_val(field)?;
        if k == "pts" {
            let inner = v.strip_prefix('{')?.strip_suffix('}')?;
            found = true;
            for vs in inner.split(':') {
                if vs.trim().is_empty() {
                    continue;
                }
                out.pts.push(parse_vertex(vs)?);
            }
        } else {
            // Unknown or malformed attribute fields are ignored.
            let _ = out.attrs.set(&k, &v);
        }
    }
    found.then_some(out)
}

/// The abbreviated form `x,y : x,y : label,foo`.
fn parse_abbreviated(s: &str) -> Option<Seglist> {
    let mut out = Seglist::default();
    for elem in s.split(':') {
        let elem = elem.trim();
        if elem.is_empty() {
            continue;
        }
        if let Some(v) = parse_vertex(elem) {
            out.pts.push(v);
            continue;
        }
        let f: Vec<&str> = elem.splitn(2, ',').map(str::trim).collect();
        if f.len() == 2 && num(f[0]).is_none() && !f[0].contains('=') {
            let _ = out.attrs.set(f[0], f[1]);
            continue;
        }
        return None;
    }
    Some(out)
}

/// Parse a seglist string. `None` if malformed; an empty vertex list is possible.
pub fn parse_seglist(s: &str) -> Option<Seglist> {
    let t = s.trim();
    let lower = t.to_ascii_lowercase();
    if lower.contains("pts=") && lower.contains('{') {
        return parse_standard(t);
    }
    if lower.contains("format=") || lower.starts_with("radial:") {
        // Generators (lawnmower, zigzag, bowtie) are not supported.
        return None;
    }
    parse_abbreviated(t)
}

fn radial(x: f64, y: f64, radius: f64, pts: f64, snap: f64, label: &str) -> Option<Polygon> {
    if radius <= 0.0 || !(3.0..=10_000.0).contains(&pts) {
        return None;
    }
    let n = pts.trunc() as usize;
    let delta = 360.0 / n as f64;
    let mut verts = Vec::with_capacity(n);
    for i in 0..n {
        let bearing = delta / 2.0 + i as f64 * delta;
        let (px, py) = project_point(bearing, radius, x, y);
        verts.push(Vertex::new(px, py));
    }
    let mut poly = Polygon::new(verts);
    if snap > 0.0 {
        poly.apply_snap(snap);
    }
    poly.attrs.label = label.to_string();
    Some(poly)
}

fn radial_keyed(fields: &[String]) -> Option<Polygon> {
    let (mut x, mut y, mut rad, mut pts, mut snap) = (None, None, None, None, 0.0);
    let mut label = String::new();
    for f in fields {
        let f = f.trim();
        if f.is_empty() {
            continue;
        }
        let (k, v) = key_val(f)?;
        match k.as_str() {
            "format" => {}
            "x" => x = Some(num(&v)?),
            "y" => y = Some(num(&v)?),
            "radius" => rad = Some(num(&v)?),
            "pts" => pts = Some(num(&v)?),
            "snap" => snap = num(&v)?,
            "label" => label = v,
            _ => {}
        }
    }
    radial(x?, y?, rad?, pts?, snap, &label)
}

/// Parse a polygon string. `None` if malformed; convexity is for the caller to check.
pub fn parse_polygon(s: &str) -> Option<Polygon> {
    let t = s.trim();
    let lower = t.to_ascii_lowercase();
    if let Some(rest) = lower.strip_prefix("radial::") {
        let rest_orig = &t[t.len() - rest.len()..];
        return radial_keyed(&split_top(rest_orig, ','));
    }
    if let Some(rest) = lower.strip_prefix("radial:") {
        let rest_orig = &t[t.len() - rest.len()..];
        let f: Vec<&str> = rest_orig.split(',').map(str::trim).collect();
        if f.len() < 4 || f.len() > 6 {
            return None;
        }
        let snap = match f.get(4) {
            Some(s) => num(s)?,
            None => 0.0,
        };
        let label = f.get(5).copied().unwrap_or("");
        return radial(num(f[0])?, num(f[1])?, num(f[2])?, num(f[3])?, snap, label);
    }
    if lower.contains("format=") {
        let fields = split_top(t, ',');
        let format = fields
            .iter()
            .filter_map(|f| key_val(f))
            .find(|(k, _)| k == "format")
            .map(|(_, v)| v.to_ascii_lowercase())?;
        return match format.as_str() {
            "radial" => radial_keyed(&fields),
            _ => None,
        };
    }
    let sl = parse_seglist(t)?;
    let mut poly = Polygon::new(sl.pts);
    poly.attrs = sl.attrs;
    Some(poly)
}

/// Parse a point: `x,y`, `x:y`, `x=..,y=..[,z=..][,label=..]`.
pub fn parse_point(s: &str) -> Option<Point> {
    let t = s.trim();
    if !t.contains('=') {
        let f: Vec<&str> = if t.contains(':') {
            t.split(':').collect()
        } else {
            t.split(',').collect()
        };
        let v = match f.len() {
            2 => Vertex::new(num(f[0])?, num(f[1])?),
            3 => Vertex {
                x: num(f[0])?,
                y: num(f[1])?,
                z: Some(num(f[2])?),
            },
            _ => return None,
        };
        return Some(Point {
            x: v.x,
            y: v.y,
            z: v.z,
            attrs: Attrs::default(),
        });
    }
    let (mut x, mut y, mut z) = (None, None, None);
    let mut attrs = Attrs::default();
    for f in split_top(t, ',') {
        let f = f.trim();
        if f.is_empty() {
            continue;
        }
        let (k, v) = key_val(f)?;
        match k.as_str() {
            "x" => x = Some(num(&v)?),
            "y" => y = Some(num(&v)?),
            "z" => z = Some(num(&v)?),
            _ => {
                let _ = attrs.set(&k, &v);
            }
        }
    }
    Some(Point {
        x: x?,
        y: y?,
        z,
        attrs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::pts_spec;

    #[test]
    fn seglists() {
        let s = parse_seglist("0,-40 : 60,-40 : 60,-80").unwrap();
        assert_eq!(s.pts.len(), 3);
        assert_eq!(s.pts[2], Vertex::new(60.0, -80.0));
        let s = parse_seglist("pts={1,2:3,4,5:x=6,y=7},label=foo,edge_color=red").unwrap();
        assert_eq!(s.pts.len(), 3);
        assert_eq!(s.pts[1].z, Some(5.0));
        assert_eq!(s.pts[2], Vertex::new(6.0, 7.0));
        assert_eq!(s.attrs.label, "foo");
        assert_eq!(s.attrs.edge_color, "red");
        let s = parse_seglist("1,2 : label,bar : 3,4").unwrap();
        assert_eq!(s.pts.len(), 2);
        assert_eq!(s.attrs.label, "bar");
        assert!(parse_seglist("1,2 : 3,x").is_none());
        assert!(parse_seglist("format=radial, x=1, y=2, radius=3, pts=4").is_none());
        assert!(parse_seglist("pts={1,2:3}").is_none());
    }

    #[test]
    fn radial_example() {
        let mut p = parse_polygon("format=radial, x=50, y=-80, radius=20, pts=8, snap=1").unwrap();
        assert!(p.is_convex());
        assert!(p.is_clockwise());
        p.reverse();
        assert_eq!(
            pts_spec(p.vertices(), 1),
            "pts={42,-62:32,-72:32,-88:42,-98:58,-98:68,-88:68,-72:58,-62}"
        );
        let q = parse_polygon("radial:: x=50, y=-80, radius=20, pts=8, snap=1").unwrap();
        let r = parse_polygon("radial: 50, -80, 20, 8, 1, lbl").unwrap();
        assert_eq!(q.vertices(), r.vertices());
        assert_eq!(r.attrs.label, "lbl");
        let mut q2 = q.clone();
        q2.reverse();
        assert_eq!(q2.vertices(), p.vertices());
        assert!(parse_polygon("format=radial, x=50, y=-80, pts=8").is_none());
        assert!(parse_polygon("format=ellipse, x=0, y=0").is_none());
    }

    #[test]
    fn polygons_and_points() {
        let p = parse_polygon("60,-40:60,-160:150,-160:180,-100:150,-40").unwrap();
        assert_eq!(p.size(), 5);
        assert!(p.is_convex());
        let p = parse_polygon("pts={0,0:0,10:10,10:10,0},label=sq").unwrap();
        assert!(p.is_convex());
        assert_eq!(p.attrs.label, "sq");
        assert_eq!(parse_point("3,4").unwrap().x, 3.0);
        assert_eq!(parse_point("3:4").unwrap().y, 4.0);
        let q = parse_point("x=1.5, y=-2, label=a").unwrap();
        assert_eq!((q.x, q.y, q.attrs.label.as_str()), (1.5, -2.0, "a"));
        assert!(parse_point("x=1").is_none());
        assert!(parse_point("abc").is_none());
    }
}
