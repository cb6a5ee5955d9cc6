//! BHV_LegRun (behaviors-more.md §9): back and forth along the leg P1–P2 with a
//! generated U-turn at each end, leg speed schedules and per-leg/turn flags.

use std::collections::HashMap;

use behavior_api::flag::FlagList;
use behavior_api::geometry::rel_ang;
use behavior_api::ivp;
use behavior_api::platform::platform_update;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

use crate::objective::{Objective, Shape};
use crate::odometer::Odometer;
use engine::{Pt, WptEngine};
use leg::Leg;
use wrap::WrapDetector;

pub mod engine;
pub mod leg;
mod params;
#[cfg(test)]
mod tests;
pub mod turn;
mod visuals;
mod wrap;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Init,
    Leg1,
    Turn1,
    Leg2,
    Turn2,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Init => "init",
            Mode::Leg1 => "leg1",
            Mode::Turn1 => "turn1",
            Mode::Leg2 => "leg2",
            Mode::Turn2 => "turn2",
        }
    }
    fn is_turn(self) -> bool {
        matches!(self, Mode::Turn1 | Mode::Turn2)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InitMode {
    Fixed,
    CloseTurn,
    FarTurn,
    Resume,
}

#[derive(Clone, Debug, Default)]
struct Flags {
    leg_end: FlagList,
    leg1_end: FlagList,
    leg2_end: FlagList,
    turn_end: FlagList,
    turn1_end: FlagList,
    turn2_end: FlagList,
    mid_leg: FlagList,
    mid_turn: FlagList,
}

/// LegRun's speed and course functions.
const SHAPE: Shape = Shape {
    spd_high_util: 70.0,
    peak_width: None,
};

pub struct LegRun {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    max_spd: f64,
    speed: f64,
    patience: f64,
    leg: Leg,
    leg_engine: WptEngine,
    turn_engine: WptEngine,
    init_mode: InitMode,
    spds: Vec<f64>,
    spd_pos: usize,
    spds_onturn: bool,
    spds_repeat: bool,
    cur_spd: f64,
    mid_leg_pct: f64,
    mid_turn_pct: f64,
    flags: Flags,
    hints: HashMap<String, String>,
    /// The VIEW_* texts kept between iterations.
    texts: visuals::Texts,
    mode: Mode,
    pending: Option<Mode>,
    leg_count: u64,
    leg_count1: u64,
    leg_count2: u64,
    mid_leg_done: bool,
    mid_turn_done: bool,
    preview_pending: bool,
    odo: Odometer,
    wrap: WrapDetector,
    os: Pt,
    markers: [Option<Pt>; 2],
    started: bool,
    /// The track point of the engine stepped last with success.
    aim: Pt,
    objective: Objective,
}

impl LegRun {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        LegRun {
            domain: helm_domain.sub_domain(&["course", "speed"]),
            ivp_domain: helm_domain.ivp_domain(&["course", "speed"]),
            max_spd: helm_domain.var("speed").map_or(0.0, |v| v.high),
            speed: 0.0,
            patience: 50.0,
            leg: Leg::default(),
            leg_engine: WptEngine::default(),
            turn_engine: WptEngine::default(),
            init_mode: InitMode::Fixed,
            spds: Vec::new(),
            spd_pos: 0,
            spds_onturn: false,
            spds_repeat: false,
            cur_spd: -1.0,
            mid_leg_pct: 25.0,
            mid_turn_pct: 25.0,
            flags: Flags::default(),
            hints: visuals::default_hints(),
            texts: visuals::Texts::default(),
            mode: Mode::Init,
            pending: None,
            leg_count: 0,
            leg_count1: 0,
            leg_count2: 0,
            mid_leg_done: false,
            mid_turn_done: false,
            preview_pending: true,
            odo: Odometer::default(),
            wrap: WrapDetector::default(),
            os: (0.0, 0.0),
            markers: [None, None],
            started: false,
            aim: (0.0, 0.0),
            objective: Objective::default(),
        }
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    fn set_mode(&mut self, ctx: &mut Ctx<'_>, m: Mode) {
        self.mode = m;
        ctx.post_message("LR_MODE", m.name());
        self.post_mode_report(ctx);
    }

    fn post_flags(&self, ctx: &mut Ctx<'_>, flags: &FlagList, repeatable: bool) {
        flags.post(ctx, repeatable, |f| self.expand(f));
    }

    fn init_leg_mode(&mut self, ctx: &mut Ctx<'_>) {
        let (Some(p1), Some(p2)) = (self.leg.p1, self.leg.p2) else {
            return;
        };
        let d1 = (self.os.0 - p1.0).hypot(self.os.1 - p1.1);
        let d2 = (self.os.0 - p2.0).hypot(self.os.1 - p2.1);
        let leg1 = match self.init_mode {
            InitMode::Fixed => true,
            InitMode::FarTurn => d1 > d2,
            InitMode::CloseTurn => d1 < d2,
            InitMode::Resume => {
                ctx.post_emessage("Bad init leg direction, check init_leg_mode param.");
                return;
            }
        };
        if leg1 {
            self.set_mode(ctx, Mode::Leg1);
            self.leg_engine.set_curr_index(0);
        } else {
            self.set_mode(ctx, Mode::Leg2);
            self.leg_engine.set_curr_index(1);
        }
    }

    fn leg_step(&mut self, ctx: &mut Ctx<'_>) -> bool {
        if self.leg_engine.pts.is_empty() {
            return false;
        }
        self.leg_engine.step(self.os);
        if self.leg_engine.advanced() {
            self.post_flags(ctx, &self.flags.leg_end, true);
            if self.mode == Mode::Leg1 {
                self.post_flags(ctx, &self.flags.leg1_end, true);
                self.pending = Some(Mode::Turn1);
            } else {
                self.post_flags(ctx, &self.flags.leg2_end, true);
                self.pending = Some(Mode::Turn2);
            }
            self.odo.pause(true);
        }
        if self.leg_engine.completed() {
            // The reference posts the endflags under the default key without completing;
            // the SDK posts them only through the common completion (repeatable, and a
            // non-perpetual LegRun is then removed).
            ctx.set_complete();
            if ctx.perpetual() {
                self.leg_engine.reset_for_new_traversal();
            }
            self.erase_steer_points(ctx);
            return false;
        }
        let track = self.leg_engine.track;
        self.aim = track;
        let next = self.leg_engine.current().unwrap_or(track);
        self.post_steer_points(ctx, track, next);
        self.post_leg_points(ctx, true);
        let p = 100.0 * self.leg_engine.pct_to_next(self.os);
        if p > self.mid_leg_pct && !self.mid_leg_done {
            self.post_flags(ctx, &self.flags.mid_leg, true);
            self.mid_leg_done = true;
        }
        true
    }

    fn turn_step(&mut self, ctx: &mut Ctx<'_>) -> bool {
        self.turn_engine.step(self.os);
        if self.turn_engine.completed() {
            self.post_flags(ctx, &self.flags.turn_end, true);
            if self.mode == Mode::Turn1 {
                self.post_flags(ctx, &self.flags.turn1_end, true);
                self.pending = Some(Mode::Leg2);
            } else {
                self.post_flags(ctx, &self.flags.turn2_end, true);
                self.pending = Some(Mode::Leg1);
            }
            self.erase_turn_path(ctx);
            self.erase_steer_points(ctx);
            self.wrap.reset();
            self.odo.reset();
            self.odo.pause(false);
            return false;
        }
        if self.turn_engine.advanced() {
            self.post_turn_path(ctx);
        }
        let track = self.turn_engine.track;
        self.aim = track;
        let next = self.turn_engine.current().unwrap_or(track);
        self.post_steer_points(ctx, track, next);
        self.post_leg_points(ctx, true);
        let p = 100.0 * self.turn_engine.pct_to_end(self.os);
        if p > self.mid_turn_pct && !self.mid_turn_done {
            self.post_flags(ctx, &self.flags.mid_turn, true);
            self.mid_turn_done = true;
        }
        true
    }

    fn step_mode(&mut self, ctx: &mut Ctx<'_>) -> bool {
        match self.mode {
            Mode::Leg1 | Mode::Leg2 => self.leg_step(ctx),
            Mode::Turn1 | Mode::Turn2 => self.turn_step(ctx),
            Mode::Init => false,
        }
    }

    fn switch_mode(&mut self, ctx: &mut Ctx<'_>) {
        let Some(p) = self.pending.filter(|p| *p != self.mode) else {
            return;
        };
        self.set_mode(ctx, p);
        self.pending = None;
        self.mid_leg_done = false;
        self.mid_turn_done = false;
        if p.is_turn() {
            self.leg_count += 1;
            let which = if p == Mode::Turn1 {
                self.leg_count1 += 1;
                0
            } else {
                self.leg_count2 += 1;
                1
            };
            self.turn_engine.reset_state();
            self.turn_engine
                .set_seglist(self.leg.turn_path(which), false);
            self.post_turn_path(ctx);
        }
        self.update_leg_speed(p);
    }

    fn update_leg_speed(&mut self, m: Mode) {
        if m.is_turn() {
            if !self.spds_onturn {
                self.cur_spd = -1.0;
            }
            return;
        }
        self.cur_spd = -1.0;
        if self.spds.is_empty() {
            return;
        }
        if self.spd_pos >= self.spds.len() {
            if self.spds_repeat {
                self.spd_pos = 0;
                self.cur_spd = self.spds[0];
            } else {
                self.spds.clear();
            }
        } else {
            self.cur_spd = self.spds[self.spd_pos];
            self.spd_pos += 1;
        }
    }

    fn function(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let v = if self.cur_spd > 0.0 {
            self.cur_spd
        } else {
            self.speed
        };
        ctx.post_message_num("LR_NOW_SPD", v);
        let dom = self.ivp_domain.as_ref()?;
        // The engine whose step succeeded (a leg's last iteration still aims along the leg).
        let t = self.aim;
        let bearing = rel_ang(self.os.0, self.os.1, t.0, t.1);
        let mut f = self
            .objective
            .build(dom, v, bearing, self.patience, SHAPE)?;
        f.set_pwt(ctx.priority());
        Some(function_data(f))
    }
}

impl IvpBehavior for LegRun {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "legrun".into()
    }

    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        self.set_legrun_param(param, value)
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        if !self.started {
            // The reference's constructor makes LegRun perpetual.
            self.started = true;
            ctx.set_perpetual(true);
            ctx.add_info_vars("NAV_X, NAV_Y, NAV_SPEED");
        }
        if self.leg_engine.max_repeats > 0 {
            ctx.set_perpetual(true);
        }
        if self.leg.valid() {
            ctx.post_retract_wmessage("Invalid or unset legrun");
        } else {
            ctx.post_wmessage("Invalid or unset legrun");
        }
        if self.leg.modified {
            if let (Some(p1), Some(p2)) = (self.leg.p1, self.leg.p2) {
                self.leg_engine.set_seglist(vec![p1, p2], true);
            }
            if self.mode.is_turn() {
                self.erase_turn_path(ctx);
                self.erase_steer_points(ctx);
            }
            self.set_mode(ctx, Mode::Init);
            self.leg.modified = false;
        }
        self.post_settings(ctx);
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        if let Some(p) = platform_update(ctx) {
            self.os = (p.x, p.y);
            self.odo.update(p.x, p.y);
            self.wrap.update(self.os);
        }
    }

    fn on_idle_to_run(&mut self, _ctx: &mut Ctx<'_>) {
        self.preview_pending = true;
        self.mode = match self.mode {
            Mode::Turn1 => Mode::Leg2,
            Mode::Turn2 => Mode::Leg1,
            m => m,
        };
    }

    fn on_run_to_idle(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_all(ctx);
        self.leg_engine.cpa = -1.0;
        self.turn_engine.cpa = -1.0;
    }

    fn on_complete(&mut self, ctx: &mut Ctx<'_>) {
        self.erase_all(ctx);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let Some(p) = platform_update(ctx) else {
            self.erase_all(ctx);
            return None;
        };
        self.os = (p.x, p.y);
        self.odo.update(p.x, p.y);
        self.wrap.update(self.os);
        if !self.leg.valid() {
            return None;
        }
        if self.mode == Mode::Init {
            self.init_leg_mode(ctx);
            if self.mode == Mode::Init {
                return None;
            }
        }
        if self.preview_pending {
            self.post_preview(ctx);
            self.preview_pending = false;
        }
        let mut ok = self.step_mode(ctx);
        self.switch_mode(ctx);
        if !ok {
            ok = self.step_mode(ctx);
        }
        if !ok {
            return None;
        }
        self.function(ctx)
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        Some(self.expand(text))
    }
}
