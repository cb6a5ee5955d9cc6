//! The deprecated obstacle types (obstacles.md §1.15): BHV_AvoidObstacleV21,
//! BHV_AvoidObstacleX and BHV_AvoidObstacle. The real helm builds them and then, unless
//! the block says `i_understand_this_behavior_is_deprecated = true`, adds four config
//! warnings naming BHV_AvoidObstacleV24, which makes it MALCONFIG. This helm refuses them
//! at the same point (configuration) with the same four lines; acknowledged, it still
//! refuses them (they are not provided), saying so.

/// The three types the real helm refuses as deprecated.
pub const DEPRECATED_TYPES: &[&str] = &[
    "BHV_AvoidObstacleV21",
    "BHV_AvoidObstacleX",
    "BHV_AvoidObstacle",
];

/// The configuration errors of a block naming a deprecated type (`None`: not one).
pub(crate) fn refusal(bs: &bhv::reader::BehaviorSpec) -> Option<Vec<String>> {
    let ty = bs.type_name.as_str();
    if !DEPRECATED_TYPES.contains(&ty) {
        return None;
    }
    let where_ = format!("{}:{}", bs.file.display(), bs.line);
    // The helm's one reading of a boolean, as for every other flag.
    let acknowledged = bs.lines.iter().any(|l| {
        l.param
            .eq_ignore_ascii_case("i_understand_this_behavior_is_deprecated")
            && crate::config::parse_bool(l.value.trim()) == Some(true)
    });
    if acknowledged {
        return Some(vec![format!(
            "{where_}: {ty} is deprecated and not provided by this helm (the real helm would \
             run it at your own risk); use BHV_AvoidObstacleV24 instead"
        )]);
    }
    Some(
        [
            format!("{ty} is no longer supported."),
            "Use BHV_AvoidObstacleV24 or newer instead.".to_string(),
            "Set i_understand_this_behavior_is_deprecated=true".to_string(),
            "to suppress this warning and use at your own risk.".to_string(),
        ]
        .into_iter()
        .map(|w| format!("{where_}: {w}"))
        .collect(),
    )
}
