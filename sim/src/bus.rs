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

use mbutil::short_str::{assign, same};
use moos::alog::LineValue;
use rustc_hash::FxHashMap;

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
    inbox: Vec<Mail>,
}

/// What the bus knows of one variable.
#[derive(Debug)]
struct Slot {
    /// Clients subscribed to it, in ascending index order (delivery order).
    subs: Vec<usize>,
    /// Its latest value (sent on registration).
    last: Option<Mail>,
}

/// The bus. Client 0 is the helm (the [`cycle::Bus`] side).
pub struct SimBus {
    pub clients: Vec<Client>,
    /// Posted in the current time step (with its variable's slot), delivered by
    /// [`SimBus::deliver`].
    staged: Vec<(usize, Mail)>,
    pub observer: Observer,
    pub alog: Option<moos::alog::AlogFile>,
    /// Every message, when asked for (tests, replay).
    pub record: Option<Vec<Mail>>,
    /// The first alog write error (the run goes on; the error is reported at the end).
    pub alog_error: Option<std::io::Error>,
    /// Index of the helm among the clients.
    pub helm: usize,
    /// Each variable's slot in `slots` (looked up once per posting; never iterated, so
    /// the hasher cannot order anything).
    index: FxHashMap<String, usize>,
    slots: Vec<Slot>,
    /// Fetched messages handed back, whose strings the next postings reuse.
    spare: Vec<Mail>,
    /// Value strings of spare messages reused for a number.
    spare_text: Vec<String>,
    /// The list the helm last subscribed to (all of it subscribed).
    helm_subs: Vec<String>,
    /// The slots of the helm's postings in one iteration, in posting order, and the
    /// place of the next posting: the helm posts much the same variables in the same
    /// order every iteration, so [`SimBus::publish`] tries the slot of the same place
    /// last time before looking the variable up.
    helm_posts: Vec<usize>,
    helm_post_at: usize,
}

/// Postings per helm iteration whose slots are remembered (the others are looked up).
const HELM_POSTS_KEPT: usize = 1024;

pub const HELM: usize = 0;

/// Overwrite `dst` with `var = value` (keeping `dst`'s string storage; a value string
/// it cannot use goes to `spare_text`, and comes from there when needed).
fn fill(dst: &mut Mail, spare_text: &mut Vec<String>, parts: (&str, &str, &Value, &str, f64)) {
    dst.var.clear();
    dst.var.push_str(parts.1);
    fill_but_var(dst, spare_text, parts);
}

/// [`fill`] of a message that already names `var` (a slot's latest value: the slot is
/// its variable's).
fn fill_but_var(
    dst: &mut Mail,
    spare_text: &mut Vec<String>,
    (source, var, value, aux, now): (&str, &str, &Value, &str, f64),
) {
    debug_assert_eq!(dst.var, var);
    dst.time = now;
    // A slot's latest value mostly has the same source, often the same aux and
    // value: those are not copied again (see `short_str::assign`).
    assign(&mut dst.source, source);
    assign(&mut dst.source_aux, aux);
    match (&mut dst.value, value) {
        (Value::Str(old), Value::Str(new)) => assign(old, new),
        (old @ Value::Num(_), Value::Str(new)) => {
            let mut s = spare_text.pop().unwrap_or_default();
            s.clear();
            s.push_str(new);
            *old = Value::Str(s);
        }
        (old, Value::Num(n)) => {
            if let Value::Str(s) = std::mem::replace(old, Value::Num(*n)) {
                spare_text.push(s);
            }
        }
    }
}

fn blank_mail() -> Mail {
    Mail {
        var: String::new(),
        value: Value::Num(0.0),
        time: 0.0,
        source: String::new(),
        source_aux: String::new(),
    }
}

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
            index: FxHashMap::default(),
            slots: Vec::new(),
            spare: Vec::new(),
            spare_text: Vec::new(),
            helm_subs: Vec::new(),
            helm_posts: Vec::new(),
            helm_post_at: 0,
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

    /// `var`'s slot, made on first sight.
    fn slot_of(&mut self, var: &str) -> usize {
        if let Some(&i) = self.index.get(var) {
            return i;
        }
        self.slots.push(Slot {
            subs: Vec::new(),
            last: None,
        });
        self.index.insert(var.to_string(), self.slots.len() - 1);
        self.slots.len() - 1
    }

    pub fn subscribe(&mut self, client: usize, var: &str) -> bool {
        let i = self.slot_of(var);
        let subs = &mut self.slots[i].subs;
        let Err(at) = subs.binary_search(&client) else {
            return false;
        };
        subs.insert(at, client);
        if !self.staged.iter().any(|(s, _)| *s == i) {
            if let Some(m) = &self.slots[i].last {
                self.clients[client].inbox.push(m.clone());
            }
        }
        true
    }

    /// Whether `client` is subscribed to `var`.
    pub fn subscribes(&self, client: usize, var: &str) -> bool {
        self.index
            .get(var)
            .is_some_and(|&i| self.slots[i].subs.binary_search(&client).is_ok())
    }

    /// Whether anything on this bus ever reads `var`: an app subscribed to it, the
    /// `.alog`, the in-memory record, or an end condition on it. (The helm is asked
    /// after start-up, when every app has subscribed.)
    pub fn is_read(&self, var: &str) -> bool {
        self.alog.is_some()
            || self.record.is_some()
            || self
                .index
                .get(var)
                .is_some_and(|&i| !self.slots[i].subs.is_empty())
            || self.observer.when.iter().any(|w| w.var == var)
    }

    /// `var`'s place on the bus, for [`SimBus::post_at`]: an app that posts the same
    /// variables every step (the simulator's navigation) looks them up once.
    pub fn place(&mut self, var: &str) -> usize {
        self.slot_of(var)
    }

    /// Post `var = value` from `source` (`aux` its source-aux) at `now`.
    pub fn post(&mut self, source: &str, var: &str, value: &Value, aux: &str, now: f64) {
        let i = self.slot_of(var);
        self.post_at(i, source, var, value, aux, now);
    }

    /// [`SimBus::post`] of `var`, whose place `i` is known ([`SimBus::place`]).
    pub fn post_at(
        &mut self,
        i: usize,
        source: &str,
        var: &str,
        value: &Value,
        aux: &str,
        now: f64,
    ) {
        debug_assert_eq!(self.index.get(var), Some(&i));
        let zero = Value::Num(0.0);
        let value = if HOST_MEASUREMENTS.contains(&var) {
            &zero
        } else {
            value
        };
        self.observer.on_posting(var, value, now);
        let parts = (source, var, value, aux, now);
        // Keep `var`'s latest value, reusing the previous one's storage.
        let slot = &mut self.slots[i];
        match &mut slot.last {
            Some(m) => fill_but_var(m, &mut self.spare_text, parts),
            None => {
                slot.last = Some(Mail {
                    var: var.to_string(),
                    value: value.clone(),
                    time: now,
                    source: source.to_string(),
                    source_aux: aux.to_string(),
                })
            }
        }
        let wanted = self.record.is_some() || !slot.subs.is_empty();
        if self.alog.is_some() {
            self.log(source, var, value, aux, now);
        }
        if wanted {
            let mut m = self.spare.pop().unwrap_or_else(blank_mail);
            fill(&mut m, &mut self.spare_text, parts);
            self.staged.push((i, m));
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

    /// A copy of `m` in a spare message's storage.
    fn copy(spare: &mut Vec<Mail>, spare_text: &mut Vec<String>, m: &Mail) -> Mail {
        let mut c = spare.pop().unwrap_or_else(blank_mail);
        let parts = (
            m.source.as_str(),
            m.var.as_str(),
            &m.value,
            m.source_aux.as_str(),
            m.time,
        );
        fill(&mut c, spare_text, parts);
        c
    }

    /// End of a time step: what was posted in it reaches the subscribers' inboxes (the
    /// message itself goes to the last one, copies to the others).
    pub fn deliver(&mut self) {
        let mut staged = std::mem::take(&mut self.staged);
        for (i, m) in staged.drain(..) {
            let subs = &self.slots[i].subs;
            let last = subs.last().copied();
            if let Some((_, others)) = subs.split_last() {
                for &c in others {
                    let copy = Self::copy(&mut self.spare, &mut self.spare_text, &m);
                    self.clients[c].inbox.push(copy);
                }
            }
            match (&mut self.record, last) {
                (Some(r), Some(last)) => {
                    self.clients[last].inbox.push(m.clone());
                    r.push(m);
                }
                (Some(r), None) => r.push(m),
                (None, Some(last)) => self.clients[last].inbox.push(m),
                (None, None) => self.spare.push(m),
            }
        }
        // Keep the buffer's capacity for the next step.
        self.staged = staged;
    }

    /// Move `client`'s mail into `out`; what `out` held is handed back to the bus, whose
    /// next postings reuse its storage; the inbox keeps `out`'s capacity.
    pub fn fetch(&mut self, client: usize, out: &mut Vec<Mail>) {
        self.spare.append(out);
        std::mem::swap(&mut self.clients[client].inbox, out);
    }
}

impl cycle::Bus for SimBus {
    fn subscribe_new(&mut self, subs: &[String]) -> Vec<String> {
        // Called at the end of every iteration: the next posting is the next one's first.
        self.helm_post_at = 0;
        // The helm hands over its whole list every iteration. Every variable of the
        // list handled last is subscribed (and stays so): the same list again has
        // nothing new, and comparing it costs less than looking each one up.
        let kept = &self.helm_subs;
        if kept.len() == subs.len() && kept.iter().zip(subs).all(|(a, b)| same(a, b)) {
            return Vec::new();
        }
        let mut new = Vec::new();
        for var in subs {
            if self.subscribe(self.helm, var) {
                new.push(var.clone());
            }
        }
        self.helm_subs.clear();
        self.helm_subs.extend_from_slice(subs);
        new
    }

    fn publish(&mut self, p: &Posting, now: f64) {
        let j = self.helm_post_at;
        self.helm_post_at += 1;
        // A remembered slot is one posted to, so it has a latest value naming its variable.
        let i = match self.helm_posts.get(j) {
            Some(&i) if (self.slots[i].last.as_ref()).is_some_and(|m| same(&m.var, &p.var)) => i,
            _ => {
                let i = self.slot_of(&p.var);
                if let Some(kept) = self.helm_posts.get_mut(j) {
                    *kept = i;
                } else if j < HELM_POSTS_KEPT {
                    self.helm_posts.push(i);
                }
                i
            }
        };
        // The source is the helm's app name; taken out and back to satisfy the borrow.
        let name = std::mem::take(&mut self.clients[self.helm].name);
        self.post_at(i, &name, &p.var, &p.value, &p.source_aux, now);
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
