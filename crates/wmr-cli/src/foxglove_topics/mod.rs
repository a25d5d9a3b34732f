//! The Foxglove topics of a run and their encoding, shared by the MCAP file
//! ([`crate::mcap_sink`]) and the live WebSocket server ([`crate::live`]): the same bytes
//! go to both.
//!
//! One module per concept, data flowing one way: [`topics`] names the topics and their
//! schemas, [`sample`] lays out `wmr.Sample`, [`clock`] stamps log times, [`colour`] picks
//! each run's colour, [`path`] keeps the path as polyline pieces, [`mod@reference`] draws
//! a tracking run's reference path, [`mod@obstacles`] the world's obstacles, [`mod@mppi`] MPPI's plans, and [`encoder`], built on all of them, turns a run's
//! samples into the messages of every topic.

mod clock;
mod colour;
mod encoder;
mod mppi;
mod obstacles;
mod path;
mod reference;
mod sample;
mod topics;

pub use clock::LogClock;
pub use colour::{run_hex, run_rgb};
pub use encoder::RunEncoder;
pub use mppi::MppiView;
pub use reference::{MAX_REFERENCE_SAMPLES, log_positions};
pub use topics::{Kind, MESSAGE_ENCODING, Schemas, Views, WORLD_FRAME, base_link, reference_frame, topic};
