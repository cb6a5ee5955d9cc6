//! Behavior libraries (`cdylib`) loaded through the stable ABI.

use std::path::{Path, PathBuf};

use behavior_api::{BehaviorBox, BehaviorLibRef};

/// A loaded behavior library and the types it offers (never unloaded: behaviors from it
/// may live as long as the process).
#[derive(Clone)]
pub struct LoadedLibrary {
    pub path: PathBuf,
    pub types: Vec<String>,
    module: BehaviorLibRef,
}

impl LoadedLibrary {
    pub fn offers(&self, type_name: &str) -> bool {
        self.types.iter().any(|t| t == type_name)
    }

    pub fn create(&self, type_name: &str, helm_domain: &str) -> Option<BehaviorBox> {
        (self.module.create())(type_name.into(), helm_domain.into()).into_option()
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

/// Load every behavior library in `dirs`, in order; a type offered twice keeps the first.
pub fn load_dirs(
    dirs: &[PathBuf],
    builtin: &dyn Fn(&str) -> bool,
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
            .filter(|p| p.is_file() && is_library(p))
            .collect();
        files.sort();
        for path in files {
            // Not `RootModule::load_from_file`: that caches one root module per process,
            // and we load many libraries of the same root-module type.
            let loaded = abi_stable::library::lib_header_from_path(&path)
                .and_then(|h| h.init_root_module::<BehaviorLibRef>());
            match loaded {
                Ok(module) => {
                    let mut types: Vec<String> = (module.behavior_types())()
                        .into_iter()
                        .map(String::from)
                        .collect();
                    types.retain(|t| {
                        if builtin(t) {
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
                Err(e) => events.push(LoadEvent::Refused {
                    path: path.clone(),
                    reason: e.to_string(),
                }),
            }
        }
    }
    (libs, events)
}
