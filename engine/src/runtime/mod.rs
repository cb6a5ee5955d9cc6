//! The behavior runtime: the host's side of every behavior (behavior-common.md).
//!
//! A [`BehaviorInstance`] is the ABI trait object ([`behavior_api::BehaviorBox`], built-in
//! or from a plugin: the runtime cannot tell) plus the [`BehaviorCore`] the host keeps for
//! it: common parameters, conditions, flags, run state, duration and update bookkeeping,
//! and the messages it queued this iteration.

mod common_params;
mod context;
mod flags;
mod macros;
mod step;
mod updates;

use rustc_hash::FxHashMap as HashMap;

use behavior_api::BehaviorBox;
use bhv::flag::FlagSpec;
use bhv::logic::LogicCondition;

use crate::posting::Value;

pub use behavior_api::push_compact;
pub use common_params::apply_config_line;
pub use macros::fmt3;

/// Run states as reported in BHV_STATUS and the behavior lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunState {
    /// Before the first iteration (`""` in the spec).
    Fresh,
    Idle,
    Running,
    Active,
    Completed,
    Disabled,
}

impl RunState {
    pub fn as_str(self) -> &'static str {
        match self {
            RunState::Fresh => "",
            RunState::Idle => "idle",
            RunState::Running => "running",
            RunState::Active => "active",
            RunState::Completed => "completed",
            RunState::Disabled => "disabled",
        }
    }
}

/// A message a behavior queued, published by the helm at the end of the iteration.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    pub var: String,
    pub value: Value,
    /// The duplicate-filter key: `repeatable` or `<name><VAR><given key>`; empty for
    /// the default `<name><VAR>`, written where it is read (most messages have it).
    pub key: String,
    /// The helm's BHV_IPF of the behavior's function (its text in the behavior's
    /// `ipf_kept`, `value` unused): split into packets where it is published.
    pub helm_ipf: bool,
}

/// The lists of common flags (behavior-common.md §3).
#[derive(Clone, Debug, Default)]
pub struct FlagLists {
    pub run: Vec<FlagSpec>,
    pub runx: Vec<FlagSpec>,
    pub active: Vec<FlagSpec>,
    pub inactive: Vec<FlagSpec>,
    pub idle: Vec<FlagSpec>,
    pub end: Vec<FlagSpec>,
    pub spawn: Vec<FlagSpec>,
    pub spawnx: Vec<FlagSpec>,
    pub config: Vec<FlagSpec>,
}

/// Everything the host keeps for one behavior besides the behavior object itself.
#[derive(Debug)]
pub struct BehaviorCore {
    pub type_name: String,
    /// The contact this behavior is about (told by the behavior), "" for none.
    pub contact: String,
    pub name: String,
    pub pwt: f64,
    pub conditions: Vec<LogicCondition>,
    /// The iteration whose conditions were last evaluated, and the first that failed
    /// then: the runnable test runs twice an iteration on the same information.
    pub conditions_checked: Option<(u64, Option<usize>)>,
    pub flags: FlagLists,
    pub nostarve: Option<(Vec<String>, f64)>,
    pub duration: f64,
    pub duration_status: String,
    pub duration_reset: Option<(String, String)>,
    pub duration_idle_decay: bool,
    pub perpetual: bool,
    pub updates_var: String,
    pub post_mapping: HashMap<String, String>,
    pub comms_policy: String,
    pub build_info: String,
    pub ownship: String,
    /// The behavior's own domain is empty ("Null IvPDomain").
    pub empty_domain: bool,
    /// How its functions go back to whoever built them for the next build, after the
    /// host read them where they are: its library's recycler (0.1.3), or the host's own
    /// for a built-in behavior.
    pub recycler: Option<behavior_api::FunctionRecycler>,
    /// The domain text of the behavior's last function, where its variables are in the
    /// helm domain, and (for a library's function) that domain as the solver reads it
    /// (see `Helm::decide`): made again only when the text changes.
    pub placed_domain: String,
    /// `placed_domain`'s dimensions as `FunctionData::dim` counts them.
    pub placed_dim: usize,
    pub placed_vars: Vec<usize>,
    pub placed: Option<std::sync::Arc<ivp::Domain>>,
    /// The text of this behavior's last BHV_IPF function, reused while it does not change.
    pub ipf_kept: ivp_ipf::KeptIpf,
    /// For behaviors spawned from a template: the template's name prefix.
    pub spawn_prefix: Option<String>,
    /// Disabled after a panic or a function that could not be trusted.
    pub faulted: bool,

    pub state: RunState,
    pub completed: bool,
    /// Cleared by a BHV_ERROR through the error helper: halts the iteration.
    pub ok: bool,
    pub iteration: u64,
    pub config_posted: bool,
    pub state_entry_time: f64,

    // Duration bookkeeping (§6).
    pub duration_started: bool,
    pub duration_start_time: f64,
    pub duration_reset_pending: bool,
    pub last_reset_trigger_time: Option<f64>,
    pub dur_run_time: f64,
    pub dur_idle_time: f64,
    pub dur_last_call: Option<f64>,

    // Updates (§5).
    pub last_update: String,
    pub good_updates: u32,
    pub bad_updates: u32,
    /// Seconds its last decision step took (its run hook and its function's placement):
    /// the appcast report's `cpu=`.
    pub step_secs: f64,
    pub update_results: Vec<String>,

    /// `name=<name>[,pc=..][,pwt=..,pcs=..]` built during the step.
    pub status_info: String,
    /// `,pwt=..,pcs=..` of the last active step with its weight's bits and piece count,
    /// written again only when they change (the weight is positive: never bits 0).
    pub pwt_pcs: (u64, usize, String),
    /// BHV_STATUS's `,state=..,updates=..` with what it shows (the state, the update
    /// counts, whether there is an updates variable), written again only when that
    /// changes.
    pub status_tail: (Option<(RunState, u32, u32, bool)>, String),
    /// Messages queued this iteration, in order.
    pub messages: Vec<Message>,
    /// Position in `messages` where the behavior asked to complete.
    pub complete_requested: Option<usize>,
    /// Variables the behavior subscribed to, with "no warning".
    pub info_vars: Vec<(String, bool)>,
    /// Ownship as the behavior's platform update last read it.
    pub platform: [f64; 4],
    pub now_origin: Option<f64>,
    pub counters: [u64; 6],
    /// Conditions of `eval_condition` calls, parsed once.
    pub condition_cache: HashMap<String, LogicCondition>,
    /// Flags posted by the type itself, parsed once.
    pub flag_cache: HashMap<String, FlagSpec>,
    /// Spare strings for this behavior's messages, topped up by the helm as it
    /// publishes them.
    pub pool: mbutil::StringPool,
}

impl BehaviorCore {
    /// Good updates over all updates (`3/4`), or `n/a` without an updates variable,
    /// appended to `out`: the form of the appcast report and IVPHELM_SUMMARY.
    pub fn push_update_counts(&self, out: &mut String) {
        if self.updates_var.is_empty() {
            return out.push_str("n/a");
        }
        mbutil::push_u64(out, self.good_updates.into());
        out.push('/');
        mbutil::push_u64(out, (self.good_updates + self.bad_updates).into());
    }

    pub fn new(type_name: &str, default_name: &str, ownship: &str) -> Self {
        BehaviorCore {
            type_name: type_name.to_string(),
            contact: String::new(),
            name: default_name.to_string(),
            pwt: 100.0,
            conditions: Vec::new(),
            conditions_checked: None,
            flags: FlagLists::default(),
            nostarve: None,
            duration: -1.0,
            duration_status: String::new(),
            duration_reset: None,
            duration_idle_decay: true,
            perpetual: false,
            updates_var: String::new(),
            post_mapping: HashMap::default(),
            comms_policy: "open".into(),
            build_info: String::new(),
            ownship: ownship.to_string(),
            empty_domain: false,
            recycler: None,
            placed_domain: String::new(),
            placed_dim: 0,
            placed_vars: Vec::new(),
            placed: None,
            ipf_kept: ivp_ipf::KeptIpf::default(),
            faulted: false,
            spawn_prefix: None,
            state: RunState::Fresh,
            completed: false,
            ok: true,
            iteration: 0,
            config_posted: false,
            state_entry_time: 0.0,
            duration_started: false,
            duration_start_time: 0.0,
            duration_reset_pending: false,
            last_reset_trigger_time: None,
            dur_run_time: 0.0,
            dur_idle_time: 0.0,
            dur_last_call: None,
            last_update: String::new(),
            good_updates: 0,
            bad_updates: 0,
            step_secs: 0.0,
            update_results: Vec::new(),
            status_info: String::new(),
            pwt_pcs: (0, 0, String::new()),
            status_tail: (None, String::new()),
            messages: Vec::new(),
            complete_requested: None,
            info_vars: Vec::new(),
            platform: [0.0; 4],
            now_origin: None,
            counters: [0; 6],
            condition_cache: HashMap::default(),
            flag_cache: HashMap::default(),
            pool: Default::default(),
        }
    }

    /// Queue a message (behavior-common.md §8: post_mapping, then the key rule).
    pub fn post(&mut self, var: &str, value: Value, given_key: &str) {
        let var = match self.post_mapping.get(var) {
            Some(to) if to.eq_ignore_ascii_case("silent") => {
                crate::posting::give_value(&mut self.pool, value);
                return;
            }
            Some(to) => self.pool.copy_of(to),
            None => self.pool.copy_of(var),
        };
        let key = if given_key.is_empty() {
            String::new()
        } else if given_key.eq_ignore_ascii_case("repeatable") {
            self.pool.copy_of("repeatable")
        } else {
            let len = self.name.len() + var.len() + given_key.len();
            let mut key = self.pool.take_for(len);
            key.push_str(&self.name);
            key.push_str(&var);
            key.push_str(given_key);
            key
        };
        self.messages.push(Message {
            var,
            value,
            key,
            helm_ipf: false,
        });
    }

    /// `postEMessage`: BHV_ERROR and the behavior is not ok (halts the iteration).
    pub fn post_error(&mut self, msg: &str) {
        let text = self.prefixed(msg);
        self.post("BHV_ERROR", Value::Str(text), "repeatable");
        self.ok = false;
    }

    /// `postWMessage`.
    pub fn post_warning(&mut self, msg: &str) {
        if msg.is_empty() {
            return;
        }
        let text = self.prefixed(msg);
        self.post("BHV_WARNING", Value::Str(text), "repeatable");
    }

    fn prefixed(&self, msg: &str) -> String {
        if self.name.is_empty() {
            msg.to_string()
        } else {
            format!("{}: {}", self.name, msg)
        }
    }

    /// All variables the host must subscribe to for this behavior.
    pub fn subscriptions(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let mut add = |v: &str| {
            if !v.is_empty() && !out.iter().any(|o| o == v) {
                out.push(v.to_string());
            }
        };
        for c in &self.conditions {
            for v in c.vars() {
                add(v);
            }
        }
        for list in self.flags.all() {
            for f in list {
                if let Some(c) = &f.condition {
                    for v in c.vars() {
                        add(v);
                    }
                }
            }
        }
        if let Some((v, _)) = &self.duration_reset {
            add(v);
        }
        add(&self.updates_var);
        for (v, _) in &self.info_vars {
            add(v);
        }
        out
    }

    /// Condition and flag variables (IVPHELM_STATEVARS).
    pub fn state_vars(&self) -> Vec<String> {
        let mut out = Vec::new();
        for c in &self.conditions {
            out.extend(c.vars().iter().cloned());
        }
        // Run, runx, active, inactive, idle and end flags (the reader sorts them).
        for list in &self.flags.all()[..6] {
            out.extend(list.iter().map(|f| f.var.clone()));
        }
        out
    }
}

impl FlagLists {
    pub fn all(&self) -> [&Vec<FlagSpec>; 9] {
        [
            &self.run,
            &self.runx,
            &self.active,
            &self.inactive,
            &self.idle,
            &self.end,
            &self.spawn,
            &self.spawnx,
            &self.config,
        ]
    }
}

/// A behavior in the helm's behavior set.
pub struct BehaviorInstance {
    pub bhv: BehaviorBox,
    pub core: BehaviorCore,
}

pub use context::with_ctx as with_ctx_pub;
pub use step::{spawned, step};

// Shared by the runtime's modules, so it lives here rather than in one of them.
/// What every behavior call may read about the helm as a whole.
#[derive(Debug)]
pub struct HostEnv {
    pub ownship: String,
    pub helm_iteration: u64,
    /// The helm domain as `name,low,high,points` joined by `:`.
    pub helm_domain: String,
    /// The contact ledger; behaviors read its snapshot of this iteration
    /// (contacts-appcast.md §2.5).
    pub ledger: contacts::Ledger,
}

impl Default for HostEnv {
    fn default() -> Self {
        HostEnv {
            ownship: String::new(),
            helm_iteration: 0,
            helm_domain: String::new(),
            ledger: contacts::Ledger::new(None),
        }
    }
}

/// Disable a behavior that misbehaved: BHV_ERROR (halts this iteration), then disabled.
pub fn fault(core: &mut BehaviorCore, msg: &str) {
    tracing::error!(behavior = %core.name, "{msg}");
    core.post_error(msg);
    core.faulted = true;
}
