//! The ledger's per-iteration work allocates nothing in steady state: once every
//! contact has been seen, a batch of reports for known names, `maintain`, the
//! summaries and snapshot reads run without a single heap allocation (counted by this
//! test binary's own global allocator, on this thread).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use contacts::Ledger;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocs() -> usize {
    ALLOCS.with(Cell::get)
}

const N: usize = 50;

fn batch(t: f64) -> Vec<String> {
    (0..N)
        .map(|i| {
            let k = i as f64;
            format!(
                "NAME=c{i:02},X={},Y={},SPD=1.5,HDG={},DEP=0,LAT=43.8,LON=-70.3,\
                 TYPE=kayak,GROUP=g{},COLOR=yellow,MODE=DRIVE,INDEX=1,TIME={t},LENGTH=4",
                100.0 + k + t * 0.1,
                -50.0 + 2.0 * k,
                (k * 7.0) % 360.0,
                i % 3
            )
        })
        .collect()
}

/// One helm iteration's ledger work; returns something so nothing is optimised away.
fn iteration(l: &mut Ledger, reports: &[String], t: f64, keep: &[&str]) -> usize {
    let mut n = 0;
    for r in reports {
        n += l.ingest(r, t).map(|a| a.name.len()).unwrap_or(0);
    }
    l.maintain(t);
    n += l.summary().len();
    n += l.contact_summary(keep.iter().copied()).map_or(0, str::len);
    let snap = l.snapshot();
    for name in keep {
        if let Some(c) = snap.get(name) {
            let e = contacts::CpaEngine::new(c.x, c.y, c.hdg, c.spd, 0.0, 0.0);
            n += (e.cpa(45.0, 2.0, 120.0) > 0.0) as usize;
        }
    }
    n
}

#[test]
fn steady_state_iterations_do_not_allocate() {
    let mut l = Ledger::new(Some((43.8253, -70.3304)));
    let keep = ["c03", "c17", "", "c03", "c42", "c49"];
    let batches: Vec<(f64, Vec<String>)> = (0..40)
        .map(|i| {
            let t = 1000.0 + i as f64 * 0.25;
            (t, batch(t))
        })
        .collect();
    // Warm-up: every name seen, buffers grown.
    let mut sink = 0;
    for (t, b) in &batches[..5] {
        sink += iteration(&mut l, b, *t, &keep);
    }
    let before = allocs();
    for (t, b) in &batches[5..] {
        sink += iteration(&mut l, b, *t, &keep);
    }
    let during = allocs() - before;
    assert!(sink > 0);
    assert_eq!(l.snapshot().len(), N);
    assert_eq!(during, 0, "{during} allocations in 35 steady iterations");
    // The counter does count: a new name allocates.
    let before = allocs();
    l.ingest("NAME=newcomer,X=1,Y=1,TIME=1010", 1010.0).unwrap();
    assert!(allocs() > before);
}
