//! Condition and mode evaluation must not allocate once warmed up.

use bhv::{LogicCondition, ModeEntry, ModeSet, VarSource};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

// Counted per thread: the test harness's own threads allocate now and then (under load,
// 4 of them once landed in a process-wide count and failed the test).
thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
}

fn allocs() -> usize {
    ALLOCS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A fixed source: strings and numbers from static tables.
struct Src {
    deploy: &'static str,
    leg: f64,
}

impl VarSource for Src {
    fn string_val(&self, var: &str) -> Option<&str> {
        match var {
            "DEPLOY" => Some(self.deploy),
            "RETURN" => Some("false"),
            "MODE" => Some("ACTIVE:SURVEYING"),
            _ => None,
        }
    }
    fn double_val(&self, var: &str) -> Option<f64> {
        match var {
            "LEG" => Some(self.leg),
            _ => None,
        }
    }
}

#[test]
fn evaluation_does_not_allocate() {
    let mut c =
        LogicCondition::parse("(DEPLOY = true) and ((LEG <= 1) or !(MODE == SURVEYING:LEG))")
            .unwrap_or_else(|e| panic!("{e}"));
    let mut m = ModeSet::default();
    let mut e = ModeEntry::new("MODE", "ACTIVE");
    e.add_condition("DEPLOY = true")
        .unwrap_or_else(|e| panic!("{e}"));
    e.set_else_value("INACTIVE");
    m.push(e);
    let mut e = ModeEntry::new("MODE", "RETURNING");
    e.add_condition("MODE = ACTIVE")
        .unwrap_or_else(|e| panic!("{e}"));
    e.add_condition("RETURN = true")
        .unwrap_or_else(|e| panic!("{e}"));
    e.set_else_value("SURVEYING");
    m.push(e);

    let sources = [
        Src {
            deploy: "true",
            leg: 1.0,
        },
        Src {
            deploy: "false",
            leg: 2.0,
        },
    ];
    // warm-up: slots and output buffers get their capacity
    for s in &sources {
        c.update(s);
        let _ = c.eval();
        let _ = m.evaluate(s).len();
    }
    let before = allocs();
    let mut trues = 0;
    for i in 0..1000 {
        let s = &sources[i % 2];
        c.update(s);
        trues += usize::from(c.eval());
        trues += usize::from(c.eval_fresh(s));
        trues += m.evaluate(s).len();
    }
    let after = allocs();
    assert_eq!(after - before, 0, "allocations during evaluation");
    assert!(trues > 0);
}
