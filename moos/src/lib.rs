//! MOOS V10 protocol support, written from `specs/moos-wire.md` only.
//!
//! * [`wire`]: message and packet codec (little-endian, i32 lengths), stream framing.
//! * [`mission`]: `.moos` mission file reader (globals, `ProcessConfig` blocks, `define:`).
//! * [`db`]: an embeddable MOOSDB (also the `moosdb` binary).
//! * [`client`]: an asynchronous MOOS client with heartbeat, skew filter and reconnect.
//! * [`alog`]: pLogger `.alog` writer and reader.
#![forbid(unsafe_code)]

pub mod alog;
pub mod client;
pub mod db;
pub mod wire;

// The file side (mission reader, text helpers, time) is its own crate, so the helm engine
// can read missions without the client and the DB; the paths stay `moos::mission` etc.
pub use moos_mission::{mission, text, time};

pub use client::{Client, ClientConfig, ClientError};
pub use db::{Db, DbConfig, DbError};
pub use mission::{ConfigLine, MissionError, MissionFile};
pub use wire::{DataType, Message, MsgType, WireError};
