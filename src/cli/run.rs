//! `lerpit run`: simulate without a terminal and print the result as JSON,
//! CSV or text, or trace the diagnostics every K steps as CSV. Progress goes
//! to standard error when it is a terminal.

use super::progress::Progress;
use super::values::whole;
use super::{Failure, Overrides, SourceArgs, check_all_pairs};
use crate::scene::rules::{self, MAX_STEPS};
use crate::scene::{Scene, SceneError};
use crate::sim::threads::{MAX_THREADS, thread_pool};
use crate::sim::{Body, BroadPhase, Diagnostics, Integrator, Vec3, WallMode, World};
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::io::{BufWriter, Write};

#[derive(Args, Debug, Clone)]
pub struct RunArgs {
    #[command(flatten)]
    pub source: SourceArgs,
    /// Number of steps to take (0 to 10^12; 1e6 is read as 1000000).
    #[arg(long, conflicts_with = "time", allow_negative_numbers = true,
          value_parser = whole::<u64>(0, MAX_STEPS))]
    pub steps: Option<u64>,
    /// Simulated time to cover, s (rounded up to whole steps, at most 10^12
    /// of them). Default: 1 s.
    #[arg(long, allow_negative_numbers = true, value_parser = parse_time)]
    pub time: Option<f64>,
    #[command(flatten)]
    pub overrides: Overrides,
    /// Output format of the final state.
    #[arg(long, value_enum, default_value_t = Format::Json, conflicts_with = "trace")]
    pub format: Format,
    /// Print the diagnostics every K steps as CSV rows instead (for plotting).
    #[arg(long, value_name = "K", allow_negative_numbers = true,
          value_parser = whole::<u64>(1, MAX_STEPS))]
    pub trace: Option<u64>,
    /// Threads to simulate on (default: one per core). The result is the
    /// same for any number.
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = parse_threads)]
    pub threads: Option<usize>,
    /// Run all-pairs with pair collisions above 5,000 spheres (n (n - 1) / 2
    /// pair tests a step), which is otherwise refused.
    #[arg(long)]
    pub allow_slow: bool,
}

/// A number of threads in `1..=MAX_THREADS`; shared with `lerpit bench`.
pub fn parse_threads(s: &str) -> Result<usize, String> {
    super::values::whole_number(s, 1, MAX_THREADS as u64)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Json,
    Csv,
    Text,
}

fn parse_time(s: &str) -> Result<f64, String> {
    super::values::number(rules::non_negative)(s)
}

/// The steps `args` ask for with `scene`'s `dt`: `--steps`, or `--time`
/// (default 1 s) in whole steps, within [`MAX_STEPS`]. A refusal is a bad
/// command line when `--time` or `--dt` was given, else a bad scene (its
/// `dt`).
pub fn steps_to_run(args: &RunArgs, scene: &Scene) -> Result<u64, Failure> {
    if let Some(n) = args.steps {
        return Ok(n);
    }
    let dt = scene.world.dt;
    let time = args.time.unwrap_or(1.0);
    let time_from = match args.time {
        Some(t) => format!("--time {} s", rules::show(t)),
        None => "1 s (the default --time)".to_string(),
    };
    let dt_from = match args.overrides.dt {
        Some(dt) => format!("--dt {} s", rules::show(dt)),
        None => format!("the scene's dt {} s", rules::show(dt)),
    };
    rules::steps_for(time, dt).map_err(|m| {
        let message = format!(
            "{time_from} at {dt_from} would {m}: shorten the time, lengthen the step, \
             or give --steps"
        );
        if args.time.is_some() || args.overrides.dt.is_some() {
            Failure::Usage(message)
        } else {
            Failure::Scene(SceneError::new(&scene.origin, message).field("world.dt"))
        }
    })
}

/// The JSON report: names are stable, scripts read them. The readouts are
/// the world's [`Diagnostics`], flattened in: their names are the report's.
#[derive(Serialize, Debug)]
pub struct Report {
    pub scene: String,
    pub seed: u64,
    #[serde(flatten)]
    pub diagnostics: Diagnostics,
    pub dt: f64,
    pub integrator: Integrator,
    pub broad_phase: BroadPhase,
    pub substeps: u32,
    /// m/s; 0 = off.
    pub rest_threshold: f64,
    pub wall_mode: WallMode,
    pub wall_restitution: f64,
    pub pair_restitution: f64,
    pub gravity: Vec3,
    /// Contacts found over the whole run.
    pub total_contacts: u64,
    /// XXH3 of the exact state bits, as 16 hex digits.
    pub state_hash: String,
    pub bodies: Vec<Body>,
}

impl Report {
    pub fn new(scene: &Scene, world: &World, total_contacts: u64) -> Self {
        let c = &world.config;
        Self {
            scene: scene.name.clone(),
            seed: scene.seed,
            diagnostics: world.diagnostics(),
            dt: c.dt,
            integrator: c.integrator,
            broad_phase: c.broad_phase,
            substeps: c.substeps,
            rest_threshold: c.rest_threshold,
            wall_mode: c.wall_mode,
            wall_restitution: c.wall_restitution,
            pair_restitution: c.pair_restitution,
            gravity: c.gravity,
            total_contacts,
            state_hash: format!("{:016x}", world.state_hash()),
            bodies: world.bodies.iter_scene_order().collect(),
        }
    }
}

pub const TRACE_HEADER: &str = "step,time,kinetic_energy,potential_energy,total_energy,\
momentum_x,momentum_y,momentum_z,contacts,pair_tests,max_overlap,wall_impacts";

pub fn trace_row(d: &Diagnostics) -> String {
    format!(
        "{},{},{},{},{},{},{},{},{},{},{},{}",
        d.steps,
        d.time,
        d.kinetic_energy,
        d.potential_energy,
        d.total_energy,
        d.momentum.x,
        d.momentum.y,
        d.momentum.z,
        d.contacts,
        d.pair_tests,
        d.max_overlap,
        d.wall_impacts
    )
}

pub fn run(args: &RunArgs) -> Result<(), Failure> {
    let pool = thread_pool(args.threads).map_err(Failure::Runtime)?;
    pool.install(|| simulate(args))
}

fn simulate(args: &RunArgs) -> Result<(), Failure> {
    let mut scene = args.source.load()?;
    args.overrides.apply(&mut scene).map_err(Failure::Usage)?;
    let steps = steps_to_run(args, &scene)?;
    let chosen = match args.overrides.broadphase {
        Some(_) => "--broadphase all-pairs",
        None => "the scene's broad phase all-pairs",
    };
    if steps > 0 {
        check_all_pairs(
            scene.world.broad_phase,
            scene.world.pair_collisions,
            scene.body_count(),
            args.allow_slow,
            chosen,
        )?;
    }
    let mut world = scene.build()?;

    let out = std::io::stdout();
    let mut out = BufWriter::new(out.lock());
    let bar = Progress::bar(steps, "run");
    let mut total_contacts = 0u64;
    if let Some(k) = args.trace {
        writeln!(out, "{TRACE_HEADER}")?;
        writeln!(out, "{}", trace_row(&world.diagnostics()))?;
        for _ in 0..steps {
            world.step();
            bar.inc(1);
            if world.steps % k == 0 || world.steps == steps {
                writeln!(out, "{}", trace_row(&world.diagnostics()))?;
            }
        }
        bar.finish();
        out.flush()?;
        return Ok(());
    }
    for _ in 0..steps {
        world.step();
        bar.inc(1);
        total_contacts += world.last.contacts as u64;
    }
    bar.finish();
    let report = Report::new(&scene, &world, total_contacts);
    match args.format {
        Format::Json => {
            serde_json::to_writer_pretty(&mut out, &report)?;
            writeln!(out)?;
        }
        Format::Csv => {
            writeln!(out, "index,x,y,z,vx,vy,vz,radius,mass")?;
            for (i, b) in report.bodies.iter().enumerate() {
                let (p, v) = (b.position, b.velocity);
                writeln!(
                    out,
                    "{i},{},{},{},{},{},{},{},{}",
                    p.x, p.y, p.z, v.x, v.y, v.z, b.radius, b.mass
                )?;
            }
        }
        Format::Text => write_text(&mut out, &report)?,
    }
    out.flush()?;
    Ok(())
}

fn write_text(out: &mut impl Write, r: &Report) -> std::io::Result<()> {
    let v = |v: Vec3| format!("[{:.6e}, {:.6e}, {:.6e}]", v.x, v.y, v.z);
    let d = &r.diagnostics;
    writeln!(out, "scene            {} (seed {})", r.scene, r.seed)?;
    writeln!(out, "bodies           {}", r.bodies.len())?;
    writeln!(out, "steps            {}", d.steps)?;
    writeln!(out, "time             {:.6} s", d.time)?;
    writeln!(out, "dt               {:.6e} s", r.dt)?;
    writeln!(out, "integrator       {}", r.integrator)?;
    writeln!(out, "broad phase      {}", r.broad_phase)?;
    writeln!(
        out,
        "walls            {} (c_r {})",
        r.wall_mode, r.wall_restitution
    )?;
    writeln!(out, "pair restitution {}", r.pair_restitution)?;
    writeln!(out, "gravity          {} m/s^2", v(r.gravity))?;
    writeln!(out, "kinetic energy   {:.9e} J", d.kinetic_energy)?;
    writeln!(out, "potential energy {:.9e} J", d.potential_energy)?;
    writeln!(out, "total energy     {:.9e} J", d.total_energy)?;
    writeln!(out, "momentum         {} kg m/s", v(d.momentum))?;
    writeln!(
        out,
        "last step        {} contacts, {} pair tests, max overlap {:.3e} m",
        d.contacts, d.pair_tests, d.max_overlap
    )?;
    writeln!(out, "contacts in all  {}", r.total_contacts)?;
    writeln!(out, "state hash       {}", r.state_hash)?;
    Ok(())
}
