//! [`NameIndex`]: variable names to places, for a buffer read by name many times an
//! iteration (the helm's info buffer: NAV_X, NAV_HEADING, ... by every behavior). A name
//! of up to 16 bytes is its own key, two words read in place: no hash over its bytes and
//! no `memcmp` to confirm a hit. Longer names go to an ordinary map.

use rustc_hash::FxHashMap;

/// A name of at most 16 bytes, exactly: with its length, the first and last 8 bytes
/// (overlapping below 16) or the first and last 4 (below 8) or three bytes (below 4)
/// leave no byte out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Short(u64, u64, usize);

/// The length of no name: an empty slot.
const EMPTY: Short = Short(0, 0, usize::MAX);

const K: u64 = 0x9e37_79b9_7f4a_7c15;

/// Both words through one full multiply, folded: every input bit reaches the low bits
/// (the slot).
#[inline]
fn mix(a: u64, b: u64) -> u64 {
    let m = u128::from(a ^ 0xa076_1d64_78bd_642f) * u128::from(b ^ 0xe703_7ed1_a0b4_28db);
    (m as u64) ^ ((m >> 64) as u64)
}

#[inline]
fn word8(b: &[u8], at: usize) -> u64 {
    b.get(at..at + 8)
        .and_then(|w| w.try_into().ok())
        .map_or(0, u64::from_le_bytes)
}

#[inline]
fn word4(b: &[u8], at: usize) -> u64 {
    b.get(at..at + 4)
        .and_then(|w| w.try_into().ok())
        .map_or(0, |w| u64::from(u32::from_le_bytes(w)))
}

impl Short {
    #[inline]
    fn of(name: &str) -> Option<Short> {
        let b = name.as_bytes();
        let n = b.len();
        let (lo, hi) = match n {
            8..=16 => (word8(b, 0), word8(b, n - 8)),
            4..=7 => (word4(b, 0), word4(b, n - 4)),
            1..=3 => (
                u64::from(b[0]) | u64::from(b[n / 2]) << 8 | u64::from(b[n - 1]) << 16,
                0,
            ),
            0 => (0, 0),
            _ => return None,
        };
        Some(Short(lo, hi, n))
    }

    #[inline]
    fn slot(&self, mask: usize) -> usize {
        mix(self.0 ^ self.2 as u64, self.1 ^ K) as usize & mask
    }
}

/// Names to places (`usize`), never iterated: the order of the slots cannot show.
///
/// ```
/// let mut index = mbutil::NameIndex::default();
/// index.insert("NAV_X", 0);
/// index.insert("A_NAME_LONGER_THAN_SIXTEEN", 1);
/// assert_eq!(index.get("NAV_X"), Some(0));
/// assert_eq!(index.get("A_NAME_LONGER_THAN_SIXTEEN"), Some(1));
/// assert_eq!(index.get("NAV_Y"), None);
/// ```
#[derive(Clone, Debug, Default)]
pub struct NameIndex {
    /// Short names in open addressing (linear probing, at most half full, a power of
    /// two long): a hit is mostly the first slot looked at.
    slots: Vec<(Short, usize)>,
    shorts: usize,
    long: FxHashMap<String, usize>,
}

impl NameIndex {
    #[inline]
    pub fn get(&self, name: &str) -> Option<usize> {
        let Some(k) = Short::of(name) else {
            return self.get_long(name);
        };
        let mask = self.slots.len().wrapping_sub(1);
        let mut i = k.slot(mask);
        while let Some(&(s, place)) = self.slots.get(i) {
            if s == k {
                return Some(place);
            }
            if s == EMPTY {
                return None;
            }
            i = (i + 1) & mask;
        }
        None // no slots yet
    }

    /// Apart, so that the short names' path stays small enough to inline.
    #[inline(never)]
    fn get_long(&self, name: &str) -> Option<usize> {
        self.long.get(name).copied()
    }

    /// `name` at `place` (a name already there moves).
    pub fn insert(&mut self, name: &str, place: usize) {
        let Some(k) = Short::of(name) else {
            self.long.insert(name.to_string(), place);
            return;
        };
        if 2 * (self.shorts + 1) > self.slots.len() {
            let room = self.slots.len().max(32) * 2;
            let old = std::mem::replace(&mut self.slots, vec![(EMPTY, 0); room]);
            for (s, p) in old.into_iter().filter(|(s, _)| *s != EMPTY) {
                self.put(s, p);
            }
        }
        self.shorts += usize::from(self.put(k, place));
    }

    /// Into its slot; `true` if new.
    fn put(&mut self, k: Short, place: usize) -> bool {
        let mask = self.slots.len() - 1;
        let mut i = k.slot(mask);
        loop {
            let slot = &mut self.slots[i];
            if slot.0 == k || slot.0 == EMPTY {
                let new = slot.0 == EMPTY;
                *slot = (k, place);
                return new;
            }
            i = (i + 1) & mask;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    /// Against an ordinary map, over names of every length to 24 that differ in one
    /// byte anywhere, share prefixes and suffixes, or are each other's prefix.
    #[test]
    fn same_places_as_an_ordinary_map() {
        let mut names = vec![String::new()];
        for n in 1..=24 {
            let base: String = (0..n).map(|i| char::from(b'A' + (i % 26) as u8)).collect();
            names.push(base.clone());
            names.push("A".repeat(n));
            for at in 0..n {
                let mut b = base.clone().into_bytes();
                b[at] = b'_';
                names.push(String::from_utf8(b).unwrap_or_default());
            }
        }
        names.push("é".repeat(5));
        let (mut index, mut want) = (NameIndex::default(), BTreeMap::new());
        for (i, name) in names.iter().enumerate() {
            if i % 3 != 0 {
                index.insert(name, i);
                want.insert(name.clone(), i);
            }
        }
        for name in &names {
            assert_eq!(index.get(name), want.get(name).copied(), "{name:?}");
        }
        assert!(want.len() > 200, "{}", want.len());
    }
}
