//! One vehicle of a fleet: what MOOS runs in one community, on the fleet's clock.
//!
//! Its own bus ([`SimBus`]) with the helm (driven by [`HelmCycle`], as `helm run` and
//! the one-vehicle `helm sim`), the simulator, a pContactMgrV20 (the `contact-manager`
//! library, configured from the mission's `ProcessConfig = pContactMgrV20` block) and a
//! pNodeReporter that posts `NODE_REPORT_LOCAL`; a client of the shoreside picks those
//! up for the comms model. Each app ticks at its mission `AppTick` (pNodeReporter and
//! the contact manager default to 4 Hz, as their MOOS defaults).

use std::path::PathBuf;
use std::rc::Rc;

use contact_manager::{Config, ContactManager, MailValue};
use contacts::Geodesy;
use helm_cycle::HelmCycle;
use helm_engine::posting::Value;
use helm_engine::{Helm, HelmState, Mail};
use helm_mission::HelmRecipe;
use vehicle_model::{Drift, Kinematics, Nav, SimBlock, VehicleModel, SIM_NAME};

use super::relay::{Pending, Relayed};
use super::reporter::Ownship;
use super::spec::VehicleSpec;
use crate::bus::{SimBus, HELM};
use crate::observe::Observer;
use crate::run::{open_alog, sim_block, SimError, StartShift, HELM_NAME};
use crate::scenario::When;

pub const CMGR_NAME: &str = "pContactMgrV20";
pub const REPORTER_NAME: &str = "pNodeReporter";
/// The shoreside's bridge: collects `NODE_REPORT_LOCAL`, delivers `NODE_REPORT`.
pub const COMMS_NAME: &str = "uFldNodeComms";

const SIM: usize = 1;
const CMGR: usize = 2;
const SHORE: usize = 3;

/// A vehicle read once, ready to run any number of times.
pub struct VehiclePlan {
    pub spec: VehicleSpec,
    pub recipe: HelmRecipe,
    pub helm_tick: f64,
    pub sim_tick: f64,
    pub report_tick: f64,
    pub cmgr_tick: f64,
    pub start: Kinematics,
    pub cmgr: Config,
    pub origin: Option<(f64, f64)>,
    pub community: String,
    pub vtype: String,
    pub length: f64,
    pub library_report: Vec<String>,
    /// Unknown names in the simulator block, ignored but shown.
    pub warnings: Vec<String>,
    /// Its pObstacleMgr, if the mission configures one.
    pub obm: Option<super::obstacles::ObmPlan>,
}

fn fleet_err(name: &str, text: String) -> SimError {
    SimError::Fleet(format!("vehicle {name}: {text}"))
}

impl VehiclePlan {
    pub fn load(spec: &VehicleSpec) -> Result<VehiclePlan, SimError> {
        let loaded = helm_mission::load(&spec.mission, &spec.bhv, HELM_NAME)?;
        let library_report = loaded.library_report.clone();
        let (recipe, file) = loaded.into_recipe();
        let problems = recipe.build().config_warnings().to_vec();
        if !problems.is_empty() {
            return Err(SimError::Malconfig {
                problems: format!(
                    "{}\nMALCONFIG (vehicle {}): {} configuration problem(s); nothing run",
                    problems.join("\n"),
                    spec.name,
                    problems.len()
                ),
            });
        }
        let (block, warnings) = sim_block(SimBlock::read(&file))?;
        let mut start = Kinematics::from_block(&block);
        start.x = spec.x.unwrap_or(start.x);
        start.y = spec.y.unwrap_or(start.y);
        start.heading = spec.heading.unwrap_or(start.heading).rem_euclid(360.0);
        start.speed = spec.speed.unwrap_or(start.speed);

        // The contact manager's block: a line it cannot take stops the run, with its line.
        let mut cmgr = Config::default();
        let bad = contact_manager::block::read(&file, CMGR_NAME, |k, v| {
            cmgr.set(k, v).map_err(|e| e.to_string())
        })
        .unwrap_or_default();
        if !bad.is_empty() {
            return Err(fleet_err(
                &spec.name,
                format!("bad {CMGR_NAME} block:\n{}", bad.join("\n")),
            ));
        }
        let vtype = spec
            .vtype
            .clone()
            .or_else(|| file.config_value(REPORTER_NAME, "platform_type"))
            .unwrap_or_else(|| "kayak".into());
        let length = file
            .config_value(REPORTER_NAME, "platform_length")
            .and_then(|v| moos::mission::config_f64(&v))
            .filter(|l| *l > 0.0)
            .unwrap_or(4.0);
        let obm = super::obstacles::obm_plan(&file, &spec.name)?;
        Ok(VehiclePlan {
            obm,
            spec: spec.clone(),
            helm_tick: file.app_tick(HELM_NAME, 5.0),
            sim_tick: file.app_tick(SIM_NAME, 10.0),
            report_tick: file.app_tick(REPORTER_NAME, 4.0),
            cmgr_tick: file.app_tick(CMGR_NAME, 4.0),
            recipe,
            start,
            cmgr,
            origin: contact_manager::block::origin(&file),
            community: file.global("Community").unwrap_or_default(),
            vtype,
            length,
            library_report,
            warnings,
        })
    }
}

/// A vehicle during a run.
pub struct Live {
    pub bus: SimBus,
    helm: Helm,
    cycle: HelmCycle,
    model: Drift<Kinematics>,
    /// This run's perturbation (its speed change applies to every speed command).
    shift: StartShift,
    pub mgr: ContactManager,
    geo: Option<Geodesy>,
    kh: u64,
    ks: u64,
    kr: u64,
    kc: u64,
    last_sim: f64,
    pub drove: bool,
    /// The helm's stop rule fired (it is no longer iterated).
    pub over: bool,
    pub start: Nav,
    sim_in: Vec<Mail>,
    helm_in: Vec<Mail>,
    mgr_in: Vec<Mail>,
    /// The node reports posted to the helm and to the contact manager, not yet fetched.
    helm_reports: Pending,
    mgr_reports: Pending,
    /// The helm, the contact manager subscribed to `NODE_REPORT` (known once true:
    /// subscriptions are never dropped).
    hears_reports: [bool; 2],
    /// The helm subscribed to `NODE_REPORT_LOCAL` (known once true).
    hears_local: bool,
    /// The reporter's last report.
    local: Option<Rc<Relayed>>,
    /// Always a `Value::Str`: the contact manager's text postings, one after another.
    mgr_text: Value,
    /// Always a `Value::Str`: the node report being delivered.
    relay_text: Value,
    report: String,
    report_index: u64,
    /// `,LENGTH={length}` of the report, written once (the length never changes).
    length_field: String,
    /// The bus places of the simulator's `NAV_*` variables, in `Nav::vars` order.
    nav_places: [usize; 5],
    /// The bus places of `NODE_REPORT` and `NODE_REPORT_LOCAL`.
    report_places: [usize; 2],
    pub obm: Option<super::obstacles::ObmLive>,
}

impl Live {
    pub fn new(
        plan: &VehiclePlan,
        shift: StartShift,
        t0: f64,
        when: Vec<When>,
        alog: Option<PathBuf>,
    ) -> Result<Live, SimError> {
        let mut kin = plan.start.clone();
        kin.x += shift.dx;
        kin.y += shift.dy;
        kin.heading = (kin.heading + shift.dheading).rem_euclid(360.0);
        let model = Drift {
            model: kin,
            current: (0.0, 0.0),
        };
        let mut bus = SimBus::new(
            &[HELM_NAME, SIM_NAME, CMGR_NAME, COMMS_NAME],
            Observer::new(t0, when),
        );
        if let Some(path) = alog {
            bus.alog = Some(open_alog(&path, t0)?);
        }
        for var in ["DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH"] {
            bus.subscribe(SIM, var);
        }
        bus.subscribe(SHORE, "NODE_REPORT_LOCAL");
        let mgr = ContactManager::new(&plan.spec.name, plan.cmgr.clone(), plan.origin);
        for var in mgr.subscriptions() {
            bus.subscribe(CMGR, &var);
        }
        let obm = plan
            .obm
            .as_ref()
            .map(|o| super::obstacles::ObmLive::new(o, &mut bus, t0));
        let mut helm = plan.recipe.build();
        let cycle = HelmCycle::startup(&mut helm, &mut bus, t0);
        // Functions are serialised only for a reader (a log or a subscriber).
        helm.set_ipf_posting(bus.is_read("BHV_IPF"));
        bus.deliver();
        let drove = helm.state() == HelmState::Drive;
        let nav_places = model.nav().vars().map(|(var, _)| bus.place(var));
        let report_places = ["NODE_REPORT", "NODE_REPORT_LOCAL"].map(|var| bus.place(var));
        Ok(Live {
            nav_places,
            report_places,
            start: model.nav(),
            bus,
            helm,
            cycle,
            model,
            shift,
            mgr,
            geo: plan.origin.map(|(la, lo)| Geodesy::new(la, lo)),
            kh: 1,
            ks: 0,
            kr: 1,
            kc: 1,
            last_sim: 0.0,
            drove,
            over: false,
            sim_in: Vec::new(),
            helm_in: Vec::new(),
            mgr_in: Vec::new(),
            helm_reports: Pending::default(),
            mgr_reports: Pending::default(),
            hears_reports: [false; 2],
            hears_local: false,
            local: None,
            mgr_text: Value::Str(String::new()),
            relay_text: Value::Str(String::new()),
            report: String::new(),
            report_index: 0,
            length_field: format!(",LENGTH={}", plan.length),
            obm,
        })
    }

    fn times(&self, p: &VehiclePlan) -> [f64; 4] {
        let th = if self.over {
            f64::INFINITY
        } else {
            self.kh as f64 / p.helm_tick
        };
        [
            th,
            self.ks as f64 / p.sim_tick,
            self.kr as f64 / p.report_tick,
            self.kc as f64 / p.cmgr_tick,
        ]
    }

    /// The time (s from the start) of this vehicle's next app tick.
    pub fn next(&self, p: &VehiclePlan) -> f64 {
        let t = self.times(p).into_iter().fold(f64::INFINITY, f64::min);
        self.obm.as_ref().map_or(t, |o| t.min(o.next()))
    }

    pub fn nav(&self) -> Nav {
        self.model.nav()
    }

    pub fn helm_state(&self) -> &'static str {
        self.helm.state().as_str()
    }

    pub fn iterations(&self) -> u64 {
        self.cycle.status.iterations
    }

    /// The apps whose tick is `off` run (simulator, node reporter, contact manager,
    /// helm, in that order: delivery is at the end of the step, so the order only
    /// orders the log). `mission_over`: apply the helm's stop rule. True when the
    /// simulator stepped.
    pub fn step(&mut self, p: &VehiclePlan, off: f64, now: f64, mission_over: bool) -> bool {
        let [th, ts, tr, tc] = self.times(p);
        if ts == off {
            self.bus.fetch(SIM, &mut self.sim_in);
            // A parked helm's all-stop does not steer (as in the one-vehicle run).
            let parked = self.helm.state() != HelmState::Drive;
            for m in &self.sim_in {
                if let Value::Num(v) = m.value {
                    if !(parked && m.var == "DESIRED_HEADING") {
                        self.model.on_mail(&m.var, self.shift.command(&m.var, v));
                    }
                }
            }
            self.model.step(off - self.last_sim);
            self.last_sim = off;
            let nav = self.model.nav();
            self.bus.observer.track.push(nav.x, nav.y);
            for ((var, value), &i) in nav.vars().into_iter().zip(&self.nav_places) {
                self.bus
                    .post_at(i, SIM_NAME, var, &Value::Num(value), "", now);
            }
            self.ks += 1;
        }
        if tr == off {
            self.node_report(p, now);
            self.kr += 1;
        }
        if tc == off {
            self.contact_manager(now);
            self.kc += 1;
        }
        if let Some(o) = &mut self.obm {
            o.step(&mut self.bus, off, now);
        }
        if th == off {
            if mission_over && self.cycle.status.end.is_over(now) {
                self.over = true;
            } else {
                self.bus.fetch(HELM, &mut self.helm_in);
                self.helm_reports.take(&self.helm_in);
                self.cycle
                    .mail_parsed(&mut self.helm, now, &self.helm_in, &self.helm_reports);
                self.cycle.iterate(&mut self.helm, &mut self.bus, now);
                self.drove |= self.helm.state() == HelmState::Drive;
                self.kh += 1;
            }
        }
        ts == off
    }

    /// pNodeReporter's `NODE_REPORT_LOCAL` (contacts-appcast.md §2.2), kept read for
    /// its readers (see [`Ownship`]).
    fn node_report(&mut self, p: &VehiclePlan, now: f64) {
        let nav = self.model.nav();
        let own = Ownship {
            name: &p.spec.name,
            x: nav.x,
            y: nav.y,
            spd: nav.speed,
            hdg: nav.heading,
            dep: nav.depth,
            latlon: self.geo.as_ref().map(|g| g.to_latlon(nav.x, nav.y)),
            vtype: &p.vtype,
            color: &p.spec.moos_color,
            mode: self.helm.state().as_str(),
            index: self.report_index,
            yaw: (90.0 - nav.heading).to_radians(),
            time: now,
            length_field: &self.length_field,
        };
        let mut r = std::mem::take(&mut self.report);
        let local = own.relayed(&mut r);
        self.report_index += 1;
        let v = Value::Str(r);
        let [_, own] = self.report_places;
        self.bus
            .post_at(own, REPORTER_NAME, "NODE_REPORT_LOCAL", &v, "", now);
        if let Value::Str(r) = v {
            self.report = r;
        }
        // The helm reads it next (the shoreside's copy is taken from `local`).
        self.hears_local = self.hears_local || self.bus.subscribes(HELM, "NODE_REPORT_LOCAL");
        if !self.over && self.hears_local {
            self.helm_reports.push(local.clone());
        }
        self.local = Some(local);
    }

    fn contact_manager(&mut self, now: f64) {
        self.bus.fetch(CMGR, &mut self.mgr_in);
        let mut batch: Vec<(&str, MailValue<'_>)> = Vec::with_capacity(self.mgr_in.len());
        for m in &self.mgr_in {
            let v = match &m.value {
                Value::Num(n) => MailValue::Num(*n),
                Value::Str(s) => MailValue::Str(s),
            };
            batch.push((m.var.as_str(), v));
        }
        self.mgr_reports.take(&self.mgr_in);
        self.mgr.handle_mail_parsed(now, &batch, &self.mgr_reports);
        drop(batch);
        for post in self.mgr.iterate(now) {
            match &post.val {
                contact_manager::Value::Str(s) => {
                    // A kept string value, refilled (the bus copies what it keeps).
                    if let Value::Str(text) = &mut self.mgr_text {
                        text.clear();
                        text.push_str(s);
                    }
                    self.bus.post(CMGR_NAME, &post.var, &self.mgr_text, "", now);
                }
                contact_manager::Value::Num(n) => {
                    self.bus
                        .post(CMGR_NAME, &post.var, &Value::Num(*n), "", now);
                }
            }
        }
    }

    /// The comms model delivers another vehicle's report `r` (as `NODE_REPORT`); the
    /// helm and the contact manager will read it as they fetch it (see [`Pending`]).
    pub fn receive_report(&mut self, r: Rc<Relayed>, now: f64) {
        if let Value::Str(text) = &mut self.relay_text {
            text.clear();
            text.push_str(r.text());
        }
        let [relayed, _] = self.report_places;
        self.bus.post_at(
            relayed,
            COMMS_NAME,
            "NODE_REPORT",
            &self.relay_text,
            "",
            now,
        );
        // Only for an app that will fetch it (a helm that is over fetches no more).
        for (hears, app) in self.hears_reports.iter_mut().zip([HELM, CMGR]) {
            *hears = *hears || self.bus.subscribes(app, "NODE_REPORT");
        }
        if !self.over && self.hears_reports[0] {
            self.helm_reports.push(r.clone());
        }
        if self.hears_reports[1] {
            self.mgr_reports.push(r);
        }
    }

    /// The shoreside's pick-up: the node reports posted in the last step.
    pub fn take_reports(&mut self, out: &mut Vec<Mail>) {
        self.bus.fetch(SHORE, out);
    }

    /// The report this vehicle's reporter last wrote, read, if its text is `text` (the
    /// shoreside relays it rather than a copy to read again).
    pub fn written(&self, text: &str) -> Option<Rc<Relayed>> {
        self.local.as_ref().filter(|r| r.text() == text).cloned()
    }

    /// Flush the `.alog` (an error is kept on the bus and reported by the caller).
    pub fn finish(&mut self) {
        if let Some(w) = &mut self.bus.alog {
            if let Err(e) = w.flush() {
                self.bus.alog_error = Some(e);
            }
        }
    }
}
