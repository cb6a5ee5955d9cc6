//! The root module a behavior library exports, checked by abi_stable at load time.

use abi_stable::library::RootModule;
use abi_stable::package_version_strings;
use abi_stable::sabi_types::VersionStrings;
use abi_stable::std_types::{ROption, RResult, RStr, RString, RVec};
use abi_stable::StableAbi;

use crate::behavior::BehaviorBox;
use crate::function::FunctionData;

/// What a behavior library offers: the types it implements and a factory.
///
/// New entry points are added after `create` (abi_stable prefix types), so a library
/// built against an older compatible `behavior-api` keeps loading.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = BehaviorLibRef)))]
#[sabi(missing_field(panic))]
pub struct BehaviorLib {
    /// The `behavior-api` version the library was built against.
    pub api_version: extern "C" fn() -> RStr<'static>,
    /// The behavior types (`BHV_...`) this library can create.
    pub behavior_types: extern "C" fn() -> RVec<RString>,
    /// Create a behavior of `type_name` for the helm domain `helm_domain`
    /// (`name,low,high,points` joined by `:`): `None` for a type this library does not
    /// offer, `Some(Err(message))` when the constructor panicked.
    #[sabi(last_prefix_field)]
    pub create: extern "C" fn(
        type_name: RStr<'_>,
        helm_domain: RStr<'_>,
    ) -> ROption<RResult<BehaviorBox, RString>>,
    /// Since 0.1.3: take back a function one of this library's behaviors returned from
    /// `on_run`, once the helm has copied it, so that the library's next build reuses its
    /// buffers instead of allocating new ones (issue 19). Absent from a library built
    /// against an older release: the helm then frees the buffers itself.
    #[sabi(missing_field(option))]
    pub recycle_function: extern "C" fn(used: FunctionData),
}

/// [`BehaviorLib::recycle_function`]: hands a used function back to its library.
pub type FunctionRecycler = extern "C" fn(used: FunctionData);

/// The library's side of [`BehaviorLib::recycle_function`] (the export macro's): the
/// buffers go to this library's spare storage on this thread. A panic must not cross
/// the boundary, and there is nothing to report: the buffers are then simply freed.
pub extern "C" fn recycle_function(used: FunctionData) {
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || used.give_back()));
}

impl RootModule for BehaviorLibRef {
    abi_stable::declare_root_module_statics! {BehaviorLibRef}
    const BASE_NAME: &'static str = "ivp_behaviors";
    const NAME: &'static str = "ivp_behaviors";
    const VERSION_STRINGS: VersionStrings = package_version_strings!();
}

/// The version of this crate, as compiled into host and plugins.
pub const API_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Export behavior types from a `cdylib`:
///
/// ```ignore
/// behavior_api::export_behaviors! {
///     "BHV_ConstantSpeed" => ConstantSpeed::new,
/// }
/// ```
/// Each constructor is `fn(&behavior_api::sdk::HelmDomain) -> impl IvpBehavior`.
#[macro_export]
macro_rules! export_behaviors {
    ($($type_name:literal => $ctor:path),+ $(,)?) => {
        #[::abi_stable::export_root_module]
        pub fn ivp_behaviors_root_module() -> $crate::module::BehaviorLibRef {
            use ::abi_stable::prefix_type::PrefixTypeTrait;
            extern "C" fn api_version() -> ::abi_stable::std_types::RStr<'static> {
                ::abi_stable::std_types::RStr::from_str($crate::module::API_VERSION)
            }
            extern "C" fn behavior_types()
                -> ::abi_stable::std_types::RVec<::abi_stable::std_types::RString> {
                let mut v = ::abi_stable::std_types::RVec::new();
                $( v.push(::abi_stable::std_types::RString::from($type_name)); )+
                v
            }
            extern "C" fn create(
                type_name: ::abi_stable::std_types::RStr<'_>,
                helm_domain: ::abi_stable::std_types::RStr<'_>,
            ) -> ::abi_stable::std_types::ROption<
                ::abi_stable::std_types::RResult<
                    $crate::behavior::BehaviorBox,
                    ::abi_stable::std_types::RString,
                >,
            > {
                let domain = $crate::sdk::HelmDomain::new(helm_domain.as_str());
                $(
                    if type_name.as_str() == $type_name {
                        return ::abi_stable::std_types::ROption::RSome(
                            $crate::sdk::boxed_catching(|| $ctor(&domain)),
                        );
                    }
                )+
                ::abi_stable::std_types::ROption::RNone
            }
            $crate::module::BehaviorLib {
                api_version,
                behavior_types,
                create,
                recycle_function: $crate::module::recycle_function,
            }
            .leak_into_prefix()
        }
    };
}
