//! The in-process MOOS bus of `helm sim`: what a MOOSDB does, where the helm can tell.
//!
//! - Each client (the helm, the simulator) has its subscriptions and an inbox.
//! - A message posted at time `t` reaches the inbox of every client subscribed to its
//!   variable, the helm's own postings included (source = the app name, as the DB
//!   stamps them), and is fetched at the client's first tick strictly after `t`: mail
//!   arrives the next cycle, never in the cycle that posted it.
//! - Subscribing to a variable that has a value sends that value, as the MOOSDB does on
//!   registration (unless a newer one, posted in this step, is on its way anyway).
//! - Inboxes are in posting order, which is time order, so the helm's mail is sorted by
//!   time as CMOOSApp sorts it.
//! - Every message is also seen once by the [`Observer`] and, when asked, written to
//!   the `.alog` (pLogger's layout) and kept in memory.
//!
//! Host measurements (`PHELMIVP_PID`, `IVPHELM_CREATE_CPU`, `IVPHELM_LOOP_CPU`) are
//! posted as 0: they measure the machine, not the mission, and would make two runs'
//! logs differ.

use std::collections::{HashMap, HashSet};

use moos::alog::LineValue;

use super::observe::Observer;
use helm_cycle as cycle;
use helm_engine::posting::{Posting, Value};
use helm_engine::Mail;

/// Variables whose value is a measurement of the host, zeroed on the simulated bus.
pub const HOST_MEASUREMENTS: [&str; 3] = ["PHELMIVP_PID", "IVPHELM_CREATE_CPU", "IVPHELM_LOOP_CPU"];

/// One connected app.
#[derive(Debug, Default)]
pub struct Client {
    pub name: String,
    subs: HashSet<String>,
    inbox: Vec<Mail>,
}

/// The bus. Client 0 is the helm (the [`cycle::Bus`] side).
pub struct SimBus {
    pub clients: Vec<Client>,
    /// Posted in the current time step, delivered by [`SimBus::deliver`].
    staged: Vec<Mail>,
    pub observer: Observer,
    pub alog: Option<moos::alog::AlogWriter<std::io::BufWriter<std::fs::File>>>,
    /// Every message, when asked for (tests, replay).
    pub record: Option<Vec<Mail>>,
    /// The first alog write error (the run goes on; the error is reported at the end).
    pub alog_error: Option<std::io::Error>,
    /// Index of the helm among the clients.
    pub helm: usize,
    /// The latest value of every variable (sent on registration).
    last: HashMap<String, Mail>,
}

pub const HELM: usize = 0;

impl SimBus {
    pub fn new(names: &[&str], observer: Observer) -> SimBus {
        SimBus {
            clients: names
                .iter()
                .map(|n| Client {
                    name: n.to_string(),
                    ..Client::default()
                })
                .collect(),
            staged: Vec::new(),
            observer,
            alog: None,
            record: None,
            alog_error: None,
            helm: HELM,
            last: HashMap::new(),
        }
    }

    /// Connect one more app (e.g. a vehicle's pObstacleMgr); its index.
    pub fn add_client(&mut self, name: &str) -> usize {
        self.clients.push(Client {
            name: name.to_string(),
            ..Client::default()
        });
        self.clients.len() - 1
    }

    pub fn subscribe(&mut self, client: usize, var: &str) -> bool {
        let subs = &mut self.clients[client].subs;
        if subs.contains(var) {
            return false;
        }
        subs.insert(var.to_string());
        if !self.staged.iter().any(|m| m.var == var) {
            if let Some(m) = self.last.get(var) {
                self.clients[client].inbox.push(m.clone());
            }
        }
        true
    }

    /// Keep `var`'s latest value, reusing the previous one's storage.
    fn remember(&mut self, source: &str, var: &str, value: &Value, aux: &str, now: f64) {
        match self.last.get_mut(var) {
            Some(m) => {
                m.time = now;
                match (&mut m.value, value) {
                    (Value::Str(old), Value::Str(new)) => {
                        old.clear();
                        old.push_str(new);
                    }
                    (old, new) => *old = new.clone(),
                }
                m.source.clear();
                m.source.push_str(source);
                m.source_aux.clear();
                m.source_aux.push_str(aux);
            }
            None => {
                self.last.insert(
                    var.to_string(),
                    Mail {
                        var: var.to_string(),
                        value: value.clone(),
                        time: now,
                        source: source.to_string(),
                        source_aux: aux.to_string(),
                    },
                );
            }
        }
    }

    /// Whether anything on this bus ever reads `var`: an app subscribed to it, the
    /// `.alog`, the in-memory record, or an end condition on it. (The helm is asked
    /// after start-up, when every app has subscribed.)
    pub fn is_read(&self, var: &str) -> bool {
        self.alog.is_some() || self.wanted(var) || self.observer.when.iter().any(|w| w.var == var)
    }

    fn wanted(&self, var: &str) -> bool {
        self.record.is_some() || self.clients.iter().any(|c| c.subs.contains(var))
    }

    /// Post `var = value` from `source` (`aux` its source-aux) at `now`.
    pub fn post(&mut self, source: &str, var: &str, value: &Value, aux: &str, now: f64) {
        let zero = Value::Num(0.0);
        let value = if HOST_MEASUREMENTS.contains(&var) {
            &zero
        } else {
            value
        };
        self.observer.on_posting(var, value, now);
        self.remember(source, var, value, aux, now);
        if self.alog.is_some() {
            self.log(source, var, value, aux, now);
        }
        if self.wanted(var) {
            self.staged.push(Mail {
                var: var.to_string(),
                value: value.clone(),
                time: now,
                source: source.to_string(),
                source_aux: aux.to_string(),
            });
        }
    }

    fn log(&mut self, source: &str, var: &str, value: &Value, aux: &str, now: f64) {
        let Some(w) = &mut self.alog else { return };
        let value = match value {
            Value::Num(v) => LineValue::Double(*v),
            Value::Str(s) => LineValue::Text(s),
        };
        if let Err(e) = w.write_line(now, var, source, aux, value) {
            self.alog = None;
            self.alog_error = Some(e);
        }
    }

    /// End of a time step: what was posted in it reaches the subscribers' inboxes (the
    /// message itself goes to the last one, copies to the others).
    pub fn deliver(&mut self) {
        let mut staged = std::mem::take(&mut self.staged);
        for m in staged.drain(..) {
            let last = self.clients.iter().rposition(|c| c.subs.contains(&m.var));
            if let Some(last) = last {
                for c in &mut self.clients[..last] {
                    if c.subs.contains(&m.var) {
                        c.inbox.push(m.clone());
                    }
                }
            }
            match (&mut self.record, last) {
                (Some(r), Some(last)) => {
                    self.clients[last].inbox.push(m.clone());
                    r.push(m);
                }
                (Some(r), None) => r.push(m),
                (None, Some(last)) => self.clients[last].inbox.push(m),
                (None, None) => {}
            }
        }
        // Keep the buffer's capacity for the next step.
        self.staged = staged;
    }

    /// Move `client`'s mail into `out` (cleared first); the inbox keeps its capacity.
    pub fn fetch(&mut self, client: usize, out: &mut Vec<Mail>) {
        out.clear();
        std::mem::swap(&mut self.clients[client].inbox, out);
    }
}

impl cycle::Bus for SimBus {
    fn subscribe_new(&mut self, subs: &[String]) -> Vec<String> {
        let mut new = Vec::new();
        for var in subs {
            if self.subscribe(self.helm, var) {
                new.push(var.clone());
            }
        }
        new
    }

    fn publish(&mut self, p: &Posting, now: f64) {
        // The source is the helm's app name; taken out and back to satisfy the borrow.
        let name = std::mem::take(&mut self.clients[self.helm].name);
        self.post(&name, &p.var, &p.value, &p.source_aux, now);
        self.clients[self.helm].name = name;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use helm_cycle::Bus;

    #[test]
    fn a_variable_is_read_by_a_subscriber_a_record_or_an_end_condition() {
        let mut bus = SimBus::new(&["pHelmIvP", "uSimMarine"], Observer::default());
        assert!(!bus.is_read("BHV_IPF"));
        bus.subscribe(1, "BHV_IPF");
        assert!(bus.is_read("BHV_IPF"));
        let mut bus = SimBus::new(&["pHelmIvP"], Observer::default());
        bus.record = Some(Vec::new());
        assert!(bus.is_read("BHV_IPF"));
        let when = vec![crate::scenario::When {
            var: "BHV_IPF".into(),
            value: Value::Str("x".into()),
        }];
        let bus = SimBus::new(&["pHelmIvP"], Observer::new(0.0, when));
        assert!(bus.is_read("BHV_IPF") && !bus.is_read("DESIRED_SPEED"));
    }

    #[test]
    fn own_postings_come_back_next_step_to_subscribers_only() {
        let mut bus = SimBus::new(&["pHelmIvP", "uSimMarine"], Observer::default());
        assert_eq!(
            bus.subscribe_new(&["A".into(), "A".into()]),
            vec!["A".to_string()]
        );
        bus.subscribe(1, "B");
        bus.publish(
            &Posting {
                var: "A".into(),
                value: Value::Num(1.0),
                source_aux: String::new(),
            },
            5.0,
        );
        bus.post("uSimMarine", "B", &Value::Num(2.0), "", 5.0);
        let mut got = Vec::new();
        bus.fetch(0, &mut got);
        assert!(got.is_empty(), "nothing before the step ends");
        bus.deliver();
        bus.fetch(0, &mut got);
        assert_eq!(got.len(), 1);
        assert_eq!(
            (got[0].var.as_str(), got[0].source.as_str()),
            ("A", "pHelmIvP")
        );
        bus.fetch(1, &mut got);
        assert_eq!(got[0].var, "B");
        bus.fetch(1, &mut got);
        assert!(got.is_empty());
    }

    #[test]
    fn subscribing_sends_the_latest_value_once() {
        let mut bus = SimBus::new(&["pHelmIvP", "uSimMarine"], Observer::default());
        bus.post("uSimMarine", "X", &Value::Num(1.0), "", 1.0);
        bus.post("uSimMarine", "X", &Value::Num(2.0), "", 2.0);
        bus.deliver();
        bus.subscribe(0, "X");
        let mut got = Vec::new();
        bus.fetch(0, &mut got);
        assert_eq!((got.len(), &got[0].value), (1, &Value::Num(2.0)));
        // Posted in the same step as the subscription: delivered once, by the step.
        bus.subscribe(1, "Y");
        bus.post("pHelmIvP", "Z", &Value::Num(3.0), "", 3.0);
        bus.subscribe(1, "Z");
        bus.deliver();
        bus.fetch(1, &mut got);
        assert_eq!(got.len(), 1);
        assert_eq!(got[0].value, Value::Num(3.0));
    }

    #[test]
    fn host_measurements_are_zeroed() {
        let mut bus = SimBus::new(&["pHelmIvP"], Observer::default());
        bus.subscribe(0, "PHELMIVP_PID");
        bus.post("pHelmIvP", "PHELMIVP_PID", &Value::Num(4242.0), "", 1.0);
        bus.deliver();
        let mut got = Vec::new();
        bus.fetch(0, &mut got);
        assert_eq!(got[0].value, Value::Num(0.0));
    }
}
