//! The abbreviated form `x,y[,z] : x,y : key,value : …` (geometry-formats.md §4.3,
//! §5.3): an element whose lower-cased first field is an attribute key sets it; every
//! other element must be a vertex, else the whole string is invalid.

use super::vertex;
use crate::objects::Seglist;
use crate::text::{atof, bite_x, is_number, split, trim};

/// The vertices and attributes; `None` when an element is neither.
pub(crate) fn seglist(s: &str) -> Option<Seglist> {
    let mut out = Seglist::default();
    for element in split(s, ':') {
        let (key, value) = bite_x(trim(element), ',');
        let key = key.to_ascii_lowercase();
        if out.attrs.set_attr(&key, value) {
            continue;
        }
        let (y, z) = bite_x(value, ',');
        if !is_number(&key) || !is_number(y) || !(z.is_empty() || is_number(z)) {
            return None;
        }
        let z = if z.is_empty() { 0.0 } else { atof(z) };
        out.push(vertex(atof(&key), atof(y), z), "");
    }
    Some(out)
}
