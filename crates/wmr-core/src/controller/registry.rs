//! The one list of laws. Every other list of laws in wmr is an expansion of it: the
//! core's [`AnyLaw`](super::AnyLaw) and [`LawParams`](super::LawParams), the trace's law
//! codes, the C API's entry points and storage, the Python classes, the firmware's law
//! programs, the CLI's help and the docs tables.
//!
//! A line reads `Variant(Params, Law) = kind, code N, follows F;` under the law's doc
//! comment (its first line is the law's one-line description in every surface):
//! - `Variant`: the name of the law in Rust enums (`AnyLaw::Paper`) and, with
//!   `Controller` appended, the Python class (`PaperController`);
//! - `Params`, `Law`: the law's keys (a `params! { words; ... }` struct implementing
//!   [`LawSpec`](super::LawSpec)) and the law itself, both defined in the law's own file;
//! - `kind`: the `[controller] kind` of a scenario and the C names (`wmr_<kind>_...`);
//! - `code N`: its number in a trace file and in the C storage tags: never reused, never
//!   changed (a trace written today must read the same tomorrow);
//! - `follows F`: [`Follows::Goal`](super::Follows), `Trajectory`, `Path` or `GoalOrPath`.
//!
//! The lines are in documentation order (the order of `--help`, the docs and the C
//! header). A new law is its file plus one line here (CONTRIBUTING.md).

/// Calls `$callback! { $crate; line; line; ... }` with the list of laws (see the module
/// docs for a line's words). `$crate` comes first so that an expansion in another crate
/// can name each type as `$krate::Params`.
///
/// ```
/// macro_rules! kinds {
///     ($krate:tt; $( $(#[doc = $doc:literal])* $variant:ident($params:ident, $law:ident) = $kind:ident, code $code:literal, follows $follows:ident; )+) => {
///         [$( stringify!($kind) ),+]
///     };
/// }
/// assert_eq!(wmr_core::for_each_law!(kinds)[0], "paper");
/// ```
#[macro_export]
macro_rules! for_each_law {
    ($callback:ident) => {
        $callback! {
            $crate;
            /// The paper's law: two PI loops on a moving false target feeding the wheel angle servos.
            Paper(PaperParams, PaperLaw) = paper, code 0, follows Goal;
            /// The paper's law repaired: a position error that never feeds back positively, the heading settling first.
            PaperBidirectional(PaperBidirectionalParams, PaperBidirectionalLaw) = paper_bidirectional, code 3, follows Goal;
            /// Astolfi's polar law: v = k_rho rho, omega = k_alpha alpha + k_beta beta.
            Polar(PolarParams, PolarLaw) = polar, code 1, follows Goal;
            /// Aicardi et al.'s Lyapunov law in polar coordinates.
            Lyapunov(LyapunovParams, LyapunovLaw) = lyapunov, code 2, follows Goal;
            /// Park and Kuipers' graceful law as nav2's docking server drives it: curvature from egocentric polar coordinates, speed falling with it, forward or backwards.
            Graceful(GracefulParams, GracefulLaw) = graceful, code 7, follows Goal;
            /// Model predictive path integral control (nav2's MPPI): sampled twist sequences rolled out on a model, averaged by the softmax of their critics' costs.
            Mppi(MppiParams, MppiLaw) = mppi, code 8, follows GoalOrPath;
            /// Kanayama et al.'s trajectory tracking law: v = v_ref cos(theta_e) + kx x_e, omega = omega_ref + v_ref (ky y_e + sgn(v_ref) ktheta sin(theta_e)).
            Kanayama(KanayamaParams, KanayamaLaw) = kanayama, code 4, follows Trajectory;
            /// Kanayama's twist back-stepped into the dynamics: wheel torques from the controller's model.
            Backstepping(BacksteppingParams, BacksteppingLaw) = backstepping, code 5, follows Trajectory;
            /// Regulated pure pursuit (nav2's names): path following on the reference's path, its timing ignored.
            PurePursuit(PurePursuitParams, PurePursuitLaw) = pure_pursuit, code 6, follows Path;
        }
    };
}
