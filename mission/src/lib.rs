//! `helm-mission`: reading a mission as pHelmIvP does: the `.moos` file's pHelmIvP block
//! and globals, the `.bhv` files, the behavior libraries (helm.md §1-§2, §5), into a
//! built [`helm_engine::Helm`].
//!
//! It depends on `helm-engine`, `moos-mission` (the file reader) and `bhv`; it must not
//! depend on the MOOS client or DB, the app or the simulator (all three use it).
//!
//! Every problem is collected as one readable line naming the file and line; any
//! problem makes the helm MALCONFIG (it never drives), as the real helm does.
//!
//! ```
//! let moos = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/alpha/alpha.moos");
//! let loaded = helm_mission::load(&moos, &[], "pHelmIvP").unwrap();
//! let (helm, _mission) = loaded.into_helm();
//! assert!(helm.config_warnings().is_empty());
//! assert!(helm.behavior_names().contains(&"waypt_survey".to_string()));
//! ```

use std::path::{Path, PathBuf};

use helm_engine::config::{BlockLine, HelmConfig};
use helm_engine::factory::BehaviorFactory;
use helm_engine::loader::{load_dirs, LoadEvent};
use helm_engine::Helm;

/// A fatal error before the helm exists (the mission file itself cannot be read).
#[derive(Debug, thiserror::Error)]
pub enum MissionLoadError {
    #[error("{0}")]
    Mission(#[from] moos_mission::mission::MissionError),
    #[error(
        "{}: this is a behavior file (.bhv); give the mission file (.moos) that names it \
         (`behaviors = {}` in its pHelmIvP block), or a folder holding one",
        .0.display(),
        .0.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    )]
    BhvAsMission(PathBuf),
}

/// Everything read for one helm.
pub struct LoadedMission {
    pub mission: moos_mission::mission::MissionFile,
    pub app_name: String,
    pub ownship: String,
    pub config: HelmConfig,
    pub bhv_files: Vec<PathBuf>,
    /// Start-up text about behavior libraries (`Loading behavior dynamic libraries....`).
    pub library_report: Vec<String>,
    pub factory: BehaviorFactory,
    pub warnings: Vec<String>,
}

impl LoadedMission {
    /// Build the helm from what was read (MALCONFIG if there were warnings).
    pub fn into_helm(self) -> (Helm, moos_mission::mission::MissionFile) {
        let (recipe, mission) = self.into_recipe();
        (recipe.build(), mission)
    }

    /// What builds the helm, kept to build it again (e.g. once per simulated run):
    /// the `.bhv` files are read here, once.
    pub fn into_recipe(self) -> (HelmRecipe, moos_mission::mission::MissionFile) {
        let mut warnings = self.warnings;
        let spec = match bhv::reader::read_files(&self.bhv_files) {
            Ok(spec) => spec,
            Err(e) => {
                warnings.push(e.to_string());
                bhv::reader::SetSpec::default()
            }
        };
        let recipe = HelmRecipe {
            config: self.config,
            spec,
            factory: self.factory,
            ownship: self.ownship,
            app_name: self.app_name,
            warnings,
        };
        (recipe, self.mission)
    }
}

/// Everything [`Helm::new`] needs, read once; [`HelmRecipe::build`] makes a fresh helm.
#[derive(Clone)]
pub struct HelmRecipe {
    pub config: HelmConfig,
    pub spec: bhv::reader::SetSpec,
    pub factory: BehaviorFactory,
    pub ownship: String,
    pub app_name: String,
    /// Problems found while reading (non-empty: the helm is MALCONFIG).
    pub warnings: Vec<String>,
}

impl HelmRecipe {
    pub fn build(&self) -> Helm {
        let mut helm = Helm::new(
            self.config.clone(),
            self.spec.clone(),
            &self.factory,
            &self.ownship,
            self.warnings.clone(),
        );
        helm.set_app_name(&self.app_name);
        helm
    }
}

fn resolve(mission_dir: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() || p.exists() {
        p.to_path_buf()
    } else {
        let alt = mission_dir.join(p);
        if alt.exists() {
            alt
        } else {
            p.to_path_buf()
        }
    }
}

/// Read `mission` for the app `app_name` (block `ProcessConfig = <app_name>`), plus the
/// `.bhv` files named on the command line.
pub fn load(
    mission: &Path,
    extra_bhv: &[PathBuf],
    app_name: &str,
) -> Result<LoadedMission, MissionLoadError> {
    if mission
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("bhv"))
    {
        return Err(MissionLoadError::BhvAsMission(mission.to_path_buf()));
    }
    let file = moos_mission::mission::MissionFile::read(mission)?;
    let shown = mission.display().to_string();
    let dir = mission.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut warnings = Vec::new();

    let lines: Vec<BlockLine> = match file.process_config(app_name) {
        Some(lines) => lines
            .into_iter()
            .filter(|l| l.raw.contains('='))
            .map(|l| BlockLine {
                line: l.line,
                name: l.name,
                value: l.value,
            })
            .collect(),
        None => {
            warnings.push(format!(
                "{shown}: No mission config block found for {app_name}"
            ));
            Vec::new()
        }
    };
    let (mut config, cfg_warnings) = HelmConfig::from_lines(&lines);
    config.origin = file
        .global_f64("LatOrigin")
        .zip(file.global_f64("LongOrigin"));
    for w in cfg_warnings {
        warnings.push(format!("{shown}:{}: {}", w.line, w.text));
    }
    let ownship = match file.global("Community") {
        Some(c) if !c.is_empty() => c,
        _ => {
            warnings.push(format!(
                "{shown}: Community/Vehicle name not found in mission file"
            ));
            String::new()
        }
    };
    // helm.md §2.2: globals the helm reads whose bad values are config warnings (an app
    // would otherwise fall back to a default without a word).
    if let Some(v) = file.global("TERM_REPORTING") {
        if helm_engine::config::parse_bool(&v).is_none() {
            warnings.push(format!(
                "{shown}: TERM_REPORTING = {v}: not a boolean (true or false)"
            ));
        }
    }
    if let Some(v) = file.global("MOOSTimeWarp") {
        let ok = moos_mission::mission::config_f64(&v).is_some_and(moos_mission::time::warp_ok);
        if !ok {
            warnings.push(format!(
                "{shown}: MOOSTimeWarp = {v}: not a time warp (above 0, at most 400)"
            ));
        }
    }
    if file.global("LatOrigin").is_none() {
        warnings.push(format!("{shown}: No LatOrigin in *.moos file"));
    }
    if file.global("LongOrigin").is_none() {
        warnings.push(format!("{shown}: No LongOrigin set in *.moos file"));
    }

    let mut bhv_files: Vec<PathBuf> = Vec::new();
    for (i, p) in config.behaviors.iter().chain(extra_bhv.iter()).enumerate() {
        let r = resolve(&dir, p);
        if !r.exists() {
            // Name the line that asked for it: the user edits that line, not the file.
            let asked = if i < config.behaviors.len() {
                lines
                    .iter()
                    .find(|l| {
                        l.name.eq_ignore_ascii_case("behaviors")
                            && Path::new(l.value.trim()) == p.as_path()
                    })
                    .map_or_else(
                        || format!("{shown}: behaviors = {}", p.display()),
                        |l| format!("{shown}:{}: behaviors = {}", l.line, l.value.trim()),
                    )
            } else {
                format!("the command line: {}", p.display())
            };
            warnings.push(format!("{asked}: Could not find File: {}", r.display()));
            continue;
        }
        if bhv_files.contains(&r) {
            warnings.push(format!(
                "{shown}: behavior file named twice: {}",
                p.display()
            ));
        } else {
            bhv_files.push(r);
        }
    }

    let mut dirs = behavior_dirs_from_env();
    // A configured directory that does not exist is a configuration problem, unless
    // `bhv_dir_not_found_ok` (helm.md §2.1); then it is not mentioned at all.
    for (d, line) in &config.behavior_dirs {
        let r = resolve(&dir, d);
        if r.is_dir() {
            dirs.push(r);
        } else if !config.bhv_dir_not_found_ok {
            warnings.push(format!(
                "{shown}:{line}: behavior directory not found: {} \
                 (bhv_dir_not_found_ok = true allows it)",
                d.display()
            ));
        }
    }
    let (factory, library_report) = factory_with_bundled(&dirs);
    Ok(LoadedMission {
        mission: file,
        app_name: app_name.to_string(),
        ownship,
        config,
        bhv_files,
        library_report,
        factory,
        warnings,
    })
}

/// The directories of `IVP_BEHAVIOR_DIRS` (colon-separated, blanks trimmed).
pub fn behavior_dirs_from_env() -> Vec<PathBuf> {
    std::env::var("IVP_BEHAVIOR_DIRS")
        .unwrap_or_default()
        .split(':')
        .map(str::trim)
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .collect()
}

/// Where the behavior libraries shipped with the helm are (ConstantSpeed, StationKeep,
/// ...: compiled into the C++ helm, plugins here). They are searched after every
/// configured directory, so an unchanged MOOS-IvP mission finds them with no
/// `ivp_behavior_dir`. `IVP_HELM_BUNDLED_DIR` names the folders (empty: none); by
/// default the helm binary's own folder (where cargo puts the plugins) and
/// `../lib/ivp-helm` beside it.
pub fn bundled_dirs() -> Vec<PathBuf> {
    if let Some(v) = std::env::var_os("IVP_HELM_BUNDLED_DIR") {
        return std::env::split_paths(&v)
            .filter(|d| !d.as_os_str().is_empty())
            .collect();
    }
    let Some(bin_dir) = std::env::current_exe()
        .ok()
        .and_then(|e| e.canonicalize().ok())
        .and_then(|e| e.parent().map(Path::to_path_buf))
    else {
        return Vec::new();
    };
    let installed = bin_dir.join("../lib/ivp-helm");
    vec![bin_dir, installed]
}

/// Only our own libraries (`libbhv_*`) are opened in a bundled folder: other shared
/// objects next to the binary are not behavior libraries.
fn is_bundled_library(p: &Path) -> bool {
    p.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("libbhv_"))
}

/// [`factory_for`] `dirs`, then the [`bundled_dirs`] for the types still missing.
pub fn factory_with_bundled(dirs: &[PathBuf]) -> (BehaviorFactory, Vec<String>) {
    let bundled = bundled_dirs();
    let (mut factory, report) = factory_from(dirs, &bundled);
    if !factory
        .libraries()
        .iter()
        .any(|l| is_bundled_library(&l.path))
    {
        factory.bundled_missing = Some(bundled_missing_text(&bundled));
    }
    (factory, report)
}

/// Built-in behaviors plus every library found in `dirs` (only those), and the start-up
/// report. A missing directory is reported, not fatal: it only matters if a behavior the
/// `.bhv` files need is then not found (that error names the directories searched).
pub fn factory_for(dirs: &[PathBuf]) -> (BehaviorFactory, Vec<String>) {
    factory_from(dirs, &[])
}

fn factory_from(dirs: &[PathBuf], bundled: &[PathBuf]) -> (BehaviorFactory, Vec<String>) {
    let mut factory = BehaviorFactory::with_builtins();
    let builtin = |t: &str| factory.is_builtin(t);
    let (mut libs, events) = load_dirs(dirs, &builtin, &|_| true);
    let mut report = vec!["Loading behavior dynamic libraries....".to_string()];
    report_events(&events, &mut report);
    let canonical = |d: &Path| d.canonicalize().unwrap_or_else(|_| d.to_path_buf());
    let configured: Vec<PathBuf> = dirs.iter().map(|d| canonical(d)).collect();
    let mut searched: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
    for dir in bundled {
        // A folder also configured was loaded above; a missing one is just not installed.
        if configured.contains(&canonical(dir)) || !dir.is_dir() {
            continue;
        }
        // A type a configured library offers stays with it, silently.
        let taken = |t: &str| factory.is_builtin(t) || libs.iter().any(|l| l.offers(t));
        let (found, events) = load_dirs(std::slice::from_ref(dir), &taken, &is_bundled_library);
        searched.push(format!("{} (bundled)", dir.display()));
        report.push(format!("  Loading bundled directory: {}", dir.display()));
        let events: Vec<LoadEvent> = events
            .into_iter()
            .filter(|e| match e {
                LoadEvent::Directory(_) => false,
                LoadEvent::Loaded { types, .. } => !types.is_empty(),
                _ => true,
            })
            .collect();
        report_events(&events, &mut report);
        libs.extend(found.into_iter().filter(|l| !l.types.is_empty()));
    }
    factory.searched_dirs = searched;
    report.push("Loading behavior dynamic libraries.... FINISHED.".to_string());
    for l in libs {
        factory.add_library(l);
    }
    (factory, report)
}

/// Why the shipped libraries were not found, and what to do (README, Install).
fn bundled_missing_text(bundled: &[PathBuf]) -> String {
    let fix = "set IVP_BEHAVIOR_DIRS=<the folder of the libbhv_* files> or copy them there \
               (README: Install)";
    if bundled.is_empty() {
        return format!(
            "bundled behavior libraries not looked for (IVP_HELM_BUNDLED_DIR is empty); {fix}"
        );
    }
    let binary = std::env::current_exe()
        .map(|e| e.display().to_string())
        .unwrap_or_else(|_| "the helm binary".into());
    format!("bundled behavior libraries not found beside {binary} (nor in ../lib/ivp-helm from it); {fix}")
}

fn report_events(events: &[LoadEvent], report: &mut Vec<String>) {
    for e in events {
        match e {
            LoadEvent::Directory(d) => report.push(format!("  Loading directory: {}", d.display())),
            LoadEvent::MissingDirectory(d) => report.push(format!(
                "  Could not find behavior directory: {}",
                d.display()
            )),
            LoadEvent::Loaded { path, types } => {
                for t in types {
                    report.push(format!("    {t}  ({})", path.display()));
                }
            }
            LoadEvent::Refused { path, reason } => {
                report.push(format!("    skipped {}: {reason}", path.display()))
            }
            LoadEvent::Duplicate {
                type_name,
                kept,
                ignored,
            } => report.push(format!(
                "    warning: {type_name} offered by {} and {}: using the first",
                kept.display(),
                ignored.display()
            )),
        }
    }
}
