//! [`ValuesKey`]: which values of a domain variable a list was made for, so that a
//! builder that keeps per-value lists from one iteration to the next (unit vectors of
//! courses, table entries) knows when a kept list is still the one it needs.

use crate::domain::DomainVar;

/// The values of a domain variable at some of its indices, as a key: the variable's
/// `low`, `high` and `points` (bits) and the indices. Two equal keys mean the same values,
/// bit for bit ([`DomainVar::values_at`]). The default key is of no variable (a variable
/// has at least one point).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ValuesKey {
    low: u64,
    high: u64,
    points: u32,
    indices: Vec<u32>,
}

impl ValuesKey {
    /// Whether this is the key of `var`'s values at the indices `xs`.
    #[inline]
    pub fn is(&self, var: &DomainVar, xs: &[u32]) -> bool {
        self.points == var.points
            && self.low == var.low.to_bits()
            && self.high == var.high.to_bits()
            && self.indices == xs
    }

    /// Make this the key of `var`'s values at the indices `xs` (its room reused).
    pub fn set(&mut self, var: &DomainVar, xs: &[u32]) {
        (self.low, self.high, self.points) = (var.low.to_bits(), var.high.to_bits(), var.points);
        self.indices.clear();
        self.indices.extend_from_slice(xs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Domain;

    #[test]
    fn a_key_is_of_the_values_it_was_set_for_only() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let (course, speed) = (d.var(0), d.var(1));
        let mut key = ValuesKey::default();
        assert!(!key.is(course, &[]), "the default key is of no variable");
        key.set(course, &[0, 5, 9]);
        assert!(key.is(course, &[0, 5, 9]));
        assert!(!key.is(course, &[0, 5]));
        assert!(!key.is(course, &[0, 5, 10]));
        assert!(!key.is(speed, &[0, 5, 9]));
        // Same low and high, other points: other values.
        let finer = Domain::parse("course:0:359:720").unwrap();
        assert!(!key.is(finer.var(0), &[0, 5, 9]));
        key.set(speed, &[1]);
        assert!(key.is(speed, &[1]) && !key.is(course, &[0, 5, 9]));
    }

    #[test]
    fn values_at_are_the_values_of_each_index() {
        let d = Domain::parse("course:-3.7:355.1:977,speed:2:2:1").unwrap();
        for var in [d.var(0), d.var(1)] {
            let xs: Vec<u32> = (0..var.points).rev().step_by(7).collect();
            let got: Vec<u64> = var.values_at(&xs).map(f64::to_bits).collect();
            let want: Vec<u64> = xs.iter().map(|&j| var.value(j).to_bits()).collect();
            assert_eq!(got, want);
        }
    }
}
