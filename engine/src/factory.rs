//! Where behaviors come from: the types compiled into the helm, and (see `loader`) the
//! libraries found in behavior directories. Both hand out the same ABI trait object.

use behavior_api::sdk::HelmDomain;
use behavior_api::BehaviorBox;

/// The behavior types this project ships as libraries (`plugins/*`, bundled beside the
/// helm), besides the built-in ones. `helm conform` uses it to tell a case waiting for a
/// type we do not have yet from a case whose type we have but which failed to load; a
/// test checks the list against the libraries a build bundles.
pub const SHIPPED_LIBRARY_TYPES: &[&str] = &[
    "BHV_AvdColregsV17",
    "BHV_AvdColregsV19",
    "BHV_AvdColregsV22",
    "BHV_AvoidCollision",
    "BHV_AvoidObstacleV24",
    "BHV_BearingLine",
    "BHV_ConstantDepth",
    "BHV_ConstantHeading",
    "BHV_ConstantSpeed",
    "BHV_Convoy",
    "BHV_CutRange",
    "BHV_GoToDepth",
    "BHV_HSLine",
    "BHV_LegRun",
    "BHV_MaxDepth",
    "BHV_MaxSpeed",
    "BHV_OpRegion",
    "BHV_OpRegionV24",
    "BHV_PModelView",
    "BHV_PeriodicSurface",
    "BHV_Shadow",
    "BHV_StationKeep",
    "BHV_Template",
    "BHV_Trail",
    "BHV_ZigZag",
];

/// The behavior types the real helm (MOOS-IvP) creates by name (behavior-common.md §9),
/// so a mission naming one this project lacks hears that the type is real, not a typo.
pub const REAL_HELM_TYPES: &str = "BHV_OpRegion BHV_OpRegionRecover BHV_OpRegionV24 \
    BHV_Waypoint BHV_LegRun BHV_ZigZag BHV_FullStop BHV_FixTurn BHV_FixedTurn \
    BHV_ConstantSpeed BHV_Trail BHV_Convoy BHV_MaxDepth BHV_MaxSpeed BHV_ConstantDepth \
    BHV_ConstantHeading BHV_MaintainHeading BHV_Loiter BHV_StationKeep BHV_RStationKeep \
    BHV_Timer BHV_TestFailure BHV_HSLine BHV_BearingLine BHV_HeadingChange BHV_Shadow \
    BHV_CutRange BHV_AvoidCollision BHV_AvoidObstacle BHV_AvoidObstacleX \
    BHV_AvoidObstacleV21 BHV_AvoidObstacleV24 BHV_PeriodicSpeed BHV_PeriodicSurface \
    BHV_GoToDepth BHV_MemoryTurnLimit BHV_Hysteresis BHV_Attractor BHV_RubberBand \
    BHV_HeadingBias BHV_MinAltitudeX BHV_AvdColregsV17 BHV_AvdColregsV19 \
    BHV_AvdColregsV22 BHV_AvdColregsV26 BHV_PModelView";

/// Whether the real helm has `type_name` (see [`REAL_HELM_TYPES`]).
pub fn real_helm_has(type_name: &str) -> bool {
    REAL_HELM_TYPES.split_whitespace().any(|t| t == type_name)
}

/// A real helm type this project does not provide.
pub fn real_type_not_here(type_name: &str) -> bool {
    real_helm_has(type_name) && !project_has_type(type_name)
}

/// Whether this project provides `type_name`, built in or as a shipped library.
pub fn project_has_type(type_name: &str) -> bool {
    SHIPPED_LIBRARY_TYPES.contains(&type_name)
        // Refused as the real helm refuses them, so a case naming one is run, not waiting.
        || crate::engine::deprecated::DEPRECATED_TYPES.contains(&type_name)
        || behaviors_std::builtin_types()
            .iter()
            .any(|(n, _)| *n == type_name)
}

/// Constructor of a built-in behavior type.
pub type BuiltinCtor = fn(&HelmDomain) -> BehaviorBox;

/// Creates behaviors by type name.
#[derive(Clone)]
pub struct BehaviorFactory {
    builtins: Vec<(&'static str, BuiltinCtor)>,
    libraries: Vec<crate::loader::LoadedLibrary>,
    /// Directories searched for libraries, for error messages.
    pub searched_dirs: Vec<String>,
    /// Set by the loader when none of the libraries shipped with the helm was found
    /// (a binary copied alone, as `cargo install` does): said with any unknown type of
    /// [`SHIPPED_LIBRARY_TYPES`], so the user learns where they belong.
    pub bundled_missing: Option<String>,
}

impl BehaviorFactory {
    /// The built-in types only (BHV_Waypoint, BHV_Loiter, BHV_Timer).
    pub fn with_builtins() -> Self {
        BehaviorFactory {
            builtins: behaviors_std::builtin_types(),
            libraries: Vec::new(),
            searched_dirs: Vec::new(),
            bundled_missing: None,
        }
    }

    pub fn add_library(&mut self, lib: crate::loader::LoadedLibrary) {
        self.libraries.push(lib);
    }

    pub fn libraries(&self) -> &[crate::loader::LoadedLibrary] {
        &self.libraries
    }

    pub fn is_builtin(&self, type_name: &str) -> bool {
        self.builtins.iter().any(|(n, _)| *n == type_name)
    }

    /// Whether some source offers `type_name` (built-in types win).
    pub fn knows(&self, type_name: &str) -> bool {
        self.is_builtin(type_name) || self.libraries.iter().any(|l| l.offers(type_name))
    }

    /// How to hand a function of a `type_name` behavior back to the library that made
    /// it, when that library has the means (behavior-api 0.1.3 and later); a built-in
    /// behavior's goes to the host's own spare storage, where its next build takes it.
    pub fn recycler(&self, type_name: &str) -> Option<behavior_api::FunctionRecycler> {
        if self.is_builtin(type_name) {
            return Some(behavior_api::module::recycle_function);
        }
        self.libraries
            .iter()
            .find(|l| l.offers(type_name))
            .and_then(|l| l.recycler())
    }

    /// A new behavior of `type_name` for the helm domain (`name,low,high,points:...`):
    /// `None` if no source offers the type, `Some(Err(message))` if its constructor
    /// panicked.
    pub fn create(
        &self,
        type_name: &str,
        helm_domain: &str,
    ) -> Option<Result<BehaviorBox, String>> {
        if let Some((_, ctor)) = self.builtins.iter().find(|(n, _)| *n == type_name) {
            return Some(Ok(ctor(&HelmDomain::new(helm_domain))));
        }
        self.libraries
            .iter()
            .find(|l| l.offers(type_name))
            .and_then(|l| l.create(type_name, helm_domain))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every type we provide is one the real helm has, but the template (ours alone).
    #[test]
    fn what_we_provide_is_a_real_helm_type() {
        let builtins = behaviors_std::builtin_types();
        let ours = SHIPPED_LIBRARY_TYPES
            .iter()
            .copied()
            .chain(builtins.iter().map(|(n, _)| *n));
        for t in ours.filter(|t| *t != "BHV_Template") {
            assert!(real_helm_has(t), "{t}");
        }
    }

    #[test]
    fn real_types_we_lack() {
        assert_eq!(REAL_HELM_TYPES.split_whitespace().count(), 46);
        assert!(real_type_not_here("BHV_PeriodicSpeed"));
        assert!(real_type_not_here("BHV_AvdColregsV26"));
        // Ours; refused with its own reason (deprecated); a typo; case matters.
        for t in [
            "BHV_Waypoint",
            "BHV_AvoidObstacle",
            "BHV_Waypiont",
            "bhv_periodicspeed",
        ] {
            assert!(!real_type_not_here(t), "{t}");
        }
    }
}
