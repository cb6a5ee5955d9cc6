//! One helm cycle, shared by `helm run` (a MOOS client over sockets) and `helm sim` (an
//! in-process bus on a simulated clock): start-up, then per AppTick
//! mail → [`Helm::handle_mail`] → [`Helm::iterate`] → postings, with the subscriptions
//! kept in step with the helm's list. Both commands drive the helm through this and
//! nothing else, so what the helm decides cannot depend on which one runs it.

use super::status::Status;
use crate::posting::{Posting, Value};
use crate::{Helm, Mail};

/// Where the helm's postings go and how it subscribes.
pub trait Bus {
    /// Subscribe to the variables of `subs` not subscribed yet; returns the new ones.
    fn subscribe_new(&mut self, subs: &[String]) -> Vec<String>;
    /// Publish one posting of the helm, stamped `now`.
    fn publish(&mut self, p: &Posting, now: f64);
}

/// The helm's side of the loop and what the terminal and the stop rule remember.
#[derive(Debug, Default)]
pub struct HelmCycle {
    pub status: Status,
}

impl HelmCycle {
    /// Start-up at `now`: subscribe first, so the helm's own postings come back to it as
    /// mail, then publish the start-up postings.
    pub fn startup(helm: &mut Helm, bus: &mut impl Bus, now: f64) -> HelmCycle {
        let posts: Vec<Posting> = helm.startup(now).to_vec();
        let mut cycle = HelmCycle::default();
        cycle.subscribe_new(helm, bus, now);
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
        self.subscribe_new(helm, bus, now);
    }

    fn publish(&mut self, bus: &mut impl Bus, p: &Posting, now: f64) {
        bus.publish(p, now);
        self.status.on_posting(p, now);
    }

    fn subscribe_new(&mut self, helm: &Helm, bus: &mut impl Bus, now: f64) {
        for var in bus.subscribe_new(helm.subscriptions()) {
            let p = Posting {
                var: "IVPHELM_REGISTER".into(),
                value: Value::Str(var),
                source_aux: String::new(),
            };
            self.publish(bus, &p, now);
        }
    }
}
