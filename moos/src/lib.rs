//! MOOS V10 protocol support, written from `specs/moos-wire.md` only.
//!
//! * [`wire`]: message and packet codec (little-endian, i32 lengths), stream framing.
//! * [`mission`]: `.moos` mission file reader (globals, `ProcessConfig` blocks, `define:`).
//! * [`client`]: an asynchronous MOOS client with heartbeat, skew filter and reconnect.
//! * [`alog`]: pLogger `.alog` writer and reader.
//!
//! The MOOSDB itself is the `moosdb` crate. Depends on `mbutil` (MOOS-IvP's number
//! formatting), `moos-mission`, `thiserror` and `tracing`; it must not depend on the helm
//! or any behavior crate (the helm, the simulator and tools build on it, not the other
//! way round).
//!
//! ```
//! use moos::wire::{self, FrameReader, Message, Piece};
//! let mut pkt = Vec::new();
//! wire::encode_packet(&[Message::notify_double("NAV_X", 12.5, 1.0)], &mut pkt).unwrap();
//! let mut fr = FrameReader::new(1 << 20);
//! fr.fill(&mut pkt.as_slice()).unwrap();
//! let Some(Piece::Packet(r)) = fr.next_piece(256 << 10).unwrap() else { panic!() };
//! let msgs = wire::decode_packet(fr.frame(r), 1 << 20).unwrap();
//! assert_eq!((msgs[0].key.as_str(), msgs[0].dval), ("NAV_X", 12.5));
//! ```
#![forbid(unsafe_code)]

pub mod alog;
pub mod client;
pub mod wire;

// The file side (mission reader, text helpers, time) is its own crate, so the helm engine
// can read missions without the client and the DB; the paths stay `moos::mission` etc.
pub use moos_mission::{mission, text, time};

pub use client::{Client, ClientConfig, ClientError};
pub use mission::{ConfigLine, MissionError, MissionFile};
pub use wire::{DataType, Message, MsgType, WireError};
