//! Hostile reports (issue 18): NaN and huge numbers, unknown fields, 10 000 distinct
//! names. The ledger keeps working, refuses what it must with a reason, and its heap
//! stays bounded by the contact cap (measured with fuzzkit's counting allocator).

use contacts::{IngestError, Ledger};

fn ledger() -> Ledger {
    Ledger::new(Some((43.8253, -70.3304)))
}

#[test]
fn nan_and_huge_numbers() {
    let mut l = ledger();
    // "nan" is not a number to the helm: no position, no time.
    let e = l.ingest("NAME=a,X=nan,Y=nan,TIME=nan", 1.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "Missing timestamp.Missing both x/y and lat/lon."
    );
    // 400 digits pass the number test and read as infinity; stored, and the geometry
    // on them ends (heading wrapped by remainder, not by a 1e300-step loop).
    let huge = "9".repeat(400);
    let r = format!("NAME=h,X={huge},Y=-{huge},HDG={huge},SPD={huge},TIME=5");
    l.ingest(&r, 5.0).unwrap();
    let r = format!("NAME=g,X=1,Y=2,HDG=1{},SPD=2,TIME=5", "0".repeat(300));
    l.ingest(&r, 5.0).unwrap();
    l.maintain(5.0);
    for c in l.snapshot().contacts() {
        let e = contacts::CpaEngine::new(c.x, c.y, c.hdg, c.spd, 0.0, 0.0);
        let _ = e.cpa(45.0, 2.0, 120.0);
        let _ = contacts::cpa(0.0, 0.0, 45.0, 2.0, c.x, c.y, c.hdg, c.spd, 120.0);
    }
    let g = l.snapshot().get("g").unwrap();
    let e = contacts::CpaEngine::new(g.x, g.y, g.hdg, g.spd, 0.0, 0.0);
    assert!(e.cpa(45.0, 2.0, 120.0).is_finite());
    // LAT/LON-only with absurd values converts to something, never panics.
    l.ingest(&format!("NAME=ll,LAT={huge},LON=-{huge},TIME=5"), 5.0)
        .unwrap();
}

#[test]
fn unknown_fields_are_not_kept() {
    let mut l = ledger();
    let mut r = String::from("NAME=bob,X=1,Y=2,TIME=3");
    for i in 0..10_000 {
        r.push_str(&format!(",EXTRA{i}=value{i}"));
    }
    let (res, peak) = fuzzkit::peak_during(|| l.ingest(&r, 3.0).map(|a| a.name.len()));
    assert_eq!(res, Ok(3));
    assert!(
        peak < 4096,
        "{peak} bytes kept for a report with 10 000 unknown fields"
    );
}

#[test]
fn ten_thousand_names_stay_under_the_cap() {
    let mut l = ledger();
    let cap = l.max_contacts();
    let reports: Vec<String> = (0..10_000)
        .map(|i| format!("NAME=intruder{i:05},X={i},Y=0,SPD=1,HDG=0,TYPE=kayak,TIME=100"))
        .collect();
    let (full, peak) = fuzzkit::peak_during(|| {
        let mut full = 0;
        for r in &reports {
            if let Err(IngestError::Full { cap: c }) = l.ingest(r, 100.0) {
                assert_eq!(c, cap);
                full += 1;
            }
        }
        l.maintain(100.0);
        full
    });
    assert_eq!(l.len(), cap);
    assert_eq!(full, 10_000 - cap);
    assert_eq!(l.refused_full(), (10_000 - cap) as u64);
    // Records plus their snapshot copies: about 2 × 500 × (record + name). A ledger
    // that kept all 10 000 would need well over 2 MiB.
    assert!(
        peak < 1 << 20,
        "{peak} bytes at the peak for {cap} contacts"
    );
    // Still deciding: a known contact is updated, the summary is due, names are sorted.
    l.ingest("NAME=intruder00007,X=5,Y=5,TIME=101", 101.0)
        .unwrap();
    l.maintain(101.0);
    assert_eq!(l.snapshot().get("intruder00007").unwrap().x, 5.0);
    assert!(l
        .summary()
        .starts_with("now:500, reps:501, who:intruder00000,intruder00001,"));
    // Stale removal frees the room again.
    l.maintain(100.0 + 2.0 * contacts::ledger::DEFAULT_MAX_AGE + 0.5);
    assert_eq!(l.len(), 1);
    l.ingest("NAME=newcomer,X=1,Y=1,TIME=191", 191.0).unwrap();
}
