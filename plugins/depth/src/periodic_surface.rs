//! BHV_PeriodicSurface (behaviors-more.md §7): every `period` seconds without a mark
//! (e.g. a GPS fix), ascend to the surface, stay up to `max_time_at_surface`, resume.
//! A coupled speed × depth function only while ascending or at the surface.

use behavior_api::ivp;
use behavior_api::kept::{CoupledPeaks, Kept};
use behavior_api::params::non_negative;
use behavior_api::parse_number;
use behavior_api::sdk::{copy_function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::zaic::Peak;
use behavior_api::FunctionData;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grade {
    Linear,
    Quadratic,
    Quasi,
    FullSpeed,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Waiting,
    Ascending,
    AtSurface,
}

/// `VAR,INTERVAL,MAXTIME`: each new value of VAR extends the period by INTERVAL, up to
/// MAXTIME in all.
#[derive(Clone, Debug, PartialEq)]
struct Acomms {
    var: String,
    interval: f64,
    max_time: f64,
}

pub struct PeriodicSurface {
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    period: f64,
    mark_var: String,
    acomms: Option<Acomms>,
    pending_var: String,
    atsurface_var: String,
    /// Negative: NAV_SPEED at the start of the ascent (`current`).
    ascent_speed: f64,
    zero_speed_depth: f64,
    max_time_at_surface: f64,
    grade: Grade,

    state: State,
    first: bool,
    /// The reference reads this before ever setting it (0 in practice).
    mark_time: f64,
    ext: f64,
    first_num_mark: bool,
    first_str_mark: bool,
    last_num_mark: f64,
    last_str_mark: String,
    last_acomms: String,
    /// Scratch for the texts read every iteration.
    text: String,
    depth_at_ascent: f64,
    speed_at_ascent: f64,
    surface_time: f64,
    /// The function of the last desired speed (by its bits), without pwt: it depends on
    /// nothing else, so at the surface (speed 0 every iteration) it is copied, not built.
    last: Kept<u64>,
    /// The depth function (it never changes) and the speed builder, kept for the
    /// ascent, whose speed changes every iteration.
    peaks: CoupledPeaks,
}

/// The C `(int)` conversion of x86: out-of-range values become `INT_MIN`.
fn c_int(x: f64) -> f64 {
    if x.is_nan() || x >= 2_147_483_648.0 || x <= -2_147_483_649.0 {
        -2_147_483_648.0
    } else {
        x.trunc()
    }
}

impl PeriodicSurface {
    pub fn new(helm_domain: &HelmDomain) -> Self {
        PeriodicSurface {
            domain: helm_domain.sub_domain(&["speed", "depth"]),
            ivp_domain: helm_domain.ivp_domain(&["speed", "depth"]),
            period: 300.0,
            mark_var: "GPS_UPDATE_RECEIVED".into(),
            acomms: None,
            pending_var: "PENDING_SURFACE".into(),
            atsurface_var: "TIME_AT_SURFACE".into(),
            ascent_speed: -1.0,
            zero_speed_depth: 0.0,
            max_time_at_surface: 300.0,
            grade: Grade::Linear,
            state: State::Waiting,
            first: true,
            mark_time: 0.0,
            ext: 0.0,
            first_num_mark: true,
            first_str_mark: true,
            last_num_mark: 0.0,
            last_str_mark: String::new(),
            last_acomms: String::new(),
            text: String::new(),
            depth_at_ascent: 0.0,
            speed_at_ascent: 0.0,
            surface_time: 0.0,
            last: Kept::default(),
            peaks: CoupledPeaks::over("speed", "depth"),
        }
    }

    /// (depth, speed, now); `None` (after the error) when either is missing.
    fn read(&self, ctx: &mut Ctx<'_>) -> (Option<(f64, f64)>, f64) {
        let depth = ctx.get_buffer_double_val("NAV_DEPTH");
        let speed = ctx.get_buffer_double_val("NAV_SPEED");
        let now = ctx.get_buffer_curr_time();
        match (depth, speed) {
            (Some(d), Some(s)) => (Some((d, s)), now),
            _ => {
                ctx.post_emessage("No ownship NAV_DEPTH or NAV_SPEED in info_buffer");
                (None, now)
            }
        }
    }

    fn remaining(&self, now: f64) -> f64 {
        self.period - (now - self.mark_time) + self.ext
    }

    fn post_pending(&self, ctx: &mut Ctx<'_>, now: f64) {
        let r = self.remaining(now);
        ctx.post_message_num(&self.pending_var, c_int(r + 0.5));
    }

    /// A new mark in the mark variable (numeric or string form) since the last one.
    fn mark_noted(&mut self, ctx: &mut Ctx<'_>) -> bool {
        let mut noted = false;
        if let Some(v) = ctx.get_buffer_double_val_quiet(&self.mark_var) {
            if self.first_num_mark || v != self.last_num_mark {
                self.first_num_mark = false;
                self.last_num_mark = v;
                noted = true;
            }
        }
        // Read into a kept string: the mark variable is read every iteration.
        let mut s = std::mem::take(&mut self.text);
        if ctx.get_buffer_string_val_quiet_into(&self.mark_var, &mut s)
            && (self.first_str_mark || s != self.last_str_mark)
        {
            self.first_str_mark = false;
            std::mem::swap(&mut self.last_str_mark, &mut s);
            noted = true;
        }
        self.text = s;
        noted
    }

    fn check_acomms(&mut self, ctx: &mut Ctx<'_>) {
        let Some(a) = &self.acomms else { return };
        if self.ext >= a.max_time {
            return;
        }
        let (interval, max_time) = (a.interval, a.max_time);
        let mut s = std::mem::take(&mut self.text);
        if ctx.get_buffer_string_val_into(&a.var, &mut s) && s != self.last_acomms {
            std::mem::swap(&mut self.last_acomms, &mut s);
            self.ext = (self.ext + interval).min(max_time);
        }
        self.text = s;
    }

    fn ascent_speed_now(&self, depth: f64) -> f64 {
        let (d0, z, v0) = (
            self.depth_at_ascent,
            self.zero_speed_depth,
            self.speed_at_ascent,
        );
        if d0 <= z || depth <= z {
            return 0.0;
        }
        if depth > d0 {
            return v0;
        }
        let pct = (depth - z) / (d0 - z);
        match self.grade {
            Grade::Linear => v0 * pct,
            Grade::Quadratic => v0 * pct * pct,
            Grade::Quasi => v0 * pct.powf(1.5),
            Grade::FullSpeed => v0,
        }
    }

    fn function(&mut self, ctx: &mut Ctx<'_>, speed: f64) -> Option<FunctionData> {
        let (dom, peaks) = (&self.ivp_domain, &mut self.peaks);
        let kept = self
            .last
            .get(speed.to_bits(), || build(dom, peaks, speed).ok_or(()));
        Some(copy_function_data(kept.ok()?, ctx.priority()))
    }
}

/// The coupled speed × depth function of ascending at `speed`, without pwt: a speed
/// peak at `speed`, 0.5 wide (a point at 0), and a depth peak at the surface, coupled
/// 50/50.
fn build(
    dom: &Option<ivp::Domain>,
    peaks: &mut CoupledPeaks,
    speed: f64,
) -> Option<ivp::IvpFunction> {
    let spd = Peak {
        summit: speed,
        base_width: if speed == 0.0 { 0.0 } else { 0.5 },
        ..Peak::default()
    };
    peaks.build(dom.as_ref()?, &spd, &Peak::default())
}

impl IvpBehavior for PeriodicSurface {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "???".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let value = value.trim();
        let nonempty = |v: &str| (!v.is_empty()).then(|| v.to_string());
        match param {
            "period" => match parse_number(value) {
                Some(v) if v > 0.0 => self.period = v,
                _ => return false,
            },
            "mark_variable" => match nonempty(value) {
                Some(v) => {
                    ctx.add_info_vars_no_warning(&v);
                    self.mark_var = v;
                }
                None => return false,
            },
            "acomms_mark_variable" => {
                let f: Vec<&str> = value.split(',').map(str::trim).collect();
                if f.len() != 3 || f[0].is_empty() || f[0].chars().any(char::is_whitespace) {
                    return false;
                }
                let (Some(interval), Some(max_time)) = (parse_number(f[1]), parse_number(f[2]))
                else {
                    return false;
                };
                if interval <= 0.0 || max_time < interval {
                    return false;
                }
                ctx.add_info_vars(f[0]);
                self.acomms = Some(Acomms {
                    var: f[0].to_string(),
                    interval,
                    max_time,
                });
                self.ext = 0.0;
            }
            "pending_status_variable" | "pending_status_var" => match nonempty(value) {
                Some(v) => self.pending_var = v,
                None => return false,
            },
            "atsurface_status_variable" | "atsurface_status_var" => match nonempty(value) {
                Some(v) => self.atsurface_var = v,
                None => return false,
            },
            "ascent_speed" | "speed_to_surface" => {
                if value == "current" {
                    self.ascent_speed = -1.0;
                } else {
                    match non_negative(value) {
                        Some(v) => self.ascent_speed = v,
                        None => return false,
                    }
                }
            }
            "zero_speed_depth" => match non_negative(value) {
                Some(v) => self.zero_speed_depth = v,
                None => return false,
            },
            "max_time_at_surface" => match non_negative(value) {
                Some(v) => self.max_time_at_surface = v,
                None => return false,
            },
            "ascent_grade" => {
                self.grade = match value.to_ascii_lowercase().as_str() {
                    "linear" => Grade::Linear,
                    "quadratic" => Grade::Quadratic,
                    "quasi" => Grade::Quasi,
                    "fullspeed" => Grade::FullSpeed,
                    _ => return false,
                }
            }
            _ => return false,
        }
        true
    }

    fn on_params_complete(&mut self, ctx: &mut Ctx<'_>) {
        ctx.add_info_vars("NAV_DEPTH, NAV_SPEED");
        let mark = self.mark_var.clone();
        ctx.add_info_vars_no_warning(&mark);
    }

    fn on_idle_state(&mut self, ctx: &mut Ctx<'_>) {
        let (nav, now) = self.read(ctx);
        let depth = nav.map_or(0.0, |n| n.0);
        if depth >= self.zero_speed_depth && self.first {
            self.first = false;
            self.mark_time = now;
        }
        self.post_pending(ctx, now);
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        let (nav, now) = self.read(ctx);
        let Some((depth, spd)) = nav else {
            let var = self.pending_var.clone();
            ctx.post_message(&var, "ERROR");
            return None;
        };
        let remaining = self.remaining(now);
        self.post_pending(ctx, now);

        let noted = if self.first {
            self.first = false;
            true
        } else {
            self.mark_noted(ctx)
        };
        if noted {
            self.mark_time = now;
            self.ext = 0.0;
            return None;
        }
        self.check_acomms(ctx);

        let at_var = self.atsurface_var.as_str();
        if remaining > 0.0 {
            self.state = State::Waiting;
            ctx.post_message_num(at_var, 0.0);
            return None;
        }
        if self.state == State::Waiting {
            self.state = State::Ascending;
            ctx.post_message("PERIODIC_ASCEND", "true");
            self.depth_at_ascent = depth;
            self.speed_at_ascent = if self.ascent_speed < 0.0 {
                spd
            } else {
                self.ascent_speed
            };
        }
        if self.state == State::Ascending && depth <= self.zero_speed_depth {
            ctx.post_message("PERIODIC_ASCEND", "false");
            self.state = State::AtSurface;
            self.surface_time = now;
        }
        if self.state == State::AtSurface {
            let t = now - self.surface_time;
            ctx.post_message_num(at_var, c_int(t + 0.5));
            if t >= self.max_time_at_surface {
                self.mark_time = now;
                self.state = State::Waiting;
                ctx.post_message("PSF_AT_SURFACE_TIMEOUT", &format!("Timestamp={now:.2}"));
                return None;
            }
        } else {
            ctx.post_message_num(at_var, 0.0);
        }
        let ds = if self.state == State::Ascending {
            self.ascent_speed_now(depth)
        } else {
            0.0
        };
        self.function(ctx, ds)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::ivp::ZaicPeak;
    use behavior_api::testing::MockHelm;

    /// The function handed out (copied from the kept one while the speed repeats) is bit
    /// for bit the fresh build's, over speeds that change, repeat and come back.
    #[test]
    fn kept_function_equals_a_fresh_build() {
        let (mut b, mut helm) = psurf(&[]);
        let speeds = [0.0, 0.0, 1.25, 1.25, 0.7, 0.0, -0.0, 1.25, 3.9, 0.0];
        for (round, &speed) in speeds.iter().cycle().take(100).enumerate() {
            let got = helm.with(|ctx| b.function(ctx, speed)).unwrap();
            let mut want = reference(&b.ivp_domain, speed).unwrap();
            want.set_pwt(helm.with(|ctx| ctx.priority()));
            let want = behavior_api::sdk::function_data(want);
            let parts = behavior_api::testing::function_data_bits;
            assert_eq!(parts(&got), parts(&want), "round {round} speed {speed}");
        }
    }

    /// The reference: the speed and depth peaks set up as the spec describes, each
    /// made into a function afresh, then coupled.
    fn reference(dom: &Option<ivp::Domain>, speed: f64) -> Option<ivp::IvpFunction> {
        let dom = dom.as_ref()?;
        let mut zs = ZaicPeak::new(dom, "speed").ok()?;
        zs.set_summit(speed, 0);
        zs.set_base_width(if speed == 0.0 { 0.0 } else { 0.5 }, 0);
        zs.set_peak_width(0.0, 0);
        zs.set_min_max_util(0.0, 100.0, 0);
        let mut zd = ZaicPeak::new(dom, "depth").ok()?;
        zd.set_summit(0.0, 0);
        zd.set_base_width(0.0, 0);
        zd.set_peak_width(0.0, 0);
        zd.set_min_max_util(0.0, 100.0, 0);
        behavior_api::ivp::couple(zs.extract(true)?, zd.extract(true)?, 50.0, 50.0, true)
    }

    /// The kept depth function and speed builder give the fresh build bit for bit, or
    /// fail where it fails, over speeds in and out of range (a refused one included).
    #[test]
    fn kept_parts_equal_a_fresh_build() {
        let (b, _) = psurf(&[]);
        let mut peaks = CoupledPeaks::over("speed", "depth");
        let speeds = [
            0.7,
            0.0,
            4.0,
            f64::NAN,
            5.5,
            -0.0,
            -1.0,
            2.35,
            f64::INFINITY,
            0.7,
        ];
        for (round, &speed) in speeds.iter().cycle().take(60).enumerate() {
            let want = reference(&b.ivp_domain, speed);
            let got = build(&b.ivp_domain, &mut peaks, speed);
            let bits = behavior_api::testing::function_bits;
            assert_eq!(
                want.as_ref().map(bits),
                got.as_ref().map(bits),
                "round {round} speed {speed}"
            );
        }
    }

    fn psurf(params: &[(&str, &str)]) -> (PeriodicSurface, MockHelm) {
        let mut b = PeriodicSurface::new(&HelmDomain::new(
            "course,0,359,360:speed,0,4,41:depth,0,100,101",
        ));
        let mut helm = MockHelm::new("psurf");
        for (p, v) in params {
            assert!(helm.with(|ctx| b.set_param(ctx, p, v)), "{p}={v}");
        }
        (b, helm)
    }

    #[test]
    fn parameters_and_refusals() {
        let (mut b, mut helm) = psurf(&[
            ("ascent_speed", "current"),
            ("ascent_grade", "QUASI"),
            ("acomms_mark_variable", "ACOMMS, 10, 30"),
        ]);
        assert_eq!(b.domain(), "speed,0,4,41:depth,0,100,101");
        assert_eq!(b.default_name(), "???");
        assert_eq!(
            (b.period, b.grade, b.ascent_speed),
            (300.0, Grade::Quasi, -1.0)
        );
        helm.with(|ctx| {
            for (p, v) in [
                ("period", "0"),
                ("period", "often"),
                ("mark_variable", " "),
                ("acomms_mark_variable", "A,10"),
                ("acomms_mark_variable", "A,10,5"),
                ("acomms_mark_variable", "A,0,5"),
                ("ascent_speed", "-1"),
                ("ascent_grade", "steep"),
                ("zero_speed_depth", "-2"),
                ("max_time_at_surface", "x"),
                ("pending_status_var", ""),
            ] {
                assert!(!b.set_param(ctx, p, v), "{p}={v}");
            }
        });
        assert_eq!(b.acomms.as_ref().map(|a| a.max_time), Some(30.0));
    }

    /// A text mark is noted when it changes (and the first time), not while it holds;
    /// each new acomms text extends the period by its interval up to the maximum.
    #[test]
    fn text_marks_and_acomms_extensions() {
        let (mut b, mut helm) = psurf(&[("acomms_mark_variable", "ACOMMS, 10, 25")]);
        helm.with(|ctx| assert!(!b.mark_noted(ctx)));
        let mut noted = Vec::new();
        for text in ["a", "a", "b", "b", "b", "a"] {
            helm.strs.insert("GPS_UPDATE_RECEIVED".into(), text.into());
            noted.push(helm.with(|ctx| b.mark_noted(ctx)));
        }
        assert_eq!(noted, [true, false, true, false, false, true]);
        let mut ext = Vec::new();
        for text in ["m1", "m1", "m2", "m3", "m4", "m5"] {
            helm.strs.insert("ACOMMS".into(), text.into());
            helm.with(|ctx| b.check_acomms(ctx));
            ext.push(b.ext);
        }
        assert_eq!(ext, [10.0, 10.0, 20.0, 25.0, 25.0, 25.0]);
    }

    #[test]
    fn first_idle_pending_overflows_like_the_reference() {
        let (mut b, mut helm) = psurf(&[("zero_speed_depth", "1")]);
        helm.time = 17_955_199_444.0;
        helm.set("NAV_DEPTH", 0.0);
        helm.set("NAV_SPEED", 0.0);
        helm.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(helm.last("PENDING_SURFACE").as_deref(), Some("-2147483648"));
        // At depth the mark time is set and the count starts at the period.
        helm.set("NAV_DEPTH", 5.0);
        helm.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(helm.last("PENDING_SURFACE").as_deref(), Some("300"));
    }

    #[test]
    fn cycle_ascend_surface_timeout() {
        let (mut b, mut helm) = psurf(&[
            ("period", "40"),
            ("zero_speed_depth", "1"),
            ("max_time_at_surface", "15"),
            ("ascent_speed", "1"),
        ]);
        helm.set("NAV_DEPTH", 10.0);
        helm.set("NAV_SPEED", 2.0);
        // First running iteration without an idle one before: counts as a mark.
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        helm.time += 41.0;
        let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(helm.last("PERIODIC_ASCEND").as_deref(), Some("true"));
        assert_eq!(helm.last("TIME_AT_SURFACE").as_deref(), Some("0"));
        assert_eq!(f.var_names().collect::<Vec<_>>(), vec!["speed", "depth"]);
        // Half way up: half the ascent speed (linear).
        assert_eq!(b.ascent_speed_now(5.5), 0.5);
        helm.set("NAV_DEPTH", 0.5);
        helm.time += 5.0;
        assert!(helm.with(|ctx| b.on_run(ctx)).is_some());
        assert_eq!(helm.last("PERIODIC_ASCEND").as_deref(), Some("false"));
        helm.time += 15.0;
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(helm.last("TIME_AT_SURFACE").as_deref(), Some("15"));
        assert_eq!(
            helm.last("PSF_AT_SURFACE_TIMEOUT").unwrap(),
            format!("Timestamp={:.2}", helm.time)
        );
        assert_eq!(b.state, State::Waiting);
    }

    #[test]
    fn missing_nav_is_an_error_in_both_states() {
        let (mut b, mut helm) = psurf(&[]);
        helm.with(|ctx| b.on_idle_state(ctx));
        assert_eq!(helm.posted("BHV_ERROR").len(), 1);
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(helm.last("PENDING_SURFACE").as_deref(), Some("ERROR"));
    }
}
