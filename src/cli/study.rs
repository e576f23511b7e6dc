//! `lerpit study`: the work-precision sweep, the conservation run and the
//! stability suite, printed as text charts and tables; data as CSV and
//! charts as SVG with `--out DIR`. Progress goes to standard error.

use super::Failure;
use crate::scene::Lesson;
use crate::sim::Integrator;
use crate::sim::reference::collisions::predictability_horizon;
use crate::study::charts::{
    Series, TextChart, log10, marker, series_by_method, work_precision_series,
};
use crate::study::conservation::{self, Drift};
use crate::study::metrics::{BOUNCES, fitted_order};
use crate::study::stability::{self, Scale};
use crate::study::svg;
use crate::study::sweep::{self, Plan, Row};
use clap::Args;
use std::fmt::Write as _;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Args, Debug, Clone)]
pub struct StudyArgs {
    /// A few seconds instead of about half a minute (release build): fewer
    /// and larger time steps, shorter runs, no repeats; with --stability,
    /// smaller piles and shorter runs.
    #[arg(long)]
    pub quick: bool,
    /// Run the stability suite and print its table instead of the sweep.
    #[arg(long)]
    pub stability: bool,
    /// Write the data (CSV) and the charts (SVG) into this folder (created
    /// if missing).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// Pair collisions the continuous method resolves in the conservation run.
pub const CONSERVATION_COLLISIONS: u64 = 10_000;

fn progress(done: usize, total: usize, what: &str) {
    eprint!("\rstudy: [{done:>3}/{total}] {what:<60}");
    if done == total {
        eprintln!();
    }
}

pub fn run(args: &StudyArgs) -> Result<(), Failure> {
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).map_err(|e| {
            Failure::Runtime(format!("cannot create the folder {}: {e}", dir.display()))
        })?;
    }
    let out = std::io::stdout();
    let mut out = out.lock();
    if args.stability {
        let scale = if args.quick {
            Scale::quick()
        } else {
            Scale::full()
        };
        let findings = stability::suite(scale, &mut |what| eprintln!("stability: {what}"));
        let table = stability::table(&findings);
        out.write_all(table.as_bytes())?;
        if let Some(dir) = &args.out {
            write_file(&dir.join("stability.txt"), &table)?;
        }
        return Ok(());
    }

    let plan = if args.quick {
        Plan::quick()
    } else {
        Plan::full()
    };
    let rows = sweep::run(&plan, &mut progress).map_err(Failure::Runtime)?;
    let mut text = String::new();
    for &lesson in &plan.lessons {
        let lesson_rows: Vec<&Row> = rows.iter().filter(|r| r.lesson == lesson).collect();
        text += &lesson_report(lesson, &lesson_rows, plan.horizon(lesson));
        if let Some(dir) = &args.out {
            write_svgs(dir, lesson, &lesson_rows)?;
        }
    }
    if plan.lessons.contains(&Lesson::Collisions) {
        text += &horizon_report(plan.horizon(Lesson::Collisions))?;
    }
    text += &goals(&rows);

    let drifts = conservation_runs(args.quick).map_err(Failure::Runtime)?;
    text += &conservation_report(&drifts);
    out.write_all(text.as_bytes())?;

    if let Some(dir) = &args.out {
        let mut csv = String::from(sweep::CSV_HEADER);
        csv.push('\n');
        for r in &rows {
            csv += &r.csv();
            csv.push('\n');
        }
        write_file(&dir.join("sweep.csv"), &csv)?;
        let mut csv = String::from(conservation::CSV_HEADER);
        csv.push('\n');
        for d in &drifts {
            csv += &d.csv();
            csv.push('\n');
        }
        write_file(&dir.join("conservation.csv"), &csv)?;
        let series = drift_series(&drifts, false);
        svg::write_log_log(
            &dir.join("conservation.svg"),
            "Elastic collisions, no gravity: energy drift against dt",
            "dt (s)",
            "max |E(t) - E(0)| / E(0)",
            &series,
        )
        .map_err(Failure::Runtime)?;
        writeln!(
            out,
            "wrote sweep.csv, conservation.csv and the SVG charts to {}",
            dir.display()
        )?;
    }
    Ok(())
}

fn write_file(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::Runtime(format!("cannot write {}: {e}", path.display())))
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
        let m = Integrator::from_name(&series.name).unwrap_or(Integrator::SemiImplicitEuler);
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.method == m)
            .map(|r| (r.dt, r.error()))
            .collect();
        series.name = match fitted_order(&pts) {
            Some(p) if p < 0.0 => format!(
                "{}  no convergence: the error grows as dt shrinks, rounding accumulated over \
                 more steps (slope {p:.2})",
                series.name
            ),
            Some(p) => format!("{}  fitted order {p:.2}", series.name),
            None => format!("{}  at rounding level (no order to fit)", series.name),
        };
    }
    s += &conv.render();
    let _ = writeln!(
        s,
        "\n{:<20} {:>10} {:>12} {:>11} {:>11} {:>11} {:>11}",
        "method", "dt (s)", "ns/body-step", "rms error", "bounce t", "apex ratio", "energy"
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
    s
}

fn write_svgs(dir: &Path, lesson: Lesson, rows: &[&Row]) -> Result<(), Failure> {
    let wp = series_by_method(rows, |r| (r.cost_per_second, r.error()));
    svg::write_log_log(
        &dir.join(format!("work-precision-{}.svg", lesson.name())),
        &format!("{} lesson: work against precision", lesson.name()),
        "wall time per simulated second (s)",
        "RMS position error (m)",
        &wp,
    )
    .map_err(Failure::Runtime)?;
    let conv = series_by_method(rows, |r| (r.dt, r.error()));
    svg::write_log_log(
        &dir.join(format!("convergence-{}.svg", lesson.name())),
        &format!("{} lesson: error against dt", lesson.name()),
        "dt (s)",
        "RMS position error (m)",
        &conv,
    )
    .map_err(Failure::Runtime)
}

/// Nudge applied to one sphere to find the predictability horizon, m.
pub const NUDGE: f64 = 1e-12;
/// Distance (RMS) at which two runs no longer tell the same story, m.
pub const DIVERGED: f64 = 1e-3;

/// Where the collisions lesson stops being predictable.
fn horizon_report(sweep_horizon: f64) -> Result<String, Failure> {
    let world = Lesson::Collisions.scene().build()?;
    eprintln!("study: predictability horizon of the collisions lesson");
    let h = predictability_horizon(&world, NUDGE, DIVERGED, 0.01, 5.0);
    let mut s = String::new();
    let _ = writeln!(s, "\n=== collisions lesson: predictability horizon ===");
    match h {
        Some(t) => {
            let _ = writeln!(
                s,
                "moving one sphere by {NUDGE:e} m moves the event-driven reference by {DIVERGED:e} m \
                 (RMS) after {t:.2} s: positions are compared at t = {sweep_horizon} s, inside it; \
                 beyond it compare energy and collision counts, not positions."
            );
        }
        None => {
            let _ = writeln!(
                s,
                "the nudged and the plain reference stay within {DIVERGED:e} m for 5 s"
            );
        }
    }
    Ok(s)
}

/// The gravity goal: the continuous method's bounce-time and apex-ratio
/// errors at every dt, and its cost per step against semi-implicit Euler.
fn goals(rows: &[Row]) -> String {
    let mut s = String::new();
    let of = |m: Integrator| -> Vec<&Row> {
        rows.iter()
            .filter(|r| r.lesson == Lesson::Gravity && r.method == m)
            .collect()
    };
    let (cont, sie) = (
        of(Integrator::Continuous),
        of(Integrator::SemiImplicitEuler),
    );
    if cont.is_empty() || sie.is_empty() {
        return s;
    }
    let worst = |f: fn(&Row) -> Option<f64>| cont.iter().filter_map(|r| f(r)).fold(0.0, f64::max);
    let bounce = worst(|r| r.bounce_time_error);
    let apex = worst(|r| r.apex_ratio_error);
    let largest = cont.iter().map(|r| r.dt).fold(0.0, f64::max);
    let ratios: Vec<(f64, f64)> = cont
        .iter()
        .zip(&sie)
        .map(|(c, s)| (c.dt, c.ns_per_body_step / s.ns_per_body_step))
        .collect();
    let _ = writeln!(s, "\n=== goal: gravity lesson, continuous method ===");
    let _ = writeln!(
        s,
        "bounce-time error (first {BOUNCES} floor bounces, every dt up to {largest:.4} s): \
         {bounce:.2e} s  [goal <= 1e-12: {}]",
        if bounce <= 1e-12 { "met" } else { "missed" }
    );
    let _ = writeln!(
        s,
        "apex-ratio error: {apex:.2e}  [goal <= 1e-12: {}]",
        if apex <= 1e-12 { "met" } else { "missed" }
    );
    let _ = writeln!(s, "cost per step, continuous / semi-implicit Euler:");
    for (dt, ratio) in &ratios {
        let _ = writeln!(s, "  dt {dt:.3e} s: {ratio:.2}");
    }
    let over: Vec<f64> = ratios.iter().filter(|r| r.1 > 2.0).map(|r| r.0).collect();
    let verdict = match over.iter().copied().reduce(f64::min) {
        None => "met at every dt".to_string(),
        Some(dt) => format!("missed at dt >= {dt:.3e} s"),
    };
    let _ = writeln!(s, "  [goal <= 2: {verdict}]");
    s
}

fn conservation_runs(quick: bool) -> Result<Vec<Drift>, String> {
    let dt = 1.0 / 240.0;
    let target = if quick {
        CONSERVATION_COLLISIONS / 20
    } else {
        CONSERVATION_COLLISIONS
    };
    eprintln!("study: conservation, continuous method to {target} collisions");
    let cont = conservation::drift(Integrator::Continuous, dt, Some(target), 0.0)?;
    let seconds = cont.time;
    let mut out = vec![cont];
    let dts = sweep::log_spaced(
        sweep::LARGEST_DT,
        if quick { 1.0 } else { 2.0 },
        if quick { 3 } else { 8 },
    );
    for m in Integrator::DISCRETE {
        for &dt in &dts {
            eprint!(
                "\rstudy: conservation, {} dt={dt:.2e}            ",
                m.name()
            );
            out.push(conservation::drift(m, dt, None, seconds)?);
        }
    }
    eprintln!();
    Ok(out)
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
    if let Some(c) = drifts.iter().find(|d| d.method == Integrator::Continuous) {
        let _ = writeln!(
            s,
            "continuous, dt {:.3e} s: {} collisions in {:.1} s; momentum error {:.1e} [goal <= 1e-12: {}]; energy drift {:.1e} [goal < 1e-9: {}]",
            c.dt,
            c.collisions,
            c.time,
            c.momentum_error,
            if c.momentum_error <= 1e-12 {
                "met"
            } else {
                "missed"
            },
            c.energy_drift,
            if c.energy_drift < 1e-9 {
                "met"
            } else {
                "missed"
            }
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
    s
}
