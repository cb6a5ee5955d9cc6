//! The cell coordinate of every grid index, per dimension: the solver's cell grids and
//! the last function's cell index both turn piece bounds into cells many times per
//! solve, so the divisions are done once per domain and cell size.

/// `index / points-per-cell` for every index of every dimension, kept until the points
/// or the cell sizes change.
#[derive(Debug, Default)]
pub(crate) struct CoordTable {
    /// Points then points per cell the table was made for.
    key: Vec<i32>,
    /// Dimension `d`'s coordinates are `coord[off[d]..off[d + 1]]`.
    coord: Vec<u32>,
    off: Vec<usize>,
}

impl CoordTable {
    /// Whether the table is the one of these points and cell sizes.
    pub(crate) fn is_for(&self, pts: &[i32], ppg: &[i32]) -> bool {
        let dim = pts.len();
        // Every function of every solve asks: see `same_small`.
        self.key.len() == 2 * dim
            && same_small(&self.key[..dim], pts)
            && same_small(&self.key[dim..], ppg)
    }

    /// (Re)make the table for `pts` points and `ppg` points per cell, unless it is theirs.
    pub(crate) fn make(&mut self, pts: &[i32], ppg: &[i32]) {
        if self.is_for(pts, ppg) {
            return;
        }
        self.key.clear();
        self.key.extend_from_slice(pts);
        self.key.extend_from_slice(ppg);
        self.coord.clear();
        self.off.clear();
        for (&n, &per) in pts.iter().zip(ppg) {
            self.off.push(self.coord.len());
            self.coord.extend((0..n.max(0)).map(|i| (i / per) as u32));
        }
        self.off.push(self.coord.len());
    }

    /// Where dimension `d`'s coordinates start in [`CoordTable::all`], and how many.
    pub(crate) fn span(&self, d: usize) -> (usize, usize) {
        (self.off[d], self.off[d + 1] - self.off[d])
    }

    /// Every dimension's coordinates, one after the other.
    #[inline(always)]
    pub(crate) fn all(&self) -> &[u32] {
        &self.coord
    }

    /// The coordinates of dimension `d`'s indices (one per point).
    #[inline(always)]
    pub(crate) fn line(&self, d: usize) -> &[u32] {
        &self.coord[self.off[d]..self.off[d + 1]]
    }
}

/// `a == b` for the few entries of a map, the problem's points or cell sizes, element
/// by element (no call to compare a couple of words).
#[inline(always)]
pub(crate) fn same_small<T: PartialEq>(a: &[T], b: &[T]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y)
}
