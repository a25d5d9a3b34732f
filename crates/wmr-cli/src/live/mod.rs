//! `wmr-cli run FILE.toml --live [ADDR]`: the runs served live over Foxglove's WebSocket
//! protocol. [`session`] paces the runs and encodes their messages; [`server`] fans them
//! out to the clients, each served by [`client`] with a bounded queue; [`handshake`]
//! negotiates the subprotocol; [`protocol`] spells the messages; [`stop`] is the signal
//! that ends a session early.

mod client;
mod handshake;
mod protocol;
mod server;
mod session;
mod stop;

pub use server::{HANDSHAKE_DEADLINE, IDLE_LIMIT, MAX_CLIENTS};
pub use session::{DEFAULT_ADDR, MAX_SPEED, MIN_SPEED, serve, start_after};
pub use stop::{Interrupted, STOP_SIGNAL};
