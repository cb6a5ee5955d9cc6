//! The host side of a behavior call: [`HostCtx`] implements the ABI's `HelmContext`.

use std::fmt::Write as _;

use abi_stable::sabi_trait::TD_Opaque;
use abi_stable::sabi_types::RMut;
use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};
use behavior_api::context::{HelmContext, HelmContext_TO};
use behavior_api::{ContactState, HelmCtx, PostValue};
use bhv::logic::LogicCondition;

use super::{flags, macros, BehaviorCore, HostEnv};
use crate::info_buffer::InfoBuffer;
use crate::posting::Value;

/// One behavior call's view of the helm.
pub struct HostCtx<'a> {
    pub core: &'a mut BehaviorCore,
    pub env: &'a HostEnv,
    pub ib: &'a InfoBuffer,
}

/// Run `f` with an ABI context for this behavior.
pub fn with_ctx<R>(
    core: &mut BehaviorCore,
    env: &HostEnv,
    ib: &InfoBuffer,
    f: impl FnOnce(HelmCtx<'_>) -> R,
) -> R {
    let mut host = HostCtx { core, env, ib };
    let ctx = HelmContext_TO::from_ptr(RMut::new(&mut host), TD_Opaque);
    f(ctx)
}

impl HostCtx<'_> {
    /// A contact's `type`, `group` or `vsource`; "" for an unknown contact or field.
    fn contact_field(&self, name: &str, field: &str) -> &str {
        let Some(c) = self.env.ledger.snapshot().get(name) else {
            return "";
        };
        match field {
            "type" => &c.vtype,
            "group" => &c.group,
            "vsource" => &c.vsource,
            _ => "",
        }
    }

    fn quiet(&self, var: &str) -> bool {
        self.core
            .info_vars
            .iter()
            .any(|(v, no_warning)| *no_warning && v == var)
    }
}

impl HelmContext for HostCtx<'_> {
    fn curr_time(&self) -> f64 {
        self.ib.curr_time()
    }
    fn local_time(&self) -> f64 {
        self.ib.local_time()
    }
    fn helm_iteration(&self) -> u64 {
        self.env.helm_iteration
    }
    fn ownship(&self) -> RString {
        self.core.ownship.as_str().into()
    }
    fn name(&self) -> RString {
        self.core.name.as_str().into()
    }
    fn priority(&self) -> f64 {
        self.core.pwt
    }
    fn perpetual(&self) -> bool {
        self.core.perpetual
    }
    fn set_perpetual(&mut self, perpetual: bool) {
        self.core.perpetual = perpetual;
    }
    fn dur_run_time(&self) -> f64 {
        self.core.dur_run_time
    }
    fn dur_idle_time(&self) -> f64 {
        self.core.dur_idle_time
    }
    fn double_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<f64> {
        let v = self.ib.double_val(var.as_str());
        if v.is_none() && warn && !self.quiet(var.as_str()) {
            let msg = format!("{} dbl info not found in helm info_buffer", var.as_str());
            self.core.post_warning(&msg);
        }
        v.into()
    }
    fn string_val(&mut self, var: RStr<'_>, warn: bool) -> ROption<RString> {
        let v = self.ib.string_val(var.as_str());
        if v.is_none() && warn && !self.quiet(var.as_str()) {
            let msg = format!("{} str info not found in helm info_buffer", var.as_str());
            self.core.post_warning(&msg);
        }
        v.map(RString::from).into()
    }
    fn time_val(&self, var: RStr<'_>) -> f64 {
        self.ib.time_val(var.as_str())
    }
    fn msg_time_val(&self, var: RStr<'_>) -> f64 {
        self.ib.msg_time_val(var.as_str())
    }
    fn is_known(&self, var: RStr<'_>) -> bool {
        self.ib.is_known(var.as_str())
    }
    fn string_deltas(&self, var: RStr<'_>) -> RVec<RString> {
        self.ib
            .string_deltas(var.as_str())
            .iter()
            .map(|s| RString::from(s.as_str()))
            .collect()
    }
    fn double_deltas(&self, var: RStr<'_>) -> RVec<f64> {
        self.ib
            .double_deltas(var.as_str())
            .iter()
            .copied()
            .collect()
    }
    fn add_info_vars(&mut self, vars: RStr<'_>, no_warning: bool) {
        for v in vars
            .as_str()
            .split(',')
            .map(str::trim)
            .filter(|v| !v.is_empty())
        {
            if let Some(slot) = self.core.info_vars.iter_mut().find(|(n, _)| n == v) {
                slot.1 |= no_warning;
            } else {
                self.core.info_vars.push((v.to_string(), no_warning));
            }
        }
    }
    fn post(&mut self, var: RStr<'_>, value: PostValue<'_>, key: RStr<'_>) {
        let value = match value {
            PostValue::Str(s) => Value::Str(self.core.pool.copy_of(s.as_str())),
            PostValue::Num(v) => Value::Num(v),
        };
        // A repeatable BHV_ERROR is what the error helper posts: it halts the helm.
        if var.as_str() == "BHV_ERROR" && key.as_str().eq_ignore_ascii_case("repeatable") {
            self.core.ok = false;
        }
        self.core.post(var.as_str(), value, key.as_str());
    }
    fn post_flag(&mut self, flag: RStr<'_>, repeatable: bool) {
        flags::post_type_flag(self.core, self.env, self.ib, flag.as_str(), repeatable);
    }
    fn expand_common_macros(&mut self, text: RStr<'_>) -> RString {
        macros::expand_common(self.core, self.ib, text.as_str()).into()
    }
    fn eval_condition(&mut self, condition: RStr<'_>) -> RResult<bool, RString> {
        let text = condition.as_str();
        if !self.core.condition_cache.contains_key(text) {
            match LogicCondition::parse(text) {
                Ok(c) => {
                    self.core.condition_cache.insert(text.to_string(), c);
                }
                Err(e) => return RResult::RErr(e.to_string().into()),
            }
        }
        match self.core.condition_cache.get(text) {
            Some(c) => RResult::ROk(c.eval_fresh(self.ib)),
            None => RResult::RErr("condition not parsed".into()),
        }
    }
    fn set_complete(&mut self) {
        if self.core.complete_requested.is_none() {
            self.core.complete_requested = Some(self.core.messages.len());
        }
    }
    fn set_platform(&mut self, osx: f64, osy: f64, osh: f64, osv: f64) {
        self.core.platform = [osx, osy, osh, osv];
    }
    fn log(&mut self, level: u8, message: RStr<'_>) {
        let name = &self.core.name;
        match level {
            0 => tracing::error!(behavior = %name, "{}", message.as_str()),
            1 => tracing::warn!(behavior = %name, "{}", message.as_str()),
            2 => tracing::info!(behavior = %name, "{}", message.as_str()),
            3 => tracing::debug!(behavior = %name, "{}", message.as_str()),
            _ => tracing::trace!(behavior = %name, "{}", message.as_str()),
        }
    }

    fn contact_count(&self) -> u32 {
        u32::try_from(self.env.ledger.snapshot().len()).unwrap_or(u32::MAX)
    }

    fn contact_name(&self, index: u32) -> ROption<RString> {
        let all = self.env.ledger.snapshot().contacts();
        match all.get(index as usize) {
            Some(c) => ROption::RSome(RString::from(c.name.as_str())),
            None => ROption::RNone,
        }
    }

    fn contact(&self, name: RStr<'_>) -> ROption<ContactState> {
        let snap = self.env.ledger.snapshot();
        let Some(c) = snap.get(name.as_str()) else {
            return ROption::RNone;
        };
        let now = snap.now();
        ROption::RSome(ContactState {
            x: c.x,
            y: c.y,
            hdg: c.hdg,
            spd: c.spd,
            dep: c.dep,
            lat: c.lat,
            lon: c.lon,
            utc: c.utc,
            utc_age: now - c.utc,
            utc_received: c.utc_received,
            utc_age_received: now - c.utc_received,
            length: c.length,
            // The helm's ledger never extrapolates (contacts-appcast.md §2.4).
            extrapolated: false,
        })
    }

    fn contact_text(&self, name: RStr<'_>, field: RStr<'_>) -> RString {
        RString::from(self.contact_field(name.as_str(), field.as_str()))
    }

    fn set_contact(&mut self, name: RStr<'_>) {
        mbutil::short_str::assign(&mut self.core.contact, name.as_str());
    }

    // The `_into` forms (0.1.2): `out` belongs to the behavior; refilled in place, it
    // grows (through its own allocator) only for a text longer than any before.
    fn contact_text_into(&self, name: RStr<'_>, field: RStr<'_>, out: &mut RString) {
        refill(out, self.contact_field(name.as_str(), field.as_str()));
    }
    fn name_into(&self, out: &mut RString) {
        refill(out, &self.core.name);
    }
    fn ownship_into(&self, out: &mut RString) {
        refill(out, &self.core.ownship);
    }
    fn string_val_into(&mut self, var: RStr<'_>, warn: bool, out: &mut RString) -> bool {
        // `InfoBuffer::string_val`'s rule (the string, else the number `%.6f`), written
        // in place.
        let var_str = var.as_str();
        if let Some(v) = self.ib.sval(var_str) {
            refill(out, v);
            return true;
        }
        match self.ib.dval(var_str) {
            Some(d) => {
                out.clear();
                // Writing into a string cannot fail.
                let _ = write!(out, "{d:.6}");
                true
            }
            None => {
                out.clear();
                if warn && !self.quiet(var.as_str()) {
                    let msg = format!("{} str info not found in helm info_buffer", var.as_str());
                    self.core.post_warning(&msg);
                }
                false
            }
        }
    }
    fn contact_name_into(&self, index: u32, out: &mut RString) -> bool {
        let all = self.env.ledger.snapshot().contacts();
        match all.get(index as usize) {
            Some(c) => {
                refill(out, &c.name);
                true
            }
            None => {
                out.clear();
                false
            }
        }
    }
}

/// `out` holding exactly `text`, its storage kept.
fn refill(out: &mut RString, text: &str) {
    out.clear();
    out.push_str(text);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `_into` forms against the returning forms, over random buffer contents:
    /// strings, numbers of every size (printed `%.6f`), missing variables with and
    /// without the warning, and a stale `out`; the same answers and the same postings.
    #[test]
    fn into_forms_give_what_the_returning_forms_give() {
        let env = HostEnv::default();
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let (mut warnings, mut numbers) = (0, 0);
        for round in 0..200 {
            let mut ib = InfoBuffer::new(0.0);
            let mut core = BehaviorCore::new("BHV_X", "bhv_x", "abe");
            core.name = format!("x{round}");
            let mut vars = Vec::new();
            for i in 0..8 {
                let var = format!("V{i}");
                match next() % 3 {
                    0 => {
                        let text = "y".repeat((next() % 40) as usize);
                        ib.set_string(&var, &text, 0.0);
                    }
                    1 => {
                        let mag = 10f64.powi((next() % 16) as i32 - 6);
                        let v = (next() % 2_000_001) as f64 / 1000.0 - 1000.0;
                        ib.set_double(&var, v * mag, 0.0);
                    }
                    _ => {} // missing
                }
                vars.push(var);
            }
            let mut out = RString::from("stale text");
            for var in &vars {
                let warn = next() % 2 == 0;
                let mut host = HostCtx {
                    core: &mut core,
                    env: &env,
                    ib: &ib,
                };
                let before = host.core.messages.len();
                let want = host.string_val(var.as_str().into(), warn).into_option();
                let warned = host.core.messages.len() - before;
                warnings += warned;
                numbers += usize::from(ib.sval(var).is_none() && want.is_some());
                let found = host.string_val_into(var.as_str().into(), warn, &mut out);
                assert_eq!(found, want.is_some(), "{var}");
                assert_eq!(out.as_str(), want.as_ref().map_or("", RString::as_str));
                // The same warning, once more, and nothing else.
                let m = &host.core.messages;
                assert_eq!(m.len() - before, 2 * warned, "{var} warn={warn}");
                if warned == 1 {
                    assert_eq!(m[m.len() - 1].var, m[m.len() - 2].var);
                    assert_eq!(m[m.len() - 1].value, m[m.len() - 2].value);
                }
            }
            let host = HostCtx {
                core: &mut core,
                env: &env,
                ib: &ib,
            };
            host.name_into(&mut out);
            assert_eq!(out, host.name());
            host.ownship_into(&mut out);
            assert_eq!(out, host.ownship());
            host.contact_text_into("nobody".into(), "type".into(), &mut out);
            assert_eq!(out, host.contact_text("nobody".into(), "type".into()));
            assert!(!host.contact_name_into(0, &mut out));
            assert_eq!(out.as_str(), "");
        }
        assert!(
            warnings > 0 && numbers > 0,
            "{warnings} warnings, {numbers} numbers"
        );
    }
}
