//! `contact-manager`: pContactMgrV20's behaviour as a pure library (specs:
//! contacts-appcast.md §4) — the contact table fed by `NODE_REPORT`, alerts configured
//! by `alert = ...` lines and `BCM_ALERT_REQUEST` mail with their alert and CPA ranges,
//! the on-flags that make the helm spawn a behavior and the off-flags when the alert
//! no longer applies, `BCM_REPORT_REQUEST` range reports, the disable/enable/expunge
//! variables, and the status postings (`CONTACTS_LIST`, `CONTACTS_ALERTED`, ...).
//!
//! It is driven like the helm engine: [`ContactManager::handle_mail`] with a batch of
//! `(variable, value)` pairs and a time, then [`ContactManager::iterate`] with a time,
//! which returns the postings. The manager has no sockets, clocks or threads and no MOOS types (values
//! are plain strings and numbers), so the simulator runs one per vehicle in-process
//! and the `contactmgr` binary (`src/bin/contactmgr.rs`) runs it as a MOOS app in the
//! frame of [`app`], which `obstaclemgr` shares; [`block`] reads a manager's
//! `ProcessConfig` block for the binaries and the simulator alike. Only [`app`] uses
//! `moos`'s client; [`block`] its mission-file reader.
//!
//! Depends on `contacts` (report parsing, type fixing, geodesy, CPA, extrapolation,
//! filters), `mbutil` and `moos` (for [`app`] and [`block`] only); it must not depend on the helm crates, `behavior-api` or any
//! plugin.
//!
//! ```
//! use contact_manager::{Config, ContactManager, MailValue::{Num, Str}};
//! let mut cfg = Config::default();
//! cfg.set("alert", "id=avd, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME]").unwrap();
//! cfg.set("alert", "id=avd, off_flag=RESOLVED=$[VNAME], alert_range=50, cpa_range=75").unwrap();
//! let mut m = ContactManager::new("alpha", cfg, None);
//! // Ownship at the origin, stopped; bob 60 m north heading south at 2 m/s: inside the
//! // CPA range and on a collision course, so the alert turns on.
//! m.handle_mail(100.0, &[("NAV_X", Num(0.0)), ("NAV_Y", Num(0.0)),
//!     ("NODE_REPORT", Str("NAME=bob,X=0,Y=60,SPD=2,HDG=180,TIME=100,TYPE=kayak"))]);
//! let on = m.iterate(100.0).to_vec();
//! assert!(on.iter().any(|p| p.var == "CONTACT_INFO"));
//! // Bob stops being reported: at 61 s old (contact_max_age 60) the alert resolves.
//! let off = m.iterate(161.0);
//! assert!(off.iter().any(|p| p.var == "RESOLVED" && p.val.as_str() == Some("bob")));
//! ```

pub mod alert;
pub mod app;
pub mod appcast;
pub mod block;
pub mod config;
pub mod macros;
pub mod manager;
pub mod requests;
pub mod status;
pub mod table;
pub mod value;
pub mod warnings;

pub use alert::{Alert, AlertSet, AlertSpecError, Flag};
pub use config::{Config, ConfigError, LocalCoords};
pub use macros::expand;
pub use manager::{ContactManager, Geometry, Ownship, CPA_HORIZON};
pub use requests::{able_postings, Able, ReportRequest, RequestError};
pub use table::{Contact, Refused, Table};
pub use value::{MailValue, Posting, Value};
pub use warnings::Warnings;
