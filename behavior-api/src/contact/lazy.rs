//! A refresh's [`ContactRelation`], computed the first time it is asked for: most
//! iterations of most contact behaviors read only the range (relevance, completion),
//! and the whole relation (two CPA engines, bearings, crossings) was the larger part of
//! a refresh. The relation is a function of the two poses alone, so computing it later
//! from the poses kept gives the same values, bit for bit.

use std::cell::OnceCell;

use contacts::{range, ContactRelation, Pose};

/// The poses of one refresh, their range, and their relation once asked.
#[derive(Clone, Debug)]
pub(super) struct LazyRelation {
    os: Pose,
    cn: Pose,
    /// [`ContactRelation::range`], computed as its engine computes it.
    range: f64,
    full: OnceCell<ContactRelation>,
}

impl LazyRelation {
    pub(super) fn new(os: Pose, cn: Pose) -> Self {
        LazyRelation {
            os,
            cn,
            // The relation's engine E (contact as contact) takes its range so.
            range: range(os.x, os.y, cn.x, cn.y),
            full: OnceCell::new(),
        }
    }

    pub(super) fn range(&self) -> f64 {
        self.range
    }

    /// The relation of the poses (computed on the first call).
    pub(super) fn get(&self) -> &ContactRelation {
        self.full
            .get_or_init(|| ContactRelation::new(self.os, self.cn))
    }
}
