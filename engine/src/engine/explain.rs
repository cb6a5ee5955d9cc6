//! Why a `.bhv` line was refused, in words a new user can act on: an unknown parameter
//! (with a did-you-mean) or a bad value (with what was expected). The behavior ABI
//! answers only "accepted or not", so the host tells the two apart by asking a spare
//! instance of the same type about the name with a few typical values.

use crate::factory::BehaviorFactory;
use crate::info_buffer::InfoBuffer;
use crate::runtime::{apply_config_line, BehaviorCore, BehaviorInstance, HostEnv};
use bhv::vocabulary::{
    edit_distance, expected_by_name, near, COMMON, KNOWN_TYPE_PARAMS, PROBE_VALUES,
};

/// The message for a refused `param = value` line of a behavior of `type_name`.
pub(crate) fn refused_line(
    factory: &BehaviorFactory,
    env: &HostEnv,
    ib: &InfoBuffer,
    type_name: &str,
    param: &str,
    value: &str,
) -> String {
    let value = value.trim();
    let lower = param.to_ascii_lowercase();
    let common = lower.strip_prefix('_').unwrap_or(&lower);
    let common = common
        .strip_suffix("_flag")
        .map_or(common.to_string(), |s| format!("{s}flag"));
    if let Some((_, expected)) = COMMON.iter().find(|(n, _)| *n == common) {
        return format!("bad value: {param} = {value} (expected {expected})");
    }
    let accepts = |name: &str, values: &[&str]| -> bool {
        let Some(Ok(bhv)) = factory.create(type_name, &env.helm_domain) else {
            return false;
        };
        let mut probe = BehaviorInstance {
            core: BehaviorCore::new(type_name, "probe", "probe"),
            bhv,
        };
        values
            .iter()
            .any(|v| matches!(apply_config_line(&mut probe, env, ib, name, v), Ok(true)))
    };
    if accepts(param, PROBE_VALUES) {
        return format!(
            "bad value: {param} = {value} (expected {})",
            expected_by_name(param)
        );
    }
    let mut tries: Vec<&str> = vec![value];
    tries.extend(PROBE_VALUES);
    let suggestion = near(
        param,
        COMMON
            .iter()
            .map(|(n, _)| *n)
            .chain(KNOWN_TYPE_PARAMS.iter().copied()),
    )
    .into_iter()
    .find(|c| COMMON.iter().any(|(n, _)| n == c) || accepts(c, &tries));
    let hint = suggestion
        .map(|s| format!(" (did you mean `{s}`?)"))
        .unwrap_or_default();
    format!(
        "unknown parameter of {type_name}: {param} = {value}{hint}; the helm's common parameters \
         are {}; the type's own are in its documentation",
        COMMON
            .iter()
            .filter(|(n, _)| !matches!(*n, "descriptor" | "priwt" | "priority"))
            .map(|(n, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// The known behavior type nearest `type_name`, for an unknown one.
pub(crate) fn nearest_type(factory: &BehaviorFactory, type_name: &str) -> Option<String> {
    let mut names: Vec<String> = behaviors_std::builtin_types()
        .iter()
        .map(|(n, _)| n.to_string())
        .collect();
    for l in factory.libraries() {
        names.extend(l.types.iter().cloned());
    }
    names.extend(
        crate::factory::SHIPPED_LIBRARY_TYPES
            .iter()
            .map(|s| s.to_string()),
    );
    let strip = |s: &str| s.strip_prefix("BHV_").unwrap_or(s).to_ascii_lowercase();
    let want = strip(type_name);
    let limit = (want.chars().count() / 3).clamp(1, 4);
    names
        .into_iter()
        // The type itself (a shipped library not loaded) is no suggestion.
        .filter(|n| n != type_name)
        .map(|n| (edit_distance(&want, &strip(&n)), n))
        .filter(|(d, _)| *d <= limit)
        .min()
        .map(|(_, n)| n)
}
