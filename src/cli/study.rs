//! `lerpit study`: the work-precision sweep, the conservation run and the
//! stability suite, printed as text charts and tables; data as CSV and
//! charts as SVG with `--out DIR`. Progress goes to standard error when it
//! is a terminal.
//!
//! `--out DIR` is checked before the sweep starts: the folder is created if
//! missing and must take a file; a study file already there is not replaced
//! without `--force` (status 2, naming the first). The tables go to standard
//! output before any file is written; each file is written under a
//! temporary name in the folder and renamed into place, so a failure leaves
//! no half-written file and replaces nothing. Without `--out`, a study
//! whose reader has gone ends at once (status 0), not when its tables are
//! done.

use super::{Failure, write_csv};
use crate::process::progress::{Parts, Progress};
use crate::process::reader_watch::ReaderWatch;
use crate::process::unbroken::Unbroken;
use crate::scene::Lesson;
use crate::sim::Integrator;
use crate::study::charts::{
    Series, TextChart, log10, marker, series_by_method, work_precision_series,
};
use crate::study::conservation::{self, Drift};
use crate::study::goals::{
    COST_RATIO_GOAL, ConservationGoal, DIVERGED, GravityGoal, HORIZON_LIMIT, Horizon, NUDGE,
};
use crate::study::metrics::{BOUNCES, Convergence};
use crate::study::stability::{self, Scale};
use crate::study::svg;
use crate::study::sweep::{self, Plan, Row};
use clap::Args;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Args, Debug, Clone)]
pub(crate) struct StudyArgs {
    /// Under a second, and with --stability 10 to 15 s, where the full
    /// study takes 15 to 25 s and with --stability eight to eleven
    /// minutes (release build, 2 cores): fewer and larger time steps,
    /// shorter runs; with --stability, smaller piles and shorter runs.
    #[arg(long)]
    pub quick: bool,
    /// Run the stability suite and print its table instead of the sweep.
    #[arg(long)]
    pub stability: bool,
    /// Write the data (CSV) and the charts (SVG) into this folder, or with
    /// --stability its table (stability.txt); the folder is created if
    /// missing. Study files already there are not replaced without --force.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Replace the study's files already in the --out folder.
    #[arg(long, requires = "out")]
    pub force: bool,
}

/// The files a study writes into `--out`, besides each lesson's charts
/// ([`chart_files`]).
pub(crate) const STABILITY_FILE: &str = "stability.txt";
pub(crate) const SWEEP_FILE: &str = "sweep.csv";
pub(crate) const CONSERVATION_FILE: &str = "conservation.csv";
pub(crate) const CONSERVATION_CHART_FILE: &str = "conservation.svg";

/// A lesson's two charts: work against precision, and error against dt.
pub(crate) fn chart_files(lesson: Lesson) -> [String; 2] {
    [
        format!("work-precision-{lesson}.svg"),
        format!("convergence-{lesson}.svg"),
    ]
}

/// The names of the files a study writes into `--out`.
pub(crate) fn file_names(args: &StudyArgs) -> Vec<String> {
    if args.stability {
        return vec![STABILITY_FILE.into()];
    }
    let mut names: Vec<String> = plan(args.quick)
        .lessons
        .into_iter()
        .flat_map(chart_files)
        .collect();
    names.extend([SWEEP_FILE, CONSERVATION_FILE, CONSERVATION_CHART_FILE].map(String::from));
    names
}

fn plan(quick: bool) -> Plan {
    if quick { Plan::quick() } else { Plan::full() }
}

/// The `--out` folder, checked before the work starts; a missing one is
/// created only when the files are written, so a study stopped part-way
/// leaves no empty folder behind.
pub(crate) struct OutFolder {
    dir: PathBuf,
    force: bool,
}

impl OutFolder {
    /// Check that `dir`, or where it would be created, takes a new file,
    /// and unless `force`, that none of `names` is there already.
    pub(crate) fn prepare(dir: &Path, names: &[String], force: bool) -> Result<Self, Failure> {
        let shown = dir.display();
        // The folder, or its nearest existing ancestor.
        let existing = dir
            .ancestors()
            .find(|a| a.as_os_str().is_empty() || std::fs::metadata(a).is_ok())
            .map(|a| {
                if a.as_os_str().is_empty() {
                    Path::new(".")
                } else {
                    a
                }
            })
            .unwrap_or(Path::new("."));
        // A link that leads nowhere, between the folder and the nearest
        // existing ancestor: creating the folder would fail only after the
        // study's work.
        let dangling = dir
            .ancestors()
            .take_while(|a| *a != existing && !a.as_os_str().is_empty())
            .find(|a| a.symlink_metadata().is_ok());
        if let Some(link) = dangling {
            let target = std::fs::read_link(link)
                .map(|t| format!(" to {}", t.display()))
                .unwrap_or_default();
            let looped =
                std::fs::metadata(link).is_err_and(|e| e.raw_os_error() == Some(libc::ELOOP));
            let why = if looped {
                "that leads back to itself (a loop of links); choose another folder"
            } else {
                "that leads to no folder; create its folder or choose another"
            };
            return Err(Failure::Usage(format!(
                "--out {shown}: {} is a symbolic link{target} {why}",
                link.display()
            )));
        }
        match std::fs::metadata(existing) {
            Ok(m) if !m.is_dir() => {
                let what = if existing == dir {
                    "it is not a folder".to_string()
                } else {
                    format!("{} is not a folder", existing.display())
                };
                return Err(Failure::Usage(format!(
                    "--out {shown}: {what}; name a folder (it is created if missing)"
                )));
            }
            Ok(_) => {}
            Err(e) => {
                return Err(Failure::Runtime(format!(
                    "--out {shown}: cannot read {}: {e}",
                    existing.display()
                )));
            }
        }
        temporary_in(existing)
            .and_then(|probe| probe.close())
            .map_err(|e| {
                let verb = if existing == dir {
                    "write in"
                } else {
                    "create"
                };
                let mut reason = system_reason(&e);
                // The folder is there, yet "no such file" for a new one:
                // a folder of the system's own (/proc) that takes none.
                if existing == dir && e.kind() == std::io::ErrorKind::NotFound {
                    reason = format!("it takes no new files ({reason})");
                }
                Failure::Runtime(format!("--out {shown}: cannot {verb} the folder: {reason}"))
            })?;
        let folder_at = |n: &&String| dir.join(n).metadata().is_ok_and(|m| m.is_dir());
        if let Some(name) = names.iter().find(folder_at) {
            return Err(Failure::Usage(format!(
                "--out {shown}: {} is a folder, where the study writes a file; move it or \
                 choose another folder",
                dir.join(name).display()
            )));
        }
        let present = |n: &&String| dir.join(n).symlink_metadata().is_ok();
        if let Some(name) = names.iter().find(present).filter(|_| !force) {
            return Err(Failure::Usage(format!(
                "--out {shown}: {} is already there and would be replaced; add --force \
                 to replace the study's files, or choose another folder",
                dir.join(name).display()
            )));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            force,
        })
    }

    /// `text` in a new temporary file of the folder, written through to
    /// the disk, for [`OutFolder::place`].
    fn written(&self, name: &str, text: &str) -> Result<tempfile::NamedTempFile, String> {
        let fail = |e: &std::io::Error| {
            format!(
                "cannot write {}: {}",
                self.dir.join(name).display(),
                system_reason(e)
            )
        };
        let mut file = temporary_in(&self.dir).map_err(|e| fail(&e))?;
        file.write_all(text.as_bytes())
            .and_then(|()| file.as_file().sync_all())
            .map_err(|e| fail(&e))?;
        Ok(file)
    }

    /// Rename a [`OutFolder::written`] file to `name` (replacing a file
    /// only with `--force`).
    /// Returns whether it replaced a file.
    fn place(&self, name: &str, file: tempfile::NamedTempFile) -> Result<bool, String> {
        let path = self.dir.join(name);
        let older = self.force && path.symlink_metadata().is_ok();
        let fail = |e: &dyn std::fmt::Display| format!("cannot write {}: {e}", path.display());
        let placed = if self.force {
            file.persist(&path)
        } else {
            file.persist_noclobber(&path)
        };
        match placed {
            Ok(_) => Ok(older),
            Err(e) if e.error.kind() == std::io::ErrorKind::AlreadyExists => Err(fail(
                &"a file of that name appeared while the study ran; it was kept (add --force \
                  to replace it)",
            )),
            Err(e) => Err(fail(&e.error)),
        }
    }

    /// What became of the files `placed` before one could not be, each
    /// with whether it replaced a file of its name (only with `--force`):
    /// a new one is taken back out, so that the study leaves none of its
    /// files; one that replaced an older file cannot give it back, and is
    /// named.
    fn taken_back(&self, placed: &[(&str, bool)]) -> String {
        if placed.is_empty() {
            return "; no file of the study was written or replaced".into();
        }
        let (mut removed, mut replaced, mut left) = (0, Vec::new(), Vec::new());
        for &(name, older) in placed {
            if older {
                replaced.push(name);
            } else if std::fs::remove_file(self.dir.join(name))
                .is_err_and(|e| e.kind() != std::io::ErrorKind::NotFound)
            {
                left.push(name);
            } else {
                removed += 1;
            }
        }
        if replaced.is_empty() && left.is_empty() {
            return "; the files written before it were taken back: no file of the study was \
                    written"
                .into();
        }
        let mut said = Vec::new();
        if removed > 0 {
            said.push("the new files written before it were taken back".to_string());
        }
        if !replaced.is_empty() {
            said.push(format!(
                "these replaced older files, which cannot be had back: {}",
                replaced.join(", ")
            ));
        }
        if !left.is_empty() {
            said.push(format!(
                "these, new, could not be taken back: {}",
                left.join(", ")
            ));
        }
        format!("; {}", said.join("; "))
    }

    /// Write every file: each to a temporary file of the folder first, and
    /// only once all are written, each renamed into place. A file that
    /// cannot be written (a full disk) leaves the folder as it was, its
    /// earlier files included. The failures, one a line.
    pub(crate) fn write_all(&self, files: &[(String, String)]) -> Result<(), Failure> {
        std::fs::create_dir_all(&self.dir).map_err(|e| {
            Failure::Runtime(format!(
                "--out {}: cannot create the folder: {e}",
                self.dir.display()
            ))
        })?;
        let (mut written, mut failures) = (Vec::new(), Vec::new());
        for (name, text) in files {
            match self.written(name, text) {
                Ok(file) => written.push((name, file)),
                Err(e) => failures.push(e),
            }
        }
        if failures.is_empty() {
            // Placed one after the other until one cannot be; the rest
            // vanish with `written`.
            let mut placed = Vec::new();
            for (name, file) in written {
                match self.place(name, file) {
                    Ok(older) => placed.push((name.as_str(), older)),
                    Err(e) => {
                        failures.push(e + &self.taken_back(&placed));
                        break;
                    }
                }
            }
        } else {
            // The written ones vanish with `written`.
            let last = failures.len() - 1;
            failures[last] += "; no file of the study was written or replaced";
        }
        if failures.is_empty() {
            Ok(())
        } else {
            Err(Failure::Runtime(failures.join("\nlerpit: error: ")))
        }
    }
}

/// The system's reason for `e`, without the temporary file's name, which
/// tempfile adds to it (`... at path "/x/.lerpit-1a2b.tmp"`) and keeps no
/// other way.
fn system_reason(e: &std::io::Error) -> String {
    let reason = e.to_string();
    reason
        .split(" at path \"")
        .next()
        .unwrap_or_default()
        .to_string()
}

/// A new empty file in `dir` that vanishes unless persisted, readable as
/// an ordinary new file would be.
fn temporary_in(dir: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".lerpit-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// Memory the stability suite takes besides its threads' stacks, bytes:
/// its peak resident memory was 116 MB (`/usr/bin/time lerpit study
/// --stability`, 593 s on 2 cores), and with `--quick` its address space
/// grew by 2 MB beyond the stacks (`ulimit -v 12500` aborted it). The
/// accuracy sweep grew by 0.5 MB, within what every command is given.
const STABILITY_BYTES: f64 = 150e6;
const QUICK_STABILITY_BYTES: f64 = 3e6;

pub(crate) fn run(args: &StudyArgs) -> Result<(), Failure> {
    // The study's worlds step on a pool of one thread a core, started only
    // where an address-space limit leaves room for their stacks (rayon's
    // own pool, started unchecked, panicked under `ulimit -v 10000`).
    let need = match (args.stability, args.quick) {
        (true, false) => STABILITY_BYTES,
        (true, true) => QUICK_STABILITY_BYTES,
        (false, _) => 0.0,
    };
    crate::scene::memory::check_core_threads(need, "the study").map_err(Failure::Runtime)?;
    let pool = crate::sim::threads::thread_pool(None).map_err(Failure::Runtime)?;
    pool.install(|| study(args))
}

fn study(args: &StudyArgs) -> Result<(), Failure> {
    // Before the signals are held off: the progress line is taken off the
    // screen by a signal that ends the study while it is shown.
    crate::process::progress::clear_line_while_shown();
    let unbroken = Unbroken::install();
    let folder = match &args.out {
        Some(dir) => {
            Some(unbroken.hold(|| OutFolder::prepare(dir, &file_names(args), args.force))?)
        }
        None => None,
    };
    // Without files to write, what the study prints at its end is all it
    // is for: it ends (status 0) as soon as its reader has gone.
    let watch = folder.is_none().then(ReaderWatch::ending_the_program);
    let (text, files) = if args.stability {
        stability_study(args.quick)
    } else {
        sweep_study(args.quick)?
    };
    // The tables first, whatever then happens to the files.
    let printed = std::io::stdout()
        .lock()
        .write_all(text.as_bytes())
        .and_then(|()| std::io::stdout().flush());
    let written = match &folder {
        Some(folder) => unbroken.hold(|| folder.write_all(&files)),
        None => Ok(()),
    };
    drop(watch);
    printed?;
    written?;
    if let Some(dir) = &args.out {
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        writeln!(
            std::io::stdout(),
            "wrote {} to {}",
            names.join(", "),
            dir.display()
        )?;
    }
    Ok(())
}

/// The stability suite's table, and its file.
fn stability_study(quick: bool) -> (String, Vec<(String, String)>) {
    let scale = if quick { Scale::quick() } else { Scale::full() };
    let bar = Progress::spinner_cleared_while_shown("study --stability");
    let mut started = false;
    let findings = stability::suite(scale, &mut |what| {
        if std::mem::replace(&mut started, true) {
            bar.inc(1);
        }
        bar.message(what.to_string());
    });
    bar.finish();
    let table = stability::table(&findings);
    (table.clone(), vec![(STABILITY_FILE.into(), table)])
}

/// The sweep, the horizon and the conservation run: the text and the files.
fn sweep_study(quick: bool) -> Result<(String, Vec<(String, String)>), Failure> {
    let plan = plan(quick);
    let with_horizon = plan.lessons.contains(&Lesson::Collisions);
    let conservation_plan = if quick {
        conservation::Plan::quick()
    } else {
        conservation::Plan::full()
    };
    let total = plan.runs() + usize::from(with_horizon) + conservation_plan.runs();
    // Runs at a small dt take hundreds of times as long as those at a
    // large one: the bar gives the time taken, not a time left.
    let bar = Progress::bar_of_cleared_while_shown(total as u64, "study", Parts::Uneven);
    let mut progress = |done: usize, _: usize, what: &str| {
        if done > 0 {
            bar.inc(1);
        }
        bar.message(what.to_string());
    };
    let rows = sweep::run(&plan, &mut progress).map_err(Failure::Runtime)?;

    let mut files = Vec::new();
    let mut text = String::new();
    for &lesson in &plan.lessons {
        let lesson_rows: Vec<&Row> = rows.iter().filter(|r| r.lesson == lesson).collect();
        text += &lesson_report(lesson, &lesson_rows, plan.horizon(lesson));
        files.extend(lesson_svgs(lesson, &lesson_rows).map_err(Failure::Runtime)?);
    }
    if with_horizon {
        bar.message("predictability horizon of the collisions lesson");
        text += &horizon_report(&Horizon::of_collisions(plan.horizon(Lesson::Collisions))?);
        bar.inc(1);
    }
    if let Some(goal) = GravityGoal::of(&rows) {
        text += &gravity_goal_report(&goal);
    }

    let drifts = conservation::run(&conservation_plan, &mut progress).map_err(Failure::Runtime)?;
    bar.finish();
    text += &conservation_report(&drifts);

    files.push((SWEEP_FILE.into(), csv_text(&rows)?));
    files.push((CONSERVATION_FILE.into(), csv_text(&drifts)?));
    let chart = svg::log_log(
        "Elastic collisions, no gravity: energy drift against dt",
        "dt (s)",
        "max |E(t) - E(0)| / E(0)",
        &drift_series(&drifts, false),
    )
    .map_err(Failure::Runtime)?;
    files.push((CONSERVATION_CHART_FILE.into(), chart));
    Ok((text, files))
}

/// `rows` as the text of a CSV file.
fn csv_text<T: serde::Serialize>(rows: &[T]) -> Result<String, Failure> {
    let mut bytes = Vec::new();
    write_csv(&mut bytes, rows)?;
    String::from_utf8(bytes).map_err(|e| Failure::Runtime(e.to_string()))
}

fn lesson_report(lesson: Lesson, rows: &[&Row], horizon: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n=== {} lesson: RMS position error at t = {horizon} s ===\n",
        lesson.name()
    );
    let mut wp = TextChart::new(
        "work-precision (down-left is better)",
        "log10 wall time per simulated second (s)",
        "log10 RMS position error (m)",
    );
    wp.series = work_precision_series(rows);
    s += &wp.render();
    let mut conv = TextChart::new(
        "dt convergence",
        "log10 dt (s)",
        "log10 RMS position error (m)",
    );
    conv.series = series_by_method(rows, |r| (log10(r.dt), log10(r.error())));
    for series in &mut conv.series {
        let Ok(m) = series.name.parse::<Integrator>() else {
            continue;
        };
        let Some(convergence) = sweep::convergence_of(rows, m) else {
            continue;
        };
        series.name = match convergence {
            Convergence::Diverging(p) => format!(
                "{m}  no convergence: the error grows as dt shrinks, rounding accumulated over \
                 more steps (slope {p:.2})"
            ),
            Convergence::Order(p) => format!("{m}  fitted order {p:.2}"),
            Convergence::Rounding => format!("{m}  at rounding level (no order to fit)"),
        };
    }
    s += &conv.render();
    let _ = writeln!(
        s,
        "\n{:<20} {:>10} {:>12} {:>11} {:>11} {:>11} {:>11}",
        "method", "dt (s)", "ns/body-step", "rms err (m)", "bounce (s)", "apex ratio", "energy"
    );
    for r in rows {
        let opt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2e}"));
        let _ = writeln!(
            s,
            "{:<20} {:>10.3e} {:>12.1} {:>11.2e} {:>11} {:>11} {:>11.2e}{}",
            r.method.name(),
            r.dt,
            r.ns_per_body_step,
            r.rms_error,
            opt(r.bounce_time_error),
            opt(r.apex_ratio_error),
            r.energy_error,
            if r.event_cap_reached {
                "  (event cap reached)"
            } else {
                ""
            }
        );
    }
    let _ = writeln!(
        s,
        "rms err: RMS distance from the exact positions; bounce: error of the floor bounces' \
         times; apex ratio: error of the ratio of successive apex heights; energy: \
         |E - E exact| / |E at the start|"
    );
    s
}

/// The work-precision and convergence charts of one lesson, as files.
fn lesson_svgs(lesson: Lesson, rows: &[&Row]) -> Result<[(String, String); 2], String> {
    let wp = series_by_method(rows, |r| (r.cost_per_second, r.error()));
    let wp = svg::log_log(
        &format!("{} lesson: work against precision", lesson.name()),
        "wall time per simulated second (s)",
        "RMS position error (m)",
        &wp,
    )?;
    let conv = series_by_method(rows, |r| (r.dt, r.error()));
    let conv = svg::log_log(
        &format!("{} lesson: error against dt", lesson.name()),
        "dt (s)",
        "RMS position error (m)",
        &conv,
    )?;
    let [wp_file, conv_file] = chart_files(lesson);
    Ok([(wp_file, wp), (conv_file, conv)])
}

/// `met` or `missed`.
fn verdict(met: bool) -> &'static str {
    if met { "met" } else { "missed" }
}

/// Where the collisions lesson stops being predictable.
fn horizon_report(h: &Horizon) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "\n=== collisions lesson: predictability horizon ===");
    let compared = h.compared_at;
    let _ = match h.diverged_at {
        Some(t) => writeln!(
            s,
            "moving one sphere by {NUDGE:e} m moves the event-driven reference by {DIVERGED:e} m \
             (RMS) after {t:.2} s: positions are compared at t = {compared} s, {}; beyond it \
             compare energy and collision counts, not positions.",
            if h.compared_inside() {
                "inside it"
            } else {
                "NOT inside it: the position errors there measure chaos, not the methods"
            }
        ),
        None => writeln!(
            s,
            "the nudged and the plain reference stay within {DIVERGED:e} m for {HORIZON_LIMIT} s"
        ),
    };
    s
}

/// The gravity goal: the continuous method's bounce-time and apex-ratio
/// errors at every dt, and its cost per step against semi-implicit Euler.
fn gravity_goal_report(goal: &GravityGoal) -> String {
    let mut s = String::new();
    let (bounce, apex) = (goal.bounce_time, goal.apex_ratio);
    let _ = writeln!(s, "\n=== goal: gravity lesson, continuous method ===");
    let _ = writeln!(
        s,
        "bounce-time error (first {BOUNCES} floor bounces, every dt up to {:.4} s): \
         {:.2e} s  [goal <= {:e}: {}]",
        goal.largest_dt,
        bounce.value,
        bounce.limit,
        verdict(bounce.met())
    );
    let _ = writeln!(
        s,
        "apex-ratio error: {:.2e}  [goal <= {:e}: {}]",
        apex.value,
        apex.limit,
        verdict(apex.met())
    );
    let _ = writeln!(s, "cost per step, continuous / semi-implicit Euler:");
    for (dt, ratio) in &goal.cost_ratios {
        let _ = writeln!(s, "  dt {dt:.3e} s: {:.2}", ratio.value);
    }
    let missed = goal.cost_missed_at();
    let verdict = if missed.is_empty() {
        "met at every dt".to_string()
    } else {
        let dts: Vec<String> = missed.iter().map(|dt| format!("{dt:.3e}")).collect();
        format!("missed at dt {} s", dts.join(", "))
    };
    let _ = writeln!(s, "  [goal <= {COST_RATIO_GOAL}: {verdict}]");
    s
}

fn drift_series(drifts: &[Drift], log: bool) -> Vec<Series> {
    let f = |v: f64| if log { log10(v) } else { v };
    Integrator::DISCRETE
        .iter()
        .map(|&m| Series {
            name: m.name().to_string(),
            marker: marker(m),
            points: drifts
                .iter()
                .filter(|d| d.method == m)
                .map(|d| (f(d.dt), f(d.energy_drift)))
                .collect(),
        })
        .collect()
}

fn conservation_report(drifts: &[Drift]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n=== goal: elastic collisions without gravity (collisions lesson, e = c_r = 1) ==="
    );
    if let Some(ConservationGoal {
        run: c,
        momentum,
        energy,
    }) = ConservationGoal::of(drifts)
    {
        let _ = writeln!(
            s,
            "continuous, dt {:.3e} s: {} collisions in {:.1} s; momentum error {:.1e} \
             [goal <= {:e}: {}]; energy drift {:.1e} [goal < {:e}: {}]",
            c.dt,
            c.collisions,
            c.time,
            momentum.value,
            momentum.limit,
            verdict(momentum.met()),
            energy.value,
            energy.limit,
            verdict(energy.met())
        );
    }
    let mut chart = TextChart::new(
        "discrete methods: energy drift against dt, same simulated time",
        "log10 dt (s)",
        "log10 max |E(t) - E(0)| / E(0)",
    );
    chart.height = 10;
    chart.series = drift_series(drifts, true);
    s += &chart.render();
    let _ = writeln!(
        s,
        "{:<20} {:>10} {:>10} {:>12} {:>14}",
        "method", "dt (s)", "contacts", "energy drift", "momentum error"
    );
    for d in drifts {
        let _ = writeln!(
            s,
            "{:<20} {:>10.3e} {:>10} {:>12.2e} {:>14.2e}",
            d.method.name(),
            d.dt,
            d.collisions,
            d.energy_drift,
            d.momentum_error
        );
    }
    // Without a force every discrete method moves a sphere in a straight
    // line at its velocity: their runs are one and the same.
    let discrete: Vec<&Drift> = drifts.iter().filter(|d| d.method.is_discrete()).collect();
    let same = |a: &&Drift, b: &&Drift| {
        (a.collisions, a.energy_drift, a.momentum_error)
            == (b.collisions, b.energy_drift, b.momentum_error)
    };
    let coincide = !discrete.is_empty()
        && discrete.iter().all(|d| {
            let at_dt: Vec<&&Drift> = discrete.iter().filter(|o| o.dt == d.dt).collect();
            at_dt.len() > 1 && at_dt.iter().all(|o| same(o, d))
        });
    if coincide {
        let _ = writeln!(
            s,
            "the discrete methods give the same runs: without gravity each moves a sphere \
             in a straight line at its velocity, so they differ in nothing (one line in the \
             chart)"
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::OutFolder;

    #[test]
    fn files_placed_before_one_that_cannot_be_are_taken_back_unless_they_replaced_others() {
        let dir = tempfile::tempdir().unwrap();
        let put = |name: &str| std::fs::write(dir.path().join(name), "study").unwrap();
        let names = || -> Vec<String> {
            let mut n: Vec<String> = std::fs::read_dir(dir.path())
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            n.sort();
            n
        };
        let folder = |force| OutFolder {
            dir: dir.path().to_path_buf(),
            force,
        };
        assert_eq!(
            folder(false).taken_back(&[]),
            "; no file of the study was written or replaced"
        );
        // New files are taken back out.
        put("a.csv");
        put("b.svg");
        assert_eq!(
            folder(false).taken_back(&[("a.csv", false), ("b.svg", false)]),
            "; the files written before it were taken back: no file of the study was written"
        );
        assert!(names().is_empty());
        // With --force, one that replaced an older file stays and is named;
        // a new one is still taken back.
        put("a.csv");
        put("b.svg");
        assert_eq!(
            folder(true).taken_back(&[("a.csv", true), ("b.svg", false)]),
            "; the new files written before it were taken back; these replaced older files, \
             which cannot be had back: a.csv"
        );
        assert_eq!(names(), ["a.csv"]);
        // One that cannot be removed (here a folder) is named; one gone
        // already is as good as taken back.
        std::fs::create_dir(dir.path().join("c")).unwrap();
        assert_eq!(
            folder(true).taken_back(&[("a.csv", true), ("c", false), ("gone.csv", false)]),
            "; the new files written before it were taken back; these replaced older files, \
             which cannot be had back: a.csv; these, new, could not be taken back: c"
        );
        assert_eq!(names(), ["a.csv", "c"]);
    }
}
