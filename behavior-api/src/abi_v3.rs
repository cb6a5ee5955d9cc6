//! The root module of `behavior-api` 0.1.2 (the `_into` context methods), frozen, so
//! that a library built against it still loads in this helm; the same device as
//! [`crate::abi_v2`] for 0.1.1, but smaller.
//!
//! 0.1.3 appended `recycle_function` to [`crate::module::BehaviorLib`]. abi_stable
//! refuses a library whose root module has fewer fields than the helm's, so a 0.1.2
//! library is opened through [`module::BehaviorLibRef`] below, whose fields are byte for
//! byte those of 0.1.2. Its behaviors and contexts are unchanged since 0.1.2: they are
//! the current ones, with no adapter; the helm frees their functions' buffers itself.
//!
//! Nothing here may change. A plugin author never uses this module; the helm's loader
//! does.

/// `BehaviorLib` as 0.1.2 had it.
pub mod module {
    use abi_stable::library::RootModule;
    use abi_stable::package_version_strings;
    use abi_stable::sabi_types::VersionStrings;
    use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};
    use abi_stable::StableAbi;

    use crate::behavior::BehaviorBox;

    #[repr(C)]
    #[derive(StableAbi)]
    #[sabi(kind(Prefix(prefix_ref = BehaviorLibRef)))]
    #[sabi(missing_field(panic))]
    pub struct BehaviorLib {
        pub api_version: extern "C" fn() -> RStr<'static>,
        pub behavior_types: extern "C" fn() -> RVec<RString>,
        #[sabi(last_prefix_field)]
        pub create: extern "C" fn(
            type_name: RStr<'_>,
            helm_domain: RStr<'_>,
        ) -> ROption<RResult<BehaviorBox, RString>>,
    }

    impl RootModule for BehaviorLibRef {
        abi_stable::declare_root_module_statics! {BehaviorLibRef}
        const BASE_NAME: &'static str = "ivp_behaviors";
        const NAME: &'static str = "ivp_behaviors";
        const VERSION_STRINGS: VersionStrings = package_version_strings!();
    }
}

/// Whether a library built against behavior-api `version` speaks this frozen ABI.
pub fn speaks_v3(version: &str) -> bool {
    version == "0.1.2"
}
