//! A minimal host for unit tests: an info buffer of numbers and strings and a record of
//! everything posted (variable, value, key).

#![allow(dead_code)]

use std::collections::HashMap;

use behavior_api::abi_stable::sabi_trait::TD_Opaque;
use behavior_api::abi_stable::sabi_types::RMut;
use behavior_api::abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};
use behavior_api::context::{HelmContext, HelmContext_TO};
use behavior_api::sdk::Ctx;
use behavior_api::PostValue;

pub struct MockHost {
    pub nums: HashMap<String, f64>,
    pub strs: HashMap<String, String>,
    pub posts: Vec<(String, String, String)>,
    pub completes: u32,
    pub perpetual: bool,
    pub platform: (f64, f64, f64, f64),
    pub time: f64,
    pub name: String,
    pub priority: f64,
}

impl MockHost {
    pub fn new(name: &str) -> Self {
        MockHost {
            nums: HashMap::new(),
            strs: HashMap::new(),
            posts: Vec::new(),
            completes: 0,
            perpetual: false,
            platform: (0.0, 0.0, 0.0, 0.0),
            time: 1000.0,
            name: name.into(),
            priority: 100.0,
        }
    }
    pub fn set(&mut self, var: &str, v: f64) {
        self.nums.insert(var.into(), v);
    }
    pub fn unset(&mut self, var: &str) {
        self.nums.remove(var);
        self.strs.remove(var);
    }
    pub fn with<R>(&mut self, f: impl FnOnce(&mut Ctx<'_>) -> R) -> R {
        let to = HelmContext_TO::from_ptr(RMut::new(self), TD_Opaque);
        let mut ctx = Ctx::new(to);
        f(&mut ctx)
    }
    /// Values posted to `var`, in order.
    pub fn posted(&self, var: &str) -> Vec<String> {
        self.posts
            .iter()
            .filter(|p| p.0 == var)
            .map(|p| p.1.clone())
            .collect()
    }
    pub fn last(&self, var: &str) -> Option<String> {
        self.posted(var).last().cloned()
    }
    pub fn clear(&mut self) {
        self.posts.clear();
    }
}

impl HelmContext for MockHost {
    fn curr_time(&self) -> f64 {
        self.time
    }
    fn local_time(&self) -> f64 {
        self.time - 1000.0
    }
    fn helm_iteration(&self) -> u64 {
        1
    }
    fn ownship(&self) -> RString {
        "abe".into()
    }
    fn name(&self) -> RString {
        self.name.as_str().into()
    }
    fn priority(&self) -> f64 {
        self.priority
    }
    fn perpetual(&self) -> bool {
        self.perpetual
    }
    fn set_perpetual(&mut self, perpetual: bool) {
        self.perpetual = perpetual;
    }
    fn dur_run_time(&self) -> f64 {
        0.0
    }
    fn dur_idle_time(&self) -> f64 {
        0.0
    }
    fn double_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<f64> {
        if let Some(v) = self.nums.get(var.as_str()) {
            return ROption::RSome(*v);
        }
        if warn {
            let msg = format!(
                "{}: {} dbl info not found in helm info_buffer",
                self.name, var
            );
            self.posts
                .push(("BHV_WARNING".into(), msg, "repeatable".into()));
        }
        ROption::RNone
    }
    fn string_val(&mut self, var: RStr<'_>, _warn: bool) -> ROption<RString> {
        self.strs
            .get(var.as_str())
            .map(|s| RString::from(s.as_str()))
            .into()
    }
    fn time_val(&self, _var: RStr<'_>) -> f64 {
        0.0
    }
    fn msg_time_val(&self, _var: RStr<'_>) -> f64 {
        0.0
    }
    fn is_known(&self, var: RStr<'_>) -> bool {
        self.nums.contains_key(var.as_str()) || self.strs.contains_key(var.as_str())
    }
    fn string_deltas(&self, _var: RStr<'_>) -> RVec<RString> {
        RVec::new()
    }
    fn double_deltas(&self, _var: RStr<'_>) -> RVec<f64> {
        RVec::new()
    }
    fn add_info_vars(&mut self, _vars: RStr<'_>, _no_warning: bool) {}
    fn post(&mut self, var: RStr<'_>, value: PostValue<'_>, key: RStr<'_>) {
        let v = match value {
            PostValue::Str(s) => s.to_string(),
            PostValue::Num(n) => format!("{n}"),
        };
        self.posts.push((var.to_string(), v, key.to_string()));
    }
    fn post_flag(&mut self, _flag: RStr<'_>, _repeatable: bool) {}
    fn expand_common_macros(&mut self, text: RStr<'_>) -> RString {
        text.into()
    }
    fn eval_condition(&mut self, _condition: RStr<'_>) -> RResult<bool, RString> {
        RResult::ROk(true)
    }
    fn set_complete(&mut self) {
        self.completes += 1;
    }
    fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64) {
        self.platform = (osx, osy, osh, osv);
    }
    fn log(&mut self, _level: u8, _message: RStr<'_>) {}
}
