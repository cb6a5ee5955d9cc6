//! Building the helm: configuration, the behavior set, start-up (helm.md §5).

use bhv::reader::{SetSpec, Templating};

use super::instance::make_instance;
use super::{Helm, HelmState};
use crate::config::HelmConfig;
use crate::factory::BehaviorFactory;
use crate::info_buffer::InfoBuffer;
use crate::posting::DuplicateFilter;
use crate::runtime::{BehaviorInstance, HostEnv};

/// Why the helm would not drive: every configuration problem, one per line.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildError(pub Vec<String>);

impl std::fmt::Display for BuildError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0.join("\n"))
    }
}

impl std::error::Error for BuildError {}

fn names_conflict(a: &str, b: &str) -> bool {
    a.starts_with(b) || b.starts_with(a)
}

impl Helm {
    /// Build the helm from its configuration and the parsed `.bhv` files. Problems do not
    /// fail the build: they are kept as configuration warnings and the helm is MALCONFIG,
    /// as the real helm does.
    pub fn new(
        config: HelmConfig,
        spec: SetSpec,
        factory: &BehaviorFactory,
        ownship: &str,
        mut warnings: Vec<String>,
    ) -> Helm {
        let mut ledger = contacts::Ledger::new(config.origin);
        ledger.set_max_age(config.contact_max_age);
        let env = HostEnv {
            ownship: ownship.to_string(),
            helm_iteration: 0,
            helm_domain: config.domain_string(),
            ledger,
        };
        let ib = InfoBuffer::new(0.0);
        // The BHV_IPF writer's caches made now, not in the first decision.
        ivp_ipf::prepare_thread(config.domain.size());
        let mut behaviors: Vec<BehaviorInstance> = Vec::new();
        let mut startup_messages = Vec::new();
        if config.domain.size() == 0 {
            warnings.push("No decision domain: add `domain = name:low:high:points` lines".into());
        }
        let mut templates = Vec::new();
        for bs in &spec.behaviors {
            let inst = match make_instance(bs, factory, &env, &ib, ownship) {
                Ok(inst) => inst,
                Err(errs) => {
                    warnings.extend(errs);
                    continue;
                }
            };
            let mut inst = inst;
            let where_ = format!("{}:{}", bs.file.display(), bs.line);
            // A template's facts, for a helm-start hook that depends on them (contact
            // behaviors' BCM_ALERT_REQUEST); a type that does not know these
            // parameters refuses them, which is ignored.
            if bs.templating != Templating::Disallow {
                let t = if bs.templating == Templating::Spawn {
                    "spawn"
                } else {
                    "clone"
                };
                let var = bs.updates_var.clone().unwrap_or_default();
                for (p, v) in [("helm_templating", t), ("helm_updates", var.as_str())] {
                    let (b, core) = (&mut inst.bhv, &mut inst.core);
                    let _ = crate::runtime::with_ctx_pub(core, &env, &ib, |ctx| {
                        b.set_param(ctx, p.into(), v.into())
                    });
                }
            }
            let hook = {
                let (b, core) = (&mut inst.bhv, &mut inst.core);
                crate::runtime::with_ctx_pub(core, &env, &ib, |ctx| b.on_helm_start(ctx))
            };
            if let Err(p) = hook.into_result() {
                warnings.push(format!("{where_}: behavior panicked at helm start: {p}"));
            }
            for m in inst.core.messages.drain(..) {
                startup_messages.push((m.var, m.value));
            }
            if bs.templating != Templating::Disallow {
                templates.push(super::spawn::Template::new(bs.clone()));
            }
            if bs.templating == Templating::Spawn {
                continue;
            }
            if behaviors
                .iter()
                .any(|b| names_conflict(&b.core.name, &inst.core.name))
            {
                warnings.push(format!(
                    "{where_}: Duplicate behavior name found: {}",
                    inst.core.name
                ));
            }
            behaviors.push(inst);
        }
        let state = if !warnings.is_empty() {
            HelmState::Malconfig
        } else if config.standby.is_some() {
            HelmState::Standby
        } else if config.start_in_drive {
            HelmState::Drive
        } else {
            HelmState::Park
        };
        let has_control = config.start_in_drive && state != HelmState::Malconfig;
        let bhv_files = spec.files.iter().map(|f| f.display().to_string()).collect();
        let source = spec.behaviors.clone();
        Helm {
            app_name: "pHelmIvP".into(),
            env,
            bhv_cnt_ever: behaviors.len(),
            behaviors,
            inits: spec.inits,
            source,
            restart: None,
            restarted: false,
            modes: spec.modes,
            bhv_files,
            startup_messages,
            ib,
            filter: DuplicateFilter::default(),
            solver: ivp_solver::Solver::new(),
            decision: ivp_solver::Decision::default(),
            state,
            has_control,
            start_time: 0.0,
            iteration: 0,
            mail_this_cycle: false,
            helm_state_seen: false,
            deferred_done: false,
            allstop: String::new(),
            no_decision_count: 0,
            no_goal_count: 0,
            refresh_pending: false,
            last_refresh: 0.0,
            registered: Vec::new(),
            config_warnings: warnings,
            outbox: Vec::new(),
            outbox_taken: false,
            last_posted: Default::default(),
            statevars: Vec::new(),
            completed_pending_last: None,
            // The reference posts the count only when it changes from its start value 0.
            completed_count_last: Some(0),
            life_events: Vec::new(),
            turn_samples: Vec::new(),
            functions: Vec::new(),
            fn_slots: Vec::new(),
            mode_pairs: Vec::new(),
            pool: Default::default(),
            refill: Vec::new(),
            ipf: ivp_ipf::IpfWriter::default(),
            ipf_off: false,
            apps_seen: Vec::new(),
            nav_warned: false,
            last_heartbeat: None,
            statevars_dirty: true,
            summary_last: Default::default(),
            summary_fields: Default::default(),
            function_refs: Vec::new(),
            report_var: String::new(),
            last_decide_secs: 0.0,
            desired_names: config
                .domain
                .vars()
                .iter()
                .map(|v| {
                    (
                        super::iterate::desired_var(&config.helm_prefix, &v.name),
                        super::iterate::desired_var("", &v.name),
                    )
                })
                .collect(),
            templates,
            factory: factory.clone(),
            decide_time: std::time::Duration::ZERO,
            decide_count: 0,
            subs_signature: 0,
            report: Default::default(),
            config,
        }
    }

    /// Start-up (helm.md §5): returns what the helm publishes.
    pub fn startup(&mut self, now: f64) -> &[crate::posting::Posting] {
        self.outbox.clear();
        self.start_time = now;
        self.ib = InfoBuffer::new(now);
        self.post_num("PHELMIVP_PID", f64::from(std::process::id()));
        if self.state != HelmState::Malconfig || !self.behaviors.is_empty() {
            let (env, ib) = (&self.env, &self.ib);
            for inst in &mut self.behaviors {
                let (b, core) = (&mut inst.bhv, &mut inst.core);
                let r =
                    crate::runtime::with_ctx_pub(core, env, ib, |ctx| b.on_params_complete(ctx));
                if let Err(p) = r.into_result() {
                    crate::runtime::fault(core, &format!("behavior panicked: {p}"));
                }
            }
        }
        // Non-deferred initializations, in file order.
        let inits = std::mem::take(&mut self.inits);
        for init in &inits {
            if init.deferred {
                self.register(&init.var);
                continue;
            }
            // The reader already typed the value (an empty string is the number 0).
            self.ib.set_value(&init.var, &init.value, now);
            self.post(&init.var, init.value.clone(), "HELM_VAR_INIT");
        }
        self.inits = inits;
        self.register("IVPHELM_STATE");
        if self.config.hold_on_apps.is_empty() {
            for (var, value) in std::mem::take(&mut self.startup_messages) {
                self.ib.set_value(&var, &value, now);
                self.post(&var, value, "HELM_STARTUP_MSG");
            }
        }
        self.register_all();
        for f in self.bhv_files.clone() {
            self.post_str("PLOGGER_CMD", &format!("COPY_FILE_REQUEST = {f}"));
        }
        let dom = self.env.helm_domain.clone();
        self.post_str("IVPHELM_DOMAIN", &dom);
        let modeset = self.modes.modeset_string();
        self.post_str("IVPHELM_MODESET", &modeset);
        for v in [
            "IVPHELM_BHV_ACTIVE_CNT",
            "IVPHELM_BHV_IDLE_CNT",
            "IVPHELM_BHV_RUNNING_CNT",
            "IVPHELM_BHV_DISABLED_CNT",
        ] {
            self.post_num(v, 0.0);
        }
        if !self.config.helm_alias.is_empty() {
            let a = self.config.helm_alias.clone();
            self.post_str("IVPHELM_ALIAS", &a);
        }
        for inst in &self.behaviors {
            self.life_events.push(format!(
                "bname={}, btype={}, event=spawn, seed=helm_startup",
                inst.core.name, inst.core.type_name
            ));
        }
        self.outbox_taken = true;
        &self.outbox
    }

    /// Every variable the helm needs (helm.md §4.1).
    pub(crate) fn register_all(&mut self) {
        for v in self.helm_variables() {
            self.register(&v);
        }
        for v in self.info_variables() {
            self.register(&v);
        }
    }

    /// The helm's own variables (helm.md §4.1), known before start-up: what a MOOS
    /// connection registers first.
    pub fn helm_variables(&self) -> Vec<String> {
        let mut vars: Vec<String> = HELM_VARS.iter().map(|v| v.to_string()).collect();
        if !self.config.other_override_var.is_empty() {
            vars.push(self.config.other_override_var.clone());
        }
        vars
    }

    /// The behaviors' info variables and the mode-condition variables.
    pub fn info_variables(&self) -> Vec<String> {
        let mut vars = Vec::new();
        for inst in &self.behaviors {
            vars.extend(inst.core.subscriptions());
        }
        // A template spawns from mail on its `updates` variable (bhv-format.md §9), so
        // the helm needs that mail before any instance of it exists.
        for t in &self.templates {
            vars.extend(t.spec.updates_var.iter().cloned());
        }
        vars.extend(self.modes.vars());
        vars
    }
}

/// The variables every helm registers for (helm.md §4.1, besides `other_override_var`).
const HELM_VARS: [&str; 16] = [
    "DB_CLIENTS",
    "MOOS_MANUAL_OVERIDE",
    "MOOS_MANUAL_OVERRIDE",
    "RESTART_HELM",
    "IVPHELM_REJOURNAL",
    "BHV_ABLE_FILTER",
    "NAV_X",
    "NAV_Y",
    "NAV_SPEED",
    "NAV_HEADING",
    "NAV_DEPTH",
    "HELM_MAP_CLEAR",
    "AIS_REPORT",
    "NODE_REPORT",
    "AIS_REPORT_LOCAL",
    "NODE_REPORT_LOCAL",
];

impl Helm {
    /// RESTART_HELM (helm.md §13): behaviors rebuilt from their blocks, duplicate filter
    /// cleared, deferred initializations re-armed, start time reset (1 s warm-up again);
    /// `type2` re-posts the non-deferred initializations. The info buffer is kept and
    /// helm-start messages are not posted again.
    pub(crate) fn restart_behaviors(&mut self, now: f64, kind: &str) {
        tracing::info!("restart {kind}");
        self.run_warning("pHelmIvP has been re-started!!");
        let ownship = self.env.ownship.clone();
        let mut rebuilt = Vec::new();
        for bs in self
            .source
            .iter()
            .filter(|b| b.templating != Templating::Spawn)
        {
            match make_instance(bs, &self.factory, &self.env, &self.ib, &ownship) {
                Ok(mut inst) => {
                    let (b, core) = (&mut inst.bhv, &mut inst.core);
                    let _ = crate::runtime::with_ctx_pub(core, &self.env, &self.ib, |ctx| {
                        b.on_helm_start(ctx)
                    });
                    inst.core.messages.clear();
                    let (b, core) = (&mut inst.bhv, &mut inst.core);
                    let _ = crate::runtime::with_ctx_pub(core, &self.env, &self.ib, |ctx| {
                        b.on_params_complete(ctx)
                    });
                    rebuilt.push(inst);
                }
                Err(errs) => {
                    for e in errs {
                        tracing::error!("restart: {e}");
                    }
                }
            }
        }
        self.behaviors = rebuilt;
        self.bhv_cnt_ever += self.behaviors.len();
        self.filter.clear();
        self.last_posted.clear();
        self.summary_last.clear();
        self.deferred_done = false;
        self.start_time = now;
        self.allstop.clear();
        if kind == "type2" {
            let inits = std::mem::take(&mut self.inits);
            for init in inits.iter().filter(|i| !i.deferred) {
                self.ib.set_value(&init.var, &init.value, now);
                self.post(&init.var, init.value.clone(), "HELM_VAR_INIT");
            }
            self.inits = inits;
        }
        for inst in &self.behaviors {
            self.life_events.push(format!(
                "bname={}, btype={}, event=spawn, seed=helm_restart",
                inst.core.name, inst.core.type_name
            ));
        }
        self.restarted = true;
    }
}
