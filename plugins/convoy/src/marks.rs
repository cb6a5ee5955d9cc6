//! The mark trail of BHV_Convoy (behaviors-more.md §10.2–§10.3 steps 4–6): a queue of
//! points on the contact's path, newest first, its total length bounded.

use std::collections::VecDeque;

use behavior_api::geometry::dist;

/// One mark: position and id (its time is always 0 in the reference, so not kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    pub x: f64,
    pub y: f64,
    pub id: u64,
}

/// The trail: `front` is the newest mark, `back` the oldest.
#[derive(Clone, Debug, Default)]
pub struct Marks {
    queue: VecDeque<Mark>,
    next_id: u64,
    /// Length of the trail (sum of the gaps between consecutive marks).
    pub total: f64,
}

impl Marks {
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    pub fn oldest(&self) -> Option<Mark> {
        self.queue.back().copied()
    }

    pub fn newest(&self) -> Option<Mark> {
        self.queue.front().copied()
    }

    /// Newest first.
    pub fn iter(&self) -> impl Iterator<Item = &Mark> {
        self.queue.iter()
    }

    /// Add a mark at (x, y) as the newest; ids wrap to 0 past `up_bound`.
    pub fn push(&mut self, x: f64, y: f64, up_bound: u64) -> Mark {
        if let Some(n) = self.newest() {
            self.total += dist(x, y, n.x, n.y);
        }
        let m = Mark {
            x,
            y,
            id: self.next_id,
        };
        self.queue.push_front(m);
        self.next_id += 1;
        if self.next_id > up_bound {
            self.next_id = 0;
        }
        m
    }

    /// Remove the oldest mark; the trail shortens by its gap to the next.
    pub fn pop(&mut self) -> Option<Mark> {
        let m = self.queue.pop_back()?;
        if let Some(o) = self.oldest() {
            self.total -= dist(o.x, o.y, m.x, m.y);
        }
        Some(m)
    }

    /// Forget every mark (`next_id` is kept).
    pub fn clear(&mut self) {
        self.queue.clear();
        self.total = 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_pop_keep_the_length_and_wrap_ids() {
        let mut m = Marks::default();
        m.push(0.0, 0.0, 2);
        m.push(3.0, 4.0, 2);
        m.push(3.0, 10.0, 2);
        assert_eq!(m.total, 11.0);
        assert_eq!(m.newest().map(|k| k.id), Some(2));
        assert_eq!(m.push(3.0, 11.0, 2).id, 0, "wrapped past the bound");
        assert_eq!(m.pop().map(|k| (k.x, k.y)), Some((0.0, 0.0)));
        assert_eq!(m.total, 7.0);
        m.clear();
        assert!(m.is_empty());
        assert_eq!(m.total, 0.0);
        assert_eq!(m.push(0.0, 0.0, 2).id, 1, "ids go on after a clear");
    }
}
