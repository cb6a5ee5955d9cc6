//! Plateau and basin regions of the reflector (ivp-solver.md §8; obstacles.md §1.9):
//! boxes of known constant utility that the uniform tiling is cut around, and the box
//! subtraction that cuts them.

/// An index box: an inclusive `(lo, hi)` per dimension.
pub type IndexBox = Vec<(u32, u32)>;

/// Whether two boxes share a grid point.
pub fn intersects(a: &[(u32, u32)], b: &[(u32, u32)]) -> bool {
    a.iter()
        .zip(b)
        .all(|(&(alo, ahi), &(blo, bhi))| alo <= bhi && blo <= ahi)
}

/// `orig − sub` as disjoint boxes (obstacles.md §1.9): empty if `sub` contains `orig`,
/// `orig` itself if they do not meet; otherwise, dimension by dimension, the part above
/// `sub` then the part below it are cut off `orig`, each new piece put at the front.
///
/// ```
/// use ivp_reflector::reflector::box_subtract;
/// // [0,9] minus [3,5] (one dimension): the part above, then the part below, in front.
/// assert_eq!(box_subtract(&[(0, 9)], &[(3, 5)]), vec![vec![(0, 2)], vec![(6, 9)]]);
/// assert!(box_subtract(&[(3, 4)], &[(0, 9)]).is_empty());
/// ```
pub fn box_subtract(orig: &[(u32, u32)], sub: &[(u32, u32)]) -> Vec<IndexBox> {
    if !intersects(orig, sub) {
        return vec![orig.to_vec()];
    }
    let mut src = orig.to_vec();
    let mut out: Vec<IndexBox> = Vec::new();
    for d in 0..src.len() {
        if sub[d].1 < src[d].1 {
            let mut piece = src.clone();
            piece[d].0 = sub[d].1 + 1;
            out.insert(0, piece);
            src[d].1 = sub[d].1;
        }
        if sub[d].0 > src[d].0 {
            let mut piece = src.clone();
            piece[d].1 = sub[d].0 - 1;
            out.insert(0, piece);
            src[d].0 = sub[d].0;
        }
    }
    out
}

/// Cut `tiles` around each region in turn: tiles that do not meet it stay in order, the
/// remainders of those that do are appended at the end (per region, in region order).
pub fn cut_around(tiles: Vec<IndexBox>, regions: &[(IndexBox, f64)]) -> Vec<IndexBox> {
    let mut tiles = tiles;
    for (r, _) in regions {
        let mut kept = Vec::with_capacity(tiles.len());
        let mut rest = Vec::new();
        for t in tiles {
            if intersects(&t, r) {
                rest.extend(box_subtract(&t, r));
            } else {
                kept.push(t);
            }
        }
        kept.extend(rest);
        tiles = kept;
    }
    tiles
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subtraction_in_two_dimensions() {
        // [0,9]×[0,4] minus [3,5]×[0,4]: course above (6..9) then below (0..2); the
        // speed range is covered, nothing more.
        let r = box_subtract(&[(0, 9), (0, 4)], &[(3, 5), (0, 4)]);
        assert_eq!(r, vec![vec![(0, 2), (0, 4)], vec![(6, 9), (0, 4)]]);
        // A corner: above in course, then above in speed of the remaining column.
        let r = box_subtract(&[(0, 5), (0, 5)], &[(0, 2), (0, 2)]);
        assert_eq!(r, vec![vec![(0, 2), (3, 5)], vec![(3, 5), (0, 5)]]);
    }

    #[test]
    fn cutting_keeps_order_and_appends_remainders() {
        let tiles = vec![vec![(0, 2)], vec![(3, 5)], vec![(6, 8)]];
        let out = cut_around(tiles, &[(vec![(4, 4)], 1.0)]);
        assert_eq!(
            out,
            vec![vec![(0, 2)], vec![(6, 8)], vec![(3, 3)], vec![(5, 5)]]
        );
    }

    #[test]
    fn reflector_pieces_around_a_plateau() {
        use crate::{Aof, Reflector};
        use ivp::Domain;
        struct Ramp;
        impl Aof for Ramp {
            fn eval(&self, _: &Domain, ix: &[u32]) -> f64 {
                f64::from(ix[0])
            }
        }
        let mut d = Domain::new();
        d.add_var("x", 0.0, 9.0, 10).unwrap();
        let mut r = Reflector::new(&d, &Ramp);
        r.set_param("uniform_piece", "discrete@x:5");
        r.add_region(vec![(3, 6)], 100.0);
        r.add_region(vec![(3, 12)], 0.0); // beyond the domain: ignored
                                          // Tiles [5,9] and [0,4] (stored reversed) both meet [3,6]: remainders [7,9] and
                                          // [0,2], then the plateau: 3 pieces.
        assert_eq!(r.create(None, None), 3);
        let f = r.extract(false).unwrap();
        assert_eq!(f.eval(&[4]), Some(100.0));
        assert_eq!(f.eval(&[8]), Some(8.0));
        assert_eq!(f.eval(&[1]), Some(1.0));
    }

    #[test]
    fn ignored_dimension_shares_fits_bit_for_bit() {
        use crate::{Aof, Reflector};
        use ivp::Domain;
        struct Wave(bool);
        impl Aof for Wave {
            fn eval(&self, _: &Domain, ix: &[u32]) -> f64 {
                (f64::from(ix[0]) * 0.37).sin() * 50.0 + 50.0
            }
            fn ignores(&self, dim: usize) -> bool {
                self.0 && dim == 1
            }
        }
        let mut d = Domain::new();
        d.add_var("course", 0.0, 359.0, 360).unwrap();
        d.add_var("speed", 0.0, 4.0, 21).unwrap();
        let build = |aof: &Wave| {
            let mut r = Reflector::new(&d, aof);
            r.set_param("uniform_piece", "discrete@course:3,speed:4");
            r.create(None, None);
            let f = r.extract(true).unwrap();
            (f.bounds().to_vec(), f.weights().to_vec())
        };
        let (plain, shared) = (build(&Wave(false)), build(&Wave(true)));
        assert_eq!(plain.0.len(), 120 * 6 * 4);
        assert_eq!(plain, shared);
    }
}
