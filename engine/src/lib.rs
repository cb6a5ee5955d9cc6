//! `helm-engine`: the IvP Helm itself, as a library driven from outside.
//!
//! A caller hands it mail and a time and takes its postings; it never reads a socket, a
//! wall clock or a thread of its own, and knows nothing of simulation. The MOOS app
//! (`helm-app`), the simulator (`helm-sim`) and the conformance runner (`helm-conform`) all
//! drive it the same way, through `helm_cycle::HelmCycle` (the `helm-cycle` crate) or
//! [`Helm`] directly.
//!
//! It may depend on `behavior-api`, `behaviors-std`, `bhv`, `ivp` and `contacts`. It must
//! not depend on MOOS (client, DB or files), the app or the simulator; a test in
//! `helm/tests/layout.rs` checks that. Reading a whole mission from files is
//! `helm-mission`'s work.
//!
//! Where things are:
//! - the pHelmIvP block is read in [`config`], a whole mission (`.moos` + `.bhv` files +
//!   behavior libraries) in the `helm-mission` crate; a `.bhv` line in the `bhv` crate;
//! - the contact ledger (from the `contacts` crate) is fed in `engine::mail` and
//!   maintained once per iteration in `engine::iterate`;
//! - behaviors come from [`factory`] (built-in) and [`loader`] (shared libraries, the
//!   `behavior-loader` crate);
//! - a behavior is called in [`runtime`] (`runtime::step`, one behavior's part in one
//!   iteration), built-in and plugin alike through `behavior-api`;
//! - a decision is made in [`engine`]: `Helm::handle_mail` → `Helm::iterate` (modes,
//!   behaviors, `decide` with `ivp_solver::Solver`, postings), with spawning and reports;
//! - one helm cycle as every driver runs it, and what a run remembers for its terminal
//!   and its end, are the `helm-cycle` crate's.
//! - conformance cases are replayed by the `helm-conform` crate.
//!
//! One decision, driven by hand: a block, a `.bhv`, navigation mail, and the postings:
//!
//! ```
//! use helm_engine::config::{BlockLine, HelmConfig};
//! use helm_engine::factory::BehaviorFactory;
//! use helm_engine::posting::Value;
//! use helm_engine::{Helm, Mail};
//!
//! let line = |name: &str, value: &str| BlockLine { line: 1, name: name.into(), value: value.into() };
//! let (config, _) = HelmConfig::from_lines(&[
//!     line("domain", "course:0:359:360"),
//!     line("domain", "speed:0:4:41"),
//!     line("start_in_drive", "true"),
//! ]);
//! let bhv = "Behavior = BHV_Waypoint\n{\n  name = go\n  points = 0,50:0,100\n  speed = 2\n}\n";
//! let spec = bhv::reader::parse_str(bhv, std::path::Path::new("doc.bhv")).unwrap();
//! let mut helm = Helm::new(config, spec, &BehaviorFactory::with_builtins(), "doc", vec![]);
//! helm.startup(0.0);
//! let nav = |var: &str| Mail {
//!     var: var.into(),
//!     value: Value::Num(0.0),
//!     time: 1.0,
//!     source: "uSimMarine".into(),
//!     source_aux: String::new(),
//! };
//! helm.handle_mail(1.0, &["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"].map(nav));
//! // The first decision comes a second after start-up, as in the C++ helm.
//! let postings = helm.iterate(1.0);
//! let speed = postings.iter().find(|p| p.var == "DESIRED_SPEED").unwrap();
//! assert_eq!(speed.value, Value::Num(2.0));
//! ```

pub use helm_config as config;
pub mod engine;
pub mod factory;
pub mod info_buffer;
pub use behavior_loader as loader;
pub mod posting;
pub mod run_warnings;
pub mod runtime;

pub use engine::{Helm, HelmState, Mail};
