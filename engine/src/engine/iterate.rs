//! One helm iteration (helm.md §6), the decision (§7) and the all-stop logic (§9).

use std::sync::Arc;

use behavior_api::FunctionData;
use ivp_solver::{CheckedFunction, FunctionView, PieceBuffers};

use super::{Helm, HelmState};
use crate::posting::{Posting, Value};
use crate::runtime::step;

/// The run warning while NAV_* are missing after `nav_grace` (retracted once they come).
const NAV_WAIT: &str = "Waiting for Helm Nav Solution";

/// One iteration in this many times each behavior (see `Helm::decide`).
const BEHAVIOR_TIMING_EVERY: u64 = 8;

/// What the decision step produced, for the all-stop evaluation.
#[derive(Debug, Default)]
pub(crate) struct DecisionSummary {
    pub halted: Option<String>,
    pub functions: usize,
    pub solved: bool,
    /// Seconds spent building the functions (behaviors) and solving.
    pub create_secs: f64,
    pub solve_secs: f64,
    /// The whole decision step.
    pub took: std::time::Duration,
}

/// `(last, max)` with a new last value.
fn last_and_max(pair: &mut (f64, f64), last: f64) {
    *pair = (last, pair.1.max(last));
}

impl Helm {
    fn enabled(&self) -> bool {
        matches!(self.state, HelmState::Park | HelmState::Drive)
    }

    fn nav_ready(&self) -> bool {
        let mut ok = ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]
            .iter()
            .all(|v| self.ib.is_known(v));
        if self.config.domain.index_of("depth").is_some() {
            ok &= self.ib.is_known("NAV_DEPTH");
        }
        ok
    }

    /// One iteration at MOOS time `now`: returns what the helm publishes, including
    /// what it posted while handling this cycle's mail (a skew report, the all-stop of
    /// a helm disabled by its standby), as the real helm posts those at once.
    pub fn iterate(&mut self, now: f64) -> &[Posting] {
        self.fresh_outbox();
        self.iterate_steps(now);
        self.outbox_taken = true;
        &self.outbox
    }

    /// Start a new batch of postings once the last one was handed out.
    pub(crate) fn fresh_outbox(&mut self) {
        if std::mem::take(&mut self.outbox_taken) {
            for p in self.outbox.drain(..) {
                self.pool.give(p.var);
                self.pool.give(p.source_aux);
                crate::posting::give_value(&mut self.pool, p.value);
            }
        }
    }

    fn iterate_steps(&mut self, now: f64) {
        self.iteration += 1;
        if !self.mail_this_cycle {
            self.ib.set_curr_time(now);
        }
        self.mail_this_cycle = false;
        if let Some(kind) = self.restart.take() {
            self.restart_behaviors(now, &kind);
        }
        // Helm-start messages held back until every `hold_on_apps` app is connected.
        if !self.startup_messages.is_empty() && self.hold_apps_seen() {
            self.retract_run_warning(super::mail::HOLD_WAIT);
            for (var, value) in std::mem::take(&mut self.startup_messages) {
                self.ib.set_value(&var, &value, now);
                self.post(&var, value, "HELM_STARTUP_MSG");
            }
        }

        // Status update (§3).
        if self.enabled() {
            self.state = if self.has_control {
                HelmState::Drive
            } else {
                HelmState::Park
            };
        }
        let mut state = self.pool.take();
        state.push_str(self.state.as_str());
        if self.config.standby.is_some() && self.enabled() {
            state.push('+');
        }
        if self.state == HelmState::Disabled {
            self.post_on_change("IVPHELM_STATE", Value::Str(state));
        } else {
            self.post("IVPHELM_STATE", Value::Str(state), "");
        }
        if !self.enabled() {
            self.ib.clear_deltas();
            return;
        }
        if !self.nav_ready() {
            if now - self.start_time > self.config.nav_grace && !self.nav_warned {
                self.nav_warned = true;
                self.run_warning(NAV_WAIT);
            }
            return;
        }
        if self.nav_warned {
            self.nav_warned = false;
            self.retract_run_warning(NAV_WAIT);
        }
        self.maintain_ledger(now);
        if self.helm_state_seen && !self.deferred_done {
            self.deferred_done = true;
            for i in 0..self.inits.len() {
                let init = &self.inits[i];
                if !init.deferred || self.ib.is_known(&init.var) {
                    continue;
                }
                let (var, value) = (init.var.clone(), init.value.clone());
                self.ib.set_value(&var, &value, now);
                self.post(&var, value, "HELM_VAR_INIT");
            }
        }
        if self.state == HelmState::Park {
            self.all_stop("ManualOverride");
            self.ib.clear_deltas();
            return;
        }
        if now - self.start_time < 1.0 {
            return;
        }
        if std::mem::take(&mut self.restarted) {
            self.post_str("IVPHELM_RESTARTED", "true");
        }
        self.post_turn_rate(now);

        let summary = self.decide(now, std::time::Instant::now());
        let took = summary.took;
        self.last_decide_secs = took.as_secs_f64();
        self.decide_time += took;
        self.decide_count += 1;
        last_and_max(&mut self.report.loop_secs, self.last_decide_secs);
        last_and_max(&mut self.report.create_secs, summary.create_secs);
        last_and_max(&mut self.report.solve_secs, summary.solve_secs);
        self.report.halted = summary.halted.is_some();
        self.report.functions = summary.functions;

        let results: Vec<String> = self
            .behaviors
            .iter_mut()
            .flat_map(|b| std::mem::take(&mut b.core.update_results))
            .collect();
        for r in results {
            self.post_str("IVPHELM_UPDATE_RESULT", &r);
        }
        if self.refresh_pending && now - self.last_refresh > 2.0 {
            self.filter.clear();
            self.last_refresh = now;
            self.refresh_pending = false;
        }
        let sig = self.subscription_signature();
        if sig != self.subs_signature {
            self.subs_signature = sig;
            self.register_all();
            self.statevars_dirty = true;
        }
        self.publish_behavior_output(now);
        self.post_summary(now, &summary);
        self.post_num("IVPHELM_IPF_CNT", summary.functions as f64);
        self.post_num("IVPHELM_TOTAL_PCS_FORMED", self.pieces_total() as f64);
        self.post_num("IVPHELM_TOTAL_PCS_CACHED", 0.0);
        self.post_num("IVPHELM_CREATE_CPU", summary.create_secs);
        self.post_num("IVPHELM_LOOP_CPU", self.last_decide_secs);
        self.publish_behavior_lists();
        self.decide_all_stop(&summary);
        if self.config.park_on_allstop
            && self.config.allow_park
            && !self.allstop.eq_ignore_ascii_case("clear")
        {
            self.has_control = false;
        }
        self.ib.clear_deltas();
    }

    /// Changes whenever a behavior could need a new subscription (new behavior, new
    /// info variable, condition or flag through an update): registering is then redone.
    fn subscription_signature(&self) -> usize {
        self.behaviors
            .iter()
            .map(|b| {
                1 + b.core.info_vars.len()
                    + b.core.conditions.len()
                    + b.core.flags.all().iter().map(|l| l.len()).sum::<usize>()
                    + usize::from(!b.core.updates_var.is_empty())
                    + usize::from(b.core.duration_reset.is_some())
            })
            .sum()
    }

    /// The ledger step of every iteration past the nav hold, PARK and warm-up included
    /// (contacts-appcast.md §2.4): stale contacts out, the snapshot behaviors will read,
    /// `IVPHELM_CONTACT_SUMMARY` (while a behavior has a contact) and
    /// `IVPHELM_LEDGER_SUMMARY`.
    fn maintain_ledger(&mut self, now: f64) {
        // Field by field, so the summaries go straight from the ledger into the posting
        // (no extra copy each iteration).
        let (ledger, outbox, pool) = (&mut self.env.ledger, &mut self.outbox, &mut self.pool);
        let mut post = |outbox: &mut Vec<Posting>, var: &str, text: &str| {
            outbox.push(Posting {
                var: pool.copy_of(var),
                value: Value::Str(pool.copy_of(text)),
                source_aux: String::new(),
            })
        };
        ledger.maintain(now);
        let keep = self.behaviors.iter().map(|b| b.core.contact.as_str());
        if let Some(kept) = ledger.contact_summary(keep) {
            post(outbox, "IVPHELM_CONTACT_SUMMARY", kept);
        }
        post(outbox, "IVPHELM_LEDGER_SUMMARY", ledger.summary());
    }

    fn post_turn_rate(&mut self, now: f64) {
        let h = self.ib.dval("NAV_HEADING").unwrap_or(0.0);
        self.turn_samples.push((now, h));
        self.turn_samples.retain(|(t, _)| now - t <= 5.0);
        let n = self.turn_samples.len();
        let mut rate = 0.0;
        if n > 1 {
            let mut sum = 0.0;
            for w in self.turn_samples.windows(2) {
                let mut d = w[1].1 - w[0].1;
                if d > 180.0 {
                    d -= 360.0;
                } else if d < -180.0 {
                    d += 360.0;
                }
                sum += d;
            }
            rate = sum / (n - 1) as f64;
        }
        self.post_num("TURN_RATE", rate);
    }

    /// The engine iteration (§7): modes, behaviors, solve. A clock reading at each end
    /// and one after creation (tens of nanoseconds each on a virtual machine).
    fn decide(&mut self, now: f64, started: std::time::Instant) -> DecisionSummary {
        self.env.helm_iteration += 1;
        let iter = self.env.helm_iteration;
        let mut summary = DecisionSummary::default();
        self.process_spawns(now);

        // Modes, before any behavior runs: copied into the kept pairs (their strings
        // reused), each set as a number if it reads as one, else as a string.
        copy_pairs(&mut self.mode_pairs, self.modes.evaluate(&self.ib));
        for (var, val) in &self.mode_pairs {
            match mbutil::parse_number(val) {
                Some(n) => self.ib.set_double(var, n, now),
                None => self.ib.set_string(var, val, now),
            }
        }

        // Last iteration's functions: their storage goes to this iteration's builders.
        for (name, f) in self.functions.drain(..) {
            self.pool.give(name);
            self.fn_slots.push(recycle(f));
        }
        // A behavior's function lands in a kept box (`step` writes it there) and moves
        // on as the box: a pointer, not the buffers' headers, copied at each step.
        let mut fd = self.fn_slots.pop().unwrap_or_default();
        let mut t = started; // a behavior's end is the next one's start

        // Each behavior's own time (the appcast's `cpu=`, a display value) is taken on
        // one iteration in eight (the first included): on the others the creation costs
        // one clock reading instead of one per behavior.
        let each = iter % BEHAVIOR_TIMING_EVERY == 1;
        for i in 0..self.behaviors.len() {
            step(&mut self.behaviors[i], &self.env, &self.ib, &mut fd);
            if fd.is_some() {
                let fd = std::mem::replace(&mut fd, self.fn_slots.pop().unwrap_or_default());
                let name = self.pool.copy_of(&self.behaviors[i].core.name);
                let core = &mut self.behaviors[i].core;
                match place(core, fd, &self.config.domain, name, &mut self.functions) {
                    // BHV_IPF shows the function before normalization, pwt apart.
                    Ok(()) => self.post_ipf(i),
                    Err(msg) => {
                        summary.halted = Some(msg.clone());
                        crate::runtime::fault(&mut self.behaviors[i].core, &msg);
                        break;
                    }
                }
            }
            if each {
                let start = std::mem::replace(&mut t, std::time::Instant::now());
                self.behaviors[i].core.step_secs = (t - start).as_secs_f64();
            }
            if !self.behaviors[i].core.ok {
                let msgs = &self.behaviors[i].core.messages;
                let last = msgs.iter().rev().find(|m| m.var == "BHV_ERROR");
                let last = last.and_then(|m| match &m.value {
                    Value::Str(s) => Some(s.clone()),
                    Value::Num(_) => None,
                });
                let text = self.ib.sval("BHV_ERROR").map(str::to_string).or(last);
                let text = text.unwrap_or_else(|| " - unknown - ".into());
                summary.halted = Some(format!("BHV_ERROR: {text}"));
                break;
            }
        }
        self.fn_slots.push(fd);
        summary.functions = self.functions.len();
        if summary.halted.is_some() || !each {
            // The creation ends now: behaviors not timed one by one on this iteration,
            // or a placement error that left its behavior untimed.
            t = std::time::Instant::now();
        }
        summary.took = t - started;
        summary.create_secs = summary.took.as_secs_f64();
        if summary.halted.is_some() || self.functions.is_empty() {
            return summary;
        }
        let solving = t;
        self.functions
            .sort_by(|a, b| a.0.as_bytes().cmp(b.0.as_bytes()));
        // The list of views lives in last iteration's allocation.
        let mut views = reuse_views(std::mem::take(&mut self.function_refs));
        views.extend(self.functions.iter().map(|(_, f)| f.view()));
        match self
            .solver
            .solve_views_into(&self.config.domain, &views, &mut self.decision)
        {
            Ok(found) => summary.solved = found,
            Err(e) => summary.halted = Some(e.to_string()),
        }
        self.function_refs = reuse_views(views);
        // The whole step: the creation's and the solve's nanoseconds (a subtraction less).
        let solve = std::time::Instant::now() - solving;
        summary.solve_secs = solve.as_secs_f64();
        summary.took += solve;
        summary
    }

    /// BHV_IPF (behavior-common.md §4 step 10.7): the last function placed, formatted
    /// into behavior `i`'s kept text (here, before the solve changes the function) and
    /// queued as its message; the text is split into packets when the message is
    /// published (helm.md §8.3), as the real helm does.
    fn post_ipf(&mut self, i: usize) {
        let (Some((_, f)), false) = (self.functions.last(), self.ipf_off) else {
            return;
        };
        let f = f.view();
        // The function's context, `iteration:behavior`, is written with the packets.
        let source = ivp_ipf::IpfSource {
            context: "",
            domain: f.domain(),
            pwt: f.pwt(),
            gelbox: f.gelbox(),
            bounds: f.bounds(),
            weights: f.weights(),
        };
        let core = &mut self.behaviors[i].core;
        core.ipf_kept.keep(&source);
        core.messages.push(crate::runtime::Message {
            var: self.pool.copy_of("BHV_IPF"),
            value: Value::Str(String::new()),
            key: String::new(), // unread: BHV_IPF skips the duplicate filter
            helm_ipf: true,
        });
    }

    /// §9.1: all-stop or the decision.
    fn decide_all_stop(&mut self, s: &DecisionSummary) {
        let mut msg = std::borrow::Cow::Borrowed("clear");
        if s.halted.is_some() {
            msg = "BehaviorError".into();
        } else if s.functions == 0 {
            // Every behavior we run is a goal behavior (none is a constraint), so with
            // goals_mandatory "no active goal" is exactly this case, and NothingToDo
            // comes first in the spec's order.
            msg = "NothingToDo".into();
        } else if (0..self.config.domain.size()).any(|i| self.missing_decision(i)) || !s.solved {
            let missing: Vec<String> = (0..self.config.domain.size())
                .filter(|&i| self.missing_decision(i))
                .map(|i| self.config.domain.var(i).name.clone())
                .collect();
            let text = format!("MissingDecVars:{}", missing.join(","));
            self.post_str("BHV_ERROR", &text);
            msg = text.into();
        }
        if msg != "clear" {
            self.all_stop(&msg);
            return;
        }
        self.all_stop("clear");
        for i in 0..self.config.domain.size() {
            if let Some(v) = self.decision.values.get(i).copied().flatten() {
                let var = self.pool.copy_of(&self.desired_names[i].0);
                let source_aux = String::new();
                self.outbox.push(Posting {
                    var,
                    value: Value::Num(v),
                    source_aux,
                });
            }
        }
    }

    /// A decision variable that is not optional and got no value.
    fn missing_decision(&self, i: usize) -> bool {
        !self.config.optional.get(i).copied().unwrap_or(false)
            && self.decision.values.get(i).copied().flatten().is_none()
    }

    /// §9.2: the all-stop routine.
    pub(crate) fn all_stop(&mut self, m: &str) {
        if !self.enabled() || m == self.allstop {
            return;
        }
        if !m.is_empty() {
            self.allstop = m.to_string();
        }
        if m == "NothingToDo" || m.starts_with("MissingDecVars") {
            self.no_decision_count += 1;
        } else {
            self.no_decision_count = 0;
        }
        if m == "NoGoalBehavior" {
            self.no_goal_count += 1;
        } else {
            self.no_goal_count = 0;
        }
        let current = self.allstop.clone();
        self.post_str("IVPHELM_ALLSTOP", &current);
        if current.eq_ignore_ascii_case("clear") {
            return;
        }
        if self.no_decision_count == 1 {
            self.allstop = "IncompleteOrEmptyDecision".into();
            return;
        }
        if self.no_goal_count == 1 {
            self.allstop = "NoActiveGoalBehavior".into();
            return;
        }
        for i in 0..self.config.domain.size() {
            let var = self.desired_names[i].1.clone();
            self.post_num(&var, 0.0);
        }
    }
}

/// An empty list of function views in `v`'s allocation (the solver's input is
/// rebuilt every iteration; collecting in place keeps the buffer).
fn reuse_views<'b>(mut v: Vec<FunctionView<'_>>) -> Vec<FunctionView<'b>> {
    v.clear();
    v.into_iter().map(|_| unreachable!("cleared")).collect()
}

/// `DESIRED_<UPPER(name)>`, with course published as heading.
pub(crate) fn desired_var(prefix: &str, name: &str) -> String {
    let up = name.to_ascii_uppercase();
    let shown: &str = if up == "COURSE" { "HEADING" } else { &up };
    format!("{prefix}DESIRED_{shown}")
}

/// `to` made equal to `from`, its strings' room reused.
fn copy_pairs(to: &mut Vec<(String, String)>, from: &[(String, String)]) {
    to.truncate(from.len());
    for ((a, b), (x, y)) in to.iter_mut().zip(from) {
        a.clone_from(x);
        b.clone_from(y);
    }
    let have = to.len();
    to.extend_from_slice(&from[have..]);
}

/// A behavior's function of this iteration, read in place where its behavior built it
/// (copying it would cost more than the solve of a big one) until the next decision
/// hands it back.
pub(crate) type HelmFunction = CheckedFunction<AbiFunction>;

/// A behavior's function in its kept box (always `Some` once placed).
pub(crate) type FunctionSlot = Box<Option<FunctionData>>;

/// A behavior's function as it crossed the ABI, read in place, and its recycler.
#[derive(Debug)]
pub(crate) struct AbiFunction(FunctionSlot, Option<behavior_api::FunctionRecycler>);

impl AbiFunction {
    fn data(&self) -> Option<&FunctionData> {
        self.0.as_ref().as_ref()
    }
}

impl PieceBuffers for AbiFunction {
    fn bounds(&self) -> &[i32] {
        self.data().map_or(&[], |f| &f.bounds)
    }
    fn weights(&self) -> &[f64] {
        self.data().map_or(&[], |f| &f.weights)
    }
    fn gelbox(&self) -> &[u32] {
        self.data().map_or(&[], |f| &f.gelbox)
    }
    fn grid(&self) -> &[f64] {
        self.data().map_or(&[], |f| &f.grid)
    }
    fn pwt(&self) -> f64 {
        self.data().map_or(0.0, |f| f.pwt)
    }
}

/// Storage back to whoever made it: the host's spares or the library's, for the next
/// build (a library older than the recycler frees it here, through its own allocator).
/// The emptied box is kept for a later function.
fn recycle(f: HelmFunction) -> FunctionSlot {
    let AbiFunction(mut fd, give_back) = f.into_parts();
    hand_back(&mut fd, give_back);
    fd
}

fn hand_back(fd: &mut FunctionSlot, give_back: Option<behavior_api::FunctionRecycler>) {
    if let (Some(fd), Some(give_back)) = (fd.take(), give_back) {
        give_back(fd);
    }
}

/// A behavior's function on the helm domain, pushed to `out` (not moved through results).
/// Its domain text is parsed and checked against the helm's grid only when it differs
/// from the behavior's previous one (rare; the text's numbers are slow to read).
fn place(
    core: &mut crate::runtime::BehaviorCore,
    mut fd: FunctionSlot,
    helm: &ivp::Domain,
    name: String,
    out: &mut Vec<(String, HelmFunction)>,
) -> Result<(), String> {
    let data = fd.as_ref().as_ref().ok_or("no function")?; // never: the caller saw one
    if core.placed_domain != data.domain.as_str() {
        core.placed_domain.clear();
        core.placed_dim = 0;
        core.placed = None;
        data.helm_vars_into(helm, &mut core.placed_vars)?;
        core.placed_domain.push_str(data.domain.as_str());
        core.placed_dim = data.dim();
    }
    // The buffers are read where they are, then handed back for the next build (moving
    // them in would free a library's here and make it allocate anew).
    let give_back = core.recycler;
    let domain = match &core.placed {
        Some(d) => Arc::clone(d),
        None => match FunctionData::placed_domain(helm, &core.placed_vars) {
            Ok(d) => Arc::clone(core.placed.insert(Arc::new(d))),
            Err(msg) => {
                hand_back(&mut fd, give_back);
                return Err(msg);
            }
        },
    };
    match CheckedFunction::new(AbiFunction(fd, give_back), domain) {
        Ok(f) => {
            out.push((name, f));
            Ok(())
        }
        Err((AbiFunction(mut fd, _), e)) => {
            hand_back(&mut fd, give_back);
            Err(FunctionData::rejection(e))
        }
    }
}
