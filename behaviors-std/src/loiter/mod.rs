//! BHV_Loiter (placeholder while being written).
use behavior_api::sdk::{Ctx, HelmDomain, IvpBehavior};
use behavior_api::FunctionData;

pub struct BhvLoiter {
    domain: String,
}
impl BhvLoiter {
    pub fn new(helm: &HelmDomain) -> Self {
        BhvLoiter {
            domain: helm.sub_domain(&["course", "speed"]),
        }
    }
}
impl IvpBehavior for BhvLoiter {
    fn domain(&self) -> String {
        self.domain.clone()
    }
    fn default_name(&self) -> String {
        "bhv_loiter".into()
    }
    fn set_param(&mut self, _ctx: &mut Ctx<'_>, _p: &str, _v: &str) -> bool {
        false
    }
    fn on_run(&mut self, _ctx: &mut Ctx<'_>) -> Option<FunctionData> {
        None
    }
}
