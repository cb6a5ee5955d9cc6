//! The contact ledger (contacts-appcast.md §2.2–§2.6): acceptance of reports, storage by
//! name, per-iteration maintenance (stale removal, snapshot), `IVPHELM_LEDGER_SUMMARY`
//! and `IVPHELM_CONTACT_SUMMARY`.
//!
//! Cost: `ingest` is O(log n) plus an O(n) shift when a new name arrives; `maintain` is
//! O(n) and, once every name has been seen, allocates nothing (records and strings are
//! copied into the reused snapshot, summaries are written into reused strings).

use std::fmt::Write as _;

use mbutil::short_str;

use crate::geodesy::Geodesy;
use crate::report::NodeReport;
use crate::snapshot::{ContactRecord, LedgerSnap};
use crate::vtype::{default_length, fix_type, needs_depth};

/// The helm's `contact_max_age` default (s).
pub const DEFAULT_MAX_AGE: f64 = 45.0;
/// `contact_max_age` is clipped into this range.
pub const MAX_AGE_RANGE: (f64, f64) = (10.0, 1800.0);
/// A contact is removed when its report is older than this factor × `contact_max_age`.
/// The reference intends the doubling only for contacts a behavior keeps but applies
/// it to all (§2.4); named so it can be switched when the reference changes.
pub const STALE_FACTOR: f64 = 2.0;
/// Names listed after `who:` in the ledger summary.
pub const SUMMARY_NAMES: usize = 20;
/// Default cap on distinct contacts (our guard against hostile mail; the reference
/// has none). 500 is pContactMgrV20's `max_contacts` default.
pub const DEFAULT_MAX_CONTACTS: usize = 500;
/// Longest name/type/group/vsource stored (bytes); a longer one refuses the report, so
/// memory stays bounded by the cap. Real names are a few characters.
pub const MAX_TEXT_FIELD: usize = 256;

/// The variables whose reports go into the ledger (`NODE_REPORT_LOCAL` does not: it is
/// ownship's own report, see [`crate::local_nav_vars`]).
pub const LEDGER_VARS: &[&str] = &["NODE_REPORT", "AIS_REPORT", "AIS_REPORT_LOCAL"];

/// True for a variable whose reports feed the ledger.
pub fn feeds_ledger(var: &str) -> bool {
    // Spelled out, not `LEDGER_VARS.contains`: each literal then is compared inline
    // (every message to the helm asks).
    matches!(var, "NODE_REPORT" | "AIS_REPORT" | "AIS_REPORT_LOCAL")
}

/// What a report lacked (§2.2 step 1); the text is the reference's "why", the pieces
/// concatenated with no separator.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Missing {
    pub name: bool,
    pub time: bool,
    pub position: bool,
}

impl std::fmt::Display for Missing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.name {
            f.write_str("Missing vname.")?;
        }
        if self.time {
            f.write_str("Missing timestamp.")?;
        }
        if self.position {
            f.write_str("Missing both x/y and lat/lon.")?;
        }
        Ok(())
    }
}

/// Why a report did not become (or update) a contact. `Display` is the "why" text of
/// the run warning `The issue: <why>` (the first warning is `Bad NodeReport: <report>`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum IngestError {
    #[error("{0}")]
    Missing(Missing),
    #[error("underwater vehicle type with no depth reported")]
    NoDepth,
    #[error("report gives only lat/lon and the mission has no LatOrigin/LongOrigin")]
    NoOrigin,
    #[error("{field} longer than {MAX_TEXT_FIELD} bytes ({len})")]
    FieldTooLong { field: &'static str, len: usize },
    #[error("contact ledger full ({cap} contacts): new contact refused")]
    Full { cap: usize },
}

impl IngestError {
    /// Whether the reference counts this report in `reps` (only the depth rejection,
    /// which comes after the counting step).
    pub fn counted(&self) -> bool {
        matches!(self, IngestError::NoDepth)
    }

    /// The two run warnings the helm reports for a refused `report`.
    pub fn run_warnings(&self, report: &str) -> [String; 2] {
        [
            format!("Bad NodeReport: {report}"),
            format!("The issue: {self}"),
        ]
    }
}

/// A report accepted: the contact's name and what the helm copies into the info buffer
/// (`<NAME>_NAV_GROUP`, `<NAME>_NAV_TYPE`, with NAME upper-cased).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accepted<'a> {
    pub name: &'a str,
    pub group: &'a str,
    pub vtype: &'a str,
    /// A name the ledger did not hold before.
    pub new: bool,
}

/// The ledger. See the crate doc for the order of calls.
#[derive(Debug)]
pub struct Ledger {
    geo: Option<Geodesy>,
    /// Sorted by name (byte order): lookups by binary search, `who:` for free.
    records: Vec<ContactRecord>,
    snap: LedgerSnap,
    max_age: f64,
    max_contacts: usize,
    reps: u64,
    refused: u64,
    refused_full: u64,
    summary: String,
    contact_summary: String,
    keep_spans: Vec<(usize, usize)>,
}

impl Ledger {
    /// A ledger for a mission with (or without) `LatOrigin`/`LongOrigin`; without, a
    /// report giving only LAT/LON is refused ([`IngestError::NoOrigin`]).
    pub fn new(origin: Option<(f64, f64)>) -> Self {
        Ledger {
            geo: origin.map(|(lat, lon)| Geodesy::new(lat, lon)),
            records: Vec::new(),
            snap: LedgerSnap::default(),
            max_age: DEFAULT_MAX_AGE,
            max_contacts: DEFAULT_MAX_CONTACTS,
            reps: 0,
            refused: 0,
            refused_full: 0,
            summary: String::new(),
            contact_summary: String::new(),
            keep_spans: Vec::new(),
        }
    }

    /// pHelmIvP's `contact_max_age`, clipped into [`MAX_AGE_RANGE`]. Returns the value set.
    pub fn set_max_age(&mut self, secs: f64) -> f64 {
        self.max_age = if secs.is_nan() {
            DEFAULT_MAX_AGE
        } else {
            secs.clamp(MAX_AGE_RANGE.0, MAX_AGE_RANGE.1)
        };
        self.max_age
    }

    pub fn max_age(&self) -> f64 {
        self.max_age
    }

    /// The cap on distinct contacts (at least 1).
    pub fn set_max_contacts(&mut self, cap: usize) {
        self.max_contacts = cap.max(1);
    }

    pub fn max_contacts(&self) -> usize {
        self.max_contacts
    }

    pub fn geodesy(&self) -> Option<&Geodesy> {
        self.geo.as_ref()
    }

    /// Reports counted since start (the summary's `reps`).
    pub fn reps(&self) -> u64 {
        self.reps
    }

    /// Reports refused, for any reason.
    pub fn refused(&self) -> u64 {
        self.refused
    }

    /// Reports refused because the ledger was full.
    pub fn refused_full(&self) -> u64 {
        self.refused_full
    }

    /// Contacts held now (between iterations this includes mail not yet maintained).
    pub fn len(&self) -> usize {
        self.records.len()
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Accept one report received at ledger time `now` (§2.2), or say why not.
    ///
    /// ```
    /// let mut l = contacts::Ledger::new(Some((43.8253, -70.3304)));
    /// let a = l.ingest("NAME=bob,X=1,Y=2,TIME=1000,TYPE=dinghy", 1000.0).unwrap();
    /// assert_eq!((a.name, a.vtype, a.new), ("bob", "ship", true));
    /// let e = l.ingest("X=1,Y=2", 1000.0).unwrap_err();
    /// assert_eq!(e.to_string(), "Missing vname.Missing timestamp.");
    /// ```
    pub fn ingest(&mut self, report: &str, now: f64) -> Result<Accepted<'_>, IngestError> {
        self.ingest_parsed(&NodeReport::parse(report), now)
    }

    /// [`Ledger::ingest`] of a report already read (`NodeReport::parse` of its text),
    /// for a caller that reads one report for several readers (a fleet simulator).
    pub fn ingest_parsed(
        &mut self,
        report: &NodeReport<'_>,
        now: f64,
    ) -> Result<Accepted<'_>, IngestError> {
        let r = match self.check(report) {
            Ok(r) => r,
            Err(e) => {
                self.refused += 1;
                if e.counted() {
                    self.reps += 1;
                }
                return Err(e);
            }
        };
        self.store(&r, now)
    }

    /// Steps 1, 2, 4, 5 and the hostile-input guards; counts nothing.
    fn check<'a>(&self, r: &NodeReport<'a>) -> Result<Checked<'a>, IngestError> {
        let missing = Missing {
            name: r.name.is_empty(),
            time: r.time.is_none(),
            position: !r.has_xy() && !r.has_latlon(),
        };
        if missing != Missing::default() {
            return Err(IngestError::Missing(missing));
        }
        for (field, s) in [
            ("NAME", r.name),
            ("TYPE", r.vtype),
            ("GROUP", r.group),
            ("VSOURCE", r.vsource),
        ] {
            if s.len() > MAX_TEXT_FIELD {
                return Err(IngestError::FieldTooLong {
                    field,
                    len: s.len(),
                });
            }
        }
        // Cross-fill (step 2): both given → both kept verbatim.
        let (x, y, lat, lon) = match (r.has_xy(), r.has_latlon()) {
            (true, true) => (
                r.x.unwrap_or(0.0),
                r.y.unwrap_or(0.0),
                r.lat.unwrap_or(0.0),
                r.lon.unwrap_or(0.0),
            ),
            (false, _) => {
                let g = self.geo.as_ref().ok_or(IngestError::NoOrigin)?;
                // LAT/LON "present" is decided on LON alone; a missing LAT is 0.
                let (lat, lon) = (r.lat.unwrap_or(0.0), r.lon.unwrap_or(0.0));
                let (x, y) = g.to_local(lat, lon);
                (x, y, lat, lon)
            }
            (true, false) => {
                let (x, y) = (r.x.unwrap_or(0.0), r.y.unwrap_or(0.0));
                let (lat, lon) = match &self.geo {
                    Some(g) => g.to_latlon(x, y),
                    None => (0.0, 0.0),
                };
                (x, y, lat, lon)
            }
        };
        let vtype = fix_type(r.vtype);
        let length = match r.length {
            Some(l) if l > 0.0 => l,
            other => default_length(vtype).unwrap_or(other.unwrap_or(0.0)),
        };
        Ok(Checked {
            name: r.name,
            vtype,
            group: r.group,
            vsource: r.vsource,
            dep: r.dep,
            x,
            y,
            lat,
            lon,
            hdg: r.hdg.unwrap_or(0.0),
            spd: r.spd.unwrap_or(0.0),
            utc: r.time.unwrap_or(0.0),
            length,
        })
    }

    /// Steps 3, 4 (depth rule) and 7, plus the cap.
    fn store(&mut self, c: &Checked<'_>, now: f64) -> Result<Accepted<'_>, IngestError> {
        let pos = self
            .records
            .binary_search_by(|r| short_str::order(&r.name, c.name));
        if pos.is_err() && self.records.len() >= self.max_contacts {
            self.refused += 1;
            self.refused_full += 1;
            if self.refused_full == 1 {
                tracing::warn!(
                    cap = self.max_contacts,
                    "contact ledger full: reports of new contacts are refused"
                );
            }
            return Err(IngestError::Full {
                cap: self.max_contacts,
            });
        }
        self.reps += 1;
        if needs_depth(c.vtype) && c.dep.is_none() {
            self.refused += 1;
            return Err(IngestError::NoDepth);
        }
        let (i, new) = match pos {
            Ok(i) => (i, false),
            Err(i) => {
                let rec = ContactRecord {
                    name: c.name.to_string(),
                    ..ContactRecord::default()
                };
                self.records.insert(i, rec);
                (i, true)
            }
        };
        let rec = &mut self.records[i];
        short_str::assign(&mut rec.vtype, c.vtype);
        short_str::assign(&mut rec.group, c.group);
        short_str::assign(&mut rec.vsource, c.vsource);
        rec.x = c.x;
        rec.y = c.y;
        rec.lat = c.lat;
        rec.lon = c.lon;
        rec.hdg = c.hdg;
        rec.spd = c.spd;
        rec.dep = c.dep.unwrap_or(0.0);
        rec.utc = c.utc;
        rec.utc_received = now;
        rec.length = c.length;
        rec.reports += 1;
        Ok(Accepted {
            name: &rec.name,
            group: &rec.group,
            vtype: &rec.vtype,
            new,
        })
    }

    /// The per-iteration work (§2.4 steps 1, 3, 4, 6): drop stale contacts, rebuild the
    /// snapshot, write the ledger summary. Returns how many contacts went stale.
    pub fn maintain(&mut self, now: f64) -> usize {
        let limit = STALE_FACTOR * self.max_age;
        let before = self.records.len();
        // Age by the report's own TIME; a TIME of 0 never goes stale.
        self.records.retain(|r| {
            let age = now - r.utc;
            r.utc == 0.0 || age.is_nan() || age <= limit
        });
        let stale = before - self.records.len();
        if stale > 0 {
            tracing::debug!(stale, "contacts removed as stale");
        }
        self.snap.now = now;
        let snap = &mut self.snap.contacts;
        snap.truncate(self.records.len());
        for (i, r) in self.records.iter().enumerate() {
            match snap.get_mut(i) {
                Some(s) => s.clone_from(r),
                None => snap.push(r.clone()),
            }
        }
        self.summary.clear();
        // Writing into a String cannot fail.
        let _ = write!(
            self.summary,
            "now:{}, reps:{}, who:",
            self.records.len(),
            self.reps
        );
        for (k, r) in self.records.iter().take(SUMMARY_NAMES).enumerate() {
            if k > 0 {
                self.summary.push(',');
            }
            self.summary.push_str(&r.name);
        }
        stale
    }

    /// This iteration's snapshot (as of the last [`Ledger::maintain`]).
    pub fn snapshot(&self) -> &LedgerSnap {
        &self.snap
    }

    /// The `IVPHELM_LEDGER_SUMMARY` value, due every iteration that reaches the ledger
    /// step (as of the last [`Ledger::maintain`]): `now:<N>, reps:<R>, who:<names>`.
    pub fn summary(&self) -> &str {
        &self.summary
    }

    /// The `IVPHELM_CONTACT_SUMMARY` value for the `contact` parameters of the behaviors
    /// now in the set (in set order): the distinct non-empty ones joined by `,`; `None`
    /// (nothing to post) when there are none.
    pub fn contact_summary<'s>(&mut self, keep: impl IntoIterator<Item = &'s str>) -> Option<&str> {
        self.contact_summary.clear();
        self.keep_spans.clear();
        for name in keep {
            if name.is_empty() {
                continue;
            }
            let seen = self
                .keep_spans
                .iter()
                .any(|&(a, b)| &self.contact_summary[a..b] == name);
            if seen {
                continue;
            }
            if !self.keep_spans.is_empty() {
                self.contact_summary.push(',');
            }
            let a = self.contact_summary.len();
            self.contact_summary.push_str(name);
            self.keep_spans.push((a, self.contact_summary.len()));
        }
        (!self.keep_spans.is_empty()).then_some(self.contact_summary.as_str())
    }
}

/// A report past the checks, borrowing its text.
struct Checked<'a> {
    name: &'a str,
    vtype: &'a str,
    group: &'a str,
    vsource: &'a str,
    dep: Option<f64>,
    x: f64,
    y: f64,
    lat: f64,
    lon: f64,
    hdg: f64,
    spd: f64,
    utc: f64,
    length: f64,
}

/// `<NAME>_NAV_<SUFFIX>` with the name upper-cased, into `out` (a kept string: reports
/// arrive every iteration): where a helm keeps a contact's, or ownship's, report fields.
pub fn nav_var(out: &mut String, name: &str, suffix: &str) {
    out.clear();
    // ASCII (every real name): the same as per char, without the char iteration.
    if name.is_ascii() {
        out.push_str(name);
        out.make_ascii_uppercase();
    } else {
        out.extend(name.chars().flat_map(char::to_uppercase));
    }
    out.push_str("_NAV_");
    out.push_str(suffix);
}

#[cfg(test)]
#[path = "ledger_tests.rs"]
mod tests;
