//! Spare buffers of IvP functions that are done with, for the next ones built on this
//! thread (issue 19: a helm iteration allocates nothing in steady state). It lives here,
//! below `ivp`, because it is plain storage; `ivp` re-exports it as `ivp::zaic::spare`.
//!
//! A behavior builds its objective functions again every iteration (ZAICs, then the
//! coupler), and the helm drops them after the solve. The helm hands each dropped
//! function to `IvpFunction::recycle`; builders take their buffers from here
//! (domains are kept the same way in `ivp::domain`). The storage only changes hands
//! within one thread (the helm runs its behaviors on its own thread), so no lock is
//! needed. A plugin has its own copy of this crate and so its own, usually empty,
//! spares: it allocates as before, with the same results.

use std::cell::RefCell;

/// More spares of one kind than any iteration uses are let go.
pub const MAX_SPARE: usize = 64;

#[derive(Default)]
struct Spare {
    ints: Vec<Vec<i32>>,
    floats: Vec<Vec<f64>>,
    uints: Vec<Vec<u32>>,
    strings: Vec<String>,
    /// Bounds buffers handed out by [`ints_holding`] and not back yet (their addresses).
    marked: Vec<usize>,
    /// Such buffers back from [`give_function_buffers`], their contents kept.
    held: Vec<Vec<i32>>,
}

thread_local! {
    static SPARE: RefCell<Spare> = RefCell::new(Spare::default());
}

fn take<T: Default>(pick: impl FnOnce(&mut Spare) -> Option<T>) -> T {
    SPARE
        .try_with(|s| s.try_borrow_mut().ok().and_then(|mut s| pick(&mut s)))
        .ok()
        .flatten()
        .unwrap_or_default()
}

fn give(put: impl FnOnce(&mut Spare)) {
    let _ = SPARE.try_with(|s| {
        if let Ok(mut s) = s.try_borrow_mut() {
            put(&mut s);
        }
    });
}

/// A thread's store of kept values of one kind: `thread_local!` of a `RefCell<Vec<T>>`
/// (a builder's scratch lists, table boxes, ...), used through [`take_kept`] and
/// [`keep_in`]. Each builder declares its own, so that kinds never mix.
pub type Store<T> = std::thread::LocalKey<RefCell<Vec<T>>>;

/// The most recently kept value of `store`, or a new (default) one when it is empty,
/// in use, or gone (the thread is ending).
pub fn take_kept<T: Default>(store: &'static Store<T>) -> T {
    take_kept_or(store, T::default)
}

/// [`take_kept`] with `new` making the value when none is kept.
pub fn take_kept_or<T>(store: &'static Store<T>, new: impl FnOnce() -> T) -> T {
    store
        .try_with(|k| k.try_borrow_mut().ok().and_then(|mut k| k.pop()))
        .ok()
        .flatten()
        .unwrap_or_else(new)
}

/// The most recently kept value of `store` that `same` accepts (one kept for the same
/// inputs, to be used as it is); else, when `store` already holds `max`, the least
/// recently kept one (to be made again), so that values of other inputs keep theirs;
/// else a new (default) one. Given back with [`keep_in`].
pub fn take_kept_matching<T: Default>(
    store: &'static Store<T>,
    same: impl Fn(&T) -> bool,
    max: usize,
) -> T {
    let take = |k: &RefCell<Vec<T>>| {
        let mut k = k.try_borrow_mut().ok()?;
        match k.iter().rposition(&same) {
            Some(i) => Some(k.remove(i)),
            None if k.len() >= max => Some(k.remove(0)),
            None => None,
        }
    };
    store.try_with(take).ok().flatten().unwrap_or_default()
}

/// Keep `item` (the caller emptied what must not carry over) in `store` for the
/// thread's next [`take_kept`], unless it already holds `max` (more than are in use at
/// once on a thread are let go) or is in use or gone: then `item` is dropped.
pub fn keep_in<T>(store: &'static Store<T>, item: T, max: usize) {
    let _ = store.try_with(|k| {
        if let Ok(mut k) = k.try_borrow_mut() {
            if k.len() < max {
                k.push(item);
            }
        }
    });
}

/// Keep `item` in `list` unless it is full (the caller cleared it).
pub fn keep<T>(list: &mut Vec<T>, item: T) {
    if list.len() < MAX_SPARE {
        list.push(item);
    }
}

/// An empty vector, in a spare allocation when one is kept.
pub fn ints() -> Vec<i32> {
    take(|s| s.ints.pop())
}
pub fn floats() -> Vec<f64> {
    take(|s| s.floats.pop())
}
pub fn uints() -> Vec<u32> {
    take(|s| s.uints.pop())
}
/// The most recently kept spare with room for `n` items (the spares are of every size:
/// a small one would grow), else the most recent one.
fn fitting<T>(list: &mut Vec<Vec<T>>, n: usize) -> Option<Vec<T>> {
    match list.iter().rposition(|v| v.capacity() >= n) {
        Some(k) => Some(list.swap_remove(k)),
        None => list.pop(),
    }
}

/// Copies of a function's four buffers (bounds, weights, gel box, grid) in spare
/// allocations, with one visit to the thread's storage instead of four: the host copies
/// every function a loaded library makes, and the Constant* plugins their kept one,
/// every iteration. An empty grid stays without a buffer (taking a spare for it would
/// leave a larger function without one).
pub fn function_buffers_from(
    bounds: &[i32],
    weights: &[f64],
    gelbox: &[u32],
    grid: &[f64],
) -> (Vec<i32>, Vec<f64>, Vec<u32>, Vec<f64>) {
    let (mut b, mut w, mut g, mut c) = <(Vec<i32>, Vec<f64>, Vec<u32>, Vec<f64>)>::default();
    let _ = SPARE.try_with(|s| {
        let Ok(mut s) = s.try_borrow_mut() else {
            return;
        };
        // The grid's spare first, as when it was taken on its own before the others.
        if !grid.is_empty() {
            c = fitting(&mut s.floats, grid.len()).unwrap_or_default();
        }
        b = fitting(&mut s.ints, bounds.len()).unwrap_or_default();
        w = fitting(&mut s.floats, weights.len()).unwrap_or_default();
        g = fitting(&mut s.uints, gelbox.len()).unwrap_or_default();
    });
    b.extend_from_slice(bounds);
    w.extend_from_slice(weights);
    g.extend_from_slice(gelbox);
    c.extend_from_slice(grid);
    (b, w, g, c)
}

/// A copy of `items` for a function's bounds that many builds share (a reflector's
/// tiling): a buffer that came back through [`give_function_buffers`] already holding
/// them is reused without copying. It is only taken after comparing its contents with
/// `items` (cheaper than the copy), so a holder having changed them, or an address
/// reused by another buffer, costs the copy, never a wrong result.
pub fn ints_holding(items: &[i32]) -> Vec<i32> {
    let picked = SPARE.try_with(|s| {
        let mut s = s.try_borrow_mut().ok()?;
        // One of the same length, else the oldest held (a shape no longer built).
        let k = s.held.iter().rposition(|v| v.len() == items.len());
        let mut v = match k.or(if s.held.is_empty() { None } else { Some(0) }) {
            Some(k) => s.held.swap_remove(k),
            None => fitting(&mut s.ints, items.len()).unwrap_or_default(),
        };
        if !same_ints(&v, items) {
            v.clear();
            v.extend_from_slice(items);
        }
        if v.capacity() == 0 {
            return Some(v);
        }
        if s.marked.len() >= MAX_SPARE {
            // Marks of buffers that never came back (dropped) let go.
            s.marked.remove(0);
        }
        s.marked.push(v.as_ptr() as usize);
        Some(v)
    });
    picked.ok().flatten().unwrap_or_else(|| items.to_vec())
}

/// `a == b`, by blocks of [`SAME_BLOCK`] numbers whose differences are OR-ed (no test
/// per number: the compiler does a block in a few vector instructions), compiled for
/// AVX2 when the CPU has it; a block that differs ends the comparison.
fn same_ints(a: &[i32], b: &[i32]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { same_ints_avx2(a, b) };
    }
    same_ints_body(a, b)
}

/// Numbers per block of [`same_ints`].
const SAME_BLOCK: usize = 64;

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn same_ints_avx2(a: &[i32], b: &[i32]) -> bool {
    same_ints_body(a, b)
}

/// [`same_ints`] of two lists of one length.
#[inline(always)]
fn same_ints_body(a: &[i32], b: &[i32]) -> bool {
    let (ab, bb) = (a.chunks_exact(SAME_BLOCK), b.chunks_exact(SAME_BLOCK));
    let rest = ab.remainder() == bb.remainder();
    for (x, y) in ab.zip(bb) {
        let d = x.iter().zip(y).fold(0, |d, (x, y)| d | (x ^ y));
        if d != 0 {
            return false;
        }
    }
    rest
}

/// An empty string, in a spare allocation when one is kept.
pub fn string() -> String {
    take(|s| s.strings.pop())
}

/// Keep a vector's allocation for later builds (an empty one is not worth keeping).
pub fn give_ints(mut v: Vec<i32>) {
    if v.capacity() > 0 {
        v.clear();
        give(|s| keep(&mut s.ints, v));
    }
}
pub fn give_floats(mut v: Vec<f64>) {
    if v.capacity() > 0 {
        v.clear();
        give(|s| keep(&mut s.floats, v));
    }
}
pub fn give_uints(mut v: Vec<u32>) {
    if v.capacity() > 0 {
        v.clear();
        give(|s| keep(&mut s.uints, v));
    }
}
/// Keep the four buffers of a function (bounds, weights, gel box, grid) for later
/// builds, with one visit to the thread's storage instead of four (a plugin hands
/// back every function it built, every iteration).
pub fn give_function_buffers(
    mut bounds: Vec<i32>,
    mut weights: Vec<f64>,
    mut gelbox: Vec<u32>,
    mut grid: Vec<f64>,
) {
    weights.clear();
    gelbox.clear();
    grid.clear();
    // The buffers are taken where they lie (the closure borrows them; moved into it,
    // the four vectors were copied for every function handed back).
    give(|s| {
        // A buffer from `ints_holding` keeps its contents for the next one.
        let at = bounds.as_ptr() as usize;
        match s.marked.iter().rposition(|&p| p == at) {
            Some(k) => {
                s.marked.swap_remove(k);
                keep(&mut s.held, std::mem::take(&mut bounds));
            }
            // In the order of the four `give_*` calls, an empty one not kept.
            None if bounds.capacity() > 0 => {
                bounds.clear();
                keep(&mut s.ints, std::mem::take(&mut bounds));
            }
            None => {}
        }
        if weights.capacity() > 0 {
            keep(&mut s.floats, std::mem::take(&mut weights));
        }
        if gelbox.capacity() > 0 {
            keep(&mut s.uints, std::mem::take(&mut gelbox));
        }
        if grid.capacity() > 0 {
            keep(&mut s.floats, std::mem::take(&mut grid));
        }
    });
}

/// Keep a string for later builds (a function's context, a variable's name).
pub fn give_string(mut text: String) {
    if text.capacity() > 0 {
        text.clear();
        give(|s| keep(&mut s.strings, text));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block comparison is `==` on lists of every length 0..=300, equal or with one
    /// number changed anywhere (in a block or in the rest), and of other lengths.
    #[test]
    fn same_ints_is_equality() {
        let mut seed = 7u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 33) as i32
        };
        for n in 0..=300usize {
            let a: Vec<i32> = (0..n).map(|_| next()).collect();
            assert!(same_ints(&a, &a.clone()), "{n}");
            for at in (0..n).step_by(7).chain(n.checked_sub(1)) {
                let mut b = a.clone();
                b[at] ^= 1 << (next() & 31);
                assert!(!same_ints(&a, &b), "{n} {at}");
                assert!(!same_ints(&b, &a), "{n} {at}");
            }
            assert!(!same_ints(&a, &a[..n.saturating_sub(1)]) || n == 0);
        }
    }

    thread_local! {
        static LISTS: RefCell<Vec<Vec<u8>>> = const { RefCell::new(Vec::new()) };
    }

    #[test]
    fn a_kept_value_comes_back_with_its_room_and_the_store_holds_at_most_max() {
        assert_eq!(take_kept(&LISTS).capacity(), 0);
        for n in [10, 20, 30] {
            keep_in(&LISTS, Vec::with_capacity(n), 2);
        }
        // The third was let go; the last kept comes back first.
        assert_eq!(take_kept(&LISTS).capacity(), 20);
        assert_eq!(take_kept(&LISTS).capacity(), 10);
        assert_eq!(take_kept(&LISTS).capacity(), 0);
        assert_eq!(take_kept_or(&LISTS, || vec![7]), vec![7]);
    }

    #[test]
    fn function_buffers_are_kept_as_the_four_gives_keep_them() {
        // This thread's storage starts empty (each test runs on its own thread).
        give_function_buffers(
            Vec::with_capacity(3),
            Vec::with_capacity(5),
            Vec::new(),
            Vec::with_capacity(7),
        );
        assert_eq!(floats().capacity(), 7);
        assert_eq!(floats().capacity(), 5);
        assert_eq!(floats().capacity(), 0);
        assert_eq!(ints().capacity(), 3);
        assert_eq!(uints().capacity(), 0);
    }

    #[test]
    fn function_buffers_are_copied_into_the_spares_that_fit() {
        give_function_buffers(
            Vec::with_capacity(8),
            Vec::with_capacity(2),
            Vec::with_capacity(1),
            Vec::with_capacity(9),
        );
        let (b, w, g, c) = function_buffers_from(&[1, 2], &[0.5, -0.0, 3.0], &[7], &[]);
        assert_eq!(
            (&b[..], &w[..], &g[..]),
            (&[1, 2][..], &[0.5, -0.0, 3.0][..], &[7][..])
        );
        assert_eq!(w[1].to_bits(), (-0.0f64).to_bits());
        // The weights took the spare with room for them; an empty grid takes none.
        assert_eq!((b.capacity(), w.capacity(), c.capacity()), (8, 9, 0));
        assert_eq!(floats().capacity(), 2);
        let (.., c) = function_buffers_from(&[], &[], &[], &[4.0]);
        assert_eq!(c, [4.0]);
    }

    #[test]
    fn a_held_buffer_serves_only_while_it_holds_the_items() {
        let items = [4, 5, 6, 7];
        let first = ints_holding(&items);
        assert_eq!(first, items);
        let at = first.as_ptr();
        // Back as a function's bounds: the next one is that buffer, not copied again.
        give_function_buffers(first, Vec::new(), Vec::new(), Vec::new());
        let again = ints_holding(&items);
        assert_eq!((again.as_ptr(), &again[..]), (at, &items[..]));
        // Changed while out: the same buffer, written again.
        let mut changed = again;
        changed[2] = -1;
        give_function_buffers(changed, Vec::new(), Vec::new(), Vec::new());
        let fixed = ints_holding(&items);
        assert_eq!((fixed.as_ptr(), &fixed[..]), (at, &items[..]));
        // Items of another length: the held buffer (of a shape no longer built) serves.
        give_function_buffers(fixed, Vec::new(), Vec::new(), Vec::new());
        let other = ints_holding(&[1, 2]);
        assert_eq!((other.as_ptr(), &other[..]), (at, &[1, 2][..]));
    }

    #[test]
    fn a_store_in_use_gives_a_new_value_and_keeps_nothing() {
        keep_in(&LISTS, Vec::with_capacity(5), 4);
        LISTS.with_borrow_mut(|_in_use| {
            assert_eq!(take_kept(&LISTS).capacity(), 0);
            keep_in(&LISTS, Vec::with_capacity(9), 4);
        });
        assert_eq!(take_kept(&LISTS).capacity(), 5);
        assert_eq!(take_kept(&LISTS).capacity(), 0);
    }

    #[test]
    fn a_matching_kept_value_comes_back_else_the_oldest_once_the_store_is_full() {
        thread_local! {
            static KEYED: RefCell<Vec<Vec<u8>>> = const { RefCell::new(Vec::new()) };
        }
        for v in [vec![1], vec![2], vec![1, 1]] {
            keep_in(&KEYED, v, 3);
        }
        // The most recently kept match, from anywhere in the store.
        assert_eq!(take_kept_matching(&KEYED, |v| v[0] == 1, 3), vec![1, 1]);
        // No match, room left: a new value, the kept ones stay.
        assert!(take_kept_matching(&KEYED, |v| v[0] == 9, 3).is_empty());
        assert_eq!(KEYED.with_borrow(|k| k.len()), 2);
        // No match, store full: the oldest kept one, to be made again.
        keep_in(&KEYED, vec![3], 3);
        assert_eq!(take_kept_matching(&KEYED, |v| v[0] == 9, 3), vec![1]);
        assert_eq!(KEYED.with_borrow(|k| k.clone()), vec![vec![2], vec![3]]);
    }
}
