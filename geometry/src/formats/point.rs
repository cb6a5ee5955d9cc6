//! Points (§6): `x,y`, `x:y`, the standard `x=…, y=…[, z=…], key=value…` form and the
//! abbreviated `x,y[,z]:key,value:…` form.

use crate::objects::Point;
use crate::spec::Attrs;
use crate::text::{atof, bite_x, is_number, split};

fn point(x: f64, y: f64, z: f64, attrs: Attrs) -> Point {
    Point {
        x,
        y,
        z: (z != 0.0).then_some(z),
        attrs,
    }
}

/// §6.1.
pub(crate) fn parse(s: &str) -> Option<Point> {
    for sep in [',', ':'] {
        let (x, y) = bite_x(s, sep);
        if is_number(x) && is_number(y) {
            return Some(point(atof(x), atof(y), 0.0, Attrs::default()));
        }
    }
    standard(s).or_else(|| abbreviated(s))
}

/// §6.2: no number checks on x, y, z (`atof`); shifts only when numbers.
fn standard(s: &str) -> Option<Point> {
    let (mut x, mut y, mut z) = ("", "", "");
    let (mut sx, mut sy, mut sz) = ("", "", "");
    let mut trans = None;
    let mut attrs = Attrs::default();
    for item in split(s, ',') {
        let (key, value) = bite_x(item, '=');
        match key.to_ascii_lowercase().as_str() {
            "x" => x = value,
            "y" => y = value,
            "z" => z = value,
            "shiftx" => sx = value,
            "shifty" => sy = value,
            "shiftz" => sz = value,
            "heading" | "hdg" => {}
            "trans" => {
                if is_number(value) {
                    trans = Some(atof(value));
                }
            }
            k => {
                attrs.set_attr(k, value);
            }
        }
    }
    if x.is_empty() || y.is_empty() {
        return None;
    }
    let shift = |t: &str| if is_number(t) { atof(t) } else { 0.0 };
    if let Some(t) = trans {
        attrs.fill_transparency = Some(t.clamp(0.0, 1.0));
    }
    Some(point(
        atof(x) + shift(sx),
        atof(y) + shift(sy),
        atof(z) + shift(sz),
        attrs,
    ))
}

/// §6.3: attribute keys are not lower-cased; a later vertex replaces an earlier one;
/// anything else is skipped. `None` if no vertex was found.
fn abbreviated(s: &str) -> Option<Point> {
    let mut attrs = Attrs::default();
    let mut xyz = None;
    for element in split(s, ':') {
        let (key, value) = bite_x(element, ',');
        if attrs.set_attr(key, value) {
            continue;
        }
        let (y, z) = if value.contains(',') {
            bite_x(value, ',')
        } else {
            (value, "")
        };
        if is_number(key) && is_number(y) && (z.is_empty() || is_number(z)) {
            let z = if z.is_empty() { 0.0 } else { atof(z) };
            xyz = Some((atof(key), atof(y), z));
        }
    }
    let (x, y, z) = xyz?;
    Some(point(x, y, z, attrs))
}
