//! Common behavior parameters (behavior-common.md §1-§2).

use bhv::flag::{parse_flag, FlagParam, FlagSpec};
use bhv::logic::LogicCondition;
use bhv::number::{atof, is_number};

use super::context::with_ctx;
use super::{BehaviorCore, BehaviorInstance, HostEnv};
use crate::config::parse_bool;
use crate::info_buffer::InfoBuffer;

/// Apply one `param = value` line (from the `.bhv` or a spawn): name first, then the
/// common handler, then the type's own. `Ok(false)`: the line is not accepted;
/// `Err(message)`: the behavior panicked on it.
pub fn apply_config_line(
    inst: &mut BehaviorInstance,
    env: &HostEnv,
    ib: &InfoBuffer,
    param: &str,
    value: &str,
) -> Result<bool, String> {
    let value = value.trim();
    if param.eq_ignore_ascii_case("name") || param.eq_ignore_ascii_case("descriptor") {
        return Ok(set_name(&mut inst.core, value));
    }
    if let Some(ok) = common_param(&mut inst.core, param, value) {
        return Ok(ok);
    }
    type_param(inst, env, ib, param, value)
}

/// The common handler, named as behavior-common.md §1 says: lower-cased, one leading
/// `_` ignored. `None` when `param` is not a common parameter.
fn common_param(core: &mut BehaviorCore, param: &str, value: &str) -> Option<bool> {
    let lower = param.to_ascii_lowercase();
    apply_common(core, lower.strip_prefix('_').unwrap_or(&lower), value)
}

/// The behavior type's own handler, with the name as given. `Err`: it panicked.
fn type_param(
    inst: &mut BehaviorInstance,
    env: &HostEnv,
    ib: &InfoBuffer,
    param: &str,
    value: &str,
) -> Result<bool, String> {
    let (bhv, core) = (&mut inst.bhv, &mut inst.core);
    with_ctx(core, env, ib, |ctx| {
        bhv.set_param(ctx, param.into(), value.into())
            .into_result()
            .map_err(String::from)
    })
}

fn set_name(core: &mut BehaviorCore, value: &str) -> bool {
    let valid = !value.is_empty()
        && value
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-[]()#@+".contains(c));
    if valid {
        // A default key names the behavior as it was when the message was queued.
        for m in core.messages.iter_mut().filter(|m| m.key.is_empty()) {
            m.key = format!("{}{}", core.name, m.var);
        }
        core.name = value.to_string();
    }
    valid
}

/// The common handler: `None` when `param` is not a common parameter.
fn apply_common(core: &mut BehaviorCore, param: &str, value: &str) -> Option<bool> {
    let ok = match param {
        "us" => {
            core.ownship = value.to_string();
            true
        }
        "pwt" | "priwt" | "priority" => {
            if is_number(value) && atof(value) >= 0.0 {
                core.pwt = atof(value);
                true
            } else {
                false
            }
        }
        "condition" => match LogicCondition::parse(&value.replace(',', "=")) {
            Ok(c) => {
                core.conditions.push(c);
                core.conditions_checked = None;
                true
            }
            Err(_) => false,
        },
        "runflag" | "run_flag" => add_flag(&mut core.flags.run, value),
        "runxflag" | "runx_flag" => add_flag(&mut core.flags.runx, value),
        "activeflag" | "active_flag" => add_flag(&mut core.flags.active, value),
        "inactiveflag" | "inactive_flag" => add_flag(&mut core.flags.inactive, value),
        "idleflag" | "idle_flag" => add_flag(&mut core.flags.idle, value),
        "endflag" | "end_flag" => add_flag(&mut core.flags.end, value),
        "spawnflag" | "spawn_flag" => add_flag(&mut core.flags.spawn, value),
        "spawnxflag" | "spawnx_flag" => add_flag(&mut core.flags.spawnx, value),
        "configflag" | "config_flag" => add_flag(&mut core.flags.config, value),
        "nostarve" | "no_starve" => set_nostarve(core, value),
        "duration" => set_duration(core, value),
        "duration_status" => {
            core.duration_status = value.to_string();
            !value.contains(char::is_whitespace)
        }
        "duration_reset" => match value.split_once('=') {
            Some((var, val)) if !var.trim().is_empty() => {
                core.duration_reset = Some((var.trim().to_string(), val.trim().to_string()));
                true
            }
            _ => false,
        },
        "duration_idle_decay" => match parse_bool(value) {
            Some(b) => {
                core.duration_idle_decay = b;
                true
            }
            None => false,
        },
        "perpetual" => {
            core.perpetual = value.eq_ignore_ascii_case("true");
            true
        }
        "updates" => {
            core.updates_var = value.to_string();
            !value.is_empty() && !value.contains(char::is_whitespace)
        }
        "post_mapping" => match value.split_once(',') {
            Some((from, to))
                if !from.is_empty() && !to.is_empty() && !value.contains(char::is_whitespace) =>
            {
                core.post_mapping.insert(from.to_string(), to.to_string());
                true
            }
            _ => false,
        },
        "comms_policy" => {
            let v = value.to_ascii_lowercase();
            if ["open", "lean", "dire"].contains(&v.as_str()) {
                core.comms_policy = v;
                true
            } else {
                false
            }
        }
        "build_info" if value.eq_ignore_ascii_case("clear") => {
            core.build_info.clear();
            true
        }
        "build_info" => prepend_build_info(core, value),
        "precision" => {
            prepend_build_info(core, &format!("precision={}", value.to_ascii_lowercase()))
        }
        _ => return None,
    };
    Some(ok)
}

/// `build_info` entries are prepended, `#`-separated.
fn prepend_build_info(core: &mut BehaviorCore, entry: &str) -> bool {
    core.build_info = if core.build_info.is_empty() {
        entry.to_string()
    } else {
        format!("{entry}#{}", core.build_info)
    };
    true
}

fn add_flag(list: &mut Vec<FlagSpec>, value: &str) -> bool {
    match parse_flag(value) {
        Ok(FlagParam::Flag(f)) => {
            list.push(f);
            true
        }
        Ok(FlagParam::ClearAll) => {
            list.clear();
            true
        }
        Err(_) => false,
    }
}

fn set_nostarve(core: &mut BehaviorCore, value: &str) -> bool {
    let fields: Vec<&str> = value.split(',').map(str::trim).collect();
    if fields.len() < 2 {
        return false;
    }
    let secs = fields[fields.len() - 1];
    if !is_number(secs) || atof(secs) <= 0.0 {
        return false;
    }
    let vars = fields[..fields.len() - 1]
        .iter()
        .map(|s| s.to_string())
        .collect();
    core.nostarve = Some((vars, atof(secs)));
    true
}

fn set_duration(core: &mut BehaviorCore, value: &str) -> bool {
    if value.eq_ignore_ascii_case("no-time-limit") {
        core.duration = -1.0;
        return true;
    }
    if !is_number(value) {
        return false;
    }
    let d = atof(value);
    if d == -1.0 {
        core.duration = -1.0;
        true
    } else if d >= 0.0 {
        core.duration = d;
        true
    } else {
        false
    }
}

/// One `param=value` pair of an update string (§5): the type's handler first (name as
/// given), then the common handler (name lower-cased).
pub fn apply_update_pair(
    inst: &mut BehaviorInstance,
    env: &HostEnv,
    ib: &InfoBuffer,
    param: &str,
    value: &str,
) -> bool {
    match type_param(inst, env, ib, param, value) {
        Ok(true) => true,
        Ok(false) => common_param(&mut inst.core, param, value).unwrap_or(false),
        Err(panic) => {
            super::fault(&mut inst.core, &format!("behavior panicked: {panic}"));
            false
        }
    }
}
