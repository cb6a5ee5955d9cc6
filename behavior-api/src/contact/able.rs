//! `BHV_ABLE_FILTER` (contacts-appcast.md §3.8): disable, enable or expunge contact
//! behaviors by contact, behavior type or vsource.

use contacts::{AbleAction, AbleFilter};

use super::ContactBase;
use crate::sdk::Ctx;

/// What this iteration's able-filter strings did to the behavior.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbleOutcome {
    /// An `expunge` applied: the behavior must complete.
    pub expunge: bool,
    /// Strings that could not be read (the helm's `Unhandled BHV_ABLE_FILTER`).
    pub malformed: u32,
}

impl ContactBase {
    /// Subscribe to `BHV_ABLE_FILTER` (call from `on_params_complete` when the type
    /// offers `can_disable`).
    pub fn subscribe_able_filter(&self, ctx: &mut Ctx<'_>) {
        if self.can_disable {
            ctx.add_info_vars_no_warning("BHV_ABLE_FILTER");
        }
    }

    /// Apply this iteration's `BHV_ABLE_FILTER` strings (only with `can_disable`):
    /// every given field must match (type, contact, vsource; case-insensitive).
    pub fn able_filter(&mut self, ctx: &mut Ctx<'_>, type_name: &str) -> AbleOutcome {
        let mut out = AbleOutcome::default();
        if !self.can_disable {
            return out;
        }
        for s in ctx.get_buffer_string_vector("BHV_ABLE_FILTER") {
            match AbleFilter::parse(&s) {
                Ok(f) if f.applies_to(type_name, &self.contact, &self.cn_vsource) => {
                    match f.action {
                        AbleAction::Disable => self.disabled = true,
                        AbleAction::Enable => self.disabled = false,
                        AbleAction::Expunge => out.expunge = true,
                    }
                }
                Ok(_) => {}
                Err(e) => {
                    out.malformed += 1;
                    ctx.post_wmessage(&format!("Unhandled BHV_ABLE_FILTER: {e}"));
                }
            }
        }
        out
    }
}
