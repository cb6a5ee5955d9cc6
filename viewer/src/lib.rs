//! `helm view`: a map of a MOOS-IvP mission in the browser — live from a MOOSDB, or
//! replaying an `.alog` (or a folder of runs) with a time slider.
//!
//! * [`view`], [`node`], [`feed`]: postings (VIEW_*, NODE_REPORT, APPCAST, DESIRED_*)
//!   read into what the page draws; [`frame`]: the message the page receives.
//! * [`alog_index`]: the tolerant `.alog` index of a replay; [`runs`]: run folders.
//! * [`live`]: the MOOS client side and the hub that throttles updates to viewers.
//! * [`server`]: HTTP (tiny_http), the page assets (compiled into the binary), the
//!   mission's buttons; [`ws`]: the live WebSocket (tungstenite); [`buttons`]: the
//!   mission's pMarineViewer buttons; [`cli`]: `helm view`.
//!
//! Depends on `moos` (client, mission reader), `geometry` (VIEW_* strings) and `mbutil`
//! (numbers, colours); it must not depend on the helm (the helm's binary depends on it).
//!
//! ```
//! let log = "%% LOGSTART 100\n1.0 NODE_REPORT_LOCAL pNodeReporter NAME=abe,X=5,Y=7,HDG=90\n";
//! let ix = viewer::alog_index::AlogIndex::read(log.as_bytes(), "ownship");
//! let frame = ix.frame(1.0);
//! assert_eq!((frame.vehicles[0].x, frame.vehicles[0].y), (5.0, 7.0));
//! ```
#![forbid(unsafe_code)]

pub mod alog_index;
pub mod buttons;
pub mod cli;
pub mod feed;
pub mod frame;
pub mod hosts;
pub mod live;
pub mod node;
pub mod runs;
pub mod server;
pub mod view;
pub mod ws;
