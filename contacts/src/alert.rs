//! The strings of the alert protocol between contact behaviors, the helm and a contact
//! manager: the spawn/update string (`name=bob # contact=bob`, bhv-format.md §9), the
//! `BCM_ALERT_REQUEST` a template posts at helm start (contacts-appcast.md §3.4), and
//! `BHV_ABLE_FILTER` (§3.8) with the helm's black-list.

use crate::filter::ContactFilter;

/// A malformed alert string.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AlertError {
    #[error("not key=value: {0}")]
    NotAPair(String),
    #[error("unknown key: {0}")]
    UnknownKey(String),
    #[error("repeated key: {0}")]
    RepeatedKey(String),
    #[error("action must be disable, enable or expunge: {0}")]
    BadAction(String),
    #[error("no action")]
    NoAction,
    #[error("no contact, bhv_type or vsource")]
    NoTarget,
}

/// Split at `sep` outside double quotes.
fn split_quoted(s: &str, sep: char) -> impl Iterator<Item = &str> {
    let mut in_quote = false;
    let mut start = 0;
    let mut pieces = Vec::new();
    for (i, c) in s.char_indices() {
        if c == '"' {
            in_quote = !in_quote;
        } else if c == sep && !in_quote {
            pieces.push(&s[start..i]);
            start = i + c.len_utf8();
        }
    }
    pieces.push(&s[start..]);
    pieces.into_iter()
}

/// One `key=value` field: exactly one `=` outside quotes; key and value trimmed.
fn pair(field: &str) -> Result<(&str, &str), AlertError> {
    let mut parts = split_quoted(field, '=');
    match (parts.next(), parts.next(), parts.next()) {
        (Some(k), Some(v), None) if !k.trim().is_empty() => Ok((k.trim(), v.trim())),
        _ => Err(AlertError::NotAPair(field.trim().to_string())),
    }
}

/// The pairs of an update/spawn string: fields separated by `#`, each `key=value`.
///
/// ```
/// let p = contacts::update_pairs("name=bob # contact=bob").unwrap();
/// assert_eq!(p, [("name", "bob"), ("contact", "bob")]);
/// ```
pub fn update_pairs(s: &str) -> Result<Vec<(&str, &str)>, AlertError> {
    split_quoted(s, '#').map(pair).collect()
}

/// Whether the templating specs look at an update string at all (it contains `name`).
pub fn may_spawn(s: &str) -> bool {
    s.contains("name")
}

/// The `name` of an update string, `""` when it has none or any field is not exactly
/// `key=value` (bhv-format.md §9). The spawned behavior is the template prefix + this.
///
/// ```
/// assert_eq!(contacts::spawn_name("name=bob # contact=bob"), "bob");
/// assert_eq!(contacts::spawn_name("name=bob # oops"), "");
/// ```
pub fn spawn_name(s: &str) -> &str {
    match update_pairs(s) {
        Ok(p) => p
            .iter()
            .rev()
            .find(|(k, _)| *k == "name")
            .map_or("", |(_, v)| v),
        Err(_) => "",
    }
}

/// The `BCM_ALERT_REQUEST` of a contact template (§3.4): prefix = the template's name,
/// `var` = its `updates` variable, ranges printed with one decimal at most, the filter
/// summary appended when a filter is set. Mind the irregular spaces: they are the
/// reference's.
///
/// ```
/// let f = contacts::ContactFilter::default();
/// assert_eq!(
///     contacts::alert_request("avd_", "CONTACT_INFO", 50.0, 75.0, &f),
///     "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=50, cpa_range=75"
/// );
/// ```
pub fn alert_request(
    prefix: &str,
    var: &str,
    alert_range: f64,
    cpa_range: f64,
    filter: &ContactFilter,
) -> String {
    let mut s = format!(
        "id={prefix}, on_flag={var}=name=$[VNAME] # contact=$[VNAME],alert_range={}, cpa_range={}",
        mbutil::compact(alert_range, 1),
        mbutil::compact(cpa_range, 1)
    );
    if !filter.is_empty() {
        s.push(',');
        s.push_str(&filter.summary());
    }
    s
}

/// What a `BHV_ABLE_FILTER` asks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AbleAction {
    Disable,
    Enable,
    Expunge,
}

/// A well-formed `BHV_ABLE_FILTER` (§3.8): an action and at least one of contact,
/// behavior type, vsource (all lower-cased).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AbleFilter {
    pub action: AbleAction,
    pub contact: Option<String>,
    pub bhv_type: Option<String>,
    pub vsource: Option<String>,
}

impl AbleFilter {
    /// Parse as a contact behavior with `can_disable = true` does; an error is what the
    /// helm reports as `Unhandled BHV_ABLE_FILTER`.
    ///
    /// ```
    /// let f = contacts::AbleFilter::parse("action=disable,contact=Bob").unwrap();
    /// assert!(f.applies_to("BHV_AvoidCollision", "BOB", ""));
    /// assert!(contacts::AbleFilter::parse("action=able,contact=bob").is_err());
    /// ```
    pub fn parse(s: &str) -> Result<AbleFilter, AlertError> {
        let (mut action, mut contact, mut bhv_type, mut vsource) = (None, None, None, None);
        for field in split_quoted(s, ',') {
            let (k, v) = pair(field)?;
            let (k, v) = (k.to_ascii_lowercase(), v.to_ascii_lowercase());
            let slot = match k.as_str() {
                "action" => {
                    let a = match v.as_str() {
                        "disable" => AbleAction::Disable,
                        "enable" => AbleAction::Enable,
                        "expunge" => AbleAction::Expunge,
                        _ => return Err(AlertError::BadAction(v)),
                    };
                    if action.replace(a).is_some() {
                        return Err(AlertError::RepeatedKey(k));
                    }
                    continue;
                }
                "contact" => &mut contact,
                "bhv_type" => &mut bhv_type,
                "vsource" => &mut vsource,
                _ => return Err(AlertError::UnknownKey(k)),
            };
            if slot.replace(v).is_some() {
                return Err(AlertError::RepeatedKey(k));
            }
        }
        let action = action.ok_or(AlertError::NoAction)?;
        if contact.is_none() && bhv_type.is_none() && vsource.is_none() {
            return Err(AlertError::NoTarget);
        }
        Ok(AbleFilter {
            action,
            contact,
            bhv_type,
            vsource,
        })
    }

    /// Every given field matches (case-insensitive) the behavior's type, its contact
    /// and the contact's vsource.
    pub fn applies_to(&self, bhv_type: &str, contact: &str, vsource: &str) -> bool {
        let ok = |want: &Option<String>, have: &str| {
            want.as_deref().is_none_or(|w| w.eq_ignore_ascii_case(have))
        };
        ok(&self.bhv_type, bhv_type) && ok(&self.contact, contact) && ok(&self.vsource, vsource)
    }
}

/// Most contacts the helm's black-list holds.
pub const BLACKLIST_MAX: usize = 200;

/// The helm's black-list of disabled contacts (§3.8): `action=disable,contact=X` adds X
/// (up to [`BLACKLIST_MAX`]); only `action=able,contact=X` removes it (quirk:
/// `action=enable` does not). A behavior spawned later for X gets
/// [`AbleBlacklist::seed`] applied at once.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AbleBlacklist {
    names: Vec<String>,
}

impl AbleBlacklist {
    /// Look at one `BHV_ABLE_FILTER` value (malformed ones change nothing).
    pub fn note(&mut self, s: &str) {
        let (mut action, mut contact) = (String::new(), String::new());
        for field in split_quoted(s, ',') {
            if let Ok((k, v)) = pair(field) {
                match k.to_ascii_lowercase().as_str() {
                    "action" => action = v.to_ascii_lowercase(),
                    "contact" => contact = v.to_ascii_lowercase(),
                    _ => {}
                }
            }
        }
        if contact.is_empty() {
            return;
        }
        match action.as_str() {
            "disable" if !self.contains(&contact) && self.names.len() < BLACKLIST_MAX => {
                self.names.push(contact)
            }
            "able" => self.names.retain(|n| *n != contact),
            _ => {}
        }
    }

    pub fn contains(&self, contact: &str) -> bool {
        self.names.iter().any(|n| n.eq_ignore_ascii_case(contact))
    }

    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// The filter string to apply to a behavior spawned for `contact`, if listed.
    pub fn seed(&self, contact: &str) -> Option<String> {
        self.contains(contact)
            .then(|| format!("action=disable,contact={}", contact.to_ascii_lowercase()))
    }
}

#[cfg(test)]
#[path = "alert_tests.rs"]
mod tests;
