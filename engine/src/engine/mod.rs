//! The helm engine: one iteration from mail to postings (helm.md §5-§9).
//!
//! `Helm::new` builds the behavior set, `startup` runs once, then per tick:
//! [`Helm::handle_mail`] (mail → info buffer) and [`Helm::iterate`] (modes → behaviors →
//! solve → postings). The caller moves postings to MOOS and brings the helm's own
//! postings back as mail, as a MOOSDB does.

mod build;
pub mod deprecated;
mod explain;
mod instance;
mod iterate;
mod mail;
mod publish;
mod report;
mod spawn;
mod summary;

use bhv::modes::ModeSet;
use bhv::reader::Init;

use crate::config::HelmConfig;
use crate::info_buffer::InfoBuffer;
use crate::posting::{DuplicateFilter, Posting};
use crate::runtime::{BehaviorInstance, HostEnv};

pub use build::BuildError;
pub use mail::Mail;

/// Helm status (helm.md §3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HelmState {
    Park,
    Drive,
    Standby,
    Disabled,
    Malconfig,
}

impl HelmState {
    pub fn as_str(self) -> &'static str {
        match self {
            HelmState::Park => "PARK",
            HelmState::Drive => "DRIVE",
            HelmState::Standby => "STANDBY",
            HelmState::Disabled => "DISABLED",
            HelmState::Malconfig => "MALCONFIG",
        }
    }
}

/// The IvP Helm.
pub struct Helm {
    pub(crate) config: HelmConfig,
    pub(crate) app_name: String,
    pub(crate) env: HostEnv,
    pub(crate) behaviors: Vec<BehaviorInstance>,
    pub(crate) inits: Vec<Init>,
    /// The `.bhv` blocks, kept to rebuild the behavior set on RESTART_HELM.
    pub(crate) source: Vec<bhv::reader::BehaviorSpec>,
    /// A RESTART_HELM request (`type1`/`type2`) to carry out at the next iteration.
    pub(crate) restart: Option<String>,
    /// Post IVPHELM_RESTARTED at the next decision.
    pub(crate) restarted: bool,
    pub(crate) modes: ModeSet,
    pub(crate) bhv_files: Vec<String>,
    /// Messages behaviors queued while being built (published once at start-up).
    pub(crate) startup_messages: Vec<(String, crate::posting::Value)>,
    pub(crate) ib: InfoBuffer,
    pub(crate) filter: DuplicateFilter,
    pub(crate) solver: ivp_solver::Solver,
    pub(crate) decision: ivp_solver::Decision,
    pub(crate) state: HelmState,
    pub(crate) has_control: bool,
    pub(crate) start_time: f64,
    pub(crate) iteration: u64,
    pub(crate) mail_this_cycle: bool,
    pub(crate) helm_state_seen: bool,
    pub(crate) deferred_done: bool,
    pub(crate) allstop: String,
    pub(crate) no_decision_count: u32,
    pub(crate) no_goal_count: u32,
    pub(crate) refresh_pending: bool,
    pub(crate) last_refresh: f64,
    /// Variables registered with MOOS, in registration order.
    pub(crate) registered: Vec<String>,
    pub(crate) config_warnings: Vec<String>,
    pub(crate) outbox: Vec<Posting>,
    /// The outbox was handed out: the next posting starts a new batch.
    pub(crate) outbox_taken: bool,
    /// Last values of the helm's "on change" postings.
    pub(crate) last_posted: PostedMap,
    pub(crate) statevars: Vec<String>,
    pub(crate) bhv_cnt_ever: usize,
    pub(crate) completed_pending_last: Option<bool>,
    pub(crate) completed_count_last: Option<usize>,
    pub(crate) life_events: Vec<String>,
    pub(crate) turn_samples: Vec<(f64, f64)>,
    /// Functions of this iteration (behavior name, function), reused across iterations.
    pub(crate) functions: Vec<(String, iterate::HelmFunction)>,
    /// Emptied function boxes, for the next functions (see `Helm::decide`).
    pub(crate) fn_slots: Vec<iterate::FunctionSlot>,
    /// Time spent in the engine's decision step (what the C++ timing measures), and count.
    pub(crate) decide_time: std::time::Duration,
    pub(crate) decide_count: u64,
    /// See `subscription_signature`.
    pub(crate) subs_signature: usize,
    pub(crate) nav_warned: bool,
    /// Last IVPHELM_STATE heard from the primary helm (standby helm only).
    pub(crate) last_heartbeat: Option<f64>,
    /// The behavior set's conditions or flags changed: IVPHELM_STATEVARS may grow.
    pub(crate) statevars_dirty: bool,
    /// Fields of the last IVPHELM_SUMMARY by position (empty: the next one is full),
    /// and this iteration's, both kept for their strings.
    pub(crate) summary_last: Vec<String>,
    pub(crate) summary_fields: Vec<String>,
    pub(crate) last_decide_secs: f64,
    /// Apps seen in DB_CLIENTS (for `hold_on_apps`).
    pub(crate) apps_seen: Vec<String>,
    /// Per domain variable: `<prefix>DESIRED_<VAR>` and the unprefixed all-stop name.
    pub(crate) desired_names: Vec<(String, String)>,
    /// `.bhv` blocks with `templating = spawn|clone`.
    pub(crate) templates: Vec<spawn::Template>,
    /// Kept for spawning behaviors at run time.
    pub(crate) factory: crate::factory::BehaviorFactory,
    /// Mode variable values of this iteration, sorted by variable.
    pub(crate) mode_pairs: Vec<(String, String)>,
    /// What the AppCasting report shows (run warnings, events, last postings).
    pub(crate) report: report::ReportFeed,
    /// Strings of handed-out postings, reused by the next ones.
    pub(crate) pool: mbutil::StringPool,
    /// The lengths of the texts a behavior posted this iteration: it gets back spare
    /// strings of these sizes for its next messages (reused, kept between iterations).
    pub(crate) refill: Vec<usize>,
    /// BHV_IPF text and packet id, reused for every function.
    pub(crate) ipf: ivp_ipf::IpfWriter,
    /// BHV_IPF is not made at all (see [`Helm::set_ipf_posting`]).
    pub(crate) ipf_off: bool,
    /// Scratch for a contact report's info-buffer variable names.
    pub(crate) report_var: String,
    /// The solver's list of this iteration's functions, kept for its allocation.
    pub(crate) function_refs: Vec<ivp_solver::FunctionView<'static>>,
}

/// What an "on change" posting last posted under its variable: the text, and the bits
/// of the number it was written from (`None`: a text was posted). The same bits write
/// the same text, so a repeated number is known without formatting it.
#[derive(Debug, Default)]
pub(crate) struct LastPosted {
    pub(crate) text: String,
    pub(crate) bits: Option<u64>,
}

/// [`LastPosted`] by variable: a dozen names, all `IVPHELM_...`, looked up several
/// times an iteration. A list searched by the names' addresses (the same literal each
/// time), then their bytes in place: an ordered map compared the shared prefix with a
/// `memcmp` call at every step of its search. Never iterated: order cannot show.
#[derive(Debug, Default)]
pub(crate) struct PostedMap(Vec<(&'static str, LastPosted)>);

impl PostedMap {
    fn at(&self, var: &str) -> Option<usize> {
        let by_addr = |k: &&str| k.as_ptr() == var.as_ptr() && k.len() == var.len();
        (self.0.iter().position(|(k, _)| by_addr(k)))
            .or_else(|| (self.0.iter()).position(|(k, _)| mbutil::short_str::same(k, var)))
    }
    pub(crate) fn get(&self, var: &str) -> Option<&LastPosted> {
        self.at(var).map(|i| &self.0[i].1)
    }
    pub(crate) fn get_mut(&mut self, var: &str) -> Option<&mut LastPosted> {
        self.at(var).map(|i| &mut self.0[i].1)
    }
    /// `v` under `var`; the value it replaces.
    pub(crate) fn insert(&mut self, var: &'static str, v: LastPosted) -> Option<LastPosted> {
        match self.at(var) {
            Some(i) => Some(std::mem::replace(&mut self.0[i].1, v)),
            None => {
                self.0.push((var, v));
                None
            }
        }
    }
    pub(crate) fn clear(&mut self) {
        self.0.clear();
    }
}

impl Helm {
    /// Total time spent in decision steps (modes, behaviors, solve) and their number:
    /// the measure of the C++ `determineNextDecision` timings.
    pub fn decision_timing(&self) -> (std::time::Duration, u64) {
        (self.decide_time, self.decide_count)
    }

    /// The current status.
    pub fn state(&self) -> HelmState {
        self.state
    }

    /// The `verbose =` setting of the pHelmIvP block.
    pub fn configured_verbose(&self) -> crate::config::Verbose {
        self.config.verbose
    }

    /// Configuration problems (non-empty means MALCONFIG).
    pub fn config_warnings(&self) -> &[String] {
        &self.config_warnings
    }

    /// Variables the helm subscribes to.
    pub fn subscriptions(&self) -> &[String] {
        &self.registered
    }

    pub fn is_subscribed(&self, var: &str) -> bool {
        self.registered.iter().any(|v| v == var)
    }

    /// Set the MOOS app name (the source of its own postings, `pHelmIvP` by default).
    pub fn set_app_name(&mut self, name: &str) {
        self.app_name = name.to_string();
    }

    /// Whether functions are serialised and posted as BHV_IPF (on by default, as the
    /// real helm always does). A host that knows no one reads BHV_IPF (a simulated
    /// bus with no subscriber and no log) turns it off: the encoding is the largest
    /// cost of an iteration with big functions, and nothing else depends on it.
    pub fn set_ipf_posting(&mut self, on: bool) {
        self.ipf_off = !on;
    }

    /// Name of the helm as a MOOS app (the source of its postings).
    pub fn app_name(&self) -> &str {
        &self.app_name
    }

    /// Behavior names in set order.
    pub fn behavior_names(&self) -> Vec<String> {
        self.behaviors.iter().map(|b| b.core.name.clone()).collect()
    }

    /// The info buffer (read-only), e.g. for reports.
    pub fn info_buffer(&self) -> &InfoBuffer {
        &self.ib
    }

    pub(crate) fn post(&mut self, var: &str, value: crate::posting::Value, aux: &str) {
        let (var, source_aux) = (self.pool.copy_of(var), self.pool.copy_of(aux));
        self.outbox.push(Posting {
            var,
            value,
            source_aux,
        });
    }

    pub(crate) fn post_str(&mut self, var: &str, value: &str) {
        let value = self.pool.copy_of(value);
        self.post(var, crate::posting::Value::Str(value), "");
    }

    pub(crate) fn post_num(&mut self, var: &str, value: f64) {
        self.post(var, crate::posting::Value::Num(value), "");
    }

    /// Post only when the text differs from what was last posted under `var`. The
    /// text is formatted into a scratch string and compared first: only a changed
    /// value is kept (a new string the first time a variable is posted).
    pub(crate) fn post_on_change(&mut self, var: &'static str, value: crate::posting::Value) {
        use std::fmt::Write as _;
        let bits = match &value {
            crate::posting::Value::Num(v) => Some(v.to_bits()),
            crate::posting::Value::Str(_) => None,
        };
        let last = self.last_posted.get(var);
        if bits.is_some() && last.is_some_and(|l| l.bits == bits) {
            return;
        }
        let mut text = self.pool.take_for(match &value {
            crate::posting::Value::Str(s) => s.len(),
            crate::posting::Value::Num(_) => 24,
        });
        match &value {
            crate::posting::Value::Str(s) => text.push_str(s),
            crate::posting::Value::Num(v) => {
                let _ = write!(text, "{v}");
            }
        }
        match self.last_posted.get_mut(var) {
            Some(last) if last.text == text => {
                last.bits = bits;
                self.pool.give(text);
                crate::posting::give_value(&mut self.pool, value);
                return;
            }
            Some(last) => {
                let old = std::mem::replace(&mut last.text, text);
                last.bits = bits;
                self.pool.give(old);
            }
            None => {
                self.last_posted.insert(var, LastPosted { text, bits });
            }
        }
        self.post(var, value, "");
    }

    pub(crate) fn register(&mut self, var: &str) {
        if !var.is_empty() && !self.is_subscribed(var) {
            self.registered.push(var.to_string());
        }
    }
}
