//! Run-time parameter updates through the `updates` variable (behavior-common.md §5).

use super::common_params::apply_update_pair;
use super::{BehaviorInstance, HostEnv};
use crate::info_buffer::InfoBuffer;
use crate::posting::Value;

/// Apply this iteration's update strings; `true` if at least one was applied.
pub fn process_updates(inst: &mut BehaviorInstance, env: &HostEnv, ib: &InfoBuffer) -> bool {
    if inst.core.updates_var.is_empty() {
        return false;
    }
    let deltas = ib.string_deltas(&inst.core.updates_var);
    if deltas.is_empty() {
        return false;
    }
    let mut applied = false;
    for u in deltas {
        let result = apply_update(inst, env, ib, u);
        applied |= result == "success";
        let line = format!(
            "bhv={},var={},time={:.2},result={},val={}",
            inst.core.name,
            inst.core.updates_var,
            ib.local_time(),
            result,
            u
        );
        inst.core.update_results.push(line);
    }
    applied
}

fn apply_update(
    inst: &mut BehaviorInstance,
    env: &HostEnv,
    ib: &InfoBuffer,
    update: &str,
) -> &'static str {
    let lower = update.to_ascii_lowercase();
    let forced = ["toggle", "engage", "mod"]
        .iter()
        .any(|w| lower.contains(w));
    if update.is_empty() || (update == inst.core.last_update && !forced) {
        return "duplicate";
    }
    let mut pairs = Vec::new();
    for part in update.split('#') {
        let (p, v) = match part.split_once('=') {
            Some((p, v)) => (p.trim(), v.trim()),
            None => (part.trim(), ""),
        };
        if p == "name" {
            let expected = match &inst.core.spawn_prefix {
                Some(prefix) => format!("{prefix}{v}"),
                None => v.to_string(),
            };
            if expected != inst.core.name {
                return "name_mismatch";
            }
            continue;
        }
        pairs.push((p, v));
    }
    let mut bad: Vec<&str> = Vec::new();
    for (p, v) in pairs {
        if p.is_empty() || !apply_update_pair(inst, env, ib, p, v) {
            bad.push(p);
        }
    }
    if bad.is_empty() {
        inst.core.good_updates += 1;
        inst.core.last_update = update.to_string();
        "success"
    } else {
        let msg = format!(
            "Faulty update for behavior: {}. Bad parameter(s): {}",
            inst.core.name,
            bad.join(",")
        );
        inst.core.post("BHV_WARNING", Value::Str(msg.clone()), "");
        inst.core.post("BHV_CONFIG_WARNING", Value::Str(msg), "");
        inst.core.bad_updates += 1;
        "param_error"
    }
}
