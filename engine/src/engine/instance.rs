//! One behavior instance built from its `.bhv` block, for start-up, restarts and
//! spawning alike.

use crate::factory::BehaviorFactory;
use crate::info_buffer::InfoBuffer;
use crate::runtime::{apply_config_line, BehaviorCore, BehaviorInstance, HostEnv};

/// Build one behavior from its `.bhv` block: create it, set `us`, apply the lines in
/// order, run the collective check. Every problem is one line naming file and line.
pub(crate) fn make_instance(
    bs: &bhv::reader::BehaviorSpec,
    factory: &BehaviorFactory,
    env: &HostEnv,
    ib: &InfoBuffer,
    ownship: &str,
) -> Result<BehaviorInstance, Vec<String>> {
    if let Some(errors) = super::deprecated::refusal(bs) {
        return Err(errors);
    }
    let where_ = format!("{}:{}", bs.file.display(), bs.line);
    let created = factory.create(&bs.type_name, &env.helm_domain);
    if let Some(Err(panic)) = &created {
        return Err(vec![format!(
            "{where_}: {} could not be created: the constructor panicked: {panic}",
            bs.type_name
        )]);
    }
    let Some(Ok(bhv)) = created else {
        let dirs = if factory.searched_dirs.is_empty() {
            "none (set IVP_BEHAVIOR_DIRS or ivp_behavior_dir)".to_string()
        } else {
            factory.searched_dirs.join(", ")
        };
        let hint = super::explain::nearest_type(factory, &bs.type_name)
            .map(|n| format!(" (did you mean {n}?)"))
            .unwrap_or_default();
        // A type the helm ships as a library: the likely cause is a helm binary
        // without its libraries beside it.
        let shipped = match &factory.bundled_missing {
            Some(why) if crate::factory::SHIPPED_LIBRARY_TYPES.contains(&bs.type_name.as_str()) => {
                format!(": it is one of the helm's shipped libraries: {why}")
            }
            _ if crate::factory::real_type_not_here(&bs.type_name) => {
                ": the real helm has this type and this helm does not yet; a library \
                 providing it loads from IVP_BEHAVIOR_DIRS or an ivp_behavior_dir line"
                    .to_string()
            }
            _ => String::new(),
        };
        return Err(vec![format!(
            "{where_}: unknown behavior type {}{hint} (directories searched: {dirs}){shipped}",
            bs.type_name
        )]);
    };
    let mut errors = Vec::new();
    let default_name = bhv.default_name().to_string();
    let empty_domain = bhv.domain().is_empty();
    let mut inst = BehaviorInstance {
        bhv,
        core: BehaviorCore::new(&bs.type_name, &default_name, ownship),
    };
    inst.core.empty_domain = empty_domain;
    inst.core.recycler = factory.recycler(&bs.type_name);
    if let Ok(d) = inst.bhv.default_duration().into_result() {
        inst.core.duration = d;
    }
    let _ = apply_config_line(&mut inst, env, ib, "us", ownship);
    for line in &bs.lines {
        match apply_config_line(&mut inst, env, ib, &line.param, &line.value) {
            Ok(true) => {}
            Ok(false) => errors.push(format!(
                "{}:{}: {}",
                bs.file.display(),
                line.line,
                super::explain::refused_line(
                    factory,
                    env,
                    ib,
                    &bs.type_name,
                    &line.param,
                    &line.value
                )
            )),
            Err(panic) => errors.push(format!(
                "{}:{}: behavior panicked on this parameter: {} ({panic})",
                bs.file.display(),
                line.line,
                line.raw.trim()
            )),
        }
    }
    match inst.bhv.collective_check().into_result() {
        Ok(msg) if !msg.is_empty() => errors.push(format!("{where_}: {msg}")),
        Ok(_) => {}
        Err(p) => errors.push(format!("{where_}: behavior panicked while checking: {p}")),
    }
    if errors.is_empty() {
        Ok(inst)
    } else {
        Err(errors)
    }
}
