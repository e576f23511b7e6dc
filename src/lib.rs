//! lerpit: learn and explore simple body dynamics.
//!
//! - [`sim`]: the simulation core (no terminal code);
//! - [`scene`]: scenes as data: the built-in lessons and TOML scene files;
//! - [`study`]: the accuracy study: work-precision sweeps, stability suite;
//! - [`cli`]: the command line, including the headless runner;
//! - `tui`: the full-screen terminal visualiser (feature `tui`).

pub mod cli;
pub mod scene;
pub mod sim;
pub mod study;
#[cfg(feature = "tui")]
pub mod tui;
