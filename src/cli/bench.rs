//! `lerpit bench`: the program's own speed measurements. `--render` times
//! drawing one frame of the visualiser headless (see
//! `tui::render_bench`). Quote medians from release builds.

use super::Failure;
use clap::Args;

#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// Time drawing frames of the visualiser into an off-screen buffer.
    #[arg(long)]
    pub render: bool,
    /// Spheres to draw.
    #[arg(long, default_value_t = 10_000, value_parser = parse_particles)]
    pub particles: usize,
    /// Buffer width, cells.
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u16).range(1..=1000))]
    pub width: u16,
    /// Buffer height, cells.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u16).range(1..=1000))]
    pub height: u16,
    /// Frames to draw.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub frames: u64,
}

fn parse_particles(s: &str) -> Result<usize, String> {
    let n: usize = s
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a whole number"))?;
    if n == 0 {
        return Err("must be at least 1".into());
    }
    crate::scene::rules::count(n)
}

pub fn bench(args: &BenchArgs) -> Result<(), Failure> {
    if !args.render {
        return Err(Failure::Usage(
            "choose what to measure: `lerpit bench --render`".into(),
        ));
    }
    render(args)
}

#[cfg(feature = "tui")]
fn render(args: &BenchArgs) -> Result<(), Failure> {
    use crate::tui::render_bench::RenderBench;
    use std::io::Write;
    let bench = RenderBench {
        particles: args.particles,
        width: args.width,
        height: args.height,
        frames: args.frames as usize,
    };
    let figures = bench.run().map_err(Failure::Usage)?;
    let mut out = std::io::stdout().lock();
    if cfg!(debug_assertions) {
        writeln!(
            out,
            "note: a debug build; measure with `cargo run --release`"
        )?;
    }
    write!(out, "{}", figures.report(&bench))?;
    Ok(())
}

#[cfg(not(feature = "tui"))]
fn render(_args: &BenchArgs) -> Result<(), Failure> {
    Err(Failure::Usage(
        "this build of lerpit has no visualiser (built without the `tui` feature), \
         so there is nothing to draw"
            .into(),
    ))
}
