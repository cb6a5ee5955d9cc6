//! What BHV_Loiter posts every iteration, kept from one iteration to the next: the
//! status variables' names with their suffix, the report text, and the view attributes
//! with their labels. Names and attributes are made again only after a parameter
//! changes ([`Posts::forget`]), so a steady iteration formats only its numbers.

use geometry::Attrs;

/// The status variables in posting order, before the `post_suffix`.
const STATUS: [&str; 6] = [
    "LOITER_REPORT",
    "LOITER_INDEX",
    "LOITER_MODE",
    "LOITER_ACQUIRE",
    "LOITER_DIST_TO_POLY",
    "LOITER_ETA_TO_POLY",
];

/// Index of each status variable in [`Posts::names`].
pub(super) const REPORT: usize = 0;
pub(super) const INDEX: usize = 1;
pub(super) const MODE: usize = 2;
pub(super) const ACQUIRE: usize = 3;
pub(super) const DIST_TO_POLY: usize = 4;
pub(super) const ETA_TO_POLY: usize = 5;

#[derive(Debug, Default)]
pub(super) struct Posts {
    /// [`STATUS`] with the suffix (empty: not made yet).
    names: Vec<String>,
    /// The LOITER_REPORT text and the VIEW_POINT spec, written again each iteration.
    pub(super) report: String,
    pub(super) point: String,
    /// The polygon's and the next point's view attributes.
    pub(super) views: Option<(Attrs, Attrs)>,
}

impl Posts {
    /// A parameter changed: names and attributes are made again when next used.
    pub(super) fn forget(&mut self) {
        self.names.clear();
        self.views = None;
    }

    /// The status variables' names with `suffix`.
    pub(super) fn names(&mut self, suffix: &str) -> &[String] {
        if self.names.is_empty() {
            self.names = STATUS.iter().map(|v| format!("{v}{suffix}")).collect();
        }
        &self.names
    }
}
