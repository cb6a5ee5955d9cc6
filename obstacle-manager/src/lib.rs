//! `obstacle-manager`: pObstacleMgr's behaviour as a pure library (specs: obstacles.md
//! §2) — given obstacles (`given_obstacle` lines, `GIVEN_OBSTACLE` mail with its
//! duration limit), tracked points grouped by key into clusters and their convex (or
//! lasso) hulls, time-outs and the `OBM_RESOLVED` resolution, the alert protocol with
//! the helm (`OBM_ALERT_REQUEST` in, the update strings the helm's spawn mechanism
//! reads out, and the general alert), `OBM_DIST_TO_OBJ`, `OBM_MIN_DIST_EVER`, the hull
//! drawings, the disable/enable/expunge relays and the flags.
//!
//! Beside it, for simulators: [`obstacle_sim`] reads uFldObstacleSim's obstacle file
//! (§3.2, every bad line a `file:line` error) and makes its postings (§3.5), and
//! [`collision`] counts encounters, near misses and collisions as uFldCollObDetect
//! does (§4).
//!
//! Driven like the helm engine: [`ObstacleManager::handle_mail`] with a batch of
//! `(variable, value)` pairs and a time, then [`ObstacleManager::iterate`], which
//! returns the postings. No sockets, clocks or threads; the `obstaclemgr` binary
//! (`src/bin/obstaclemgr.rs`, the only user of `moos` here) runs it as a MOOS app.
//!
//! Depends on `geometry` (polygons), `mbutil`, `moos-mission` (number format) and
//! `contact-manager` (the mail/posting/warning types the two managers share); it must
//! not depend on the helm crates, `behavior-api` or any plugin.
//!
//! ```
//! use obstacle_manager::{Config, ObstacleManager, MailValue::{Num, Str}};
//! let mut m = ObstacleManager::new(Config::default(), 1000.0);
//! // The helm's V24 template asks for alerts; an obstacle 14 m ahead is given.
//! m.handle_mail(1000.0, &[
//!     ("NAV_X", Num(46.0)), ("NAV_Y", Num(0.0)),
//!     ("OBM_ALERT_REQUEST", Str("name=avd_ob_,update_var=OBSTACLE_ALERT,alert_range=15")),
//!     ("GIVEN_OBSTACLE", Str("pts={60,-12:60,6:80,6:80,-12},label=oba,duration=30")),
//! ]);
//! let p = m.iterate(1000.0);
//! assert!(p.iter().any(|p| p.var == "OBSTACLE_ALERT"
//!     && p.val.as_str() == Some("name=avd_ob_oba#poly=pts={60,-12:60,6:80,6:80,-12},label=oba#id=oba")));
//! // Not given again: 31 s later it times out and is resolved.
//! let p = m.iterate(1031.0);
//! assert!(p.iter().any(|p| p.var == "OBM_RESOLVED" && p.val.as_str() == Some("oba")));
//! ```

pub mod able;
pub mod alert;
pub mod appcast;
pub mod collision;
pub mod config;
pub mod flags;
pub mod hull;
pub mod manager;
pub mod obstacle;
pub mod obstacle_sim;

pub use alert::{AlertRequest, RequestError};
pub use collision::{CollisionConfig, CollisionDetector, PairStats};
pub use config::{Config, ConfigError, DistPolicy};
pub use contact_manager::{MailValue, Posting, Value, Warnings};
pub use flags::{Flag, FlagError, MailFlag};
pub use manager::{Counts, ObstacleManager};
pub use obstacle::{Given, GivenError, Obstacle, PointError, Source, TrackedPoint};
pub use obstacle_sim::{ObstacleFile, ObstacleFileError, ObstacleSim, SimConfig, SimVehicle};
