//! The `.bhv` language of the IvP helm (specs/bhv-format.md).
//!
//! * [`reader`]: reads behavior files into a [`reader::SetSpec`]:
//!   initializations, behavior blocks (their configuration lines), mode
//!   declarations; every syntax error is reported with file, line and text.
//! * [`logic`]: logic conditions, parsed once into a tree with persistent,
//!   type-sticky variable slots, evaluated without allocating.
//! * [`modes`]: mode declarations (`set` blocks) and their evaluation.
//! * [`flag`]: flag values (`VAR = VALUE [if] CONDITION`).
//! * [`number`]: the helm's number test, C `atof`, value typing.
//!
//! ```
//! use bhv::number::Value;
//! use std::collections::HashMap;
//! use std::path::Path;
//!
//! let text = "initialize DEPLOY = false
//! set MODE = ACTIVE {
//!   DEPLOY = true
//! } INACTIVE
//!
//! Behavior = BHV_Waypoint
//! {
//!   name      = survey
//!   condition = MODE == ACTIVE
//!   speed     = 2   // m/s
//! }
//! ";
//! let mut spec = bhv::reader::parse_str(text, Path::new("alpha.bhv")).unwrap();
//! assert_eq!(spec.inits[0].value, Value::Str("false".into()));
//! let b = &spec.behaviors[0];
//! assert_eq!((b.type_name.as_str(), b.line), ("BHV_Waypoint", 6));
//! assert_eq!(b.lines[2].value, "2");
//!
//! let mut info: HashMap<String, Value> = HashMap::new();
//! info.insert("DEPLOY".into(), Value::Str("true".into()));
//! let modes = spec.modes.evaluate(&info).to_vec();
//! assert_eq!(modes, [("MODE".to_string(), "ACTIVE".to_string())]);
//!
//! let mut cond = bhv::logic::parse_condition_param(&b.lines[1].value).unwrap();
//! info.insert("MODE".into(), Value::Str(modes[0].1.clone()));
//! cond.update(&info);
//! assert!(cond.eval());
//! ```

pub mod error;
pub mod flag;
pub mod logic;
pub mod modes;
pub mod number;
pub mod reader;
pub mod vocabulary;

pub use error::{BhvError, BhvErrorKind, LogicError};
pub use flag::{parse_flag, FlagParam, FlagSpec};
pub use logic::{LogicCondition, VarSource};
pub use modes::{ModeEntry, ModeSet};
pub use number::{atof, is_number, typed_value, Value};
pub use reader::{parse_str, read_files, BehaviorSpec, ConfigLine, Init, SetSpec, Templating};
