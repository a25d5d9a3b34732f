//! Controllers: an outer law (where should the wheels go) composed with a wheel stage
//! (make them go there), run every control period.
//!
//! - [`law`]: the [`Law`] contract and what a law asks of the wheels ([`WheelDemand`]).
//! - [`paper`], [`paper_bidirectional`], [`polar`], [`lyapunov`]: the laws; [`polar_frame`]
//!   the polar laws' shared geometry.
//! - [`kanayama`], [`backstepping`]: trajectory tracking; [`pure_pursuit`]: path following.
//! - [`any`]: every law behind one enum, chosen by name at run time.
//! - [`wheel_stage`]: the wheel servos and the curvature-keeping wheel speed limit.
//! - [`composed`]: [`Controller`] = law + wheel stage + control period.

pub mod any;
pub mod backstepping;
pub mod composed;
pub mod kanayama;
pub mod law;
pub mod lyapunov;
pub mod paper;
pub mod paper_bidirectional;
pub mod polar;
pub mod polar_frame;
pub mod pure_pursuit;
pub mod saturation;
pub mod servo;
pub mod wheel_stage;

pub use any::{AnyLaw, LawParams};
pub use backstepping::{BacksteppingLaw, BacksteppingParams};
pub use composed::{ControlOutput, Controller, ControllerParams};
pub use kanayama::{KanayamaLaw, KanayamaParams};
pub use law::{ControlErrors, Law, LawOutput, WheelDemand};
pub use lyapunov::{LyapunovLaw, LyapunovParams};
pub use paper::{AntiWindup, HoldMode, PaperLaw, PaperMode, PaperParams};
pub use paper_bidirectional::{PaperBidirectionalLaw, PaperBidirectionalParams};
pub use polar::{PolarLaw, PolarParams};
pub use polar_frame::{Direction, DirectionSelector, PolarCoordinateLaw, PolarCoords, PolarGains, Steering};
pub use pure_pursuit::{PurePursuitLaw, PurePursuitParams};
pub use saturation::{WheelRateLimiter, limit_wheel_speeds, wheel_speed_scale};
pub use servo::{ServoGains, WheelServo};
pub use wheel_stage::{WheelStage, WheelStageParams};
