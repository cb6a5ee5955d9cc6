//! One helm cycle, shared by `helm run` (a MOOS client over sockets) and `helm sim` (an
//! in-process bus on a simulated clock): start-up, then per AppTick
//! mail → [`Helm::handle_mail`] → [`Helm::iterate`] → postings, with the subscriptions
//! kept in step with the helm's list. Both commands drive the helm through this and
//! nothing else, so what the helm decides cannot depend on which one runs it.

use crate::posting::{Posting, Value};
use crate::status::Status;
use crate::{Helm, Mail};

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
        for m in mail {
            self.status.on_mail(m);
        }
        if !mail.is_empty() {
            helm.handle_mail(now, mail);
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
