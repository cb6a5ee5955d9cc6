//! `behavior-loader`: behavior libraries (`cdylib`) found in the behavior folders and
//! loaded through the stable ABI, each file opened and its layout checked once per
//! process, and the behaviors they offer created by type name. Libraries built against
//! an earlier `behavior-api` release are adapted here (see `Module`).
//!
//! It depends on the SDK (`behavior-api`) and `abi_stable` only: it must not depend on
//! the helm's engine, its drivers, MOOS or the simulator (the engine's factory holds the
//! libraries it loads).

use std::path::{Path, PathBuf};

use behavior_api::{abi_v1, abi_v2, abi_v3, BehaviorBox, BehaviorLibRef};

/// A loaded behavior library and the types it offers (never unloaded: behaviors from it
/// may live as long as the process).
#[derive(Clone)]
pub struct LoadedLibrary {
    pub path: PathBuf,
    pub types: Vec<String>,
    module: Module,
}

/// A library's root module, in the ABI it was built with.
#[derive(Clone, Copy)]
enum Module {
    Current(BehaviorLibRef),
    /// Built against behavior-api 0.1.0 (before contacts): its behaviors are adapted.
    V1(abi_v1::module::BehaviorLibRef),
    /// Built against behavior-api 0.1.1 (contacts, before the `_into` context methods).
    V2(abi_v2::module::BehaviorLibRef),
    /// Built against behavior-api 0.1.2 (before `recycle_function`): its behaviors are
    /// current ones.
    V3(abi_v3::module::BehaviorLibRef),
}

impl Module {
    fn behavior_types(self) -> abi_stable::std_types::RVec<abi_stable::std_types::RString> {
        match self {
            Module::Current(m) => (m.behavior_types())(),
            Module::V1(m) => (m.behavior_types())(),
            Module::V2(m) => (m.behavior_types())(),
            Module::V3(m) => (m.behavior_types())(),
        }
    }
}

impl LoadedLibrary {
    pub fn offers(&self, type_name: &str) -> bool {
        self.types.iter().any(|t| t == type_name)
    }

    /// How to hand this library's functions back once the helm has read them (0.1.3
    /// and later).
    pub fn recycler(&self) -> Option<behavior_api::FunctionRecycler> {
        match self.module {
            Module::Current(m) => m.recycle_function(),
            Module::V1(_) | Module::V2(_) | Module::V3(_) => None,
        }
    }

    /// `None`: not offered here; `Some(Err)`: the constructor panicked (its message).
    pub fn create(
        &self,
        type_name: &str,
        helm_domain: &str,
    ) -> Option<Result<BehaviorBox, String>> {
        match self.module {
            Module::Current(m) => (m.create())(type_name.into(), helm_domain.into())
                .into_option()
                .map(|r| r.into_result().map_err(String::from)),
            Module::V1(m) => (m.create())(type_name.into(), helm_domain.into())
                .into_option()
                .map(|r| r.into_result().map(abi_v1::adapt).map_err(String::from)),
            Module::V2(m) => (m.create())(type_name.into(), helm_domain.into())
                .into_option()
                .map(|r| r.into_result().map(abi_v2::adapt).map_err(String::from)),
            Module::V3(m) => (m.create())(type_name.into(), helm_domain.into())
                .into_option()
                .map(|r| r.into_result().map_err(String::from)),
        }
    }
}

/// What happened to one file or directory while loading.
#[derive(Debug, Clone, PartialEq)]
pub enum LoadEvent {
    Directory(PathBuf),
    MissingDirectory(PathBuf),
    Loaded {
        path: PathBuf,
        types: Vec<String>,
    },
    Refused {
        path: PathBuf,
        reason: String,
    },
    Duplicate {
        type_name: String,
        kept: PathBuf,
        ignored: PathBuf,
    },
}

fn is_library(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| e == "so" || e == "dylib" || e == "dll")
}

/// Libraries this process has opened, by path. A fleet's every vehicle loads the same
/// ones, and abi_stable's layout check walks every type of the ABI each time (about
/// 2.6 M instructions a library, a tenth of a second for ten vehicles). A library stays
/// loaded for the life of the process, and the system would hand back the loaded one
/// for the same path anyway, so the module found the first time is the answer.
static OPENED: std::sync::Mutex<Vec<(PathBuf, Module)>> = std::sync::Mutex::new(Vec::new());

/// [`load_one`], once per path and process (refusals are not kept: they are rare, and
/// the file may be mended).
fn load_once(path: &Path) -> Result<Module, String> {
    let opened = || OPENED.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(&(_, module)) = opened().iter().find(|(p, _)| p == path) {
        return Ok(module);
    }
    let module = load_one(path)?;
    let mut all = opened();
    if !all.iter().any(|(p, _)| p == path) {
        all.push((path.to_path_buf(), module));
    }
    Ok(module)
}

/// Open one library: check the `behavior-api` version it was built against, then let
/// abi_stable check every type layout. The reason for a refusal is one line.
fn load_one(path: &Path) -> Result<Module, String> {
    let header = abi_stable::library::lib_header_from_path(path).map_err(|e| first_line(&e))?;
    let theirs = header.version_strings().version.as_str().to_string();
    let ours = behavior_api::API_VERSION;
    if !versions_compatible(&theirs, ours) {
        return Err(format!(
            "built against behavior-api {theirs}, this helm has behavior-api {ours} \
             (rebuild the library against {ours})"
        ));
    }
    let refused = |e: abi_stable::library::LibraryError| {
        format!(
            "incompatible with this helm's behavior-api {ours}: {}",
            first_line(&e)
        )
    };
    // Not `RootModule::load_from_file`: that caches one root module per process, and we
    // load many libraries of the same root-module type.
    if abi_v1::speaks_v1(&theirs) {
        return header
            .init_root_module::<abi_v1::module::BehaviorLibRef>()
            .map(Module::V1)
            .map_err(refused);
    }
    if abi_v2::speaks_v2(&theirs) {
        return header
            .init_root_module::<abi_v2::module::BehaviorLibRef>()
            .map(Module::V2)
            .map_err(refused);
    }
    if abi_v3::speaks_v3(&theirs) {
        return header
            .init_root_module::<abi_v3::module::BehaviorLibRef>()
            .map(Module::V3)
            .map_err(refused);
    }
    header
        .init_root_module::<BehaviorLibRef>()
        .map(Module::Current)
        .map_err(refused)
}

/// The whole reason on one line (abi_stable splits "could not open library at: PATH"
/// and the system's reason over several lines; cutting at the first lost the reason).
/// Only a layout report of many lines is shortened, and says by how much.
fn first_line(e: &dyn std::fmt::Display) -> String {
    const MAX: usize = 1500;
    let text = e.to_string();
    let joined = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    if joined.len() <= MAX {
        return joined;
    }
    let cut = (0..=MAX)
        .rev()
        .find(|&i| joined.is_char_boundary(i))
        .unwrap_or(0);
    format!(
        "{} ... ({} more characters)",
        &joined[..cut],
        joined.len() - cut
    )
}

/// abi_stable's rule: same major; for 0.x, same minor; the library's minor (or patch
/// for 0.x) may not be newer than ours.
fn versions_compatible(theirs: &str, ours: &str) -> bool {
    let parse = |v: &str| -> Option<(u32, u32, u32)> {
        let mut it = v.split('.').map(|p| p.parse::<u32>().ok());
        Some((it.next()??, it.next()??, it.next()??))
    };
    match (parse(theirs), parse(ours)) {
        (Some((a, b, c)), Some((x, y, z))) => {
            if a != x {
                false
            } else if a == 0 {
                b == y && c <= z
            } else {
                b <= y
            }
        }
        _ => false,
    }
}

/// Load every behavior library in `dirs` that `wanted` accepts, in order; a type offered
/// twice keeps the first; a type `taken` says is had already is not offered at all.
pub fn load_dirs(
    dirs: &[PathBuf],
    taken: &dyn Fn(&str) -> bool,
    wanted: &dyn Fn(&Path) -> bool,
) -> (Vec<LoadedLibrary>, Vec<LoadEvent>) {
    let mut libs: Vec<LoadedLibrary> = Vec::new();
    let mut events = Vec::new();
    let mut seen_dirs: Vec<PathBuf> = Vec::new();
    for dir in dirs {
        if seen_dirs.contains(dir) {
            continue;
        }
        seen_dirs.push(dir.clone());
        let Ok(entries) = std::fs::read_dir(dir) else {
            events.push(LoadEvent::MissingDirectory(dir.clone()));
            continue;
        };
        events.push(LoadEvent::Directory(dir.clone()));
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file() && is_library(p) && wanted(p))
            .collect();
        files.sort();
        for path in files {
            match load_once(&path) {
                Ok(module) => {
                    let mut types: Vec<String> = module
                        .behavior_types()
                        .into_iter()
                        .map(String::from)
                        .collect();
                    types.retain(|t| {
                        if taken(t) {
                            return false;
                        }
                        if let Some(first) = libs.iter().find(|l| l.offers(t)) {
                            events.push(LoadEvent::Duplicate {
                                type_name: t.clone(),
                                kept: first.path.clone(),
                                ignored: path.clone(),
                            });
                            return false;
                        }
                        true
                    });
                    events.push(LoadEvent::Loaded {
                        path: path.clone(),
                        types: types.clone(),
                    });
                    libs.push(LoadedLibrary {
                        path,
                        types,
                        module,
                    });
                }
                Err(reason) => events.push(LoadEvent::Refused {
                    path: path.clone(),
                    reason,
                }),
            }
        }
    }
    (libs, events)
}

#[cfg(test)]
mod tests {
    use super::versions_compatible;

    #[test]
    fn version_rule() {
        assert!(versions_compatible("0.1.0", "0.1.0"));
        assert!(versions_compatible("0.1.0", "0.1.3"));
        assert!(!versions_compatible("0.1.4", "0.1.3"));
        assert!(!versions_compatible("0.2.0", "0.1.0"));
        assert!(versions_compatible("1.0.0", "1.2.0"));
        assert!(!versions_compatible("1.3.0", "1.2.0"));
        assert!(!versions_compatible("2.0.0", "1.2.0"));
    }
}
