//! `lerpit run`: simulate without a terminal and print the result as JSON,
//! CSV or text, or trace the diagnostics or every sphere's path every K
//! steps as CSV. Progress goes to standard error when it is a terminal.

use super::values::whole;
use super::{ALLOW_SLOW_HELP, Failure, Overrides, SourceArgs, write_csv};
use crate::process::progress::{Clearing, Parts, Progress};
use crate::process::reader_watch::ReaderWatch;
use crate::process::unbroken::Unbroken;
use crate::process::whole_rows::{WholeRows, stdout_is_regular_file};
use crate::scene::rules::{self, MAX_STEPS, unsigned_zero};
use crate::scene::{Scene, SceneError};
use crate::sim::threads::{MAX_THREADS, thread_pool};
use crate::sim::{Body, Diagnostics, StepStats, Vec3, WallMode, World, WorldConfig};
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::io::{BufWriter, Write};
use std::time::{Duration, Instant};

#[derive(Args, Debug, Clone)]
pub(crate) struct RunArgs {
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
    #[arg(long, value_enum, default_value_t = Format::Json,
          conflicts_with_all = ["trace", "trajectory"])]
    pub format: Format,
    /// Print the diagnostics every K steps as CSV rows instead (for plotting).
    #[arg(long, value_name = "K", allow_negative_numbers = true,
          value_parser = whole::<u64>(1, MAX_STEPS))]
    pub trace: Option<u64>,
    /// Print every sphere's position and velocity every K steps as CSV rows
    /// instead (step, time, index, x, y, z, vx, vy, vz; for plotting paths).
    #[arg(long, value_name = "K", allow_negative_numbers = true, conflicts_with = "trace",
          value_parser = whole::<u64>(1, MAX_STEPS))]
    pub trajectory: Option<u64>,
    /// Threads to simulate on (default: one per core). The result is the
    /// same for any number.
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = parse_threads)]
    pub threads: Option<usize>,
    #[arg(long, help = ALLOW_SLOW_HELP)]
    pub allow_slow: bool,
}

/// A number of threads in `1..=MAX_THREADS`; shared with `lerpit bench`.
pub(crate) fn parse_threads(s: &str) -> Result<usize, String> {
    super::values::whole_number(s, 1, MAX_THREADS as u64)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
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
pub(crate) fn steps_to_run(args: &RunArgs, scene: &Scene) -> Result<u64, Failure> {
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
pub(crate) struct Report {
    pub scene: String,
    pub seed: u64,
    #[serde(flatten)]
    pub diagnostics: Diagnostics,
    /// What the world ran: gravity, dt, method, walls, pairs, sub-steps,
    /// rest rules, projection passes.
    #[serde(flatten)]
    pub config: WorldConfig,
    /// What the run's steps added up to.
    #[serde(flatten)]
    pub totals: RunTotals,
    /// XXH3 of the exact state bits, as 16 hex digits.
    pub state_hash: String,
    pub bodies: Vec<Body>,
}

/// What a run's steps add up to: contacts, and the steps where a remedy
/// ran out of its budget (the run goes on; the report says so).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub(crate) struct RunTotals {
    /// Contacts found over the whole run.
    pub total_contacts: u64,
    /// Steps whose further projection passes ran out before every pair
    /// was within tolerance (`StepStats::projection_unconverged`).
    pub unconverged_projection_steps: u64,
    /// Steps in which the continuous method reached its impact cap
    /// (`StepStats::event_cap_reached`).
    pub impact_cap_steps: u64,
    /// Spheres the support pass's sweeps left unsettled, summed over the
    /// steps (`StepStats::support_unsettled`).
    pub support_unsettled: u64,
}

impl RunTotals {
    fn add(&mut self, last: &StepStats) {
        self.total_contacts += last.contacts as u64;
        self.unconverged_projection_steps += u64::from(last.projection_unconverged);
        self.impact_cap_steps += u64::from(last.event_cap_reached);
        self.support_unsettled += last.support_unsettled as u64;
    }
}

impl Report {
    pub(crate) fn new(scene: &Scene, world: &World, totals: RunTotals) -> Self {
        Self {
            scene: scene.name.clone(),
            seed: scene.seed,
            diagnostics: world.diagnostics(),
            config: world.config.clone(),
            totals,
            state_hash: format!("{:016x}", world.state_hash()),
            bodies: world.bodies.iter_scene_order().collect(),
        }
    }
}

/// One line of `--format csv`: a sphere, in scene order.
#[derive(Serialize)]
struct BodyRow {
    index: usize,
    x: f64,
    y: f64,
    z: f64,
    vx: f64,
    vy: f64,
    vz: f64,
    radius: f64,
    mass: f64,
}

impl BodyRow {
    fn new(index: usize, b: &Body) -> Self {
        let (p, v) = (b.position, b.velocity);
        Self {
            index,
            x: p.x,
            y: p.y,
            z: p.z,
            vx: v.x,
            vy: v.y,
            vz: v.z,
            radius: b.radius,
            mass: b.mass,
        }
    }
}

/// One line of `--trajectory`: a sphere after a step, in scene order.
#[derive(Serialize)]
struct PathRow {
    step: u64,
    time: f64,
    index: usize,
    x: f64,
    y: f64,
    z: f64,
    vx: f64,
    vy: f64,
    vz: f64,
}

/// The rows `--trace` or `--trajectory` writes after a step.
fn write_rows(
    rows: &mut csv::Writer<impl Write>,
    world: &World,
    paths: bool,
) -> Result<(), csv::Error> {
    if !paths {
        return rows.serialize(TraceRow::from(world.diagnostics()));
    }
    // The paths need no energies: the step and the time are the world's.
    for (index, b) in world.bodies.iter_scene_order().enumerate() {
        let (p, v) = (b.position, b.velocity);
        rows.serialize(PathRow {
            step: world.steps,
            time: world.time,
            index,
            x: p.x,
            y: p.y,
            z: p.z,
            vx: v.x,
            vy: v.y,
            vz: v.z,
        })?;
    }
    Ok(())
}

/// How often `--trace` and `--trajectory` hand their rows on.
const TRACE_FLUSH: Duration = Duration::from_millis(250);

/// One line of `--trace`: the diagnostics after a step, vectors split into
/// their components.
#[derive(Serialize)]
struct TraceRow {
    step: u64,
    time: f64,
    kinetic_energy: f64,
    potential_energy: f64,
    total_energy: f64,
    momentum_x: f64,
    momentum_y: f64,
    momentum_z: f64,
    contacts: usize,
    pair_tests: u64,
    max_overlap: f64,
    wall_impacts: usize,
}

impl From<Diagnostics> for TraceRow {
    fn from(d: Diagnostics) -> Self {
        Self {
            step: d.steps,
            time: d.time,
            kinetic_energy: d.kinetic_energy,
            potential_energy: d.potential_energy,
            total_energy: d.total_energy,
            momentum_x: d.momentum.x,
            momentum_y: d.momentum.y,
            momentum_z: d.momentum.z,
            contacts: d.contacts,
            pair_tests: d.pair_tests,
            max_overlap: d.max_overlap,
            wall_impacts: d.wall_impacts,
        }
    }
}

pub(crate) fn run(args: &RunArgs) -> Result<(), Failure> {
    let threads = args
        .threads
        .unwrap_or_else(crate::sim::threads::default_threads);
    crate::scene::memory::check_threads(threads).map_err(Failure::Runtime)?;
    let pool = thread_pool(args.threads).map_err(Failure::Runtime)?;
    pool.install(|| simulate(args))
}

fn simulate(args: &RunArgs) -> Result<(), Failure> {
    let mut scene = args.source.load()?;
    args.overrides.apply(&mut scene).map_err(Failure::Usage)?;
    args.overrides
        .check_for_run(&scene)
        .map_err(Failure::Usage)?;
    let steps = steps_to_run(args, &scene)?;
    let chosen = match args.overrides.broadphase {
        Some(_) => "--broadphase all-pairs",
        None => "the scene's broad phase all-pairs",
    };
    // A spawn that cannot fit is the scene's fault, whatever the run costs.
    scene.check_packing()?;
    if steps > 0 {
        super::check_cost(&scene, args.allow_slow, chosen)?;
    }
    // Rows to a file are written with the signals held off, so a signal
    // ends the output after a whole row (`whole_rows.rs`); the progress
    // lines' handlers go in first, gated.
    let rows_to_file = args.trace.or(args.trajectory).is_some() && stdout_is_regular_file();
    let unbroken = rows_to_file.then(|| {
        crate::process::progress::clear_line_while_shown();
        Unbroken::install()
    });
    let clearing = match unbroken {
        Some(_) => Clearing::WhileShown,
        None => Clearing::ForGood,
    };
    let building = crate::process::progress::building("run", scene.body_count(), clearing);
    let (spawned, checked) = (scene.spawned(), scene.world.pair_collisions);
    let mut world = scene.build_telling(&|placed| {
        if let Some(line) = &building {
            line.message(crate::process::progress::placing(placed, spawned, checked));
        }
    })?;
    drop(building);
    // The run reports counts, never the list of contacts.
    world.keep_contacts(false);

    let watch = ReaderWatch::start();
    if let Some(k) = args.trace.or(args.trajectory) {
        let bar = match unbroken {
            Some(_) => Progress::bar_of_cleared_while_shown(steps, "run", Parts::Even),
            None => Progress::bar_cleared_on_signals(steps, "run"),
        };
        let paths = args.trajectory.is_some();
        let out = WholeRows::new(std::io::stdout().lock(), unbroken.as_ref(), &bar);
        let mut trace = csv::Writer::from_writer(out);
        write_rows(&mut trace, &world, paths)?;
        trace.flush()?;
        let mut flushed = Instant::now();
        for _ in 0..steps {
            world.step();
            bar.inc(1);
            watch.check()?;
            if world.steps % k == 0 || world.steps == steps {
                write_rows(&mut trace, &world, paths)?;
                // A run stopped by a signal keeps the rows of all but its
                // last moments.
                if flushed.elapsed() >= TRACE_FLUSH {
                    trace.flush()?;
                    flushed = Instant::now();
                }
            }
        }
        // The last rows before the line goes: its gate stays shut after.
        trace.flush()?;
        bar.finish();
        return Ok(());
    }
    let out = std::io::stdout();
    let mut out = BufWriter::new(out.lock());
    let bar = Progress::bar_cleared_on_signals(steps, "run");
    let mut totals = RunTotals::default();
    for _ in 0..steps {
        world.step();
        bar.inc(1);
        watch.check()?;
        totals.add(&world.last);
    }
    bar.finish();
    let report = Report::new(&scene, &world, totals);
    match args.format {
        Format::Json => {
            serde_json::to_writer_pretty(&mut out, &report)?;
            writeln!(out)?;
        }
        Format::Csv => write_csv(
            &mut out,
            report
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| BodyRow::new(i, b)),
        )?,
        Format::Text => write_text(&mut out, &report)?,
    }
    out.flush()?;
    Ok(())
}

/// `x` to `figures` significant figures, as a person reads it: plain
/// decimals for everyday magnitudes, exponent form for the very large and
/// very small (as `rules::show` chooses).
pub(super) fn to_figures(x: f64, figures: usize) -> String {
    let a = x.abs();
    if a == 0.0 {
        "0".to_string()
    } else if !a.is_finite() || !(1e-4..1e9).contains(&a) {
        format!("{x:.*e}", figures.saturating_sub(1))
    } else {
        let decimals = (figures as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    }
}

/// Simulated time for the text output: to the microsecond, or, under a
/// millisecond, to seven significant figures (a run of a few tiny steps
/// does not read as no time at all).
fn time_text(t: f64) -> String {
    if t == 0.0 || t >= 1e-3 {
        format!("{t:.6}")
    } else {
        to_figures(t, 7)
    }
}

fn write_text(out: &mut impl Write, r: &Report) -> std::io::Result<()> {
    let f = to_figures;
    let v = |v: Vec3| format!("[{}, {}, {}]", f(v.x, 7), f(v.y, 7), f(v.z, 7));
    let (d, c) = (&r.diagnostics, &r.config);
    writeln!(
        out,
        "scene            {} (seed {})",
        super::printable_line(&r.scene, super::MESSAGE_CHARS),
        r.seed
    )?;
    writeln!(out, "bodies           {}", r.bodies.len())?;
    writeln!(out, "steps            {}", d.steps)?;
    writeln!(out, "time             {} s", time_text(d.time))?;
    writeln!(out, "dt               {} s", f(c.dt, 7))?;
    writeln!(out, "substeps         {}", c.substeps)?;
    writeln!(out, "integrator       {}", c.integrator)?;
    writeln!(out, "broad phase      {}", c.broad_phase)?;
    let walls = match c.wall_mode {
        WallMode::Flip if c.wall_restitution != 1.0 => format!(
            "flip (keep the speed; wall_restitution {} applies to restitution walls only)",
            c.wall_restitution
        ),
        WallMode::Flip => "flip (keep the speed)".to_string(),
        WallMode::Restitution => format!("restitution (c_r {})", c.wall_restitution),
    };
    writeln!(out, "walls            {walls}")?;
    if c.pair_collisions {
        writeln!(out, "pair restitution {}", c.pair_restitution)?;
    } else {
        writeln!(
            out,
            "pair restitution {} (unused: no pair collisions)",
            c.pair_restitution
        )?;
    }
    writeln!(out, "gravity          {} m/s^2", v(c.gravity))?;
    // A rule set in a scene file that no impact of this scene can use is
    // shown as unused, as `run`'s flags refuse it (`check_for_run`).
    let flip_alone = !c.pair_collisions && c.wall_mode == WallMode::Flip;
    let rest_steps = if c.rest_steps > 0.0 && c.gravity == Vec3::ZERO {
        "unused: no gravity"
    } else if c.rest_steps > 0.0 && flip_alone {
        "unused: flip walls keep the speed and there are no pair collisions"
    } else {
        "resting contact; 0: off"
    };
    writeln!(out, "rest steps       {} ({rest_steps})", c.rest_steps)?;
    let rest_threshold = if c.rest_threshold > 0.0 && flip_alone {
        "unused: flip walls keep the speed and there are no pair collisions"
    } else {
        "slower impacts are inelastic; 0: off"
    };
    writeln!(
        out,
        "rest threshold   {} m/s ({rest_threshold})",
        c.rest_threshold
    )?;
    writeln!(
        out,
        "projection       {} pass{}",
        c.projection_passes,
        if c.projection_passes == 1 { "" } else { "es" }
    )?;
    match (c.support, c.support_idle()) {
        (false, _) => writeln!(out, "support pass     off")?,
        (true, None) => writeln!(out, "support pass     on")?,
        (true, Some(why)) => writeln!(out, "support pass     on, idle: {why}")?,
    }
    match (c.sleep, c.integrator.is_discrete()) {
        (false, _) => writeln!(out, "sleeping         off")?,
        (true, true) => writeln!(
            out,
            "sleeping         on: {} of {} asleep",
            d.asleep,
            crate::scene::spheres(r.bodies.len())
        )?,
        (true, false) => writeln!(out, "sleeping         on, idle: the continuous method")?,
    }
    writeln!(out, "kinetic energy   {} J", f(d.kinetic_energy, 10))?;
    writeln!(out, "potential energy {} J", f(d.potential_energy, 10))?;
    writeln!(out, "total energy     {} J", f(d.total_energy, 10))?;
    writeln!(out, "momentum         {} kg m/s", v(d.momentum))?;
    let s = |n: u64| if n == 1 { "" } else { "s" };
    writeln!(
        out,
        "last step        {} contact{}, {} pair test{}, max overlap {} m, {} wall impact{}",
        d.contacts,
        s(d.contacts as u64),
        d.pair_tests,
        s(d.pair_tests),
        f(d.max_overlap, 4),
        d.wall_impacts,
        s(d.wall_impacts as u64)
    )?;
    let t = &r.totals;
    writeln!(out, "contacts in all  {}", t.total_contacts)?;
    if t.unconverged_projection_steps > 0 {
        writeln!(
            out,
            "projection       ran out of passes in {} step{} (pile left overlapping)",
            t.unconverged_projection_steps,
            s(t.unconverged_projection_steps)
        )?;
    }
    if t.impact_cap_steps > 0 {
        writeln!(
            out,
            "impact cap       reached in {} step{} (finished by the contact stages)",
            t.impact_cap_steps,
            s(t.impact_cap_steps)
        )?;
    }
    if t.support_unsettled > 0 {
        writeln!(
            out,
            "support sweeps   left {} sphere-steps unsettled (short of their target by > 1% of a radius)",
            t.support_unsettled
        )?;
    }
    writeln!(out, "state hash       {}", r.state_hash)?;
    write_text_spheres(out, &r.bodies)
}

/// The spheres a text report lists; `--format csv` and `json` give all.
const TEXT_SPHERES: usize = 20;

/// The text report's spheres: the first [`TEXT_SPHERES`] in scene order,
/// to a nanometre and a nanometre a second.
fn write_text_spheres(out: &mut impl Write, bodies: &[Body]) -> std::io::Result<()> {
    let shown = bodies.len().min(TEXT_SPHERES);
    if shown == 0 {
        return Ok(());
    }
    if shown == bodies.len() {
        writeln!(out, "spheres          in scene order")?;
    } else {
        writeln!(
            out,
            "spheres          the first {shown} of {}, in scene order (--format csv lists every one)",
            bodies.len()
        )?;
    }
    writeln!(
        out,
        "{:>7} {:>12} {:>12} {:>12} {:>13} {:>13} {:>13} {:>9} {:>11}",
        "index", "x m", "y m", "z m", "vx m/s", "vy m/s", "vz m/s", "radius m", "mass kg"
    )?;
    // To nine decimals where that fits the column (a centre lies in the
    // box; speeds under 100 m/s), else to seven figures in exponent form;
    // -0, and what rounds to it, reads 0.
    let cell = |x: f64| {
        if x.abs() < 99.999_999_999_5 {
            unsigned_zero(format!("{x:.9}"))
        } else {
            format!("{x:.6e}")
        }
    };
    for (index, b) in bodies.iter().take(shown).enumerate() {
        let (p, v) = (b.position, b.velocity);
        writeln!(
            out,
            "{index:>7} {:>12} {:>12} {:>12} {:>13} {:>13} {:>13} {:>9} {:>11}",
            cell(p.x),
            cell(p.y),
            cell(p.z),
            cell(v.x),
            cell(v.y),
            cell(v.z),
            to_figures(b.radius, 4),
            to_figures(b.mass, 4)
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{time_text, to_figures, write_text_spheres};
    use crate::sim::{Body, Vec3};

    #[test]
    fn the_text_sphere_table_keeps_its_columns_for_any_speed() {
        let body = |v: Vec3, mass: f64| Body {
            position: Vec3::new(0.5, 1e-12, -0.0),
            velocity: v,
            radius: 0.01,
            mass,
        };
        let mut out = Vec::new();
        write_text_spheres(
            &mut out,
            &[
                body(Vec3::new(-1234.5, -1e-12, -3e5), 1e7),
                body(Vec3::new(-99.9999999999, 0.0, 99.99), 1.0),
            ],
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        let rows: Vec<&str> = text.lines().skip(1).collect();
        assert_eq!(
            rows,
            [
                "  index          x m          y m          z m        vx m/s        vy m/s        \
                 vz m/s  radius m     mass kg",
                "      0  0.500000000  0.000000000  0.000000000   -1.234500e3   0.000000000   \
                 -3.000000e5   0.01000    10000000",
                "      1  0.500000000  0.000000000  0.000000000   -1.000000e2   0.000000000  \
                 99.990000000   0.01000       1.000",
            ]
        );
    }

    #[test]
    fn text_figures_are_plain_for_everyday_magnitudes() {
        assert_eq!(to_figures(380.17556871, 10), "380.1755687");
        assert_eq!(to_figures(1.0 / 240.0, 7), "0.004166667");
        assert_eq!(to_figures(-9.81, 7), "-9.810000");
        assert_eq!(to_figures(0.0, 7), "0");
        assert_eq!(to_figures(1.2346e-7, 4), "1.235e-7");
        assert_eq!(to_figures(6.02e23, 4), "6.020e23");
    }

    #[test]
    fn a_time_under_a_millisecond_keeps_its_figures() {
        assert_eq!(time_text(7e-9), "7.000000e-9");
        assert_eq!(time_text(3.0 / 240.0 / 16.0), "0.0007812500");
        assert_eq!(time_text(0.0), "0.000000");
        assert_eq!(time_text(1.0), "1.000000");
        assert_eq!(time_text(4166.6666666667), "4166.666667");
    }
}
