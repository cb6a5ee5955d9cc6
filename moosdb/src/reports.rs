//! The DB's reports: replies to `Q` server requests (spec §5.8) and the `DB_*`
//! variables it publishes (spec §5.9). Part of [`State`].

use super::State;
use moos::text::format_g;
use moos::wire::{DataType, Message, MsgType, MsgView};

impl State {
    /// `Q` (spec §5.8). Replies are generated in walk order; the caller reverses them.
    pub(super) fn server_request(&mut self, m: &MsgView<'_>, now: f64, out: &mut Vec<Message>) {
        let key = m.key;
        let reply = |key: &str, time: f64, sval: String| Message {
            id: m.id,
            msg_type: MsgType::NOTIFY,
            data_type: DataType::STRING,
            source: self.db_name.clone(),
            community: self.community.clone(),
            key: key.to_owned(),
            time,
            sval: sval.into_bytes(),
            ..Message::default()
        };
        if key == "ALL" {
            let mut names: Vec<&String> = self.vars.keys().collect();
            names.sort();
            // Pushed to the front one by one: final order is reverse alphabetical.
            for n in names {
                let v = &self.vars[n];
                let t = v.written_db - self.start;
                out.push(Message {
                    id: m.id,
                    msg_type: MsgType::NOTIFY,
                    data_type: v.data_type,
                    source: v.source.clone(),
                    source_aux: v.source_aux.clone(),
                    community: v.community.clone(),
                    key: n.clone(),
                    time: if t < 0.0 { -1.0 } else { t },
                    dval: v.dval,
                    dval2: v.freq,
                    sval: v.sval.clone(),
                });
            }
        } else if key.contains("PROC_SUMMARY") {
            let uptime = now - self.start;
            let mut rs = Vec::new();
            for name in self.order.iter().rev() {
                let Some(c) = self.client(name) else {
                    continue;
                };
                let mut subs: Vec<&String> = self
                    .vars
                    .iter()
                    .filter(|(_, v)| v.subs.iter().any(|s| *s.client == **name))
                    .map(|(k, _)| k)
                    .collect();
                subs.sort();
                let mut s = format!("{name}:SUBSCRIBED=");
                for v in subs {
                    s.push(',');
                    s.push_str(v);
                }
                s.push_str(",PUBLISHED=");
                let mut pubs: Vec<&String> = c.published.iter().collect();
                pubs.sort();
                for v in pubs {
                    s.push(',');
                    s.push_str(v);
                }
                rs.push(reply("PROC_SUMMARY", uptime, s));
            }
            out.extend(rs);
        } else if key.contains("VAR_SUMMARY") {
            let mut names: Vec<&String> = self.vars.keys().collect();
            names.sort();
            let joined = names
                .iter()
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join(",");
            out.push(reply("VAR_SUMMARY", now, joined));
        } else if key.contains("DB_CLEAR") {
            let mut freed = 0;
            for v in self.vars.values_mut() {
                v.dval = -1.0;
                freed += v.sval.len();
                v.sval.clear();
                v.writers.clear();
                v.write_count = 0;
                v.freq = 0.0;
            }
            let marks = self.marks_for(self.clients.len());
            for c in self.slots.iter_mut().flatten() {
                c.held.clear();
                c.held_count = 0;
                if !c.is_async {
                    c.out.set_extra(0, None, marks);
                }
            }
            self.start = now;
            self.values_grew(-(freed as isize));
        }
    }

    fn db_notify(&mut self, mut m: Message, now: f64) {
        m.source = self.db_name.clone();
        m.community = self.community.clone();
        m.time = now;
        self.notify(&m.view(), None, now);
    }

    pub(super) fn db_notify_str(&mut self, key: &str, val: &str, now: f64) {
        self.db_notify(Message::notify_string(key, val, now), now);
    }

    /// Refresh the DB_* variables (spec §5.9).
    pub(super) fn refresh(&mut self, now: f64) {
        self.last_refresh = now;
        self.db_notify(Message::notify_double("DB_TIME", now, now), now);
        self.db_notify(
            Message::notify_double("DB_UPTIME", now - self.start, now),
            now,
        );
        let clients: String = self.order.iter().rev().map(|n| format!("{n},")).collect();
        self.db_notify_str("DB_CLIENTS", &clients, now);
        let summary = self.var_summary();
        self.db_notify_str("DB_VARSUMMARY", &summary, now);
        let mut names: Vec<&String> = self.clients.keys().collect();
        names.sort();
        let mut qos = String::new();
        for n in names {
            match self.client(n).and_then(|c| c.qos.as_ref()) {
                Some(q) => qos.push_str(&format!(
                    "{n}={}:{}:{}:{},",
                    format_g(q.recent),
                    format_g(q.max),
                    format_g(q.min),
                    format_g(q.avg)
                )),
                None => qos.push_str(&format!("{n}=0:0:1e+09:0,")),
            }
        }
        self.db_notify_str("DB_QOS", &qos, now);
        let rw = self
            .order
            .iter()
            .rev()
            .map(|n| {
                let mut subs: Vec<&str> = self
                    .vars
                    .iter()
                    .filter(|(_, v)| v.subs.iter().any(|s| *s.client == **n))
                    .map(|(k, _)| k.as_str())
                    .collect();
                subs.sort();
                let mut pubs: Vec<&str> = self
                    .client(n)
                    .map(|c| c.published.iter().map(String::as_str).collect())
                    .unwrap_or_default();
                pubs.sort();
                format!("{n}={}&{}", subs.join(":"), pubs.join(":"))
            })
            .collect::<Vec<_>>()
            .join(",");
        self.db_notify_str("DB_RWSUMMARY", &rw, now);
    }

    fn var_summary(&self) -> String {
        let mut names: Vec<&String> = self.vars.keys().collect();
        names.sort();
        let mut s = String::new();
        for n in names {
            let v = &self.vars[n];
            let (when, who) = if v.write_count == 0 {
                (String::new(), "(write pending)".to_owned())
            } else {
                (time_of_day(v.written_db), v.source.clone())
            };
            let value = match v.data_type {
                DataType::DOUBLE if v.write_count > 0 => format!("{:.1}", v.dval),
                DataType::STRING => {
                    let t = String::from_utf8_lossy(&v.sval);
                    if t.chars().count() > 25 {
                        format!("{}...", t.chars().take(22).collect::<String>())
                    } else {
                        t.into_owned()
                    }
                }
                DataType::BINARY => binary_size(v.sval.len()),
                _ => String::new(),
            };
            let dt = if v.write_count == 0 {
                '~'
            } else {
                v.data_type.0 as char
            };
            s.push_str(&format!(
                "{n:<20} {when:<20} {who:<20} {:>4.1}Hz {dt:<2} {value}\n",
                v.freq
            ));
        }
        s
    }
}

/// `HH:MM:SS.mmm` of a (possibly warped) UNIX time, in UTC (display only).
fn time_of_day(t: f64) -> String {
    let ms = (t.rem_euclid(86400.0) * 1000.0) as u64;
    format!(
        "{:02}:{:02}:{:02}.{:03}",
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1000 % 60,
        ms % 1000
    )
}

fn binary_size(n: usize) -> String {
    if n < 1024 {
        format!("*binary* {n} B")
    } else if n < 1024 * 1024 {
        format!("*binary* {} KB", n / 1024)
    } else {
        format!("*binary* {} MB", n / (1024 * 1024))
    }
}
