//! Subscriptions: `R`/`U` registrations, wildcard registrations and the QoS record
//! (spec §5.4), as an `impl State` apart from the message flow in `state.rs`.

use super::{add_sub, Filter, Qos, State, Var};
use moos::text::{find_value, wildcard_match};
use moos::wire::{DataType, MsgView};

impl State {
    /// `R` (spec §5.4.2).
    pub(super) fn register(&mut self, client: &str, key: &str, interval: f64, now: f64) {
        if client.is_empty() {
            tracing::warn!(var = key, "register with empty source refused");
            return;
        }
        if !self.vars.contains_key(key) {
            self.values_grew(key.len() as isize);
        }
        let v = match self.vars.get_mut(key) {
            Some(v) => v,
            None => self
                .vars
                .entry(key.to_owned())
                .or_insert_with(|| Var::new(DataType::NOT_SET)),
        };
        let last = add_sub(v, client, interval);
        if v.write_count > 0 {
            v.subs[last].last_sent = now;
            let cur = v.current(key);
            let mut enc = Vec::with_capacity(cur.encoded_len());
            let _ = cur.encode_into(&mut enc);
            if let Some(&slot) = self.clients.get(client) {
                self.hold(slot, &enc);
            }
        }
    }

    pub(super) fn unregister(&mut self, client: &str, key: &str) {
        if let Some(v) = self.vars.get_mut(key) {
            v.subs.retain(|s| &*s.client != client);
        }
    }

    /// `*` (spec §5.4.5).
    pub(super) fn wildcard_register(&mut self, m: &MsgView<'_>, now: f64) {
        let s = m.string();
        let app = find_value(&s, "AppPattern", false).unwrap_or_default();
        let var = find_value(&s, "VarPattern", false).unwrap_or_default();
        let interval = find_value(&s, "Interval", false)
            .map(|i| moos::text::atof(&i))
            .filter(|i| i.is_finite())
            .unwrap_or(0.0);
        let Some(c) = self.client_mut(m.source) else {
            return;
        };
        if !c.filters.iter().any(|f| f.app == app && f.var == var) {
            c.filters.push(Filter {
                app: app.clone(),
                var: var.clone(),
                interval,
            });
        }
        let mut hits: Vec<String> = self
            .vars
            .iter()
            .filter(|(k, v)| wildcard_match(&var, k) && wildcard_match(&app, &v.source))
            .map(|(k, _)| k.clone())
            .collect();
        hits.sort();
        for k in hits {
            self.register(m.source, &k, interval, now);
        }
    }

    /// `/` (spec §5.4.6): the filter itself stays.
    pub(super) fn wildcard_unregister(&mut self, m: &MsgView<'_>) {
        let s = m.string();
        let app = find_value(&s, "AppPattern", false).unwrap_or_default();
        let var = find_value(&s, "VarPattern", false).unwrap_or_default();
        for (k, v) in self.vars.iter_mut() {
            if wildcard_match(&var, k) && wildcard_match(&app, &v.source) {
                v.subs.retain(|s| *s.client != *m.source);
            }
        }
    }

    pub(super) fn record_qos(&mut self, name: &str, ms: f64) {
        if let Some(c) = self.client_mut(name) {
            let q = c.qos.get_or_insert_with(|| Qos {
                min: f64::INFINITY,
                ..Qos::default()
            });
            q.recent = ms;
            q.max = q.max.max(ms);
            q.min = q.min.min(ms);
            q.n += 1;
            q.avg += (ms - q.avg) / (q.n.min(100) as f64);
        }
    }
}
