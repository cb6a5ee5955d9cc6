//! The manager's contact table (contacts-appcast.md §4.2): the last report of each
//! contact by name, after the global filter and the ownship check, with type fixing,
//! the "underwater vehicle without depth" rejection and the `max_contacts` cap; retired
//! by age and by range.
//!
//! Unlike the helm's ledger, a report needs neither TIME nor a position: without TIME
//! its age is "now" (it is retired at the next iteration), without a position it
//! sits at (0, 0).

use contacts::vtype::needs_depth;
use contacts::{default_length, fix_type, ContactFilter, Geodesy, NodeReport};

use mbutil::short_str;

use crate::config::LocalCoords;

/// Beyond the reject range by more than this, a contact is retired (V20 keeps it up to
/// 2100 m with the 2000 m default; we read that as a fixed margin).
pub const REJECT_MARGIN: f64 = 100.0;
/// Longest name/type/group/vsource kept (bytes): hostile reports cannot grow memory.
pub const MAX_TEXT_FIELD: usize = 256;

/// One contact: its last accepted report.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Contact {
    pub name: String,
    /// After type fixing (`uuv` → `auv`, unknown → `ship`).
    pub vtype: String,
    pub group: String,
    pub vsource: String,
    pub x: f64,
    pub y: f64,
    pub hdg: f64,
    pub spd: f64,
    pub dep: f64,
    pub lat: f64,
    pub lon: f64,
    /// The report's TIME (0 when it had none).
    pub utc: f64,
    pub length: f64,
}

/// Why a report did not update the table.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Refused {
    #[error("Missing vname.")]
    NoName,
    #[error("ownship report")]
    Ownship,
    #[error("filtered out")]
    Filtered,
    #[error("underwater vehicle type with no depth reported")]
    NoDepth,
    #[error("{field} longer than {MAX_TEXT_FIELD} bytes")]
    TooLong { field: &'static str },
    #[error("contact table full ({cap} contacts): new contact refused")]
    Full { cap: usize },
}

impl Refused {
    /// Whether the reference reports this refusal as a run warning (the ownship and the
    /// filter refusals are normal).
    pub fn warns(&self) -> bool {
        !matches!(self, Refused::Ownship | Refused::Filtered)
    }
}

/// The table, sorted by name (byte order: the order of `CONTACTS_LIST`).
#[derive(Debug, Default)]
pub struct Table {
    contacts: Vec<Contact>,
    geo: Option<Geodesy>,
    coords: LocalCoords,
    max_contacts: usize,
}

impl Table {
    pub fn new(origin: Option<(f64, f64)>, coords: LocalCoords, max_contacts: usize) -> Table {
        Table {
            contacts: Vec::new(),
            geo: origin.map(|(lat, lon)| Geodesy::new(lat, lon)),
            coords,
            max_contacts: max_contacts.max(1),
        }
    }

    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    pub fn get(&self, name: &str) -> Option<&Contact> {
        self.index(name).ok().map(|i| &self.contacts[i])
    }

    pub fn len(&self) -> usize {
        self.contacts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    fn index(&self, name: &str) -> Result<usize, usize> {
        self.contacts
            .binary_search_by(|c| short_str::order(&c.name, name))
    }

    /// Take one `NODE_REPORT`. Returns the contact's name and whether it is new.
    pub fn ingest(
        &mut self,
        report: &str,
        filter: &ContactFilter,
        ownship: &str,
    ) -> Result<(&str, bool), Refused> {
        self.ingest_parsed(&NodeReport::parse(report), filter, ownship)
    }

    /// [`Self::ingest`] of a report already read.
    pub fn ingest_parsed(
        &mut self,
        r: &NodeReport<'_>,
        filter: &ContactFilter,
        ownship: &str,
    ) -> Result<(&str, bool), Refused> {
        if r.name.is_empty() {
            return Err(Refused::NoName);
        }
        if r.name.eq_ignore_ascii_case(ownship) {
            return Err(Refused::Ownship);
        }
        for (field, s) in [
            ("NAME", r.name),
            ("TYPE", r.vtype),
            ("GROUP", r.group),
            ("VSOURCE", r.vsource),
        ] {
            if s.len() > MAX_TEXT_FIELD {
                return Err(Refused::TooLong { field });
            }
        }
        let vtype = fix_type(r.vtype);
        if needs_depth(vtype) && r.dep.is_none() {
            return Err(Refused::NoDepth);
        }
        let (x, y, lat, lon) = self.position(r);
        if !filter.check(r.name, r.group, vtype, x, y).all() {
            return Err(Refused::Filtered);
        }
        let (i, new) = match self.index(r.name) {
            Ok(i) => (i, false),
            Err(i) => {
                if self.contacts.len() >= self.max_contacts {
                    return Err(Refused::Full {
                        cap: self.max_contacts,
                    });
                }
                let c = Contact {
                    name: r.name.to_string(),
                    ..Contact::default()
                };
                self.contacts.insert(i, c);
                (i, true)
            }
        };
        let c = &mut self.contacts[i];
        short_str::assign(&mut c.vtype, vtype);
        short_str::assign(&mut c.group, r.group);
        short_str::assign(&mut c.vsource, r.vsource);
        (c.x, c.y, c.lat, c.lon) = (x, y, lat, lon);
        c.hdg = r.hdg.unwrap_or(0.0);
        c.spd = r.spd.unwrap_or(0.0);
        c.dep = r.dep.unwrap_or(0.0);
        c.utc = r.time.unwrap_or(0.0);
        c.length = match r.length {
            Some(l) if l > 0.0 => l,
            other => default_length(vtype).unwrap_or(other.unwrap_or(0.0)),
        };
        Ok((&c.name, new))
    }

    /// x, y, lat, lon of a report under the `contact_local_coords` policy.
    fn position(&self, r: &NodeReport<'_>) -> (f64, f64, f64, f64) {
        let (lat, lon) = (r.lat.unwrap_or(0.0), r.lon.unwrap_or(0.0));
        let from_latlon = r.has_latlon()
            && (!r.has_xy() || self.coords == LocalCoords::ForceLatLon)
            && self.geo.is_some();
        match &self.geo {
            Some(g) if from_latlon => {
                let (x, y) = g.to_local(lat, lon);
                (x, y, lat, lon)
            }
            _ => (r.x.unwrap_or(0.0), r.y.unwrap_or(0.0), lat, lon),
        }
    }

    /// Retire contacts older than `max_age` (by their report's TIME) or farther than
    /// the reject range (+ [`REJECT_MARGIN`]) from ownship at (osx, osy); their names
    /// are appended to `out` in table order (records moved out, for the off-flags).
    pub fn retire(
        &mut self,
        now: f64,
        max_age: f64,
        os: (f64, f64),
        reject_range: f64,
        out: &mut Vec<Contact>,
    ) {
        let limit = reject_range + REJECT_MARGIN;
        self.contacts.retain_mut(|c| {
            let age = now - c.utc;
            let far = contacts::range(os.0, os.1, c.x, c.y) > limit;
            let keep = age <= max_age && !far;
            if !keep {
                out.push(std::mem::take(c));
            }
            keep
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> Table {
        Table::new(Some((43.8253, -70.3304)), LocalCoords::Verbatim, 3)
    }

    #[test]
    fn reports_are_filtered_fixed_and_capped() {
        let mut t = table();
        let f = ContactFilter::default();
        assert_eq!(
            t.ingest("NAME=Bob,X=1,Y=2,TIME=5,TYPE=uuv,DEP=3", &f, "alpha"),
            Ok(("Bob", true))
        );
        assert_eq!(t.get("Bob").unwrap().vtype, "auv");
        assert_eq!(t.get("Bob").unwrap().length, 3.0);
        assert_eq!(
            t.ingest("NAME=Bob,X=4,Y=2,TIME=6", &f, "alpha"),
            Ok(("Bob", false))
        );
        assert_eq!(t.get("Bob").unwrap().x, 4.0);
        // Ownship, case-insensitively.
        assert_eq!(
            t.ingest("NAME=ALPHA,X=1,Y=1,TIME=1", &f, "alpha"),
            Err(Refused::Ownship)
        );
        assert_eq!(
            t.ingest("NAME=g,X=1,Y=1,TIME=1,TYPE=glider", &f, "alpha"),
            Err(Refused::NoDepth)
        );
        assert_eq!(t.ingest("X=1", &f, "alpha"), Err(Refused::NoName));
        // No TIME, no position: kept at (0, 0) with TIME 0.
        assert!(t.ingest("NAME=c", &f, "alpha").is_ok());
        assert_eq!((t.get("c").unwrap().x, t.get("c").unwrap().utc), (0.0, 0.0));
        assert!(t.ingest("NAME=d,X=1,Y=1", &f, "alpha").is_ok());
        assert_eq!(
            t.ingest("NAME=e,X=1,Y=1", &f, "alpha"),
            Err(Refused::Full { cap: 3 })
        );
        let names: Vec<&str> = t.contacts().iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["Bob", "c", "d"]);
    }

    #[test]
    fn global_filter_applies() {
        let mut t = table();
        let mut f = ContactFilter::default();
        f.set_param("ignore_group", "red").unwrap();
        f.set_param("strict_ignore", "false").unwrap();
        assert_eq!(
            t.ingest("NAME=r,X=1,Y=1,TIME=1,GROUP=Red", &f, "a"),
            Err(Refused::Filtered)
        );
        assert!(t
            .ingest("NAME=b,X=1,Y=1,TIME=1,GROUP=blue", &f, "a")
            .is_ok());
        assert!(t.ingest("NAME=n,X=1,Y=1,TIME=1", &f, "a").is_ok());
    }

    #[test]
    fn force_lat_lon_replaces_xy() {
        let f = ContactFilter::default();
        let rep = "NAME=b,X=500,Y=500,LAT=43.8253,LON=-70.3304,TIME=1";
        let mut t = table();
        t.ingest(rep, &f, "a").unwrap();
        assert_eq!(t.get("b").unwrap().x, 500.0);
        let mut t = Table::new(Some((43.8253, -70.3304)), LocalCoords::ForceLatLon, 9);
        t.ingest(rep, &f, "a").unwrap();
        // The origin itself: (0, 0) within a millimetre.
        let b = t.get("b").unwrap();
        assert!(b.x.abs() < 1e-3 && b.y.abs() < 1e-3, "{b:?}");
    }

    #[test]
    fn retirement_by_age_and_range() {
        let mut t = Table::new(None, LocalCoords::Verbatim, 10);
        let f = ContactFilter::default();
        t.ingest("NAME=old,X=0,Y=10,TIME=100", &f, "a").unwrap();
        t.ingest("NAME=far,X=0,Y=2101,TIME=160", &f, "a").unwrap();
        t.ingest("NAME=ok,X=0,Y=2099,TIME=160", &f, "a").unwrap();
        t.ingest("NAME=notime,X=0,Y=1", &f, "a").unwrap();
        let mut out = Vec::new();
        // Age of old = 60: kept at exactly max_age.
        t.retire(160.0, 60.0, (0.0, 0.0), 2000.0, &mut out);
        let names = |o: &[Contact]| o.iter().map(|c| c.name.clone()).collect::<Vec<_>>();
        assert_eq!(names(&out), ["far", "notime"]);
        t.retire(160.5, 60.0, (0.0, 0.0), 2000.0, &mut out);
        assert_eq!(names(&out), ["far", "notime", "old"]);
        assert_eq!(out[2].utc, 100.0);
        assert_eq!(t.len(), 1);
    }
}
