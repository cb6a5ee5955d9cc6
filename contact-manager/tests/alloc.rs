//! The manager's iteration allocates nothing in steady state: once every contact has
//! been seen and nothing changes, a mail batch (ownship's NAV_* and a report of every
//! known contact) and `iterate` (alerts checked, retirement, a range report, the status
//! lists compared) run without a heap allocation (counted by this test binary's own
//! global allocator, on this thread). Postings that do go out (transitions, changed
//! lists, the recap each `recap_interval`) allocate their values.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use contact_manager::{Config, ContactManager, MailValue};

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

#[test]
fn steady_iterations_allocate_nothing() {
    let mut cfg = Config::default();
    for (p, v) in [
        ("alert", "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=50, cpa_range=75"),
        ("alert", "id=far, on_flag=FAR=$[VNAME], alert_range=300"),
        ("recap_interval", "1000000"),
        ("post_closest_range", "true"),
    ] {
        cfg.set(p, v).expect("config");
    }
    let mut m = ContactManager::new("alpha", cfg, Some((43.8253, -70.3304)));
    // 20 stationary contacts, some inside the alert ranges (alerted, steadily).
    let reports: Vec<String> = (0..20)
        .map(|i| {
            format!(
                "NAME=c{i:02},X={},Y=40,SPD=0,HDG=90,TYPE=kayak,TIME=1000",
                i * 30
            )
        })
        .collect();
    let request = "var=NEAR,range=200";
    let mut t = 1000.0;
    let step = |m: &mut ContactManager, t: f64, with_request: bool| -> usize {
        let mut mail: Vec<(&str, MailValue<'_>)> = Vec::with_capacity(32);
        mail.extend([
            ("NAV_X", MailValue::Num(0.0)),
            ("NAV_Y", MailValue::Num(0.0)),
            ("NAV_HEADING", MailValue::Num(0.0)),
            ("NAV_SPEED", MailValue::Num(0.0)),
        ]);
        mail.extend(reports.iter().map(|r| ("NODE_REPORT", MailValue::Str(r))));
        if with_request {
            mail.push(("BCM_REPORT_REQUEST", MailValue::Str(request)));
        }
        let before = allocs();
        m.handle_mail(t, &mail);
        let n = m.iterate(t).len();
        let used = allocs() - before;
        assert!(n < 1000);
        drop(mail);
        used
    };
    // Warm-up: contacts new, alerts fire, lists posted.
    step(&mut m, t, true);
    for _ in 0..3 {
        t += 0.5;
        step(&mut m, t, false);
    }
    assert_eq!(
        m.alerted().count(),
        2 + 10,
        "c00, c01 by avd_; c00..c09 by far"
    );
    for k in 0..20 {
        t += 0.5;
        let used = step(&mut m, t, false);
        assert_eq!(used, 0, "iteration {k} allocated {used} times");
    }
}
