//! `moosdb`: a MOOSDB compatible with MOOS V10 C++ clients.

use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use moos::mission::MissionFile;
use moosdb::{mib_to_bytes, Db, DbConfig};

/// A MOOS V10 database server (MOOSDB).
///
/// MOOS apps connect over TCP, publish variables and subscribe to them; the DB forwards
/// every write to the subscribers. Real C++ MOOS apps (pHelmIvP, pLogger, uMS, ...) work
/// against it as against the C++ MOOSDB.
///
/// Settings come from the mission file's globals (ServerPort, Community, MOOSTimeWarp,
/// ClientTimeout, StallTimeout, HoldLimit, MaxQueueMB) and are overridden by the flags below. Flags
/// use the C++ spelling, e.g. `--moos_port=9001`.
///
/// Overload: nothing is dropped for a client that keeps reading, and the DB's memory
/// stays under --max_queue_mb (queues, incoming packets and values together; about
/// 24 MiB more for buffers). When a client's queue passes its high-water mark (the cap
/// shared among the clients, at most 8 MiB each), the DB stops reading from the
/// publishers that filled it (the heaviest ones; a light publisher goes on) until it has
/// drained 256 KiB. Only clients making progress hold publishers back: one whose socket
/// takes less than 64 KiB in --hold_limit seconds holds no one back until it does, and
/// no hold lasts longer than --hold_limit; such a client's queue grows instead, and it
/// is cut off when the DB-wide cap is reached. A client whose socket accepts no bytes
/// for --stall_timeout seconds, or that sends nothing for --moos_timeout seconds, is cut
/// off; it gets current values when it reconnects. A packet longer than 256 KiB is read
/// in pieces of whole messages; a message longer than that waits, not read, until the
/// DB has room for it: a publisher is never dropped for the size of what it sends.
///
/// Reconnects: a client connecting under the name of a connected client is refused
/// ("A client of this name ... already exists"), as by the C++ MOOSDB, while that
/// connection is live. If it is known dead (its peer closed or reset it, a read or
/// write failed, or it sent nothing for --moos_timeout while not held back), the DB
/// closes it (disconnected=<name>) and welcomes the new one.
///
/// DB_EVENT values posted:
///   connected=<name>          a client completed the handshake
///   disconnected=<name>       a client left (any reason)
///   stalled=<name>,reason=accepted no bytes for <s> s
///   stalled=<name>,reason=accepted no bytes while its queue reached <n> KiB
///   stalled=<name>,reason=sent nothing for <s> s
///                             the DB cut the client off (posted before disconnected=)
///
/// Examples:
///   moosdb                                   # port 9000, community "#1"
///   moosdb alpha.moos                        # read ServerPort/Community from the mission
///   moosdb --moos_port=9001 --moos_community=alpha
///   moosdb alpha.moos --moos_time_warp=10    # all apps must use the same warp
///
/// Log verbosity: RUST_LOG=info (default), RUST_LOG=debug for per-connection detail.
#[derive(Parser, Debug)]
#[command(name = "moosdb", version, verbatim_doc_comment)]
struct Args {
    /// Mission file (.moos) to read globals from.
    mission: Option<PathBuf>,
    /// TCP port to listen on [mission ServerPort, default 9000].
    #[arg(long = "moos_port", value_name = "PORT")]
    port: Option<u16>,
    /// Community name sent to clients [mission Community, default "#1"].
    #[arg(long = "moos_community", value_name = "NAME")]
    community: Option<String>,
    /// Time-warp factor, 0 < warp <= 400 [mission MOOSTimeWarp, default 1].
    #[arg(long = "moos_time_warp", value_name = "WARP")]
    time_warp: Option<f64>,
    /// Drop a client silent for this many real seconds [mission ClientTimeout, default 5].
    #[arg(long = "moos_timeout", value_name = "SECONDS")]
    timeout: Option<f64>,
    /// Address to listen on. Use 127.0.0.1 to accept local apps only.
    #[arg(long, default_value = "0.0.0.0", value_name = "ADDR")]
    bind: IpAddr,
    /// Cap in MiB on the bytes the DB holds for all clients together (queues, incoming
    /// packets not yet complete, values); publishers are held back before it is reached,
    /// and stalled clients cut off when it is [mission MaxQueueMB, default 64]. Long
    /// messages being read may take half of it at most (one at a time past that).
    #[arg(long = "max_queue_mb", value_name = "MIB")]
    max_queue_mb: Option<f64>,
    /// Cut off a client whose socket accepted no bytes for this many seconds while some
    /// were waiting for it [mission StallTimeout, default 5].
    #[arg(long = "stall_timeout", value_name = "SECONDS")]
    stall_timeout: Option<f64>,
    /// A client whose socket accepted no bytes for this many seconds while some were
    /// waiting holds no publisher back until it takes bytes again; its own queue grows
    /// instead, up to half the cap [mission HoldLimit, default 0.1].
    #[arg(long = "hold_limit", value_name = "SECONDS")]
    hold_limit: Option<f64>,
    /// Consolidation delays returned in timing echoes: `name:ms,pattern:ms,...`
    /// (a bare number means `*`). Clients sleep that long after each send.
    #[arg(long, value_name = "LIST")]
    response: Option<String>,
}

fn parse_response(s: &str) -> Result<Vec<(String, f64)>, String> {
    let mut v = Vec::new();
    for part in s.split(',').filter(|p| !p.trim().is_empty()) {
        let (pat, ms) = match part.rsplit_once(':') {
            Some((p, m)) => (p.trim().to_owned(), m.trim()),
            None => ("*".to_owned(), part.trim()),
        };
        let ms: f64 = ms
            .parse()
            .map_err(|_| format!("bad --response entry {part:?}"))?;
        v.push((pat, ms));
    }
    Ok(v)
}

/// glibc gives each thread that allocates its own malloc arena (up to 8 per core); with
/// two threads per client, the memory freed in them is kept per arena and the DB's
/// peak RSS under a flood (tests/overload.rs) was 18-20 MB with the default, 12-13 MB
/// with 2 arenas. The message path barely allocates, so fewer arenas cost no
/// contention worth having. An explicit `MALLOC_ARENA_MAX` in the environment wins.
///
/// A fixed mmap threshold too: by default glibc raises it to the size of each large
/// block freed (up to 32 MiB), so after a stalled client's queue of 16 MiB is dropped,
/// queues up to that size come from the heap and their memory stays with the process
/// when they are freed (tests/stall.rs: peak RSS 56 MiB for a 32 MiB cap). Queues and
/// read buffers over 256 KiB are then mapped, and given back when freed.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn limit_malloc_arenas() {
    const M_ARENA_MAX: i32 = -8;
    const M_MMAP_THRESHOLD: i32 = -3;
    extern "C" {
        fn mallopt(param: i32, value: i32) -> i32;
    }
    if std::env::var_os("MALLOC_ARENA_MAX").is_none() {
        // SAFETY: mallopt only sets an allocator tunable; called before any thread starts.
        unsafe {
            mallopt(M_ARENA_MAX, 2);
        }
    }
    if std::env::var_os("MALLOC_MMAP_THRESHOLD_").is_none() {
        // SAFETY: as above.
        unsafe {
            mallopt(M_MMAP_THRESHOLD, 256 << 10);
        }
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn limit_malloc_arenas() {}

fn main() -> ExitCode {
    limit_malloc_arenas();
    // Logs on stderr: stdout carries only what a script reads (the port line).
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        // Colours only on a terminal: a log file gets plain text.
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .init();
    let args = Args::parse();
    let mut cfg = DbConfig {
        bind: args.bind,
        ..DbConfig::default()
    };
    if let Some(path) = &args.mission {
        match MissionFile::read(path) {
            Ok(m) => cfg.apply_mission(&m),
            Err(e) => {
                eprintln!("moosdb: {e}");
                return ExitCode::from(2);
            }
        }
    }
    if let Some(p) = args.port {
        cfg.port = p;
    }
    if let Some(c) = args.community {
        cfg.community = c;
    }
    if let Some(w) = args.time_warp {
        cfg.time_warp = w;
    }
    if let Some(t) = args.timeout {
        if !(t > 0.0 && t.is_finite()) {
            eprintln!("moosdb: --moos_timeout must be a positive number of seconds");
            return ExitCode::from(2);
        }
        cfg.client_timeout = Duration::from_secs_f64(t);
    }
    if let Some(t) = args.stall_timeout {
        if !(t > 0.0 && t.is_finite()) {
            eprintln!("moosdb: --stall_timeout must be a positive number of seconds");
            return ExitCode::from(2);
        }
        cfg.stall_timeout = Duration::from_secs_f64(t);
    }
    if let Some(t) = args.hold_limit {
        if !(t > 0.0 && t.is_finite()) {
            eprintln!("moosdb: --hold_limit must be a positive number of seconds");
            return ExitCode::from(2);
        }
        cfg.hold_limit = Duration::from_secs_f64(t);
    }
    if let Some(mb) = args.max_queue_mb {
        match mib_to_bytes(mb) {
            Some(b) => cfg.max_queue_bytes = b,
            None => {
                eprintln!("moosdb: --max_queue_mb must be a number of MiB, at least 1");
                return ExitCode::from(2);
            }
        }
    }
    if let Some(r) = &args.response {
        match parse_response(r) {
            Ok(v) => cfg.response = v,
            Err(e) => {
                eprintln!("moosdb: {e}");
                return ExitCode::from(2);
            }
        }
    }
    let db = match Db::start(cfg) {
        Ok(db) => db,
        Err(e) => {
            eprintln!("moosdb: {e}");
            return ExitCode::from(1);
        }
    };
    println!("moosdb listening on port {}", db.port());
    loop {
        std::thread::park();
    }
}
