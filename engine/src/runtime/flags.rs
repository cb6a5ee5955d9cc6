//! Posting flags (behavior-common.md §3.2-§3.3).

use bhv::flag::{parse_flag, FlagParam, FlagSpec};
use bhv::number::{atof, is_number};

use super::{macros, BehaviorCore, BehaviorInstance, FlagLists, HostEnv, Message};
use crate::info_buffer::InfoBuffer;
use crate::posting::Value;

/// Which common flag list to post.
#[derive(Clone, Copy, Debug)]
pub enum FlagKind {
    Run,
    Runx,
    Active,
    Inactive,
    Idle,
    End,
    Spawn,
    Spawnx,
    Config,
}

fn list_mut(lists: &mut FlagLists, kind: FlagKind) -> &mut Vec<FlagSpec> {
    match kind {
        FlagKind::Run => &mut lists.run,
        FlagKind::Runx => &mut lists.runx,
        FlagKind::Active => &mut lists.active,
        FlagKind::Inactive => &mut lists.inactive,
        FlagKind::Idle => &mut lists.idle,
        FlagKind::End => &mut lists.end,
        FlagKind::Spawn => &mut lists.spawn,
        FlagKind::Spawnx => &mut lists.spawnx,
        FlagKind::Config => &mut lists.config,
    }
}

/// Post one of the behavior's common flag lists, with common and type macros expanded.
pub fn post_flags(
    inst: &mut BehaviorInstance,
    env: &HostEnv,
    ib: &InfoBuffer,
    kind: FlagKind,
    repeatable: bool,
) {
    // Most kinds have no flags: then nothing is lent out and put back.
    let list = match list_mut(&mut inst.core.flags, kind) {
        list if list.is_empty() => return,
        list => std::mem::take(list),
    };
    let bhv = &inst.bhv;
    for flag in &list {
        let expand_type = |s: &str| -> String {
            bhv.expand_macros(s.into())
                .into_result()
                .map(String::from)
                .unwrap_or_else(|_| s.to_string())
        };
        post_one(&mut inst.core, env, ib, flag, repeatable, &expand_type);
    }
    *list_mut(&mut inst.core.flags, kind) = list;
}

/// Post a flag a behavior type hands over as text (its own macros already expanded).
pub fn post_type_flag(
    core: &mut BehaviorCore,
    env: &HostEnv,
    ib: &InfoBuffer,
    text: &str,
    repeatable: bool,
) {
    if !core.flag_cache.contains_key(text) {
        match parse_flag(text) {
            Ok(FlagParam::Flag(f)) => {
                core.flag_cache.insert(text.to_string(), f);
            }
            _ => {
                core.post_warning(&format!("Bad flag: {text}"));
                return;
            }
        }
    }
    if let Some(flag) = core.flag_cache.remove(text) {
        post_one(core, env, ib, &flag, repeatable, &|s: &str| s.to_string());
        core.flag_cache.insert(text.to_string(), flag);
    }
}

fn is_single_macro(s: &str) -> bool {
    s.starts_with("$[")
        && s.ends_with(']')
        && s.matches('[').count() == 1
        && s.matches(']').count() == 1
}

fn post_one(
    core: &mut BehaviorCore,
    env: &HostEnv,
    ib: &InfoBuffer,
    flag: &FlagSpec,
    repeatable: bool,
    expand_type: &dyn Fn(&str) -> String,
) {
    if let Some(cond) = &flag.condition {
        if !cond.eval_fresh(ib) {
            return;
        }
    }
    let value = match &flag.value {
        Value::Num(v) => Value::Num(*v),
        Value::Str(s) => {
            let expanded = expand_type(&macros::expand_common(core, ib, s));
            if is_single_macro(s) && is_number(&expanded) {
                Value::Num(atof(&expanded))
            } else {
                Value::Str(expanded)
            }
        }
    };
    let key = if repeatable { "repeatable" } else { "" };
    let (local, remote) = match flag.dest.as_deref() {
        None => (true, None),
        Some("all") => (false, Some(false)),
        Some("group") => (false, Some(true)),
        Some("all+") => (true, Some(false)),
        Some("group+") => (true, Some(true)),
        Some(_) => (false, None),
    };
    if let Some(group) = remote {
        post_remote(core, env, ib, &flag.var, &value, group, repeatable);
    }
    if local {
        core.post(&flag.var, value, key);
    }
}

fn post_remote(
    core: &mut BehaviorCore,
    env: &HostEnv,
    ib: &InfoBuffer,
    var: &str,
    value: &Value,
    group: bool,
    repeatable: bool,
) {
    let mut msg = format!("src_node={},dest_node=all", env.ownship);
    if group {
        let gvar = format!("{}_NAV_GROUP", env.ownship.to_ascii_uppercase());
        match ib.sval(&gvar) {
            Some(g) => msg.push_str(&format!(",dest_group={g}")),
            None => core.post_warning(&format!("{gvar} str info not found in helm info_buffer")),
        }
    }
    msg.push_str(&format!(
        ",src_app=pHelmIvP,src_bhv={},var_name={var},",
        core.name
    ));
    match value {
        Value::Num(v) => msg.push_str(&format!("double_val={}", bhv::number::compact(*v, 6))),
        Value::Str(s) if s.contains(',') && !s.starts_with('"') => {
            msg.push_str(&format!("string_val=\"{s}\",string_val_quoted=true"))
        }
        Value::Str(s) => msg.push_str(&format!("string_val={s}")),
    }
    let key = if repeatable {
        "repeatable".to_string()
    } else {
        format!("{}{}", core.name, var)
    };
    core.messages.push(Message {
        var: "NODE_MESSAGE_LOCAL".into(),
        value: Value::Str(msg),
        key,
        helm_ipf: false,
    });
}
