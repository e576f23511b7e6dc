//! `lerpit bench`: the program's own speed and memory measurements. Quote
//! medians from release builds.
//!
//! By default it measures how fast the collisions scene steps, at any size;
//! `--render` instead times drawing frames of the visualiser headless (see
//! `tui::render_bench`).
//!
//! It steps the benchmark scene ([`crate::scene::bench`]) from its dilute
//! start (spheres in flight through the box, as spawned) or its settled
//! start (`--start settled`: at rest in a layer on the floor, as dense as
//! gravity leaves them with one contact pass a step, where a step costs 3
//! to 10 times as much; the support pass holds a looser pile, which the
//! dilute start reaches after `--warmup 600`, and the text output says so
//! when both are asked for): one
//! untimed step that sizes the buffers, `--warmup` further untimed steps,
//! then `--steps` timed steps. A settled start that would need more memory
//! than the system has available is refused before it starts.
//!
//! `--sweep` runs the scene for N = 100 ... 1,000,000 (half-decade steps):
//! from the dilute start for each broad phase, and from the settled start
//! with `auto`, and prints a scaling table. Peak resident memory
//! comes from `/proc/self/status` (VmHWM); between the runs of a sweep it is
//! reset through `/proc/self/clear_refs` so each run reports its own.

use super::overrides::parse_particles;
use super::run::parse_threads;
use super::values::{choice, whole};
use super::{BENCH_ALLOW_SLOW_HELP, Failure, check_all_pairs};
use crate::process::progress::Progress;
use crate::process::reader_watch::ReaderWatch;
use crate::scene::bench::{
    BENCH_DT, BenchStart, bench_support_margin, settled_pairs_per_sphere, settled_pairs_within,
};
use crate::scene::memory::{
    Available, BYTES_PER_SPHERE, available_memory_for, first_step_bytes, memory_size,
};
use crate::scene::rules::{MAX_BODIES, MAX_STEPS};
use crate::sim::sleep::TIME_TO_SLEEP;
use crate::sim::threads::{ThreadPool, thread_pool};
use crate::sim::{BroadPhase, Stage, StageSeconds};
use clap::{Args, ValueEnum};
use serde::Serialize;
use std::io::{BufWriter, Write};
use std::time::Instant;

/// The benchmark scene, kept here too for the code that finds it at this
/// path (the visualiser's tests).
pub use crate::scene::bench::{
    BENCH_SEED, SOLID_FRACTION, bench_radius, bench_world, bench_world_from,
};

/// Smallest and largest sizes of a sweep.
pub(crate) const SWEEP_MIN: usize = 100;
pub(crate) const SWEEP_MAX: usize = 1_000_000;
/// Timed steps per run unless `--steps` says otherwise.
pub(crate) const DEFAULT_STEPS: u64 = 20;
/// A sweep repeats a run of a small size until it has timed this long, s.
const SWEEP_MIN_SECONDS: f64 = 0.3;
const SWEEP_MAX_REPEATS: u32 = 100;
/// A sweep skips all-pairs where a run would make more pair tests than this
/// (about half a minute of testing on one core).
pub(crate) const SWEEP_ALL_PAIRS_MAX_TESTS: u64 = 20_000_000_000;

/// Spheres the simulation benchmark steps unless `--particles` says.
pub(crate) const DEFAULT_PARTICLES: usize = 100_000;
/// Spheres `--render` draws unless `--particles` says.
#[cfg(feature = "tui")]
pub(crate) const DEFAULT_RENDER_PARTICLES: usize = 10_000;

#[derive(Args, Debug, Clone)]
pub struct BenchArgs {
    /// Number of spheres (default: 100,000 stepped; 10,000 drawn with
    /// --render).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = parse_particles)]
    pub particles: Option<usize>,
    /// Timed steps, after the untimed ones (with them, at most 10^12).
    #[arg(long, value_name = "K", default_value_t = DEFAULT_STEPS, allow_negative_numbers = true,
          value_parser = whole::<u64>(1, MAX_STEPS - 1), conflicts_with = "render")]
    pub steps: u64,
    /// The state the steps start from (--sweep runs both); with --render,
    /// the gravity lesson (dilute) or the benchmark's pile (settled).
    #[arg(long, value_name = "STATE", value_parser = choice::<BenchStart>(),
          default_value = "dilute", conflicts_with = "sweep")]
    pub start: BenchStart,
    /// Untimed steps before the timed ones, besides the first, which sizes
    /// the buffers.
    #[arg(long, value_name = "K", default_value_t = 0, allow_negative_numbers = true,
          value_parser = whole::<u64>(0, MAX_STEPS - 2), conflicts_with = "render")]
    pub warmup: u64,
    /// Threads to simulate on (default: one per core).
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = parse_threads,
          conflicts_with = "render")]
    pub threads: Option<usize>,
    /// Which pairs are tested for contact.
    #[arg(long, value_name = "METHOD", value_parser = choice::<BroadPhase>(),
          default_value = "auto", conflicts_with_all = ["sweep", "render"])]
    pub broadphase: BroadPhase,
    /// Step with the support pass: resting contacts solved together.
    #[arg(long, conflicts_with = "render")]
    pub support: bool,
    /// Keep every sphere awake: no sleeping (spheres at rest for half a
    /// second otherwise sleep until disturbed, and a pile all asleep costs
    /// nothing), so that a
    /// pile at rest is solved every step.
    #[arg(long, conflicts_with = "render")]
    pub awake: bool,
    /// Refused: bench sleeps spheres unless --awake (`run` and the
    /// visualiser take --sleep; here it would change nothing).
    #[arg(long, hide = true)]
    pub sleep: bool,
    /// Keep the list of each step's contacts, as the visualiser does while
    /// it marks contacts or a sphere is picked. A world of 4,096 spheres or
    /// more finds and resolves its contacts in one sweep
    /// (`narrow_and_solve`), with the same bits as the narrow phase then
    /// the contact solve, in every step where the support pass does not
    /// read them and no sphere sleeps; with this flag (or in a step that
    /// may put spheres to sleep) the sweep also writes each contact to the
    /// list, and the first such step runs the two stages to size it.
    #[arg(long, conflicts_with = "render")]
    pub keep_contacts: bool,
    /// Output format of the simulation benchmark (--render prints text).
    #[arg(long, value_enum, default_value_t = BenchFormat::Text, conflicts_with = "render")]
    pub format: BenchFormat,
    /// Run N = 100 ... 1,000,000 (log spaced) from the dilute start for each
    /// broad phase and from the settled start with auto, and print a scaling
    /// table.
    #[arg(long, conflicts_with_all = ["particles", "render"])]
    pub sweep: bool,
    /// Largest size a sweep runs (at least 100) [default: 1000000]
    // No clap default: without --sweep, `bench` refuses one given.
    #[arg(long, value_name = "N", allow_negative_numbers = true,
          value_parser = whole::<usize>(SWEEP_MIN as u64, MAX_BODIES as u64))]
    pub sweep_max: Option<usize>,
    #[arg(long, help = BENCH_ALLOW_SLOW_HELP, conflicts_with_all = ["sweep", "render"])]
    pub allow_slow: bool,
    /// Time drawing frames of the visualiser into an off-screen buffer
    /// instead, as text (with --particles, --start, --width, --height and
    /// --frames only).
    #[arg(long)]
    pub render: bool,
    /// Buffer width, cells (--render) [default: 200]
    // No clap default: without --render, `bench` refuses one given.
    #[arg(long, allow_negative_numbers = true,
          value_parser = whole::<u16>(1, 1000))]
    pub width: Option<u16>,
    /// Buffer height, cells (--render) [default: 60]
    #[arg(long, allow_negative_numbers = true,
          value_parser = whole::<u16>(1, 1000))]
    pub height: Option<u16>,
    /// Frames to draw (--render) [default: 100]
    #[arg(long, allow_negative_numbers = true,
          value_parser = whole::<u64>(1, 100_000))]
    pub frames: Option<u64>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BenchFormat {
    Json,
    Text,
}

/// What one benchmark run steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Plan {
    pub particles: usize,
    pub start: BenchStart,
    /// Untimed steps after the first.
    pub warmup: u64,
    /// Timed steps.
    pub steps: u64,
    pub broad_phase: BroadPhase,
    /// The support pass on.
    pub support: bool,
    /// Sleeping off.
    pub awake: bool,
    /// The list of contacts kept every step.
    pub keep_contacts: bool,
}

impl Plan {
    /// Steps a run takes: the first, the warm-up and the timed ones.
    pub(crate) fn total_steps(&self) -> u64 {
        1 + self.warmup + self.steps
    }

    /// Whether some step of the run may list its contacts: kept, or read
    /// by the support pass, or by sleeping once a sphere can have rested
    /// for [`TIME_TO_SLEEP`] (from the start every sphere has rested for
    /// none; a step short, for the rounding of the sum).
    pub(crate) fn may_list_contacts(&self) -> bool {
        self.keep_contacts
            || self.support
            || (!self.awake && self.total_steps() >= steps_to_sleep())
    }
}

/// Steps in all (the first, untimed, included) from which a sphere at rest
/// since the start may fall asleep (see [`Plan::may_list_contacts`]).
fn steps_to_sleep() -> u64 {
    (f64::from(TIME_TO_SLEEP) / BENCH_DT).floor() as u64 - 1
}

/// One benchmark run. Names are stable: scripts read them.
#[derive(Clone, Debug, Serialize)]
pub(crate) struct BenchResult {
    pub particles: usize,
    /// The state the run started from: `dilute` or `settled`.
    pub start: BenchStart,
    /// Untimed steps before the timed ones, besides the first (which sizes
    /// the buffers).
    pub warmup: u64,
    /// Timed steps per run.
    pub steps: u64,
    /// Whether the support pass ran.
    pub support: bool,
    /// Whether every sphere was kept awake (`--awake`: no sleeping).
    pub awake: bool,
    /// Whether the list of contacts was kept every step (`--keep-contacts`).
    pub keep_contacts: bool,
    /// Runs timed (a sweep repeats small sizes; otherwise 1).
    pub runs: u32,
    pub threads: usize,
    /// The broad phase that ran (`auto` resolved).
    pub broadphase: &'static str,
    /// The broad phase asked for.
    pub broadphase_requested: &'static str,
    /// Sphere radius, m.
    pub radius: f64,
    /// Wall-clock time of the timed steps of all runs, s.
    pub seconds: f64,
    pub seconds_per_step: f64,
    pub sphere_steps_per_s: f64,
    pub ns_per_sphere_step: f64,
    pub pair_tests_per_step: f64,
    pub contacts_per_step: f64,
    /// Contact pairs (overlapping pairs found) per sphere, the mean over the
    /// timed steps.
    pub contacts_per_sphere: f64,
    /// Spheres the support pass's sweeps left unsettled, per timed step
    /// (0 without `--support`; `StepStats::support_unsettled`).
    pub support_unsettled_per_step: f64,
    /// Spheres asleep after a timed step, the mean (0 with `--awake`).
    pub asleep_per_step: f64,
    /// Seconds of the timed steps spent in each stage of the step (all
    /// runs; `sim::Stage`).
    pub stage_seconds: StageSeconds,
    /// Peak resident memory of the process (VmHWM), bytes; null where the
    /// system does not report it.
    pub peak_rss_bytes: Option<u64>,
    pub peak_rss_bytes_per_sphere: Option<f64>,
    /// XXH3 of the final state (the same for any number of threads).
    pub state_hash: String,
}

/// Memory the settled start of `n` spheres needs, bytes: each sphere's
/// share, and its contact list from the first step, with the quarter more
/// room the grid leaves for the next (at N = 10^6 this is 1,450 bytes a
/// sphere; the peak resident memory measured, 1,448).
pub(crate) fn settled_memory_bytes(n: usize) -> f64 {
    let pairs = (n as f64 * settled_pairs_per_sphere(n)).ceil() as u64;
    first_step_bytes(n as u64, pairs)
}

/// Bytes a pair within the support pass's margin takes: its place in the
/// list with the grid's room, its row and the sweeps' copy of it, its
/// carried impulse and the pass's working memory. Measured: the peak
/// resident memory of `bench --start settled --support --steps 1` less
/// [`BYTES_PER_SPHERE`] a sphere, over the pairs [`settled_pairs_within`]
/// gives, was 230, 231 and 229 bytes at 100,000, 300,000 and 1,000,000
/// spheres (7,091 to 16,508 bytes a sphere).
const SUPPORT_BYTES_PER_PAIR: f64 = 260.0;

/// The pairs per sphere within the support pass's margin in the settled
/// start of `n` spheres.
fn settled_support_pairs_per_sphere(n: usize) -> f64 {
    settled_pairs_within(n, 2.0 * bench_radius(n) + bench_support_margin(n))
}

/// Memory the settled start of `n` spheres needs with the support pass,
/// bytes.
pub(crate) fn settled_support_memory_bytes(n: usize) -> f64 {
    n as f64 * (BYTES_PER_SPHERE + SUPPORT_BYTES_PER_PAIR * settled_support_pairs_per_sphere(n))
}

/// Steps after which the dilute start has fallen into a pile as dense as
/// the settled start's: a second of falling (a sphere spawned at the top
/// of the box reaches the floor in under half of one).
const STEPS_TO_PILE: u64 = 60;

/// Refuse plans that need more memory than `available` (bytes; `None`:
/// not known, nothing is refused). A run that reaches a pile (the settled
/// start, or the dilute one after [`STEPS_TO_PILE`] steps) and may list its
/// contacts ([`Plan::may_list_contacts`]) needs the dense layer's list,
/// which grows as `N^(4/3)`: 10^7 spheres then need about 28 GB; with the
/// support pass, the pairs within its margin and their rows as well.
fn check_memory(plans: &[Plan], available: Option<Available>) -> Result<(), Failure> {
    let Some(available) = available else {
        return Ok(());
    };
    for plan in plans {
        let piled = plan.start == BenchStart::Settled || plan.total_steps() >= STEPS_TO_PILE;
        let n = plan.particles;
        // How the pile is reached, and the way round it other than fewer
        // spheres and no list: the dilute start, or for that start fewer
        // steps, before its spheres have landed.
        let (pile, sooner) = match plan.start {
            BenchStart::Settled => (
                format!("the settled start of {} has", crate::scene::spheres(n)),
                "the dilute start".to_string(),
            ),
            BenchStart::Dilute => (
                format!("the pile {} fall into has", crate::scene::spheres(n)),
                format!(
                    "--steps and --warmup adding up to under {} (the spheres still falling)",
                    STEPS_TO_PILE - 1
                ),
            ),
        };
        // Only the contact list has other ways out than fewer spheres.
        let (need, what, or) = if piled && plan.support {
            (
                settled_support_memory_bytes(n),
                format!(
                    "{pile} about {:.0} pairs per sphere within the support pass's \
                     margin; with them it needs",
                    settled_support_pairs_per_sphere(n),
                ),
                format!(", {sooner}, or a run without --support"),
            )
        } else if piled && plan.may_list_contacts() {
            (
                settled_memory_bytes(n),
                format!(
                    "{pile} about {:.0} overlapping pairs per sphere; with them it needs",
                    settled_pairs_per_sphere(n),
                ),
                format!(
                    ", {sooner}, or a run that lists no contacts (--awake, or --steps and \
                     --warmup adding up to under {}, without --support or --keep-contacts)",
                    steps_to_sleep() - 1
                ),
            )
        } else {
            (
                n as f64 * BYTES_PER_SPHERE,
                format!(
                    "{} {}",
                    crate::scene::spheres(n),
                    if n == 1 { "needs" } else { "need" }
                ),
                String::new(),
            )
        };
        if !available.fits(need) {
            return Err(Failure::Runtime(format!(
                "{what} about {} of memory, and {available}. {}",
                memory_size(need),
                available.way_out(need, &format!("Use fewer spheres{or}")),
            )));
        }
    }
    Ok(())
}

/// An average over steps: whole from 1,000 up, else to three figures
/// (0.4 contacts a step reads 0.400, not 0).
fn average(x: f64) -> String {
    if x.fract() == 0.0 || x.abs() >= 1e3 || !x.is_finite() {
        format!("{x:.0}")
    } else {
        super::run::to_figures(x, 3)
    }
}

/// Peak resident memory of this process, bytes (Linux: VmHWM).
pub(crate) fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Reset the peak to the current resident memory (Linux 4.0+); false when
/// the system does not allow it.
pub(crate) fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Build the scene, take the untimed steps, time the plan's steps; repeat
/// the whole run until `min_seconds` have been timed (at most `max_runs`).
/// `progress` hears of every step. `None` when `gone` (asked after every
/// step: the reader of the output has left) stopped it.
pub(crate) fn measure(
    pool: &ThreadPool,
    plan: Plan,
    (min_seconds, max_runs): (f64, u32),
    progress: &Progress,
    gone: &(dyn Fn() -> bool + Sync),
) -> Option<BenchResult> {
    let Plan {
        particles: n,
        start,
        warmup,
        steps,
        broad_phase,
        support,
        awake,
        keep_contacts,
    } = plan;
    let (mut seconds, mut tests, mut contacts, mut runs) = (0.0, 0u64, 0u64, 0u32);
    let (mut unsettled, mut asleep) = (0u64, 0u64);
    let mut stages = StageSeconds::default();
    let mut hash = 0;
    let mut peak = None;
    while runs == 0 || (seconds < min_seconds && runs < max_runs) {
        reset_peak_rss();
        let mut world = bench_world_from(start, n, broad_phase);
        world.config.support = support;
        world.config.sleep = !awake;
        // Nothing here reads the list of contacts (only their count)
        // unless asked to keep it.
        world.keep_contacts(keep_contacts);
        let finished = pool.install(|| {
            for _ in 0..1 + warmup {
                world.step();
                progress.inc(1);
                if gone() {
                    return false;
                }
            }
            world.time_stages(true);
            let start = Instant::now();
            for _ in 0..steps {
                world.step();
                progress.inc(1);
                tests += world.last.pair_tests;
                contacts += world.last.contacts as u64;
                unsettled += world.last.support_unsettled as u64;
                asleep += world.last.asleep as u64;
                if gone() {
                    return false;
                }
            }
            seconds += start.elapsed().as_secs_f64();
            true
        });
        if !finished {
            return None;
        }
        stages.add(world.stage_seconds().unwrap_or_default());
        hash = world.state_hash();
        peak = peak.max(peak_rss_bytes());
        runs += 1;
    }
    let sphere_steps = (n as u64 * steps * runs as u64) as f64;
    let total_steps = (steps * runs as u64) as f64;
    Some(BenchResult {
        particles: n,
        start,
        warmup,
        steps,
        support,
        awake,
        keep_contacts,
        runs,
        threads: pool.current_num_threads(),
        broadphase: broad_phase.resolve(n).name(),
        broadphase_requested: broad_phase.name(),
        radius: bench_radius(n),
        seconds,
        stage_seconds: stages,
        seconds_per_step: seconds / total_steps,
        sphere_steps_per_s: sphere_steps / seconds,
        ns_per_sphere_step: seconds * 1e9 / sphere_steps,
        pair_tests_per_step: tests as f64 / total_steps,
        contacts_per_step: contacts as f64 / total_steps,
        contacts_per_sphere: contacts as f64 / total_steps / n as f64,
        support_unsettled_per_step: unsettled as f64 / total_steps,
        asleep_per_step: asleep as f64 / total_steps,
        peak_rss_bytes: peak,
        peak_rss_bytes_per_sphere: peak.map(|b| b as f64 / n as f64),
        state_hash: format!("{hash:016x}"),
    })
}

/// The sizes of a sweep: half-decades from [`SWEEP_MIN`] to `max`.
pub(crate) fn sweep_sizes(max: usize) -> Vec<usize> {
    (0..)
        .map(|k| (SWEEP_MIN as f64 * 10f64.powf(k as f64 / 2.0)).round() as usize)
        .take_while(|&n| n <= max)
        .collect()
}

/// A sweep: every size, every broad phase from the dilute start and `auto`
/// from the settled start, and what it found.
#[derive(Debug, Serialize)]
pub(crate) struct Sweep {
    pub results: Vec<BenchResult>,
    /// Sizes where all-pairs was not run, and why.
    pub all_pairs_skipped_above: Option<usize>,
    /// The smallest size where the grid stepped faster than all-pairs.
    pub crossover_particles: Option<usize>,
    /// Grid time per step at 1,000,000 spheres over that at 100,000 (the
    /// dilute start).
    pub grid_time_ratio_1m_100k: Option<f64>,
    /// The sweep's largest size.
    pub largest_particles: Option<usize>,
    /// Time per step from the settled start over that from the dilute
    /// start, with `auto`, at the largest size.
    pub settled_time_ratio: Option<f64>,
}

/// Whether a sweep runs all-pairs for `n` spheres and `steps` steps in all.
fn sweep_runs_all_pairs(n: usize, steps: u64) -> bool {
    let tests = crate::sim::broad_phase::all_pairs_tests(n).saturating_mul(steps);
    tests <= SWEEP_ALL_PAIRS_MAX_TESTS
}

/// The runs of a sweep up to `max` spheres, in order: at each size every
/// broad phase from the dilute start (all-pairs only within
/// [`SWEEP_ALL_PAIRS_MAX_TESTS`]), then `auto` from the settled start.
/// Returns the plans and the smallest size where all-pairs was left out.
fn sweep_plans(
    max: usize,
    warmup: u64,
    steps: u64,
    (support, awake, keep_contacts): (bool, bool, bool),
) -> (Vec<Plan>, Option<usize>) {
    let mut plans = Vec::new();
    let mut skipped = None;
    for n in sweep_sizes(max) {
        let plan = |start, broad_phase| Plan {
            particles: n,
            start,
            warmup,
            steps,
            broad_phase,
            support,
            awake,
            keep_contacts,
        };
        for bp in BroadPhase::ALL {
            let p = plan(BenchStart::Dilute, bp);
            if bp == BroadPhase::AllPairs && !sweep_runs_all_pairs(n, p.total_steps()) {
                skipped.get_or_insert(n);
                continue;
            }
            plans.push(p);
        }
        plans.push(plan(BenchStart::Settled, BroadPhase::Auto));
    }
    (plans, skipped)
}

/// `None` when `gone` stopped a run (see [`measure`]).
fn sweep(
    pool: &ThreadPool,
    args: &BenchArgs,
    mut progress: impl FnMut(&BenchResult),
    gone: &(dyn Fn() -> bool + Sync),
) -> Option<Sweep> {
    let mut results = Vec::new();
    let (plans, skipped) = sweep_plans(
        args.sweep_max.unwrap_or(SWEEP_MAX),
        args.warmup,
        args.steps,
        (args.support, args.awake, args.keep_contacts),
    );
    let bar = Progress::bar_cleared_on_signals(plans.len() as u64, "bench --sweep");
    for plan in plans {
        bar.message(format!(
            "N = {}, {}, {}",
            plan.particles,
            plan.start.name(),
            plan.broad_phase.name()
        ));
        let r = measure(
            pool,
            plan,
            (SWEEP_MIN_SECONDS, SWEEP_MAX_REPEATS),
            &Progress::hidden(),
            gone,
        )?;
        bar.inc(1);
        progress(&r);
        results.push(r);
    }
    bar.finish();
    let time_from = |start: BenchStart, n: usize, bp: BroadPhase| {
        results
            .iter()
            .find(|r| r.start == start && r.particles == n && r.broadphase_requested == bp.name())
            .map(|r| r.seconds_per_step)
    };
    let time = |n, bp| time_from(BenchStart::Dilute, n, bp);
    let crossover = sweep_sizes(args.sweep_max.unwrap_or(SWEEP_MAX))
        .into_iter()
        .find(|&n| {
            matches!((time(n, BroadPhase::Grid), time(n, BroadPhase::AllPairs)),
                 (Some(g), Some(a)) if g < a)
        });
    let ratio = match (
        time(1_000_000, BroadPhase::Grid),
        time(100_000, BroadPhase::Grid),
    ) {
        (Some(a), Some(b)) => Some(a / b),
        _ => None,
    };
    let largest = sweep_sizes(args.sweep_max.unwrap_or(SWEEP_MAX))
        .last()
        .copied();
    let settled_ratio = largest.and_then(|n| {
        let settled = time_from(BenchStart::Settled, n, BroadPhase::Auto)?;
        Some(settled / time(n, BroadPhase::Auto)?)
    });
    Some(Sweep {
        results,
        all_pairs_skipped_above: skipped,
        crossover_particles: crossover,
        grid_time_ratio_1m_100k: ratio,
        largest_particles: largest,
        settled_time_ratio: settled_ratio,
    })
}

/// Refuse runs of more than [`MAX_STEPS`] steps in all (the first untimed
/// step, `--warmup` and `--steps`), as `lerpit run` refuses them.
fn check_step_limit(args: &BenchArgs) -> Result<(), Failure> {
    let total = 1u128 + u128::from(args.warmup) + u128::from(args.steps);
    if total <= u128::from(MAX_STEPS) {
        return Ok(());
    }
    Err(Failure::Usage(format!(
        "--warmup {} and --steps {} make {total} steps with the first untimed one; \
         at most {MAX_STEPS} are allowed",
        args.warmup, args.steps
    )))
}

pub fn bench(args: &BenchArgs) -> Result<(), Failure> {
    if args.sleep {
        return Err(Failure::Usage(
            "--sleep would change nothing: bench sleeps spheres unless --awake keeps them awake"
                .into(),
        ));
    }
    if args.sweep_max.is_some() && !args.sweep {
        return Err(Failure::Usage(
            "--sweep-max sizes the largest run of --sweep; add --sweep, or leave --sweep-max out"
                .into(),
        ));
    }
    if args.render {
        return render(args);
    }
    // (clap's `requires` cannot see that a flag such as --render is
    // absent: it counts its default.)
    let drawing = [
        ("--width", args.width.is_some()),
        ("--height", args.height.is_some()),
        ("--frames", args.frames.is_some()),
    ];
    if let Some((flag, _)) = drawing.iter().find(|(_, given)| *given) {
        return Err(Failure::Usage(format!(
            "{flag} sizes the drawing that --render times; add --render, or leave {flag} out"
        )));
    }
    check_step_limit(args)?;
    let threads = args
        .threads
        .unwrap_or_else(crate::sim::threads::available_threads);
    crate::scene::memory::check_threads(threads).map_err(Failure::Runtime)?;
    let plan = Plan {
        particles: args.particles.unwrap_or(DEFAULT_PARTICLES),
        start: args.start,
        warmup: args.warmup,
        steps: args.steps,
        broad_phase: args.broadphase,
        support: args.support,
        awake: args.awake,
        keep_contacts: args.keep_contacts,
    };
    if args.sweep {
        let (plans, _) = sweep_plans(
            args.sweep_max.unwrap_or(SWEEP_MAX),
            args.warmup,
            args.steps,
            (args.support, args.awake, args.keep_contacts),
        );
        check_memory(&plans, available_memory_for(threads))?;
    } else {
        check_all_pairs(
            args.broadphase,
            true,
            plan.particles,
            args.allow_slow,
            "--broadphase all-pairs",
        )?;
        check_memory(&[plan], available_memory_for(threads))?;
    }
    let pool = thread_pool(args.threads).map_err(Failure::Runtime)?;
    // A benchmark whose reader has left (`bench --steps 1e9 | head -1`)
    // stops after the step it is in, as `run` does.
    let watch = ReaderWatch::start();
    let gone = || watch.gone();
    let out = std::io::stdout();
    let mut out = BufWriter::new(out.lock());
    if args.sweep {
        let text = args.format == BenchFormat::Text;
        if text {
            writeln!(out, "{}", TABLE_HEADER)?;
            out.flush()?;
        }
        let mut failed = None;
        let s = sweep(
            &pool,
            args,
            |r| {
                if text {
                    let row = writeln!(out, "{}", table_row(r)).and_then(|_| out.flush());
                    failed = failed.take().or(row.err());
                }
            },
            &gone,
        );
        if let Some(e) = failed {
            return Err(e.into());
        }
        let s = s.ok_or_else(reader_left)?;
        match args.format {
            BenchFormat::Text => write_sweep_summary(&mut out, &s)?,
            BenchFormat::Json => write_json(&mut out, &s)?,
        }
    } else {
        let bar = Progress::bar_cleared_on_signals(plan.total_steps(), "bench");
        let untimed = 1 + plan.warmup;
        bar.message(format!(
            "{}, {} start, {} ({untimed} untimed step{})",
            crate::scene::spheres(plan.particles),
            plan.start.name(),
            plan.broad_phase.name(),
            if untimed == 1 { "" } else { "s" }
        ));
        let r = measure(&pool, plan, (0.0, 1), &bar, &gone).ok_or_else(reader_left)?;
        bar.finish();
        match args.format {
            BenchFormat::Text => write_text(&mut out, &r)?,
            BenchFormat::Json => write_json(&mut out, &r)?,
        }
    }
    out.flush()?;
    Ok(())
}

/// What a benchmark stopped by [`ReaderWatch`] ends with: a closed pipe,
/// status 0.
fn reader_left() -> Failure {
    Failure::Output(std::io::ErrorKind::BrokenPipe.into())
}

/// Bytes a sphere takes in the frame the visualiser draws from (its copy
/// of the world's bodies: centres, velocities, radii, ids, rest).
#[cfg(feature = "tui")]
const RENDER_FRAME_BYTES_PER_SPHERE: f64 = 80.0;

#[cfg(feature = "tui")]
fn render(args: &BenchArgs) -> Result<(), Failure> {
    use crate::tui::render_bench::RenderBench;
    let bench = RenderBench {
        particles: args.particles.unwrap_or(DEFAULT_RENDER_PARTICLES),
        width: args.width.unwrap_or(200),
        height: args.height.unwrap_or(60),
        frames: args.frames.unwrap_or(100) as usize,
        start: args.start,
    };
    // The visualiser holds, besides the world, a frame's copy of the
    // spheres and its history of the steps taken, up to its budget:
    // unchecked, 6 million spheres under a 2 GB limit passed the world's
    // check and then aborted.
    // The settled pile's first step holds its overlapping pairs too, as
    // the simulation benchmark's does: refused here, before the pile is
    // built (which took 37 s for 10^7 spheres before the world refused it).
    let n = bench.particles as f64;
    let (world, what, way_out) = match bench.start {
        BenchStart::Dilute => (
            n * BYTES_PER_SPHERE,
            crate::scene::spheres(bench.particles),
            "Use fewer spheres",
        ),
        BenchStart::Settled => (
            settled_memory_bytes(bench.particles),
            format!(
                "the settled pile of {} (its first step holds about {} overlapping pairs)",
                crate::scene::spheres(bench.particles),
                crate::scene::thousands(
                    (n * settled_pairs_per_sphere(bench.particles)).ceil() as u64
                )
            ),
            "Use fewer spheres, or the dilute start",
        ),
    };
    let need = world
        + n * RENDER_FRAME_BYTES_PER_SPHERE
        + crate::tui::history::bytes_after(bench.particles, bench.frames) as f64;
    if let Some(available) = available_memory_for(crate::sim::threads::available_threads())
        && !available.fits(need)
    {
        return Err(Failure::Runtime(format!(
            "drawing {what} needs about {} of memory, and {available}. {}",
            memory_size(need),
            available.way_out(need, way_out),
        )));
    }
    // The lesson is built in; what can fail in building it is its size.
    let building = crate::process::progress::building(
        "bench --render",
        bench.particles,
        crate::process::progress::Clearing::ForGood,
    );
    let app = bench.app().map_err(Failure::Runtime)?;
    drop(building);
    let bar = Progress::bar_cleared_on_signals(bench.frames as u64, "bench --render");
    bar.message(format!(
        "drawing {} at {}x{}",
        crate::scene::spheres(bench.particles),
        bench.width,
        bench.height
    ));
    let figures = bench.draw(app, || bar.inc(1));
    bar.finish();
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

fn write_json(out: &mut impl Write, value: &impl Serialize) -> Result<(), Failure> {
    serde_json::to_writer_pretty(&mut *out, value)?;
    writeln!(out)?;
    Ok(())
}

fn rss_per_sphere(r: &BenchResult) -> String {
    r.peak_rss_bytes_per_sphere
        .map_or_else(|| "n/a".to_string(), |b| format!("{b:.0}"))
}

/// The broad phase of a run: `grid`, or `auto (grid)` when resolved.
fn broad_phase_label(r: &BenchResult) -> String {
    if r.broadphase == r.broadphase_requested {
        r.broadphase.to_string()
    } else {
        format!("{} ({})", r.broadphase_requested, r.broadphase)
    }
}

fn write_text(out: &mut impl Write, r: &BenchResult) -> std::io::Result<()> {
    let broad = broad_phase_label(r);
    writeln!(out, "particles            {}", r.particles)?;
    writeln!(out, "start                {}", r.start)?;
    writeln!(out, "radius               {:.6e} m", r.radius)?;
    writeln!(
        out,
        "steps                {} (after {} untimed: 1 + --warmup {})",
        r.steps,
        1 + r.warmup,
        r.warmup
    )?;
    writeln!(out, "threads              {}", r.threads)?;
    if r.support {
        writeln!(out, "support pass         on")?;
        if r.start == BenchStart::Settled {
            writeln!(
                out,
                "                     (from the settled start: the denser layer of one pass a step;\n\
                 \x20                     --start dilute --warmup 600 times the pass's own pile)"
            )?;
        }
    }
    if r.keep_contacts {
        writeln!(out, "contact list         kept (--keep-contacts)")?;
    }
    if r.awake {
        writeln!(out, "sleeping             off (--awake)")?;
    } else {
        let asleep = average(r.asleep_per_step);
        let word = if asleep == "1" { "sphere" } else { "spheres" };
        writeln!(
            out,
            "sleeping             on: {asleep} {word} asleep a step (--awake: none)"
        )?;
    }
    writeln!(out, "broad phase          {broad}")?;
    let seconds = if r.seconds >= 1e-3 {
        format!("{:.6}", r.seconds)
    } else {
        format!("{:.6e}", r.seconds)
    };
    writeln!(out, "seconds              {seconds}")?;
    writeln!(out, "seconds per step     {:.6e}", r.seconds_per_step)?;
    writeln!(out, "sphere-steps per s   {:.4e}", r.sphere_steps_per_s)?;
    writeln!(out, "ns per sphere-step   {:.2}", r.ns_per_sphere_step)?;
    writeln!(
        out,
        "pair tests per step  {}",
        average(r.pair_tests_per_step)
    )?;
    writeln!(out, "contacts per step    {}", average(r.contacts_per_step))?;
    writeln!(out, "contacts per sphere  {:.3}", r.contacts_per_sphere)?;
    if r.support {
        writeln!(
            out,
            "support unsettled    {} a step (sweeps ran out, short of their target by > 1% of a radius)",
            average(r.support_unsettled_per_step)
        )?;
    }
    let stages = r.stage_seconds;
    let total = stages.total().max(f64::MIN_POSITIVE);
    let per_step = 1e3 / (r.steps * u64::from(r.runs)).max(1) as f64;
    for &stage in <Stage as strum::VariantArray>::VARIANTS {
        let t = stages.get(stage);
        if t > 0.0 {
            let ms = t * per_step;
            let ms = if ms >= 1e-2 {
                format!("{ms:.4}")
            } else {
                format!("{ms:.2e}")
            };
            writeln!(
                out,
                "  {:<18} {ms} ms a step ({:.0}%)",
                stage.name(),
                100.0 * t / total
            )?;
        }
    }
    match r.peak_rss_bytes {
        Some(b) => writeln!(
            out,
            "peak RSS             {b} bytes ({} per sphere)",
            rss_per_sphere(r)
        )?,
        None => writeln!(out, "peak RSS             not reported by this system")?,
    }
    writeln!(out, "state hash           {}", r.state_hash)?;
    Ok(())
}

const TABLE_HEADER: &str = "        N  start    broad phase        steps x runs    ms/step  \
sphere-steps/s  ns/sphere-step  pair tests/step  contacts/sphere  peak RSS B/sphere";

fn table_row(r: &BenchResult) -> String {
    format!(
        "{:>9}  {:<8} {:<17} {:>6} x {:<4} {:>10.4}  {:>14.4e}  {:>14.2}  {:>15.0}  {:>15.3}  {:>17}",
        r.particles,
        r.start.name(),
        broad_phase_label(r),
        r.steps,
        r.runs,
        r.seconds_per_step * 1e3,
        r.sphere_steps_per_s,
        r.ns_per_sphere_step,
        r.pair_tests_per_step,
        r.contacts_per_sphere,
        rss_per_sphere(r)
    )
}

fn write_sweep_summary(out: &mut impl Write, s: &Sweep) -> std::io::Result<()> {
    writeln!(out)?;
    if let Some(n) = s.all_pairs_skipped_above {
        writeln!(
            out,
            "all-pairs not run from N = {n} up: a run would make more than {:.0e} pair tests",
            SWEEP_ALL_PAIRS_MAX_TESTS as f64
        )?;
    }
    match s.crossover_particles {
        Some(n) => writeln!(
            out,
            "crossover: the grid is faster than all-pairs from N = {n} of this sweep \
             (auto switches at {})",
            crate::sim::broad_phase::AUTO_GRID_MIN_BODIES
        )?,
        None => writeln!(
            out,
            "crossover: all-pairs was faster at every size both ran"
        )?,
    }
    if let Some(ratio) = s.grid_time_ratio_1m_100k {
        writeln!(
            out,
            "grid time per step, N = 1,000,000 over N = 100,000: {ratio:.2} (linear: 10)"
        )?;
    }
    if let (Some(n), Some(ratio)) = (s.largest_particles, s.settled_time_ratio) {
        writeln!(
            out,
            "auto time per step at N = {n}, settled start over dilute start: {ratio:.2}"
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(particles: usize, start: BenchStart) -> Plan {
        Plan {
            particles,
            start,
            warmup: 0,
            steps: DEFAULT_STEPS,
            broad_phase: BroadPhase::Auto,
            support: false,
            awake: false,
            keep_contacts: false,
        }
    }

    #[test]
    fn a_settled_start_beyond_the_memory_available_is_refused_before_it_runs() {
        let gb = 1_000_000_000;
        let free = |bytes: u64| {
            Some(Available {
                bytes,
                what: "the system's available memory",
                reserved: None,
            })
        };
        // Listing its contacts, the dense layer needs them in memory.
        let big = Plan {
            keep_contacts: true,
            ..plan(10_000_000, BenchStart::Settled)
        };
        let e = check_memory(&[big], free(16 * gb)).unwrap_err();
        assert_eq!(e.status(), 1);
        let message = e.to_string();
        for needle in [
            "settled start of 10,000,000 spheres",
            "about 51 overlapping pairs per sphere",
            "about 28.3 GB of memory",
            "16.0 GB are available (the system's available memory)",
            "fewer spheres, the dilute start, or a run that lists no contacts",
        ] {
            assert!(message.contains(needle), "lacks {needle:?}: {message}");
        }
        assert!(check_memory(&[big], free(32 * gb)).is_ok());
        assert!(check_memory(&[big], None).is_ok());
        // The dilute start: its spheres alone, 256 bytes each.
        let dilute = plan(10_000_000, BenchStart::Dilute);
        assert!(check_memory(&[dilute], free(3 * gb)).is_ok());
        let e = check_memory(&[dilute], free(2 * gb))
            .unwrap_err()
            .to_string();
        assert!(e.contains("10,000,000 spheres need about 2.6 GB"), "{e}");
        assert!(check_memory(&[plan(1_000_000, BenchStart::Settled)], free(2 * gb)).is_ok());
        // The support pass lists them, and so does sleeping once a sphere
        // can have rested for half a second (30 steps of 1/60 s); without
        // either the settled start needs what the dilute one does.
        let settled = plan(10_000_000, BenchStart::Settled);
        assert!(check_memory(&[settled], free(3 * gb)).is_ok());
        // Short of that, only fewer spheres help: no other way is offered.
        let e = check_memory(&[settled], free(2 * gb))
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("10,000,000 spheres need about 2.6 GB of memory, and 2.0 GB are available (the system's available memory). Use fewer spheres"), "{e}");
        for listing in [
            Plan {
                support: true,
                ..settled
            },
            Plan {
                warmup: 9,
                ..settled
            },
        ] {
            assert!(
                check_memory(&[listing], free(16 * gb)).is_err(),
                "{listing:?}"
            );
        }
        // With the support pass, the pairs within its margin and their
        // rows: 16,508 bytes a sphere measured at 1,000,000 settled.
        let support = Plan {
            support: true,
            ..plan(1_000_000, BenchStart::Settled)
        };
        let need = settled_support_memory_bytes(1_000_000);
        assert!((16.5e9..20e9).contains(&need), "{need}");
        assert!(check_memory(&[support], free(20 * gb)).is_ok());
        let e = check_memory(&[support], free(16 * gb))
            .unwrap_err()
            .to_string();
        for needle in [
            "settled start of 1,000,000 spheres has about 71 pairs per sphere within the \
             support pass's margin",
            "Use fewer spheres, the dilute start, or a run without --support",
        ] {
            assert!(e.contains(needle), "lacks {needle:?}: {e}");
        }
        // The dilute start falls into that pile within its first second.
        let falling = Plan {
            warmup: 600,
            ..plan(1_000_000, BenchStart::Dilute)
        };
        let e = check_memory(
            &[Plan {
                support: true,
                ..falling
            }],
            free(12 * gb),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("the pile 1,000,000 spheres fall into has"),
            "{e}"
        );
        assert!(
            e.ends_with(
                "Use fewer spheres, --steps and --warmup adding up to under 59 (the spheres \
                 still falling), or a run without --support"
            ),
            "{e}"
        );
        let e = check_memory(
            &[Plan {
                keep_contacts: true,
                ..falling
            }],
            free(gb),
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("overlapping pairs per sphere"), "{e}");
        assert!(
            e.contains("Use fewer spheres, --steps and --warmup adding up to under 59"),
            "{e}"
        );
        assert!(!e.contains("the dilute start"), "{e}");
        let short = Plan {
            support: true,
            ..plan(1_000_000, BenchStart::Dilute)
        };
        assert!(
            check_memory(&[short], free(gb)).is_ok(),
            "20 steps: still in flight"
        );
        let awake = Plan {
            warmup: 600,
            awake: true,
            ..settled
        };
        assert!(check_memory(&[awake], free(3 * gb)).is_ok());
        let (sweep, _) = sweep_plans(10_000_000, 0, 20, (false, false, true));
        assert!(check_memory(&sweep, free(16 * gb)).is_err());
        let (sweep, _) = sweep_plans(10_000_000, 0, 20, (false, false, false));
        assert!(check_memory(&sweep, free(16 * gb)).is_ok());
    }
}
