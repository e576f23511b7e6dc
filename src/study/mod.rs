//! The accuracy study: how fast against how accurate each method is, and
//! where each fails. Not physics: it builds worlds from the library's
//! scenes, runs them, and compares them with the exact references of
//! [`crate::sim::reference`].
//!
//! | file              | concept                                                    |
//! |-------------------|------------------------------------------------------------|
//! | `metrics.rs`      | what is measured: errors against the reference, cost, order |
//! | `sweep.rs`        | every method at every dt on each lesson: the work-precision data |
//! | `conservation.rs` | elastic collisions without gravity: momentum and energy drift |
//! | `goals.rs`        | the goals, their thresholds, and whether they are met      |
//! | `stability.rs`    | the stability suite: each method's failures and remedies   |
//! | `charts.rs`       | plain-text charts for the terminal                         |
//! | `svg.rs`          | the same charts as SVG files (plotters)                    |
//!
//! Nothing here draws on a terminal screen or changes how a method steps.

pub(crate) mod charts;
pub mod conservation;
pub(crate) mod goals;
pub(crate) mod metrics;
pub mod stability;
pub(crate) mod svg;
pub mod sweep;

pub use sweep::{Plan, Row, work_precision};
