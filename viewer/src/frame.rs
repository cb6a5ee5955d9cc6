//! What the page receives: a [`Frame`], either the whole picture (`full`, a replay at
//! one time or a live viewer's first message) or what changed since the last one (live).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::feed::Appcast;
use crate::node::VehicleState;
use crate::view::Shape;

/// One message to the page (JSON). Every text in it is data, shown with `textContent`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Frame {
    /// True: replace everything shown; false: apply as changes.
    pub full: bool,
    /// The time of the picture (s).
    pub t: f64,
    pub vehicles: Vec<VehicleState>,
    /// Trail points per vehicle: the whole trail when `full`, else points to append.
    pub trails: BTreeMap<String, Vec<[f64; 2]>>,
    /// Shapes drawn (or redrawn) under their keys.
    pub objects: Vec<Shape>,
    /// Keys of shapes erased.
    pub removed: Vec<String>,
    pub vars: BTreeMap<String, String>,
    pub appcasts: Vec<Appcast>,
    /// Live: what the viewer skipped so far (malformed VIEW_*, ...), when it changed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

impl Frame {
    pub fn full(t: f64) -> Frame {
        Frame {
            full: true,
            t,
            ..Frame::default()
        }
    }

    /// True when a delta carries nothing.
    pub fn is_empty(&self) -> bool {
        self.vehicles.is_empty()
            && self.trails.is_empty()
            && self.objects.is_empty()
            && self.removed.is_empty()
            && self.vars.is_empty()
            && self.appcasts.is_empty()
    }
}

/// Each variable's values over time, for "the value at time t".
#[derive(Clone, Debug, Default)]
pub struct VarTimeline {
    vars: BTreeMap<String, Vec<(f64, String)>>,
}

impl VarTimeline {
    /// Record a value; a repeat of the last value is not stored.
    pub fn push(&mut self, var: String, t: f64, value: String) {
        let v = self.vars.entry(var).or_default();
        if v.last().map(|l| &l.1) != Some(&value) {
            v.push((t, value));
        }
    }

    pub fn sort(&mut self) {
        for v in self.vars.values_mut() {
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
    }

    /// Every variable's last value at or before `t`.
    pub fn at(&self, t: f64) -> BTreeMap<String, String> {
        self.vars
            .iter()
            .filter_map(|(k, v)| {
                let i = v.partition_point(|e| e.0 <= t);
                i.checked_sub(1).map(|i| (k.clone(), v[i].1.clone()))
            })
            .collect()
    }
}
