//! `contacts`: the helm's world of other vessels, as a pure library — `NODE_REPORT`
//! parsing and acceptance, the contact ledger with its per-iteration snapshot and
//! summaries, local coordinates from LAT/LON (UTM), and the contact geometry, filters
//! and alert strings every contact behavior shares (specs: contacts-appcast.md §2–§4,
//! behaviors-contacts.md §1).
//!
//! It knows nothing of the helm, MOOS, clocks or plugins: times are passed in, strings
//! come in and go out. It depends on `mbutil` (number test, formatter) and `geometry`
//! (compass angles, polygons) only; it must not depend on the helm, `moos`, `ivp`,
//! `behavior-api` or any plugin, so both the engine and a behavior SDK can use it.
//!
//! The engine's order per iteration: [`Ledger::ingest`] every ledger report of the mail
//! batch (`NODE_REPORT`, `AIS_REPORT`, `AIS_REPORT_LOCAL`: [`feeds_ledger`]), then
//! [`Ledger::maintain`], then post [`Ledger::summary`] (and [`Ledger::contact_summary`]
//! when it is `Some`), then let the behaviors read [`Ledger::snapshot`].
//!
//! ```
//! use contacts::Ledger;
//! let mut ledger = Ledger::new(Some((43.8253, -70.3304)));
//! ledger.ingest("NAME=bob,X=115,Y=120,SPD=1.8,HDG=270,TYPE=kayak,TIME=1000", 1000.0).unwrap();
//! ledger.maintain(1000.25);
//! assert_eq!(ledger.summary(), "now:1, reps:1, who:bob");
//! let bob = ledger.snapshot().get("bob").unwrap();
//! assert_eq!((bob.x, bob.y, bob.hdg), (115.0, 120.0, 270.0));
//! // Closest approach if ownship at (0,0) heads 0° at 2 m/s for up to 120 s:
//! let cpa = contacts::cpa(0.0, 0.0, 0.0, 2.0, bob.x, bob.y, bob.hdg, bob.spd, 120.0);
//! assert!(cpa.dist < 10.0 && cpa.time > 0.0);
//! ```

pub mod alert;
pub mod cnflag;
pub mod engine;
pub mod extrap;
pub mod filter;
pub mod geodesy;
pub mod ledger;
pub mod local;
pub mod relation;
pub mod report;
pub mod snapshot;
pub mod vtype;

pub use alert::{
    alert_request, may_spawn, spawn_name, update_pairs, AbleAction, AbleBlacklist, AbleFilter,
    AlertError,
};
pub use cnflag::{CnFlag, CnFlagError, CnTag};
pub use engine::{cpa, range, rel_bearing, Cpa, CpaEngine};
pub use extrap::{Decay, DecayError};
pub use filter::{ContactFilter, FilterCheck, FilterError};
pub use geodesy::Geodesy;
pub use ledger::{feeds_ledger, Accepted, IngestError, Ledger, Missing};
pub use local::{for_each_local_nav, local_nav_vars, LocalValue, NavValue, UnhandledLocal};
pub use relation::{ContactRelation, Pose};
pub use report::NodeReport;
pub use snapshot::{ContactRecord, LedgerSnap, SnapField, CONTACT_BASE_GROUP_FIELD};
pub use vtype::{default_length, fix_type};
