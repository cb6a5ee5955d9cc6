//! The match/ignore filter of the contact behaviors (contacts-appcast.md §3.2): names,
//! groups and types lower-cased when stored, regions as convex polygons, and the summary
//! forwarded in the alert request (§3.4). The behaviors do not drop contacts by it
//! themselves; they complete on a failed check only with `exit_on_filter_*`.

use geometry::{parse_polygon, Polygon};

/// A filter parameter's value was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FilterError {
    #[error("{param}: empty value")]
    Empty { param: String },
    #[error("{param}: {value} is both matched and ignored")]
    Conflict { param: String, value: String },
    #[error("{param}: not a convex polygon: {value}")]
    BadRegion { param: String, value: String },
    #[error("{param}: not a boolean: {value}")]
    BadBool { param: String, value: String },
}

/// Which parts of the filter a contact passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FilterCheck {
    pub name: bool,
    pub group: bool,
    pub vtype: bool,
    pub region: bool,
}

impl FilterCheck {
    pub fn all(&self) -> bool {
        self.name && self.group && self.vtype && self.region
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
struct MatchIgnore {
    matches: Vec<String>,
    ignores: Vec<String>,
}

impl MatchIgnore {
    fn add(&mut self, ignore: bool, param: &str, value: &str) -> Result<(), FilterError> {
        let v = value.trim();
        let v = v
            .strip_prefix('{')
            .and_then(|v| v.strip_suffix('}'))
            .unwrap_or(v);
        let items: Vec<String> = v
            .split(',')
            .map(|s| s.trim().to_ascii_lowercase())
            .filter(|s| !s.is_empty())
            .collect();
        if items.is_empty() {
            return Err(FilterError::Empty {
                param: param.to_string(),
            });
        }
        let (mine, other) = if ignore {
            (&mut self.ignores, &self.matches)
        } else {
            (&mut self.matches, &self.ignores)
        };
        if let Some(c) = items.iter().find(|i| other.contains(i)) {
            return Err(FilterError::Conflict {
                param: param.to_string(),
                value: c.clone(),
            });
        }
        for i in items {
            if !mine.contains(&i) {
                mine.push(i);
            }
        }
        Ok(())
    }

    fn passes(&self, field: &str, strict_ignore: bool) -> bool {
        let has = |l: &[String]| l.iter().any(|s| s.eq_ignore_ascii_case(field));
        if !self.matches.is_empty() && !has(&self.matches) {
            return false;
        }
        if !self.ignores.is_empty() {
            if field.is_empty() {
                return !strict_ignore;
            }
            if has(&self.ignores) {
                return false;
            }
        }
        true
    }
}

/// The filter of one contact behavior (`match_*`, `ignore_*`, `strict_ignore`).
#[derive(Clone, Debug, PartialEq)]
pub struct ContactFilter {
    name: MatchIgnore,
    group: MatchIgnore,
    vtype: MatchIgnore,
    match_region: Vec<Polygon>,
    ignore_region: Vec<Polygon>,
    strict_ignore: bool,
}

impl Default for ContactFilter {
    fn default() -> Self {
        ContactFilter {
            name: MatchIgnore::default(),
            group: MatchIgnore::default(),
            vtype: MatchIgnore::default(),
            match_region: Vec::new(),
            ignore_region: Vec::new(),
            strict_ignore: true,
        }
    }
}

impl ContactFilter {
    /// Apply one behavior parameter (name lower-cased by the caller). `Ok(false)`: not
    /// a filter parameter. `contact_type_required` is AvoidCollision's alias of
    /// `match_type`.
    ///
    /// ```
    /// let mut f = contacts::ContactFilter::default();
    /// f.set_param("match_type", "{Kayak,usv}").unwrap();
    /// assert!(f.check("bob", "", "KAYAK", 0.0, 0.0).all());
    /// assert!(!f.check("bob", "", "ship", 0.0, 0.0).all());
    /// ```
    pub fn set_param(&mut self, param: &str, value: &str) -> Result<bool, FilterError> {
        match param {
            "match_name" => self.name.add(false, param, value)?,
            "ignore_name" => self.name.add(true, param, value)?,
            "match_group" => self.group.add(false, param, value)?,
            "ignore_group" => self.group.add(true, param, value)?,
            "match_type" | "contact_type_required" => self.vtype.add(false, param, value)?,
            "ignore_type" => self.vtype.add(true, param, value)?,
            "match_region" | "ignore_region" => {
                let poly = parse_polygon(value)
                    .filter(|p| p.is_convex())
                    .ok_or_else(|| FilterError::BadRegion {
                        param: param.to_string(),
                        value: value.to_string(),
                    })?;
                if param == "match_region" {
                    self.match_region.push(poly);
                } else {
                    self.ignore_region.push(poly);
                }
            }
            "strict_ignore" => {
                self.strict_ignore = match value.trim().to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => {
                        return Err(FilterError::BadBool {
                            param: param.to_string(),
                            value: value.to_string(),
                        })
                    }
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// No filter set.
    pub fn is_empty(&self) -> bool {
        self.name == MatchIgnore::default()
            && self.group == MatchIgnore::default()
            && self.vtype == MatchIgnore::default()
            && self.match_region.is_empty()
            && self.ignore_region.is_empty()
    }

    /// Check a contact (name, group, type as in the snapshot; position x, y).
    /// Comparisons are case-insensitive; with `strict_ignore` an empty field fails a
    /// non-empty ignore list. A position must be inside every match region and outside
    /// every ignore region.
    pub fn check(&self, name: &str, group: &str, vtype: &str, x: f64, y: f64) -> FilterCheck {
        FilterCheck {
            name: self.name.passes(name, self.strict_ignore),
            group: self.group.passes(group, self.strict_ignore),
            vtype: self.vtype.passes(vtype, self.strict_ignore),
            region: self.match_region.iter().all(|p| p.contains(x, y))
                && !self.ignore_region.iter().any(|p| p.contains(x, y)),
        }
    }

    /// The filter as appended to a `BCM_ALERT_REQUEST` (§3.4): items in the order
    /// ignore_group, match_group, ignore_name, match_name, ignore_type, match_type,
    /// ignore_region, match_region, then `strict_ignore=` when there are ignore types
    /// or groups; joined by `, `. Several values of one item are joined by `,`
    /// (unsure: the spec shows only single values). Empty when no filter is set.
    pub fn summary(&self) -> String {
        let mut items: Vec<String> = Vec::new();
        let mut list = |key: &str, l: &[String]| {
            if !l.is_empty() {
                items.push(format!("{key}={}", l.join(",")));
            }
        };
        list("ignore_group", &self.group.ignores);
        list("match_group", &self.group.matches);
        list("ignore_name", &self.name.ignores);
        list("match_name", &self.name.matches);
        list("ignore_type", &self.vtype.ignores);
        list("match_type", &self.vtype.matches);
        for p in &self.ignore_region {
            items.push(format!("ignore_region={}", p.spec(2)));
        }
        for p in &self.match_region {
            items.push(format!("match_region={}", p.spec(2)));
        }
        if !self.vtype.ignores.is_empty() || !self.group.ignores.is_empty() {
            items.push(format!("strict_ignore={}", self.strict_ignore));
        }
        items.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn match_and_ignore_lists() {
        let mut f = ContactFilter::default();
        assert!(f.is_empty());
        assert!(f.check("", "", "", 0.0, 0.0).all());
        assert_eq!(f.set_param("match_name", "Abe, ben"), Ok(true));
        assert_eq!(f.set_param("pwt", "100"), Ok(false));
        assert!(f.check("ABE", "", "", 0.0, 0.0).all());
        assert!(!f.check("cal", "", "", 0.0, 0.0).name);
        // A name may not be both matched and ignored.
        assert!(matches!(
            f.set_param("ignore_name", "abe"),
            Err(FilterError::Conflict { .. })
        ));
        assert!(matches!(
            f.set_param("match_type", " "),
            Err(FilterError::Empty { .. })
        ));
        assert_eq!(f.summary(), "match_name=abe,ben");
    }

    #[test]
    fn strict_ignore_and_empty_fields() {
        let mut f = ContactFilter::default();
        f.set_param("ignore_group", "blue").unwrap();
        assert!(!f.check("a", "Blue", "", 0.0, 0.0).group);
        assert!(f.check("a", "red", "", 0.0, 0.0).group);
        // Strict (default): an empty group fails a non-empty ignore list.
        assert!(!f.check("a", "", "", 0.0, 0.0).group);
        f.set_param("strict_ignore", "FALSE").unwrap();
        assert!(f.check("a", "", "", 0.0, 0.0).group);
        assert!(f.set_param("strict_ignore", "maybe").is_err());
        f.set_param("match_type", "kayak").unwrap();
        assert_eq!(
            f.summary(),
            "ignore_group=blue, match_type=kayak, strict_ignore=false"
        );
    }

    #[test]
    fn regions() {
        let mut f = ContactFilter::default();
        f.set_param("match_region", "pts={0,0:100,0:100,100:0,100}")
            .unwrap();
        f.set_param("ignore_region", "pts={40,40:60,40:60,60:40,60}")
            .unwrap();
        assert!(f.check("a", "", "", 10.0, 10.0).region);
        assert!(!f.check("a", "", "", 50.0, 50.0).region); // in the hole
        assert!(!f.check("a", "", "", 150.0, 10.0).region); // outside
        assert!(matches!(
            f.set_param("match_region", "nonsense"),
            Err(FilterError::BadRegion { .. })
        ));
        assert!(f.summary().starts_with("ignore_region=pts={"));
    }
}
