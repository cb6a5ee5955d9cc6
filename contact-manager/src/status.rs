//! The status postings of each iteration (contacts-appcast.md §4.4): the contact and
//! alert lists on change, the recap every `recap_interval`, the closest contact, the
//! alert circle. Lists are built into a reused buffer and posted only when they differ
//! from the last posting, so a steady iteration allocates nothing here.

use std::collections::VecDeque;

use mbutil::short_str;

use crate::config::Config;
use crate::table::Table;
use crate::value::{Ownship, Posting};

/// What was last posted, per status variable.
#[derive(Debug, Default)]
pub struct Status {
    /// Recently retired names, newest first.
    pub retired: VecDeque<String>,
    prev_list: String,
    prev_alerted: String,
    prev_unalerted: String,
    prev_retired: String,
    prev_count: usize,
    prev_ranges: String,
    last_recap: Option<f64>,
    closest: String,
    prev_closest_range: Option<i64>,
    prev_relbng: Option<i64>,
    buf: String,
}

/// Post `var = buf` when it differs from `prev` (which then takes the new value).
fn on_change(out: &mut Vec<Posting>, var: &str, buf: &mut String, prev: &mut String) {
    if !short_str::same(buf, prev) {
        std::mem::swap(buf, prev);
        out.push(Posting::str(var, prev.clone()));
    }
}

impl Status {
    pub fn note_retired(&mut self, name: &str, max: usize) {
        self.retired.push_front(name.to_string());
        self.retired.truncate(max);
    }

    #[allow(clippy::too_many_arguments)]
    pub fn post(
        &mut self,
        out: &mut Vec<Posting>,
        now: f64,
        cfg: &Config,
        ownship: &str,
        os: &Ownship,
        table: &Table,
        alerted: &[(String, String)],
        display_radii: bool,
    ) {
        let buf = &mut self.buf;
        // CONTACTS_LIST: names in table order.
        buf.clear();
        for (k, c) in table.contacts().iter().enumerate() {
            if k > 0 {
                buf.push(',');
            }
            buf.push_str(&c.name);
        }
        on_change(out, "CONTACTS_LIST", buf, &mut self.prev_list);

        buf.clear();
        for (n, i) in alerted {
            push_pair(buf, n, i);
        }
        on_change(out, "CONTACTS_ALERTED", buf, &mut self.prev_alerted);

        buf.clear();
        for c in table.contacts() {
            for a in cfg
                .alerts
                .alerts()
                .iter()
                .filter(|a| a.valid() && a.enabled)
            {
                let hit = (alerted.iter())
                    .any(|(n, i)| short_str::same(n, &c.name) && short_str::same(i, &a.id));
                if !hit {
                    push_pair(buf, &c.name, &a.id);
                }
            }
        }
        on_change(out, "CONTACTS_UNALERTED", buf, &mut self.prev_unalerted);

        if alerted.len() != self.prev_count {
            self.prev_count = alerted.len();
            out.push(Posting::num("CONTACTS_COUNT", alerted.len() as f64));
        }

        buf.clear();
        for (k, n) in self.retired.iter().enumerate() {
            if k > 0 {
                buf.push(',');
            }
            buf.push_str(n);
        }
        on_change(out, "CONTACTS_RETIRED", buf, &mut self.prev_retired);

        let due = self
            .last_recap
            .is_none_or(|t| now - t >= cfg.recap_interval);
        if due {
            self.last_recap = Some(now);
            buf.clear();
            for (k, c) in table.contacts().iter().enumerate() {
                if k > 0 {
                    buf.push_str(" # ");
                }
                let r = contacts::range(os.x, os.y, c.x, c.y);
                buf.push_str("vname=");
                buf.push_str(&c.name);
                buf.push_str(",range=");
                mbutil::push_fixed(buf, r, 2);
                buf.push_str(",age=");
                mbutil::push_fixed(buf, now - c.utc, 2);
            }
            out.push(Posting::str("CONTACTS_RECAP", buf.as_str()));
        }

        if cfg.post_all_ranges {
            buf.clear();
            for (k, c) in table.contacts().iter().enumerate() {
                if k > 0 {
                    buf.push(',');
                }
                let r = contacts::range(os.x, os.y, c.x, c.y);
                buf.push_str(&c.name);
                buf.push('=');
                mbutil::push_fixed(buf, r, 0);
            }
            on_change(out, "CONTACT_RANGES", buf, &mut self.prev_ranges);
        }
        self.closest(out, now, cfg, os, table);

        if display_radii {
            let chosen = cfg
                .alerts
                .get(&cfg.display_radii_id)
                .filter(|a| a.valid())
                .map(|a| a.cpa_range());
            let radius = chosen.unwrap_or_else(|| cfg.alerts.max_cpa_range());
            if radius > 0.0 {
                out.push(Posting::str(
                    "VIEW_CIRCLE",
                    format!(
                        "x={},y={},radius={},duration=3,label=alert_{ownship},edge_color={}",
                        mbutil::compact(os.x, 1),
                        mbutil::compact(os.y, 1),
                        mbutil::compact(radius, 1),
                        cfg.cpa_range_color
                    ),
                ));
            }
        }
    }

    fn closest(&mut self, out: &mut Vec<Posting>, now: f64, cfg: &Config, os: &Ownship, t: &Table) {
        let best = t
            .contacts()
            .iter()
            .map(|c| (c, contacts::range(os.x, os.y, c.x, c.y)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((c, r)) = best else {
            return;
        };
        if !short_str::same(&c.name, &self.closest) {
            self.closest.clone_from(&c.name);
            out.push(Posting::str("CONTACT_CLOSEST", c.name.as_str()));
            out.push(Posting::num("CONTACT_CLOSEST_TIME", now));
        }
        if cfg.post_closest_range {
            let ri = r.trunc() as i64;
            if self.prev_closest_range != Some(ri) {
                self.prev_closest_range = Some(ri);
                out.push(Posting::num("CONTACT_CLOSEST_RANGE", ri as f64));
            }
        }
        if cfg.post_closest_relbng {
            let b = contacts::rel_bearing(os.x, os.y, os.hdg, c.x, c.y).trunc() as i64;
            if self.prev_relbng != Some(b) {
                self.prev_relbng = Some(b);
                out.push(Posting::num("CONTACT_CLOSEST_RELBNG", b as f64));
            }
        }
    }
}

/// `(name,id)`: one entry of CONTACTS_ALERTED and CONTACTS_UNALERTED.
fn push_pair(buf: &mut String, name: &str, id: &str) {
    buf.push('(');
    buf.push_str(name);
    buf.push(',');
    buf.push_str(id);
    buf.push(')');
}
