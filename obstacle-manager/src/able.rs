//! Disable / enable / expunge relays (obstacles.md §2.8): mail on the configured
//! variables becomes a `BHV_ABLE_FILTER` posting for the helm.

use std::collections::VecDeque;

/// Which relay variable the mail came on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    Disable,
    Enable,
    Expunge,
}

impl Action {
    pub fn as_str(self) -> &'static str {
        match self {
            Action::Disable => "disable",
            Action::Enable => "enable",
            Action::Expunge => "expunge",
        }
    }
}

/// A refused relay value.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AbleError {
    #[error("empty value")]
    Empty,
    #[error("neither obstacle_id nor vsource given")]
    NoTarget,
}

/// What one relay mail asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Relay {
    /// The `BHV_ABLE_FILTER` value.
    pub filter: String,
    /// The id, when it came from an `obstacle_id=` field (only then are the recent
    /// lists and the table touched: the reference's quirk for bare ids).
    pub listed_id: Option<String>,
}

/// Read one relay value: a bare id, or a comma list with `obstacle_id` (else `vsource`).
///
/// ```
/// use obstacle_manager::able::{relay, Action};
/// let r = relay(Action::Disable, "ob_2").unwrap();
/// assert_eq!(r.filter, "obstacle_id=ob_2,action=disable");
/// assert_eq!(r.listed_id, None);
/// let r = relay(Action::Expunge, "vsource=lidar").unwrap();
/// assert_eq!(r.filter, "vsource=lidar,action=expunge");
/// ```
pub fn relay(action: Action, value: &str) -> Result<Relay, AbleError> {
    let v = value.trim();
    if v.is_empty() {
        return Err(AbleError::Empty);
    }
    let (msg, listed_id) = if !v.contains('=') && !v.contains(',') {
        (format!("obstacle_id={v}"), None)
    } else {
        let field = |name: &str| {
            v.split(',').find_map(|p| {
                let (k, val) = p.split_once('=')?;
                (k.trim() == name && !val.trim().is_empty()).then(|| val.trim().to_string())
            })
        };
        if let Some(id) = field("obstacle_id") {
            (format!("obstacle_id={id}"), Some(id))
        } else if let Some(src) = field("vsource") {
            (format!("vsource={src}"), None)
        } else {
            return Err(AbleError::NoTarget);
        }
    };
    Ok(Relay {
        filter: format!("{msg},action={}", action.as_str()),
        listed_id,
    })
}

/// Most recent disabled / enabled ids kept, and expunged ids kept.
pub const MAX_RECENT: usize = 250;
pub const MAX_EXPUNGED: usize = 50;

/// The recent-disabled / recent-enabled / expunged lists (most recent first).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AbleLists {
    pub disabled: VecDeque<String>,
    pub enabled: VecDeque<String>,
    pub expunged: VecDeque<String>,
}

fn to_front(list: &mut VecDeque<String>, id: &str, cap: usize) {
    list.retain(|x| x != id);
    list.push_front(id.to_string());
    list.truncate(cap);
}

impl AbleLists {
    pub fn note(&mut self, action: Action, id: &str) {
        match action {
            Action::Disable => {
                to_front(&mut self.disabled, id, MAX_RECENT);
                self.enabled.retain(|x| x != id);
            }
            Action::Enable => {
                to_front(&mut self.enabled, id, MAX_RECENT);
                self.disabled.retain(|x| x != id);
            }
            Action::Expunge => to_front(&mut self.expunged, id, MAX_EXPUNGED),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relays_and_lists() {
        let r = relay(Action::Enable, "vsource=ais, obstacle_id=b").unwrap();
        assert_eq!(r.filter, "obstacle_id=b,action=enable");
        assert_eq!(r.listed_id.as_deref(), Some("b"));
        assert_eq!(
            relay(Action::Enable, "colour=red"),
            Err(AbleError::NoTarget)
        );
        assert_eq!(relay(Action::Enable, "  "), Err(AbleError::Empty));
        let mut l = AbleLists::default();
        l.note(Action::Disable, "a");
        l.note(Action::Disable, "b");
        l.note(Action::Disable, "a");
        assert_eq!(l.disabled, ["a", "b"]);
        l.note(Action::Enable, "a");
        assert_eq!((l.disabled.len(), l.enabled.len()), (1, 1));
        for i in 0..60 {
            l.note(Action::Expunge, &i.to_string());
        }
        assert_eq!(l.expunged.len(), MAX_EXPUNGED);
        assert_eq!(l.expunged[0], "59");
    }
}
