//! The standard form `pts={x,y[,z[,property]]:…}, key=value, …` (geometry-formats.md
//! §4.2 for polygons, §5.2 for seglists).

use super::vertex;
use crate::objects::Seglist;
use crate::polygon::Polygon;
use crate::text::{atof, bite, bite_x, is_number, split, trim};

/// The two flavours differ in a few details.
#[derive(Clone, Copy, PartialEq)]
enum Flavour {
    Polygon,
    Seglist,
}

/// Parse the items; `None` when a `pts` item is malformed (the parser gives up there).
fn items(s: &str, flavour: Flavour) -> Option<Seglist> {
    let mut out = Seglist::default();
    let mut rest = trim(s);
    while !rest.is_empty() {
        let (k, r) = bite(rest, '=');
        let key = trim(k);
        rest = trim(r);
        if key == "pts" {
            let (body, r) = bite_x(rest, '}');
            let body = body.strip_prefix('{')?;
            rest = match r.strip_prefix(',') {
                Some(after) => after,
                None if r.is_empty() => r,
                None => return None,
            };
            for element in split(body, ':') {
                let (x, y, z, prop) = vertex_fields(trim(element), flavour)?;
                out.push(vertex(x, y, z), &prop);
            }
        } else {
            let (v, r) = bite(rest, ',');
            let value = trim(v);
            rest = trim(r);
            // A seglist's `tags` item is read and discarded (§5.2); attributes the
            // setter does not know are ignored.
            if !(flavour == Flavour::Seglist && key == "tags") {
                out.attrs.set_attr(key, value);
            }
        }
    }
    Some(out)
}

/// `x,y[,z[,property[,ignored]]]`; a seglist also takes `x=`, `y=`, `z=` spellings.
fn vertex_fields(e: &str, flavour: Flavour) -> Option<(f64, f64, f64, String)> {
    let (x, r) = bite_x(e, ',');
    let (y, r) = bite_x(r, ',');
    let (zt, r) = bite_x(r, ',');
    let (pt, _) = bite_x(r, ',');
    let (x, y, zt) = if flavour == Flavour::Seglist {
        (
            x.strip_prefix("x=").unwrap_or(x),
            y.strip_prefix("y=").unwrap_or(y),
            zt.strip_prefix("z=").unwrap_or(zt),
        )
    } else {
        (x, y, zt)
    };
    if !is_number(x) || !is_number(y) {
        return None;
    }
    let mut z = 0.0;
    let mut prop = String::new();
    if is_number(zt) {
        z = atof(zt);
    } else {
        prop.push_str(zt);
    }
    if !pt.is_empty() {
        if !prop.is_empty() {
            prop.push(',');
        }
        prop.push_str(pt);
    }
    Some((atof(x), atof(y), z, prop))
}

/// §4.2: a convex polygon, or the empty inactive polygon keeping only its label when
/// the items set `active=false`; `None` otherwise.
pub(crate) fn polygon(s: &str) -> Option<Polygon> {
    let sl = items(s, Flavour::Polygon)?;
    let inactive = sl.attrs.active == Some(false);
    let label = sl.attrs.label.clone();
    let poly = sl.into_polygon();
    if poly.is_convex() {
        return Some(poly);
    }
    inactive.then(|| {
        let mut p = Polygon::new(Vec::new());
        p.attrs.active = Some(false);
        p.attrs.label = label;
        p
    })
}

/// §5.2: the seglist as read (valid or not: the caller checks).
pub(crate) fn seglist(s: &str) -> Option<Seglist> {
    items(s, Flavour::Seglist)
}
