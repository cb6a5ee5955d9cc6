//! BHV_Shadow (behaviors-contacts.md §4): match the contact's heading and speed.

use behavior_api::contact::ContactBase;
use behavior_api::ivp::{couple, Domain, ZaicPeak};
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::{parse_number, FunctionData};

use behavior_api::kept::CoupledPeaks;
use behavior_api::zaic::Peak;

pub struct Shadow {
    base: ContactBase,
    domain: Option<Domain>,
    domain_spec: String,
    pwt_outer_dist: f64,
    hdg_peak: f64,
    hdg_base: f64,
    spd_peak: f64,
    spd_base: f64,
    /// The coupled function's kept parts.
    peaks: CoupledPeaks,
}

impl Shadow {
    pub fn new(helm: &HelmDomain) -> Self {
        Shadow {
            base: ContactBase::new(60.0),
            domain: helm.ivp_domain(&["course", "speed"]),
            domain_spec: helm.sub_domain(&["course", "speed"]),
            pwt_outer_dist: 0.0,
            hdg_peak: 20.0,
            hdg_base: 160.0,
            spd_peak: 0.1,
            spd_base: 2.0,
            peaks: CoupledPeaks::default(),
        }
    }

    fn peak(
        &self,
        var: &str,
        summit: f64,
        widths: (f64, f64),
        delta: f64,
        wrap: bool,
    ) -> Result<behavior_api::ivp::IvpFunction, String> {
        let domain = self.domain.as_ref().ok_or_else(String::new)?;
        let mut z = ZaicPeak::new(domain, var).map_err(|e| e.to_string())?;
        z.set_params(summit, widths.0, widths.1, delta, 0.0, 100.0, 0);
        if wrap {
            z.set_value_wrap(true);
        }
        let w = z.warnings().to_string();
        z.extract(true).ok_or(w)
    }

    /// The function as the reference builds it (both peaks afresh, then coupled),
    /// posting what fails; run when the kept path fails.
    fn reference(
        &self,
        ctx: &mut Ctx<'_>,
        (hdg, spd): (f64, f64),
    ) -> Option<behavior_api::ivp::IvpFunction> {
        let mut failed = |part: &str, warnings: String| {
            ctx.post_emessage(&format!(
                "Unable to generate {part} component of IvP function"
            ));
            ctx.post_wmessage(&warnings);
        };
        let fh = self.peak("course", hdg, (self.hdg_peak, self.hdg_base), 50.0, true);
        let fh = fh.map_err(|w| failed("hdg", w)).ok()?;
        let fs = self.peak("speed", spd, (self.spd_peak, self.spd_base), 10.0, false);
        let fs = fs.map_err(|w| failed("spd", w)).ok()?;
        let f = couple(fh, fs, 50.0, 50.0, true);
        if f.is_none() {
            ctx.post_emessage("Unable to generate coupled IvP function");
        }
        f
    }
}

impl IvpBehavior for Shadow {
    fn domain(&self) -> String {
        self.domain_spec.clone()
    }

    fn default_name(&self) -> String {
        "bhv_shadow".into()
    }

    fn set_param(&mut self, ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        let param = param.to_ascii_lowercase();
        if let Some(ok) = self.base.set_param_with(ctx, &param, value) {
            return ok;
        }
        let field = match param.as_str() {
            "pwt_outer_dist" => &mut self.pwt_outer_dist,
            "heading_peakwidth" | "hdg_peakwidth" => &mut self.hdg_peak,
            "heading_basewidth" | "hdg_basewidth" => &mut self.hdg_base,
            "speed_peakwidth" | "spd_peakwidth" => &mut self.spd_peak,
            "speed_basewidth" | "spd_basewidth" => &mut self.spd_base,
            _ => return false,
        };
        match parse_number(value) {
            Some(v) if v >= 0.0 => {
                *field = v;
                true
            }
            _ => false,
        }
    }

    fn on_spawn(&mut self, _ctx: &mut Ctx<'_>) {
        self.base.spawned();
    }

    fn on_every_state(&mut self, ctx: &mut Ctx<'_>) {
        self.base.every_state(ctx);
    }

    fn on_complete(&mut self, _ctx: &mut Ctx<'_>) {
        self.base.on_complete();
    }

    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if !self.base.update_ok {
            return None;
        }
        self.base.handle_cnflags(ctx);
        // The reference refreshes a second time at the start of its run hook.
        if !self.base.update(ctx) {
            return None;
        }
        let r = self.base.range();
        let relevance = if self.pwt_outer_dist == 0.0 || r < self.pwt_outer_dist {
            1.0
        } else {
            0.0
        };
        let cn = self.base.cn;
        ctx.post_int_message("SHADOW_CONTACT_X", cn.x);
        ctx.post_int_message("SHADOW_CONTACT_Y", cn.y);
        ctx.post_int_message("SHADOW_CONTACT_SPEED", cn.spd);
        ctx.post_int_message("SHADOW_CONTACT_HEADING", cn.hdg);
        ctx.post_int_message("SHADOW_RELEVANCE", relevance);
        if relevance <= 0.0 {
            return None;
        }
        let crs = Peak {
            summit: cn.hdg,
            peak_width: self.hdg_peak,
            base_width: self.hdg_base,
            summit_delta: 50.0,
            value_wrap: true,
            ..Peak::default()
        };
        let spd = Peak {
            summit: cn.spd,
            peak_width: self.spd_peak,
            base_width: self.spd_base,
            summit_delta: 10.0,
            ..Peak::default()
        };
        let built = match self.domain.as_ref() {
            Some(d) => self.peaks.build(d, &crs, &spd),
            None => None,
        };
        // A failure takes the reference's path, which posts what failed.
        let mut f = built.or_else(|| self.reference(ctx, (cn.hdg, cn.spd)))?;
        f.normalize(0.0, 100.0);
        f.set_pwt(relevance * ctx.priority());
        Some(function_data(f))
    }

    fn expand_macros(&self, text: &str) -> Option<String> {
        self.base.expand_macros(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use behavior_api::testing::MockHelm;

    #[test]
    fn posts_rounded_contact_and_relevance_by_range() {
        let mut b = Shadow::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("shadow_ben");
        assert!(helm.with(|ctx| b.set_param(ctx, "contact", "ben")));
        assert!(helm.with(|ctx| b.set_param(ctx, "pwt_outer_dist", "45")));
        assert!(!helm.with(|ctx| b.set_param(ctx, "hdg_peakwidth", "-1")));
        helm.nav(0.0, 0.0, 0.0, 1.0);
        helm.contact("ben", 30.4, 20.6, 120.0, 1.5, "heron");
        helm.with(|ctx| b.on_every_state(ctx));
        let f = helm.with(|ctx| b.on_run(ctx)).unwrap();
        assert_eq!(f.pwt, 100.0);
        assert_eq!(helm.last("SHADOW_CONTACT_X").as_deref(), Some("30"));
        assert_eq!(helm.last("SHADOW_CONTACT_Y").as_deref(), Some("21"));
        assert_eq!(helm.last("SHADOW_CONTACT_SPEED").as_deref(), Some("2"));
        // hypot(30.4, 20.6) = 36.7 < 45: relevant. At 50 m: not.
        helm.contact("ben", 30.0, 40.0, 120.0, 1.5, "heron");
        helm.with(|ctx| b.on_every_state(ctx));
        assert!(helm.with(|ctx| b.on_run(ctx)).is_none());
        assert_eq!(helm.last("SHADOW_RELEVANCE").as_deref(), Some("0"));
    }

    /// Where a peak cannot be built, the reference path names the part that failed and
    /// posts the builder's warnings.
    #[test]
    fn a_failed_part_is_named_with_its_warnings() {
        let b = Shadow::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        let mut helm = MockHelm::new("shadow_ben");
        assert!(helm.with(|ctx| b.reference(ctx, (f64::NAN, 1.0))).is_none());
        let err = helm.posted("BHV_ERROR").concat();
        assert!(
            err.contains("Unable to generate hdg component of IvP function"),
            "{err}"
        );
        let warn = helm.posted("BHV_WARNING").concat();
        assert!(warn.contains("summit:not a finite number"), "{warn}");
        helm.clear();
        assert!(helm
            .with(|ctx| b.reference(ctx, (90.0, f64::NAN)))
            .is_none());
        let err = helm.posted("BHV_ERROR").concat();
        assert!(
            err.contains("Unable to generate spd component of IvP function"),
            "{err}"
        );
        assert!(helm.with(|ctx| b.reference(ctx, (90.0, 1.0))).is_some());
    }
}
