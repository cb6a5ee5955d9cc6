//! BHV_Template: the smallest useful behavior plugin, meant to be copied.
//!
//! It prefers one speed (`speed`, default 1) with a ZAIC_PEAK of half-width `tolerance`
//! (default 0.5) and posts `<report_var> = <NAV_SPEED>` every running iteration when
//! `report_var` is set. Everything common (name, pwt, condition, duration, flags,
//! updates, BHV_STATUS) is done by the helm. To copy it: `README.md` beside this folder.

use behavior_api::ivp;
use behavior_api::sdk::{function_data, Ctx, HelmDomain, IvpBehavior};
use behavior_api::zaic::Peak;
use behavior_api::FunctionData;

pub struct Template {
    /// The behavior's domain as the helm wants it (empty = not runnable).
    domain: String,
    ivp_domain: Option<ivp::Domain>,
    speed: f64,
    tolerance: f64,
    report_var: String,
}

impl Template {
    /// Called once per behavior block, with the helm's decision domain.
    pub fn new(helm_domain: &HelmDomain) -> Self {
        Template {
            domain: helm_domain.sub_domain(&["speed"]),
            ivp_domain: helm_domain.ivp_domain(&["speed"]),
            speed: 1.0,
            tolerance: 0.5,
            report_var: String::new(),
        }
    }
}

fn number(s: &str) -> Option<f64> {
    // The helm's own number test: what the helm calls a number, nothing else.
    behavior_api::parse_number(s)
}

impl IvpBehavior for Template {
    fn domain(&self) -> String {
        self.domain.clone()
    }

    fn default_name(&self) -> String {
        "bhv_template".into()
    }

    /// Type parameters only (names arrive lower-cased from .bhv files, as written from
    /// `updates`); return false for unknown names or bad values.
    fn set_param(&mut self, _ctx: &mut Ctx<'_>, param: &str, value: &str) -> bool {
        match param {
            "speed" => number(value).map(|v| self.speed = v.max(0.0)).is_some(),
            "tolerance" => number(value).map(|v| self.tolerance = v.max(0.0)).is_some(),
            "report_var" => {
                self.report_var = value.trim().to_string();
                true
            }
            _ => false,
        }
    }

    // Runs every iteration: keep it free of new allocations where that is easy. A text
    // read here would go into a `String` field with the `_into` forms
    // (`ctx.get_buffer_string_val_into(var, &mut self.text)`, `name_into`,
    // `ownship_into`, `contact_text_into`), which refill it in place.
    fn on_run(&mut self, ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        if let Some(v) = ctx.get_buffer_double_val("NAV_SPEED") {
            if !self.report_var.is_empty() {
                ctx.post_message_num(&self.report_var, v);
            }
        }
        let Some(dom) = self.ivp_domain.as_ref() else {
            ctx.post_emessage("No 'speed' variable in the helm domain");
            return None;
        };
        let peak = Peak {
            summit: self.speed,
            base_width: self.tolerance,
            ..Peak::default()
        };
        let mut f = peak.build(dom, "speed").ok()?;
        f.set_pwt(ctx.priority());
        Some(function_data(f))
    }
}

// The library's root module: the type names this library offers and their constructors.
behavior_api::export_behaviors! {
    "BHV_Template" => Template::new,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn domain_and_defaults() {
        let b = Template::new(&HelmDomain::new("course,0,359,360:speed,0,4,41"));
        assert_eq!(b.domain(), "speed,0,4,41");
        assert_eq!(b.default_name(), "bhv_template");
        assert_eq!((b.speed, b.tolerance), (1.0, 0.5));
        // Without a speed variable the domain is empty: the helm reports it.
        assert_eq!(
            Template::new(&HelmDomain::new("course,0,359,360")).domain(),
            ""
        );
    }

    /// What the helm sees: the exported root module, its type list and factory.
    #[test]
    fn exported_root_module() {
        let lib = ivp_behaviors_root_module();
        let types: Vec<String> = (lib.behavior_types())()
            .into_iter()
            .map(String::from)
            .collect();
        assert_eq!(types, vec!["BHV_Template"]);
        assert_eq!((lib.api_version())().as_str(), behavior_api::API_VERSION);
        let b = (lib.create())("BHV_Template".into(), "speed,0,4,41".into())
            .unwrap()
            .unwrap();
        assert_eq!(b.domain().as_str(), "speed,0,4,41");
        assert!((lib.create())("BHV_Other".into(), "speed,0,4,41".into()).is_none());
    }
}
