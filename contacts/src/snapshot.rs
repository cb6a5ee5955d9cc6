//! What behaviors read: the ledger snapshot (contacts-appcast.md §2.5), rebuilt by
//! [`crate::Ledger::maintain`] once per iteration into reused buffers.

/// One contact as the ledger keeps it: the last accepted report (X/Y filled from
/// LAT/LON and the other way round), the type after fixing, the receipt time.
#[derive(Debug, Default, PartialEq)]
pub struct ContactRecord {
    /// The ledger key, case kept.
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
    /// The report's TIME.
    pub utc: f64,
    /// Ledger time when the report was accepted.
    pub utc_received: f64,
    pub length: f64,
    /// How many reports of this name were accepted.
    pub reports: u64,
}

impl Clone for ContactRecord {
    fn clone(&self) -> Self {
        let mut c = ContactRecord::default();
        c.clone_from(self);
        c
    }

    /// Field by field, reusing this record's strings: the per-iteration snapshot copy
    /// allocates nothing once the names have been seen.
    fn clone_from(&mut self, s: &Self) {
        self.name.clone_from(&s.name);
        self.vtype.clone_from(&s.vtype);
        self.group.clone_from(&s.group);
        self.vsource.clone_from(&s.vsource);
        self.x = s.x;
        self.y = s.y;
        self.hdg = s.hdg;
        self.spd = s.spd;
        self.dep = s.dep;
        self.lat = s.lat;
        self.lon = s.lon;
        self.utc = s.utc;
        self.utc_received = s.utc_received;
        self.length = s.length;
        self.reports = s.reports;
    }
}

/// A field of the snapshot by the name behaviors ask for it (§2.5 table).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SnapField {
    X,
    Y,
    Hdg,
    Spd,
    Dep,
    Lat,
    Lon,
    Utc,
    UtcAge,
    UtcReceived,
    UtcAgeReceived,
    Group,
    Type,
    Vsource,
}

/// The field name the reference's contact base asks the group by. The snapshot does
/// not know it, so a contact behavior's group is always "" (§2.5 quirk); kept as a
/// named constant so it can be switched when the reference changes.
pub const CONTACT_BASE_GROUP_FIELD: &str = "grp";

impl SnapField {
    /// The snapshot's field names; anything else (`grp` included) is unknown.
    pub fn parse(s: &str) -> Option<SnapField> {
        Some(match s {
            "x" => SnapField::X,
            "y" => SnapField::Y,
            "hdg" => SnapField::Hdg,
            "spd" => SnapField::Spd,
            "dep" => SnapField::Dep,
            "lat" => SnapField::Lat,
            "lon" => SnapField::Lon,
            "utc" => SnapField::Utc,
            "utc_age" => SnapField::UtcAge,
            "utc_received" => SnapField::UtcReceived,
            "utc_age_received" => SnapField::UtcAgeReceived,
            "group" => SnapField::Group,
            "type" => SnapField::Type,
            "vsource" => SnapField::Vsource,
            _ => return None,
        })
    }
}

/// The contacts of one iteration, sorted by name (byte order), and the ledger time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LedgerSnap {
    pub(crate) now: f64,
    pub(crate) contacts: Vec<ContactRecord>,
}

impl LedgerSnap {
    /// The ledger time this snapshot was taken at.
    pub fn now(&self) -> f64 {
        self.now
    }

    pub fn len(&self) -> usize {
        self.contacts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    /// All contacts, in byte order of their names.
    pub fn contacts(&self) -> &[ContactRecord] {
        &self.contacts
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.contacts.iter().map(|c| c.name.as_str())
    }

    /// One contact by exact (case-sensitive) name; O(log n).
    pub fn get(&self, name: &str) -> Option<&ContactRecord> {
        self.contacts
            .binary_search_by(|c| mbutil::short_str::order(&c.name, name))
            .ok()
            .map(|i| &self.contacts[i])
    }

    pub fn has(&self, name: &str) -> bool {
        self.get(name).is_some()
    }

    /// A numeric field; `None` ("not found", the reference answers 0) for a missing
    /// contact, an unknown field or a text field.
    pub fn num(&self, name: &str, field: &str) -> Option<f64> {
        let c = self.get(name)?;
        Some(match SnapField::parse(field)? {
            SnapField::X => c.x,
            SnapField::Y => c.y,
            SnapField::Hdg => c.hdg,
            SnapField::Spd => c.spd,
            SnapField::Dep => c.dep,
            SnapField::Lat => c.lat,
            SnapField::Lon => c.lon,
            SnapField::Utc => c.utc,
            SnapField::UtcAge => self.now - c.utc,
            SnapField::UtcReceived => c.utc_received,
            SnapField::UtcAgeReceived => self.now - c.utc_received,
            SnapField::Group | SnapField::Type | SnapField::Vsource => return None,
        })
    }

    /// A text field; `None` (the reference answers "") for a missing contact, an
    /// unknown field (such as [`CONTACT_BASE_GROUP_FIELD`]) or a numeric field.
    pub fn text(&self, name: &str, field: &str) -> Option<&str> {
        let c = self.get(name)?;
        Some(match SnapField::parse(field)? {
            SnapField::Group => &c.group,
            SnapField::Type => &c.vtype,
            SnapField::Vsource => &c.vsource,
            _ => return None,
        })
    }
}
