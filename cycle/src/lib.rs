//! `helm-cycle`: one helm cycle, shared by `helm run` (a MOOS client over sockets) and
//! `helm sim` (an in-process bus on a simulated clock): start-up, then per AppTick
//! mail → [`Helm::handle_mail`] → [`Helm::iterate`] → postings, with the subscriptions
//! kept in step with the helm's list. Both commands drive the helm through this and
//! nothing else, so what the helm decides cannot depend on which one runs it. [`status`]
//! is what a run remembers of the traffic for its terminal lines and its stop rule.
//!
//! It may depend on `helm-engine` alone (it drives the engine through its public API);
//! it must not depend on MOOS, the app or the simulator, which depend on it.
//!
//! A cycle on a bus that only records (start-up, navigation mail, one decision):
//!
//! ```
//! use helm_cycle::{Bus, HelmCycle};
//! use helm_engine::config::{BlockLine, HelmConfig};
//! use helm_engine::factory::BehaviorFactory;
//! use helm_engine::posting::{Posting, Value};
//! use helm_engine::{Helm, Mail};
//!
//! #[derive(Default)]
//! struct Recorder { subscribed: Vec<String>, posted: Vec<Posting> }
//! impl Bus for Recorder {
//!     fn subscribe_new(&mut self, subs: &[String]) -> Vec<String> {
//!         let new: Vec<String> = subs.iter().filter(|v| !self.subscribed.contains(v)).cloned().collect();
//!         self.subscribed.extend(new.iter().cloned());
//!         new
//!     }
//!     fn publish(&mut self, p: &Posting, _now: f64) { self.posted.push(p.clone()); }
//! }
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
//! let mut bus = Recorder::default();
//! let mut cycle = HelmCycle::startup(&mut helm, &mut bus, 0.0);
//! assert!(bus.subscribed.iter().any(|v| v == "NAV_X"));
//! let nav = |var: &str| Mail {
//!     var: var.into(),
//!     value: Value::Num(0.0),
//!     time: 1.0,
//!     source: "uSimMarine".into(),
//!     source_aux: String::new(),
//! };
//! cycle.mail(&mut helm, 1.0, &["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"].map(nav));
//! cycle.iterate(&mut helm, &mut bus, 1.0);
//! let speed = bus.posted.iter().find(|p| p.var == "DESIRED_SPEED").unwrap();
//! assert_eq!(speed.value, Value::Num(2.0));
//! assert_eq!(cycle.status.iterations, 1);
//! ```

pub mod status;

use helm_engine::posting::{Posting, Value};
use helm_engine::{Helm, Mail};
use status::Status;

/// Where the helm's postings go and how it subscribes.
pub trait Bus {
    /// Subscribe to the variables of `subs` not subscribed yet; returns the new ones.
    fn subscribe_new(&mut self, subs: &[String]) -> Vec<String>;
    /// Publish one posting of the helm, stamped `now`.
    fn publish(&mut self, p: &Posting, now: f64);
    /// A registration round of the real helm (helm.md §4.1): every variable of `vars`
    /// registered again; returns those registered. By default only the new ones are
    /// subscribed, and all are announced.
    fn subscribe_again(&mut self, vars: &[String]) -> Vec<String> {
        self.subscribe_new(vars);
        vars.iter().filter(|v| !v.is_empty()).cloned().collect()
    }
}

/// The helm's side of the loop and what the terminal and the stop rule remember.
#[derive(Debug, Default)]
pub struct HelmCycle {
    pub status: Status,
    /// The first decision happened (it registers every info variable once more).
    decided: bool,
}

impl HelmCycle {
    /// Start-up at `now`: the helm's own variables are registered as at connection,
    /// then everything again at the end of start-up (helm.md §4.1), before the start-up
    /// postings, so the helm's own postings come back to it as mail.
    pub fn startup(helm: &mut Helm, bus: &mut impl Bus, now: f64) -> HelmCycle {
        let mut cycle = HelmCycle::default();
        let own = helm.helm_variables();
        cycle.register_round(bus, &own, now);
        let posts: Vec<Posting> = helm.startup(now).to_vec();
        let all = helm.subscriptions().to_vec();
        cycle.register_round(bus, &all, now);
        for p in &posts {
            cycle.publish(bus, p, now);
        }
        cycle
    }

    /// One batch of mail (already in time order), before the iteration.
    pub fn mail(&mut self, helm: &mut Helm, now: f64, mail: &[Mail]) {
        self.mail_parsed(helm, now, mail, &());
    }

    /// [`HelmCycle::mail`] with some contact reports already read (see
    /// [`Helm::handle_mail_parsed`]).
    pub fn mail_parsed(
        &mut self,
        helm: &mut Helm,
        now: f64,
        mail: &[Mail],
        parsed: &dyn contacts::report::ReadReports,
    ) {
        for m in mail {
            self.status.on_mail(m);
        }
        if !mail.is_empty() {
            helm.handle_mail_parsed(now, mail, parsed);
        }
    }

    /// One iteration: publish what the helm posts, then subscribe to new variables.
    pub fn iterate(&mut self, helm: &mut Helm, bus: &mut impl Bus, now: f64) {
        self.status.iterations += 1;
        for p in helm.iterate(now) {
            bus.publish(p, now);
            self.status.on_posting(p, now);
        }
        if !self.decided && helm.decision_timing().1 > 0 {
            self.decided = true;
            let info = helm.info_variables();
            self.register_round(bus, &info, now);
        }
        self.subscribe_new(helm, bus, now);
    }

    fn register_round(&mut self, bus: &mut impl Bus, vars: &[String], now: f64) {
        let done = bus.subscribe_again(vars);
        self.announce(bus, done, now);
    }

    fn publish(&mut self, bus: &mut impl Bus, p: &Posting, now: f64) {
        bus.publish(p, now);
        self.status.on_posting(p, now);
    }

    fn subscribe_new(&mut self, helm: &Helm, bus: &mut impl Bus, now: f64) {
        let new = bus.subscribe_new(helm.subscriptions());
        self.announce(bus, new, now);
    }

    fn announce(&mut self, bus: &mut impl Bus, vars: Vec<String>, now: f64) {
        for var in vars {
            let p = Posting {
                var: "IVPHELM_REGISTER".into(),
                value: Value::Str(var),
                source_aux: String::new(),
            };
            self.publish(bus, &p, now);
        }
    }
}
