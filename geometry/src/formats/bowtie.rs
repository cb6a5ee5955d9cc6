//! Bowtie seglists `format=bowtie, x=…, y=…, height=…, wid1=…, wid2=…, wid3=…` (§5.6):
//! ten points visited in an order chosen by the quadrant of the optional start point.

use super::{keyed_items, vertex};
use crate::angles::rel_ang;
use crate::objects::Seglist;
use crate::text::{atof, is_number};

pub(crate) fn seglist(text: &str) -> Option<Seglist> {
    let mut out = Seglist::default();
    let mut v: [Option<f64>; 8] = [None; 8];
    const KEYS: [&str; 8] = [
        "x", "y", "height", "wid1", "wid2", "wid3", "startx", "starty",
    ];
    for (key, value) in keyed_items(text) {
        match KEYS.iter().position(|k| *k == key) {
            Some(i) if is_number(value) => v[i] = Some(atof(value)),
            _ => {
                out.attrs.set_attr(&key, value);
            }
        }
    }
    let [Some(x), Some(y), Some(height), Some(w1), Some(w2), Some(w3), sx, sy] = v else {
        return None;
    };
    let h = height / 2.0;
    let p = [
        (x - w2, y + h),
        (x - w1, y + h),
        (x + w1, y + h),
        (x + w2, y + h),
        (x - w3, y),
        (x + w3, y),
        (x - w2, y - h),
        (x - w1, y - h),
        (x + w1, y - h),
        (x + w2, y - h),
    ];
    let r = match (sx, sy) {
        (Some(sx), Some(sy)) => rel_ang(x, y, sx, sy),
        _ => 0.0,
    };
    // P1…P10 of the spec, by quadrant ne, se, sw, nw.
    let order: [usize; 10] = if (0.0..90.0).contains(&r) {
        [8, 7, 5, 1, 2, 9, 10, 6, 4, 3]
    } else if (90.0..180.0).contains(&r) {
        [2, 1, 5, 7, 8, 3, 4, 6, 10, 9]
    } else if (180.0..270.0).contains(&r) {
        [3, 4, 6, 10, 9, 2, 1, 5, 7, 8]
    } else {
        [9, 10, 6, 4, 3, 8, 7, 5, 1, 2]
    };
    for k in order {
        let (px, py) = p[k - 1];
        out.push(vertex(px, py, 0.0), "");
    }
    Some(out)
}
