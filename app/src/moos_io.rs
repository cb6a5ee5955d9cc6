//! Moving the helm's postings and mail across a MOOS client (moos-wire.md §8).
//!
//! - [`AppSettings`] reads what a CMOOSApp reads from the mission: ServerHost,
//!   ServerPort, MOOSTimeWarp (globals) and AppTick (the app's own block).
//! - [`to_mail`] turns a batch of fetched messages into the helm's [`Mail`], sorted by
//!   time (CMOOSApp's default `SortMailByTime`), binary and non-notify messages dropped.
//! - [`to_message`] turns a [`Posting`] into a notify (numbers as doubles, strings as
//!   strings) carrying the posting's source-aux.
//! - [`Registrar`] subscribes to every variable the helm lists, once each, and picks up
//!   variables that appear later.

use moos::client::{Client, ClientError};
use moos::mission::MissionFile;
use moos::wire::{Message, MsgType};

use helm_engine::posting::{Posting, Value};
use helm_engine::Mail;

/// MOOS settings of one app, read from the mission file.
#[derive(Clone, Debug, PartialEq)]
pub struct AppSettings {
    /// Address to connect to (`localhost` is mapped to 127.0.0.1).
    pub host: String,
    pub port: u16,
    pub time_warp: f64,
    /// Iterations per second of MOOS time.
    pub app_tick: f64,
}

impl AppSettings {
    /// Read the globals and `app`'s AppTick (default `default_tick` Hz when missing or
    /// not a positive number).
    pub fn read(mission: &MissionFile, app: &str, default_tick: f64) -> AppSettings {
        let host = mission
            .global("ServerHost")
            .filter(|h| !h.is_empty())
            .unwrap_or_else(|| "localhost".into());
        let host = if host.eq_ignore_ascii_case("localhost") {
            "127.0.0.1".to_string()
        } else {
            host
        };
        let port = mission
            .global_f64("ServerPort")
            .filter(|p| (1.0..=65535.0).contains(p))
            .map_or(9000, |p| p as u16);
        let time_warp = mission
            .global_f64("MOOSTimeWarp")
            .filter(|w| moos::time::warp_ok(*w))
            .unwrap_or(1.0);
        let app_tick = mission.app_tick(app, default_tick);
        AppSettings {
            host,
            port,
            time_warp,
            app_tick,
        }
    }

    /// Real-time length of one tick (AppTick is in MOOS time, so warp shortens it).
    pub fn period(&self) -> std::time::Duration {
        std::time::Duration::from_secs_f64(1.0 / (self.app_tick * self.time_warp))
    }

    pub fn client_config(&self, name: &str) -> moos::client::ClientConfig {
        let mut cfg = moos::client::ClientConfig::new(&self.host, self.port, name);
        cfg.time_warp = self.time_warp;
        cfg
    }
}

/// Convert fetched messages to helm mail, in time order (stable).
pub fn to_mail(msgs: &[Message]) -> Vec<Mail> {
    let mut mail: Vec<Mail> = msgs
        .iter()
        .filter(|m| m.msg_type == MsgType::NOTIFY && !m.is_binary())
        .map(|m| Mail {
            var: m.key.clone(),
            value: if m.is_double() {
                Value::Num(m.dval)
            } else {
                Value::Str(m.string().into_owned())
            },
            time: m.time,
            source: m.source.clone(),
            source_aux: m.source_aux.clone(),
        })
        .collect();
    mail.sort_by(|a, b| a.time.total_cmp(&b.time));
    mail
}

/// The notify message for one posting, stamped `time`.
pub fn to_message(p: &Posting, time: f64) -> Message {
    let mut m = match &p.value {
        Value::Num(v) => Message::notify_double(&p.var, *v, time),
        Value::Str(s) => Message::notify_string(&p.var, s, time),
    };
    m.source_aux = p.source_aux.clone();
    m
}

/// Publish one posting. Like the C++ client, nothing is kept while disconnected.
pub fn publish(client: &Client, p: &Posting, time: f64) -> Result<(), ClientError> {
    client.notify_with_aux(to_message(p, time), &p.source_aux)
}

/// Keeps the DB subscriptions in step with the helm's list.
///
/// The real helm registers (and posts `IVPHELM_REGISTER` for) its variables at
/// connection, again at the end of start-up, and once more for every info variable at
/// the first decision (helm.md §4.1); after that only variables that are new.
/// [`Registrar::sync`] does the latter, [`Registrar::again`] the repeated rounds.
#[derive(Debug, Default)]
pub struct Registrar {
    done: std::collections::HashSet<String>,
}

impl Registrar {
    /// Register the variables of `subs` not registered yet; returns the new ones.
    pub fn sync(&mut self, client: &Client, subs: &[String]) -> Vec<String> {
        let fresh: Vec<String> = subs
            .iter()
            .filter(|v| !self.done.contains(*v))
            .cloned()
            .collect();
        self.again(client, &fresh)
    }

    /// Register every variable of `vars`, registered before or not; returns those
    /// registered (each gets its `IVPHELM_REGISTER`).
    pub fn again(&mut self, client: &Client, vars: &[String]) -> Vec<String> {
        let mut out = Vec::new();
        for var in vars.iter().filter(|v| !v.is_empty()) {
            match client.register(var, 0.0) {
                Ok(()) => {
                    self.done.insert(var.clone());
                    out.push(var.clone());
                }
                Err(e) => tracing::warn!(%var, "cannot register: {e}"),
            }
        }
        out
    }
}

/// An `.alog` of a run: every posting of the helm and every mail it received from
/// other apps (its own postings that come back as mail are not logged twice).
pub struct AlogSink {
    w: moos::alog::AlogFile,
    path: std::path::PathBuf,
    app: String,
}

impl AlogSink {
    pub fn create(path: &std::path::Path, start: f64, app: &str) -> std::io::Result<AlogSink> {
        let w = moos::alog::AlogFile::create(path, start)?;
        Ok(AlogSink {
            w,
            path: path.to_path_buf(),
            app: app.to_string(),
        })
    }

    pub fn path(&self) -> &std::path::Path {
        &self.path
    }

    pub fn posting(&mut self, p: &Posting, time: f64) -> std::io::Result<()> {
        let mut m = to_message(p, time);
        m.source = self.app.clone();
        self.w.write(&m)
    }

    pub fn mail(&mut self, m: &Message) -> std::io::Result<()> {
        if m.msg_type != MsgType::NOTIFY || m.source == self.app {
            return Ok(());
        }
        self.w.write(m)
    }

    pub fn flush(&mut self) -> std::io::Result<()> {
        self.w.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn settings_from_mission() {
        let m = MissionFile::parse(
            "ServerHost = localhost\nServerPort = 9123\nMOOSTimeWarp = 10\n\
             ProcessConfig = pHelmIvP\n{\n  AppTick = 4\n}\n",
            Path::new("t.moos"),
        )
        .expect("parses");
        let s = AppSettings::read(&m, "pHelmIvP", 5.0);
        assert_eq!(s.host, "127.0.0.1");
        assert_eq!(s.port, 9123);
        assert_eq!(s.time_warp, 10.0);
        assert_eq!(s.app_tick, 4.0);
        assert_eq!(s.period(), std::time::Duration::from_millis(25));
        let d = AppSettings::read(&m, "uSimMarine", 10.0);
        assert_eq!(d.app_tick, 10.0);
    }

    #[test]
    fn defaults_without_globals() {
        let m = MissionFile::parse("Community = a\n", Path::new("t.moos")).expect("parses");
        let s = AppSettings::read(&m, "pHelmIvP", 5.0);
        assert_eq!(
            (s.host.as_str(), s.port, s.time_warp),
            ("127.0.0.1", 9000, 1.0)
        );
        assert_eq!(s.app_tick, 5.0);
    }

    #[test]
    fn mail_sorted_and_typed() {
        let mut a = Message::notify_string("B", "x", 2.0);
        a.source = "p".into();
        a.source_aux = "aux".into();
        let b = Message::notify_double("A", 1.5, 1.0);
        let mail = to_mail(&[a, b]);
        assert_eq!(mail[0].var, "A");
        assert_eq!(mail[0].value, Value::Num(1.5));
        assert_eq!(mail[1].value, Value::Str("x".into()));
        assert_eq!(
            (mail[1].source.as_str(), mail[1].source_aux.as_str()),
            ("p", "aux")
        );
    }

    #[test]
    fn posting_keeps_aux_and_type() {
        let p = Posting {
            var: "DEPLOY".into(),
            value: Value::Str("true".into()),
            source_aux: "HELM_VAR_INIT".into(),
        };
        let m = to_message(&p, 3.0);
        assert!(m.is_string());
        assert_eq!(m.source_aux, "HELM_VAR_INIT");
        let n = to_message(
            &Posting {
                var: "DESIRED_SPEED".into(),
                value: Value::Num(2.0),
                source_aux: String::new(),
            },
            3.0,
        );
        assert!(n.is_double() && n.dval == 2.0);
    }
}
