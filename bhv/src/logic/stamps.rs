//! Write stamps: how a persistent condition knows which of its variables were written
//! since it last read them, without looking each one up by name every iteration.

use std::sync::atomic::{AtomicU64, Ordering};

use super::{read_slot, LogicCondition, VarSource};

/// A source's write stamps, by variable place (the source's own numbering, which never
/// changes and only grows). Kept by a source that returns it from
/// [`VarSource::stamps`].
#[derive(Debug)]
pub struct Stamps {
    /// Tells sources apart: places mean nothing in another source.
    id: u64,
    clock: u64,
    of: Vec<u64>,
}

impl Default for Stamps {
    fn default() -> Self {
        // 0 is never an id: a condition that follows no source holds 0.
        static NEXT: AtomicU64 = AtomicU64::new(1);
        Stamps {
            id: NEXT.fetch_add(1, Ordering::Relaxed),
            clock: 0,
            of: Vec::new(),
        }
    }
}

impl Stamps {
    /// Records a write of the variable at `place` (a new place is the next one).
    pub fn write(&mut self, place: usize) {
        self.clock += 1;
        if place >= self.of.len() {
            self.of.resize(place + 1, 0);
        }
        self.of[place] = self.clock;
    }
}

/// What a condition last read from a stamped source.
#[derive(Clone, Debug, Default)]
pub(super) struct Follow {
    /// The source's id; 0: none (the slots may hold values read from elsewhere).
    source: u64,
    /// The source's variable count when the unplaced variables were last looked up.
    known: usize,
    /// Per variable: its place, once the source has it, and the stamp last read there.
    places: Vec<Option<(usize, u64)>>,
    /// The value of `eval` while no slot changes.
    pub(super) result: Option<bool>,
}

impl Follow {
    /// Forget what was read (the slots changed some other way).
    pub(super) fn forget(&mut self) {
        self.source = 0;
        self.result = None;
    }

    /// A variable's slot was set directly: it is read again at the next update.
    pub(super) fn unread(&mut self, i: usize) {
        if let Some(Some((_, seen))) = self.places.get_mut(i) {
            *seen = 0;
        }
        self.result = None;
    }
}

/// `update` from a stamped source: only the variables written since they were last
/// read are read again. Re-reading an unwritten variable would assign the slot what it
/// already holds, so the slots end exactly as a full update leaves them.
pub(super) fn update_stamped(c: &mut LogicCondition, src: &dyn VarSource, st: &Stamps) {
    let f = &mut c.follow;
    if f.source != st.id {
        f.source = st.id;
        f.known = usize::MAX;
        f.places.clear();
        f.places.resize(c.vars.len(), None);
    }
    // Places are never taken back: an unplaced variable can only have appeared if the
    // source has more variables than at the last look.
    let relook = f.known != st.of.len();
    f.known = st.of.len();
    for ((var, slot), place) in c.vars.iter().zip(&mut c.slots).zip(&mut f.places) {
        if place.is_none() && relook {
            *place = src.place(var).map(|p| (p, 0));
        }
        let Some((p, seen)) = place else {
            continue;
        };
        // (A place the stamps do not cover is read every time.)
        match st.of.get(*p) {
            Some(&stamp) if stamp == *seen => continue,
            Some(&stamp) => *seen = stamp,
            None => {}
        }
        if read_slot(slot, var, src) {
            f.result = None;
        }
    }
}
