//! The three polygons BHV_AvoidObstacleV24 draws (obstacles.md §1.10): the obstacle
//! ("gut"), its buffer ("mid") and the outer rim, with the visual hints applied. They are
//! posted every running iteration and seldom change, so each text is kept with what it
//! was made from and made again only when that changed.

use behavior_api::geometry::Polygon;

use crate::params::Params;

/// The polygon keys, in posting order.
pub const KEYS: [&str; 3] = ["gut", "mid", "rim"];

/// The polygon `poly` as drawn under `key`: hints with prefix `key` applied, then the
/// general ones (§1.10), no `active` attribute.
pub fn drawn(params: &Params, poly: &Polygon, key: &str) -> Polygon {
    let mut p = poly.clone();
    p.attrs.active = None;
    let get = |attr: &str| {
        params
            .hint(&format!("{key}_{attr}"))
            .or_else(|| params.hint(attr))
            .map(str::to_string)
    };
    for attr in [
        "label_color",
        "vertex_color",
        "edge_color",
        "fill_color",
        "edge_size",
        "vertex_size",
    ] {
        if let Some(v) = get(attr) {
            p.attrs.set(attr, &v);
        }
    }
    p
}

/// The last texts and what they were made of.
#[derive(Default)]
pub struct Kept {
    sources: [Polygon; 3],
    hints: Vec<(String, String)>,
    texts: [String; 3],
    made: bool,
}

impl Kept {
    /// The texts of `sources` (gut, mid, rim) with the hints of `params`.
    pub fn texts(&mut self, params: &Params, sources: [&Polygon; 3]) -> &[String; 3] {
        let same = self.made
            && params.hints == self.hints
            && self.sources.iter().zip(sources).all(|(a, b)| a == b);
        if !same {
            for (k, src) in sources.into_iter().enumerate() {
                self.texts[k] = drawn(params, src, KEYS[k]).spec(5);
                self.sources[k].clone_from(src);
            }
            self.hints.clone_from(&params.hints);
            self.made = true;
        }
        &self.texts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::geometry::parse_polygon;

    fn poly(spec: &str) -> Polygon {
        parse_polygon(spec).expect("polygon")
    }

    /// The kept texts are the fresh ones after every kind of change (a hint, a source
    /// polygon, an attribute) and when nothing changed.
    #[test]
    fn kept_texts_are_the_fresh_ones() {
        let mut params = Params::default();
        assert!(params
            .set("poly", "pts={60,-12:60,6:80,6:80,-12},label=oba")
            .is_some());
        let mut mid = poly("pts={55,-17:55,11:85,11:85,-17},label=oba_mid_poly");
        let rim = poly("pts={50,-22:50,16:90,16:90,-22},label=oba_rim_poly");
        let mut kept = Kept::default();
        for step in 0..12 {
            match step {
                3 => params.set_hint("gut_fill_color", "pink"),
                5 => mid = poly("pts={54,-17:55,11:85,11:85,-17},label=oba_mid_poly"),
                7 => params.set_hint("edge_size", "3"),
                9 => assert!(mid.attrs.set("edge_color", "red")),
                _ => {}
            }
            let got = kept
                .texts(&params, [&params.obstacle.clone(), &mid, &rim])
                .clone();
            for (k, src) in [&params.obstacle, &mid, &rim].into_iter().enumerate() {
                assert_eq!(got[k], drawn(&params, src, KEYS[k]).spec(5), "step {step}");
            }
        }
    }
}
