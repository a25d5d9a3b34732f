//! Controllers: an outer law (where should the wheels go) composed with a wheel stage
//! (make them go there), run every control period.
//!
//! - [`law`]: the [`Law`] contract and what a law asks of the wheels ([`WheelDemand`]).
//! - [`paper`], [`paper_bidirectional`], [`polar`], [`lyapunov`], [`graceful`]: the laws; [`polar_frame`]
//!   the polar laws' shared geometry.
//! - [`mppi`]: model predictive path integral control (nav2's MPPI) to a goal or along a
//!   path; [`rollout`] the dynamic model its rollouts predict with; [`mppi_path`] its
//!   local plan and path critics; [`vector_unit`] whether its planner's AVX2 build may run.
//! - [`kanayama`], [`backstepping`]: trajectory tracking; [`pure_pursuit`]: path following.
//! - [`registry`]: the one list of laws; [`any`]: every law behind one enum, chosen by
//!   name at run time, expanded from it.
//! - [`wheel_stage`]: the wheel servos and the curvature-keeping wheel speed limit.
//! - [`composed`]: [`Controller`] = law + wheel stage + control period.
//! - [`observer`]: the disturbance observer the wheel stage may carry, for every law.

pub mod any;
pub mod backstepping;
pub mod composed;
pub mod graceful;
pub mod kanayama;
pub mod law;
pub mod lyapunov;
pub mod mppi;
pub mod mppi_path;
pub mod observer;
pub mod paper;
pub mod paper_bidirectional;
pub mod polar;
pub mod polar_frame;
pub mod pure_pursuit;
pub mod registry;
pub mod rollout;
pub mod saturation;
pub mod servo;
pub mod vector_unit;
pub mod wheel_stage;

pub use any::{AnyLaw, LawParams};
pub use composed::{ControlOutput, Controller, ControllerParams};
pub use law::{ControlErrors, Follows, Law, LawContext, LawOutput, LawSpec, WheelDemand};
pub use mppi::MotionModel;
pub use observer::{DisturbanceObserver, DisturbanceObserverParams};
pub use paper::{AntiWindup, HoldMode, PaperMode};
pub use polar_frame::{Direction, DirectionSelector, PolarCoordinateLaw, PolarCoords, PolarGains, Steering};
pub use saturation::{WheelRateLimiter, limit_wheel_speeds, wheel_speed_scale};
pub use servo::{ServoGains, WheelServo};
pub use wheel_stage::{WheelStage, WheelStageParams};

/// Each law's keys and law from its file (`pub use kanayama::{KanayamaParams, KanayamaLaw}`),
/// from the registry: a law's module is named by its `kind`.
macro_rules! law_exports {
    ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
        $( pub use $kind::{$params, $law}; )+
    };
}
crate::for_each_law!(law_exports);
