//! `wmr-cli run FILE.toml --live [ADDR]`: the runs served live over Foxglove's WebSocket
//! protocol. [`session`] paces the runs and encodes their messages; [`server`] fans them
//! out to the clients, each served by [`client`] with a bounded queue; [`handshake`]
//! negotiates the subprotocol; [`protocol`] spells the messages; [`stop`] is the signal
//! that ends a session early.
//!
//! Why not the `foxglove` crate's `WebSocketServer` (0.30.3, feature
//! `live_visualization`)? Put behind this module's interface and run against these
//! tests (2026-12-07), it could not keep what they guard:
//! - it refuses a client offering `foxglove.websocket.v1` (HTTP 400, "Missing expected
//!   sec-websocket-protocol header"; Foxglove's app still offers it), and its refusal
//!   does not say what it accepts (`regression_27_both_subprotocols...` fails);
//! - it has no connection limit: the 17th client is served, not told 503
//!   (`regression_25_5_connections_are_limited...` fails);
//! - read in its source: no handshake deadline and no idle limit, an accept loop that
//!   ends for good on its first error (file descriptors exhausted), no count of dropped
//!   messages, and a shutdown that waits without a deadline on a client that does not read.
//!
//! It would also add 26 crates (tokio and its kin) and 7 MB to the binary. Fronting it
//! with a proxy of our own to restore the limits would keep about half of this code, so
//! the server stays ours.

mod client;
mod handshake;
mod protocol;
mod server;
mod session;
mod stop;

pub use server::{HANDSHAKE_DEADLINE, IDLE_LIMIT, MAX_CLIENTS};
pub use session::{DEFAULT_ADDR, MAX_SPEED, MIN_SPEED, serve, start_after};
pub use stop::{Interrupted, STOP_SIGNAL};
