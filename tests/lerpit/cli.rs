//! The real binary: `lerpit run` output against the library, `lerpit scene`,
//! and every class of bad input with its message and exit status.

use crate::support::{
    BIN, BODY, README, json, lerpit, lerpit_within, refused, refused_flags, scene_file, stderr,
};
use lerpit::scene::{Lesson, parse_scene};
use std::process::Command;

#[test]
fn run_json_has_the_documented_fields_and_matches_the_library() {
    let o = lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "1000",
        "--format",
        "json",
    ]);
    let v = json(&o);
    for key in [
        "time",
        "steps",
        "dt",
        "integrator",
        "kinetic_energy",
        "potential_energy",
        "total_energy",
        "momentum",
        "contacts",
        "max_overlap",
        "bodies",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    let mut world = Lesson::Collisions.scene().build().unwrap();
    world.run(1000);
    let d = world.diagnostics();
    assert_eq!(v["steps"], 1000);
    assert_eq!(v["integrator"], "semi-implicit-euler");
    assert_eq!(v["dt"].as_f64(), Some(world.config.dt));
    assert_eq!(v["time"].as_f64(), Some(d.time));
    assert_eq!(v["total_energy"].as_f64(), Some(d.total_energy));
    assert_eq!(v["state_hash"], format!("{:016x}", world.state_hash()));
    let bodies = v["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), world.bodies.len());
    for (i, b) in bodies.iter().enumerate() {
        let p: Vec<f64> = serde_json::from_value(b["position"].clone()).unwrap();
        let u: Vec<f64> = serde_json::from_value(b["velocity"].clone()).unwrap();
        assert_eq!(
            p,
            world.bodies.position[i].to_array().to_vec(),
            "body {i} position"
        );
        assert_eq!(
            u,
            world.bodies.velocity[i].to_array().to_vec(),
            "body {i} velocity"
        );
        assert_eq!(b["radius"].as_f64(), Some(world.bodies.radius[i]));
        assert_eq!(b["mass"].as_f64(), Some(world.bodies.mass[i]));
    }
}

/// The report's keys, in the order `--format json` prints them: the
/// scene, the world's diagnostics (flattened from `sim::Diagnostics`), the
/// parameters that ran, then the run's totals and the bodies.
const REPORT_KEYS: [&str; 33] = [
    "scene",
    "seed",
    "time",
    "steps",
    "kinetic_energy",
    "potential_energy",
    "total_energy",
    "momentum",
    "contacts",
    "pair_tests",
    "max_overlap",
    "wall_impacts",
    "asleep",
    "gravity",
    "dt",
    "integrator",
    "wall_mode",
    "wall_restitution",
    "pair_collisions",
    "pair_restitution",
    "broad_phase",
    "substeps",
    "rest_threshold",
    "rest_steps",
    "projection_passes",
    "support",
    "sleep",
    "total_contacts",
    "unconverged_projection_steps",
    "impact_cap_steps",
    "support_unsettled",
    "state_hash",
    "bodies",
];

#[test]
fn run_json_prints_its_keys_in_a_fixed_order() {
    let o = lerpit(&["run", "--lesson", "gravity", "--steps", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let keys: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("  \""))
        .filter_map(|l| l.split_once('"').map(|(k, _)| k))
        .collect();
    assert_eq!(keys, REPORT_KEYS);
}

#[test]
fn run_counts_the_steps_where_a_remedy_ran_out_of_its_budget() {
    // The collisions lesson's pile with one further projection pass: the
    // passes run out while it settles; with the default, they never do.
    let v = json(&lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--time",
        "5",
        "--projection-passes",
        "2",
    ]));
    let ran_out = v["unconverged_projection_steps"].as_u64().unwrap();
    assert!(ran_out > 0 && ran_out <= 1200, "{ran_out} of 1200 steps");
    let v = json(&lerpit(&["run", "--lesson", "collisions", "--time", "5"]));
    assert_eq!(v["unconverged_projection_steps"], 0);
    assert_eq!(v["impact_cap_steps"], 0);
    assert_eq!(v["support_unsettled"], 0);
}

#[test]
fn run_time_covers_whole_steps_and_overrides_apply() {
    let v = json(&lerpit(&[
        "run",
        "--lesson",
        "gravity",
        "--time",
        "0.5",
        "--dt",
        "0.01",
        "--integrator",
        "velocity-verlet",
        "--restitution",
        "0.5",
        "--gravity",
        "3",
        "--particles",
        "7",
        "--seed",
        "42",
        "--substeps",
        "3",
        "--rest-threshold",
        "0.1",
    ]));
    assert_eq!(v["steps"], 50);
    assert_eq!(v["substeps"], 3);
    assert_eq!(v["rest_threshold"].as_f64(), Some(0.1));
    assert_eq!(v["integrator"], "velocity-verlet");
    assert_eq!(v["wall_restitution"].as_f64(), Some(0.5));
    assert_eq!(v["gravity"][1].as_f64(), Some(-3.0));
    assert_eq!(v["seed"], 42);
    assert_eq!(v["bodies"].as_array().unwrap().len(), 7);
}

#[test]
fn gravity_flag_keeps_a_scene_s_sideways_direction() {
    // A scene pulling along (3, 0, 4)/5: --gravity 10 sets the strength
    // and keeps the direction.
    let file = scene_file(
        "[world]\ngravity = [3.0, 0.0, 4.0]\n[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n",
    );
    let path = file.path.to_str().unwrap();
    let v = json(&lerpit(&[
        "run",
        "--scene",
        path,
        "--steps",
        "1",
        "--gravity",
        "10",
    ]));
    let g: Vec<f64> = (0..3).map(|k| v["gravity"][k].as_f64().unwrap()).collect();
    assert!(
        (g[0] - 6.0).abs() < 1e-14 && (g[2] - 8.0).abs() < 1e-14,
        "{g:?}"
    );
    assert_eq!(g[1].to_bits(), 0, "+0: {g:?}");
}

#[test]
fn run_trace_prints_a_csv_row_every_k_steps() {
    let o = lerpit(&[
        "run", "--lesson", "pingpong", "--steps", "10", "--trace", "4",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("step,time,kinetic_energy"));
    let steps: Vec<&str> = lines[1..]
        .iter()
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert_eq!(steps, ["0", "4", "8", "10"]);
    assert!(
        lines[1..]
            .iter()
            .all(|l| l.split(',').count() == lines[0].split(',').count())
    );
}

/// `--trajectory` follows the ping-pong ball's closed form: from y = 0.5
/// at 1 m/s between flip walls its centre runs the triangle wave between
/// r = 0.05 and 1 - r, to rounding, at every K-th step and the last.
#[test]
fn run_trajectory_gives_the_ping_pong_ball_s_triangle_wave() {
    let o = lerpit(&[
        "run",
        "--lesson",
        "pingpong",
        "--steps",
        "200",
        "--trajectory",
        "7",
    ]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("step,time,index,x,y,z,vx,vy,vz"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let steps: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    let expected: Vec<f64> = (0..=28).map(|k| f64::from(k * 7)).chain([200.0]).collect();
    assert_eq!(steps, expected);
    let (lo, hi) = (0.05, 0.95);
    for r in &rows {
        let t = r[1];
        assert!((t - r[0] / 60.0).abs() < 1e-12, "{r:?}");
        // Unfolded, the ball has run 0.5 - lo + t from the floor's reach;
        // the wave's period is 2 (hi - lo).
        let s = (0.5 - lo + t) % (2.0 * (hi - lo));
        let (y, vy) = if s <= hi - lo {
            (lo + s, 1.0)
        } else {
            (hi - (s - (hi - lo)), -1.0)
        };
        // On a wall's reach (step 189 ends on the floor's) the step has
        // flipped the velocity already: it points away from the wall.
        let vy = match (y - lo).abs() < 1e-9 {
            true => 1.0,
            false if (y - hi).abs() < 1e-9 => -1.0,
            false => vy,
        };
        assert_eq!(r[2], 0.0, "{r:?}");
        assert!((r[4] - y).abs() < 1e-12, "{r:?}: y {y}");
        assert_eq!((r[3], r[5], r[6], r[7], r[8]), (0.5, 0.5, 0.0, vy, 0.0));
    }
    // One row a sphere each time, in scene order.
    let o = lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "3",
        "--trajectory",
        "2",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    let index: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap())
        .collect();
    let once: Vec<String> = (0..100).map(|i| i.to_string()).collect();
    assert_eq!(index, [&once[..], &once[..], &once[..]].concat());
}

/// A long trace stopped by SIGTERM keeps its header and whole rows: they
/// are handed on as the run goes, not only at its end.
#[cfg(unix)]
#[test]
fn a_trace_stopped_by_a_signal_keeps_its_rows() {
    let text = stopped_by_sigterm(
        &[
            "run",
            "--lesson",
            "collisions",
            "--steps",
            "1e9",
            "--trace",
            "10000",
        ],
        3,
        std::time::Duration::ZERO,
    );
    let rows = whole_rows(&text);
    assert!(rows >= 2, "{rows} rows");
    // Rows by the million, stopped at any moment: the output still ends
    // after a whole row (these were cut short about once in three when
    // the signal could end a write part-way).
    for k in 0..6 {
        let text = stopped_by_sigterm(
            &[
                "run",
                "--lesson",
                "collisions",
                "--dt",
                "1e-9",
                "--trajectory",
                "1",
            ],
            1000,
            std::time::Duration::from_millis(100 + 60 * k),
        );
        assert!(whole_rows(&text) >= 999);
    }
}

/// What `lerpit args` wrote to a file by the time it had written `lines`
/// lines, then ran on for `then`, and SIGTERM ended it (which the test
/// checks).
#[cfg(unix)]
fn stopped_by_sigterm(args: &[&str], lines: usize, then: std::time::Duration) -> String {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rows.csv");
    /// Ends the run if the test fails before it does.
    struct Running(std::process::Child);
    impl Drop for Running {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let mut child = Command::new(BIN)
        .args(args)
        .stdout(std::fs::File::create(&path).unwrap())
        .stderr(std::process::Stdio::null())
        .spawn()
        .map(Running)
        .unwrap();
    // A guard against waiting for ever, however slowly a loaded machine
    // steps.
    let patience = std::time::Instant::now() + std::time::Duration::from_secs(300);
    while std::fs::read_to_string(&path).unwrap().lines().count() < lines {
        assert!(
            std::time::Instant::now() < patience,
            "no rows handed on while running"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(then);
    // SAFETY: kill takes plain integers.
    assert_eq!(
        unsafe { libc::kill(child.0.id() as libc::pid_t, libc::SIGTERM) },
        0
    );
    let status = child.0.wait().unwrap();
    assert_eq!(status.signal(), Some(libc::SIGTERM), "{status:?}");
    std::fs::read_to_string(&path).unwrap()
}

/// The rows of CSV `text` after its header, each checked whole.
fn whole_rows(text: &str) -> usize {
    assert!(
        text.ends_with('\n'),
        "a cut row: {:?}",
        &text[text.len().saturating_sub(80)..]
    );
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let columns = rows.headers().unwrap().len();
    let mut count = 0;
    for row in rows.records() {
        assert_eq!(row.unwrap().len(), columns, "a whole row");
        count += 1;
    }
    count
}

#[test]
fn run_csv_and_text_formats() {
    let o = lerpit(&[
        "run", "--lesson", "gravity", "--steps", "3", "--format", "csv",
    ]);
    assert!(o.status.success());
    let csv = String::from_utf8(o.stdout).unwrap();
    assert_eq!(csv.lines().next(), Some("index,x,y,z,vx,vy,vz,radius,mass"));
    assert_eq!(csv.lines().count(), 151);
    let o = lerpit(&[
        "run", "--lesson", "pingpong", "--steps", "3", "--format", "text",
    ]);
    assert!(
        String::from_utf8(o.stdout)
            .unwrap()
            .contains("integrator       semi-implicit-euler")
    );
    // Every setting that changes the motion is in the text too, and the
    // last step's wall impacts as in JSON (here the ceiling's, in step
    // 27 of the ball rising at 1 m/s from y = 0.5, r = 0.05).
    let o = lerpit(&[
        "run",
        "--lesson",
        "pingpong",
        "--steps",
        "27",
        "--format",
        "text",
        "--rest-threshold",
        "0.25",
        "--restitution",
        "1",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains("\nrest threshold   0.25 m/s") && text.contains(", 1 wall impact\n"),
        "{text}"
    );
    // Its sphere, to a nanometre: at step 27 (0.45 s) the ball has turned
    // at the ceiling's reach 0.95 (at 0.45 s) and starts down.
    assert!(
        text.ends_with(
            "spheres          in scene order\n  \
               index          x m          y m          z m        vx m/s        vy m/s        \
             vz m/s  radius m     mass kg\n      \
             0  0.500000000  0.950000000  0.500000000   0.000000000  -1.000000000   \
             0.000000000   0.05000       1.000\n"
        ),
        "{text}"
    );
    // A scene of more spheres lists the first 20 and says where the rest are.
    let o = lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "0",
        "--format",
        "text",
    ]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains(
            "\nspheres          the first 20 of 100, in scene order (--format csv lists every one)\n"
        ) && text.lines().rev().take_while(|l| !l.starts_with("spheres")).count() == 21,
        "{text}"
    );
    // A scene named with a line break and a tab keeps to its one line.
    let dir = tempfile::tempdir().unwrap();
    let odd = dir.path().join("nl\nx\t.toml");
    std::fs::write(&odd, format!("[world]\n{BODY}")).unwrap();
    let o = lerpit(&["run", "--scene", odd.to_str().unwrap(), "--format", "text"]);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.starts_with("scene            nl\\nx\\t (seed 1)\n"),
        "{text}"
    );
    // Flags for pair collisions in a scene without them change nothing:
    // refused, by run and the visualiser alike, naming the flag and scene.
    let scene = scene_file(&format!("[world]\npair_collisions = false\n{BODY}"));
    let path = scene.path.to_str().unwrap();
    for (flags, said) in [
        (
            &["run", "--lesson", "pingpong", "--pair-restitution", "0.5"][..],
            "--pair-restitution 0.5: lesson pingpong has no pair collisions",
        ),
        (
            &["run", "--lesson", "gravity", "--projection-passes", "3"],
            "--projection-passes 3: lesson gravity has no pair collisions",
        ),
        (
            &["--lesson", "gravity", "--pair-restitution", "0"],
            "--pair-restitution 0: lesson gravity has no pair collisions",
        ),
        (
            &["run", "--lesson", "gravity", "--broadphase", "grid"],
            "--broadphase grid: lesson gravity has no pair collisions",
        ),
        (
            &["run", "--scene", path, "--pair-restitution", "1"],
            "has no pair collisions, so it would change nothing",
        ),
        (
            &["run", "--lesson", "pingpong", "--seed", "5"],
            "--seed 5: lesson pingpong places no sphere at random (no [[spawn]] places any), \
             so the seed would change no sphere",
        ),
    ] {
        let o = lerpit(flags);
        assert_eq!(o.status.code(), Some(2), "{flags:?}");
        let err = stderr(&o);
        assert!(err.contains(said), "{flags:?}: {err}");
    }
    let o = lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "3",
        "--pair-restitution",
        "0.5",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // So are, in run (no key can change the scene after), resting flags
    // with nothing to act on; the visualiser's keys may give them some.
    for (flags, said) in [
        (
            &["--rest-steps", "2"][..],
            "--rest-steps 2: lesson pingpong has no gravity",
        ),
        (
            &["--rest-threshold", "1"],
            "--rest-threshold 1: lesson pingpong has flip walls",
        ),
        // Gravity, but flip walls keep the speed and no pair meets.
        (
            &["--rest-steps", "2", "--gravity", "9.81"],
            "--rest-steps 2: lesson pingpong has flip walls",
        ),
    ] {
        let o = lerpit(&[&["run", "--lesson", "pingpong", "--steps", "1"], flags].concat());
        assert_eq!(o.status.code(), Some(2), "{flags:?}");
        assert!(stderr(&o).contains(said), "{flags:?}: {}", stderr(&o));
    }
    // The flag that took the gravity away is named, not the lesson.
    let o = lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "1",
        "--gravity",
        "0",
        "--rest-steps",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--rest-steps 2: with --gravity 0 there is no gravity"),
        "{}",
        stderr(&o)
    );
    for flags in [
        &[
            "--rest-steps",
            "2",
            "--gravity",
            "9.81",
            "--restitution",
            "1",
        ][..],
        // A gravity too faint to square is gravity all the same.
        &[
            "--rest-steps",
            "2",
            "--gravity",
            "1e-300",
            "--restitution",
            "1",
        ],
        &["--rest-threshold", "1", "--restitution", "0.9"],
    ] {
        let o = lerpit(&[&["run", "--lesson", "pingpong", "--steps", "1"], flags].concat());
        assert!(o.status.success(), "{flags:?}: {}", stderr(&o));
    }
    // A support pass asked for where it cannot run is refused, saying why,
    // and naming the flag that idles it.
    for (flags, why) in [
        (
            &["--lesson", "gravity"][..],
            "--support: the support pass would not run: there are no pair collisions",
        ),
        (
            &["--lesson", "collisions", "--gravity", "0"],
            "--support with --gravity 0: the support pass would not run: there is no gravity",
        ),
        (
            &["--lesson", "collisions", "--rest-steps", "0"],
            "--support with --rest-steps 0: the support pass would not run: it needs",
        ),
        (
            &["--lesson", "collisions", "--integrator", "continuous"],
            "--support with --integrator continuous: the support pass would not run: the \
             continuous method",
        ),
    ] {
        let o = lerpit(&[&["run", "--steps", "3", "--support"], flags].concat());
        assert_eq!(o.status.code(), Some(2), "{flags:?}");
        let err = String::from_utf8(o.stderr).unwrap();
        assert!(err.contains(why), "{flags:?}: {err}");
    }
    // A flag given beside that does not idle it is not named.
    let o = lerpit(&[
        "run",
        "--steps",
        "1",
        "--support",
        "--lesson",
        "gravity",
        "--gravity",
        "9.81",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o)
            .contains("--support: the support pass would not run: there are no pair collisions"),
        "{}",
        stderr(&o)
    );
    // A scene's pass that flags would leave idle: the message names the
    // one that does.
    let scene = scene_file(&format!("[world]\nsupport = true\n{BODY}"));
    let path = scene.path.to_str().unwrap();
    for (flags, named) in [
        (&["--gravity", "0"][..], "with --gravity 0 the scene's"),
        (
            &["--rest-steps", "0", "--integrator", "rk4"],
            "with --rest-steps 0 the scene's",
        ),
    ] {
        let o = lerpit(&[&["run", "--steps", "1", "--scene", path], flags].concat());
        assert_eq!(o.status.code(), Some(2), "{flags:?}");
        let err = stderr(&o);
        assert!(
            err.contains(named) && err.contains("support pass would not run"),
            "{err}"
        );
    }
    // So is sleeping where no sphere could sleep, from the flag or the
    // scene, and the flag that leaves a scene's sleeping idle is named.
    let why = "the continuous method moves every sphere to its impacts";
    let o = lerpit(&[
        "run",
        "--steps",
        "1",
        "--sleep",
        "--integrator",
        "continuous",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(&format!("--sleep: no sphere would sleep: {why}")),
        "{}",
        stderr(&o)
    );
    let scene = scene_file(&format!("[world]\nsleep = true\n{BODY}"));
    let path = scene.path.to_str().unwrap();
    let o = lerpit(&[
        "run",
        "--steps",
        "1",
        "--scene",
        path,
        "--integrator",
        "continuous",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains(&format!(
            "with --integrator continuous the scene's spheres would not sleep: {why}"
        )),
        "{}",
        stderr(&o)
    );
    assert!(
        lerpit(&["run", "--steps", "1", "--scene", path])
            .status
            .success()
    );
}

#[test]
fn scene_prints_each_lesson_as_a_file_that_parses_back() {
    for lesson in Lesson::ALL {
        let o = lerpit(&["scene", lesson.name()]);
        assert!(o.status.success());
        let text = String::from_utf8(o.stdout).unwrap();
        let parsed = parse_scene(&text, "stdout", lesson.name()).unwrap();
        assert_eq!(parsed.world, lesson.scene().world);
        assert_eq!(parsed.body_count(), lesson.scene().body_count());
    }
}

#[test]
fn no_gravity_is_reported_without_a_negative_zero() {
    for g in ["0", "-0"] {
        let v = json(&lerpit(&[
            "run",
            "--lesson",
            "gravity",
            "--steps",
            "1",
            &format!("--gravity={g}"),
        ]));
        let down = v["gravity"][1].as_f64().unwrap();
        assert!(
            down == 0.0 && down.is_sign_positive(),
            "--gravity {g}: {down}"
        );
    }
}

#[test]
fn the_readme_example_scene_runs() {
    let readme = README;
    let start = readme.find("```toml\n").expect("README has a toml example") + 8;
    let end = start + readme[start..].find("```").unwrap();
    let file = scene_file(&readme[start..end]);
    let run = |steps: &str| {
        let path = file.path.to_str().unwrap();
        json(&lerpit(&["run", "--scene", path, "--steps", steps]))
    };
    let v = run("100");
    assert_eq!(v["steps"], 100);
    assert!(v["bodies"].as_array().unwrap().len() > 1);
    // As it says, the light ball is thrown at the heavy one: a third of a
    // second in, it has bounced back off it, and the heavy one rolls on.
    let v = run("40");
    let vx = |k: usize| v["bodies"][k]["velocity"][0].as_f64().unwrap();
    assert!(
        vx(0) > 0.25 && vx(1) < -1.0,
        "heavy {}, light {}",
        vx(0),
        vx(1)
    );
}

/// Run with a scene file; expect exit 3 and every fragment in the message.
fn refused_scene(text: &str, fragments: &[&str]) {
    let file = scene_file(text);
    let o = lerpit(&[
        "run",
        "--scene",
        file.path.to_str().unwrap(),
        "--steps",
        "1",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "scene {text:?}: {err}");
    for f in fragments {
        assert!(err.contains(f), "message for {text:?} lacks {f:?}:\n{err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_scene_files_name_the_field_and_line() {
    refused_scene(
        "[world]\ngravty = [0.0, -9.81, 0.0]\n",
        &[":2:", "unknown field `gravty`"],
    );
    refused_scene(
        "[world]\ndt = \"fast\"\n",
        &[":2:", "world.dt: invalid type", "dt = \"fast\""],
    );
    // A line break in a file's name is shown escaped: the message keeps
    // its lines.
    let o = lerpit(&["run", "--scene", "no\nsuch.toml"]);
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(
        stderr(&o).trim_end(),
        "lerpit: error: no\\nsuch.toml: cannot read the scene file: No such file or \
         directory (os error 2)"
    );
    // So is a flag's value that holds an escape sequence, which had
    // reached the terminal (and was stripped off one: "invalid value '1'").
    let o = lerpit(&["run", "--steps", "1\x1b[2J"]);
    assert_eq!(o.status.code(), Some(2));
    let said = stderr(&o);
    assert!(
        said.starts_with("error: invalid value '1\\u{1b}[2J' for '--steps <STEPS>'")
            && !said.contains('\x1b'),
        "{said:?}"
    );
    // A line break in a value is escaped too, and a value of thousands of
    // characters is cut, the message kept whole to its last line.
    let o = lerpit(&["--lesson", "a\nb"]);
    let said = stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        said.starts_with("error: invalid value 'a\\nb' for '--lesson <LESSON>'"),
        "{said:?}"
    );
    let long = "9".repeat(3000);
    let o = lerpit(&["run", "--steps", &long]);
    let said = stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        said.contains("... (2800 more characters)'")
            && said.ends_with("For more information, try '--help'.\n"),
        "{said:?}"
    );
    // The reader's messages in the format's words, not Rust's types.
    for (text, said) in [
        (
            "[world]\nseed = 99999999999999999999\n",
            "world.seed: must be a whole number from 0 to 18446744073709551615, got \
             99999999999999999999",
        ),
        (
            "[world]\nsubsteps = 2.5\n",
            "world.substeps: must be a whole number from 1 to 10000, got 2.5",
        ),
        (
            "[world]\nrest_threshold = 99999999999999999999\n",
            "world.rest_threshold: 99999999999999999999 is a whole number too large to read \
             as one (TOML reads digits without a point as a 64-bit integer); write it with a \
             point or an exponent, as 1e20",
        ),
        // A whole-number field past 64 bits names its own range.
        (
            "[world]\nsubsteps = 9223372036854775808\n",
            "world.substeps: must be a whole number from 1 to 10000, got 9223372036854775808",
        ),
        (
            "[world]\nprojection_passes = -99999999999999999999999\n",
            "world.projection_passes: must be a whole number from 1 to 64, got \
             -99999999999999999999999",
        ),
        (
            "[world]\nprojection_passes = 1e3\n",
            "world.projection_passes: must be a whole number from 1 to 64, got 1e3",
        ),
        (
            "[world]\ndt = \"fast\"\n",
            "world.dt: invalid type: string \"fast\", expected a number",
        ),
        (
            "[world]\ndt = 1e400\n",
            "world.dt: the number is beyond the largest there is",
        ),
        (
            "[world]\nsupport = 3\n",
            "world.support: invalid type: integer `3`, expected true or false",
        ),
        // A section is a table: an array of its values by the order of
        // their fields was taken, each value meaning what its place meant.
        (
            "world = [[0.0, -1.0, 0.0], 0.5]\n",
            ":1:9: world: invalid type: sequence, expected a [world] table of settings",
        ),
        (
            "[[world]]\ndt = 0.01\n",
            "world: invalid type: sequence, expected a [world] table of settings",
        ),
        (
            "body = [[[0.5, 0.5, 0.5], [0.0, 0.0, 0.0], 0.05, 2.0]]\n",
            "body[0]: invalid type: sequence, expected a [[body]] table",
        ),
        (
            "spawn = [[10, [0.01, 0.02]]]\n",
            "spawn[0]: invalid type: sequence, expected a [[spawn]] table",
        ),
        (
            "lesson = [\"a\", \"b\", \"c\"]\n",
            "lesson: invalid type: sequence, expected a [lesson] table",
        ),
    ] {
        refused_scene(text, &[said]);
    }
    // A number typed non-zero is not taken as 0 where 64-bit numbers
    // cannot hold it (it turned a threshold off); a mass out of range
    // says the range.
    refused_scene(
        &format!("[world]\nrest_threshold = 1e-400\n{BODY}"),
        &[
            ":2:18: world.rest_threshold: 1e-400 is closer to 0 than a 64-bit number \
             can hold, so it reads as 0; write 0 if 0 is meant",
        ],
    );
    refused_scene(
        &format!("[world]\ngravity = [0.0, # down, far\n -1e-999, 0.0]\n{BODY}"),
        &["world.gravity: -1e-999 is closer to 0"],
    );
    let commented = scene_file(&format!(
        "[world]\ngravity = [0.0, -9.81, 0.0 # not, 1e-400\n]\n{BODY}"
    ));
    let path = commented.path.to_str().unwrap();
    let o = lerpit(&["run", "--scene", path, "--steps", "1"]);
    assert!(o.status.success(), "a comment is no number: {}", stderr(&o));
    refused_scene(
        "[world]\nbroad_phase = \"grid\"\n[[spawn]]\ncount = 10\nradius = [1e-300, 1e-300]\n",
        &["gives a sphere of radius 1e-300 a mass that must be between 1e-9 and 1e9 kg, got 0"],
    );
    // Inline tables are tables.
    let inline = scene_file(
        "world = { dt = 0.01 }\nbody = [{ position = [0.5, 0.5, 0.5], radius = 0.05, mass = 1.0 }]\n",
    );
    let path = inline.path.to_str().unwrap();
    let o = lerpit(&["run", "--scene", path, "--steps", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    refused_scene("[world\ndt = 0.1\n", &[":1:"]);
    refused_scene(
        &format!("[world]\ndt = nan\n{BODY}"),
        &[":2:", "world.dt", "finite"],
    );
    refused_scene(
        &format!("[world]\ngravity = [0.0, inf, 0.0]\n{BODY}"),
        &["world.gravity", "finite"],
    );
    // A count is a whole number, in exponent form too; the tables say
    // what they are.
    refused_scene(
        "[[spawn]]\ncount = 1.5\nradius = [0.01, 0.02]\n",
        &[
            ":2:",
            "spawn[0].count",
            "a whole number from 0 to 10000000, got 1.5",
        ],
    );
    refused_scene(
        "[[spawn]]\ncount = -3\nradius = [0.01, 0.02]\n",
        &[
            ":2:",
            "spawn[0].count",
            "a whole number from 0 to 10000000, got -3",
        ],
    );
    refused_scene(
        "[[spawn]]\ncount = 1e12\nradius = [0.001, 0.002]\n",
        &[":2:", "spawn[0].count", "from 0 to 10000000, got 1e12"],
    );
    refused_scene("world = 3\n", &[":1:", "a [world] table of settings"]);
    // Names nested deeper than the TOML reader goes are placed too.
    let deep = |parts: usize| vec!["a"; parts].join(".");
    refused_scene(
        &format!("[world]\ndt = 0.01\n\n  [{}]\n", deep(81)),
        &[":4:3:", "more than 80 dotted parts"],
    );
    refused_scene(
        &format!("{} = 1\n", deep(81)),
        &[":1:1:", "more than 80 dotted parts"],
    );
    refused_scene(&format!("[{}]\n", deep(80)), &[":1:", "unknown field `a`"]);
    // A support pass that could not run is a contradiction.
    refused_scene(
        &format!("[world]\nsupport = true\npair_collisions = false\n{BODY}"),
        &[
            ":2:",
            "world.support",
            "would not run",
            "no pair collisions",
        ],
    );
    refused_scene(
        &format!("[world]\nintegrator = \"continuous\"\nsleep = true\n{BODY}"),
        &[
            ":3:",
            "world.sleep",
            "no sphere would sleep",
            "the continuous method",
        ],
    );
    // Arrays of the wrong length are refused, a longer one as well: no
    // number is dropped unread.
    refused_scene(
        &format!("[world]\ngravity = [0.0, -9.81, 0.0, 1.0]\n{BODY}"),
        &[":2:", "world.gravity", "invalid length 4", "3 numbers"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5]\nradius = 0.1\nmass = 1.0\n",
        &[":2:", "body[0].position", "invalid length 2"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nvelocity = [1, 2, 3, 4, 5]\nradius = 0.1\nmass = 1.0\n",
        &[":3:", "body[0].velocity", "invalid length 5"],
    );
    refused_scene(
        "[[spawn]]\ncount = 3\nradius = [0.01, 0.02, 0.5]\n",
        &[":3:", "spawn[0].radius", "invalid length 3", "2 numbers"],
    );
    refused_scene(
        "[[spawn]]\ncount = 3\nradius = [0.01, 0.02]\nspeed = [0, 1, -7]\n",
        &[":4:", "spawn[0].speed", "invalid length 3"],
    );
    refused_scene(
        &format!("[world]\ndt = -0.01\n{BODY}"),
        &["world.dt", "greater than 0"],
    );
    refused_scene(
        &format!("[world]\ndt = 0\n{BODY}"),
        &["world.dt", "greater than 0"],
    );
    refused_scene(
        &format!("[world]\nwall_restitution = 1.5\n{BODY}"),
        &["world.wall_restitution", "between 0 and 1"],
    );
    refused_scene(
        &format!("[world]\npair_restitution = -0.1\n{BODY}"),
        &["world.pair_restitution"],
    );
    refused_scene(
        &format!("[world]\nintegrator = \"leapfrog\"\n{BODY}"),
        &[":2:", "leapfrog"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.0\nmass = 1.0\n",
        &[":3:", "body[0].radius"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = -2.0\n",
        &[":4:", "body[0].mass"],
    );
    refused_scene(
        "[[body]]\nposition = [0.95, 0.5, 0.5]\nradius = 0.1\nmass = 1.0\n",
        &[":2:", "body[0].position", "outside the box"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.6\nmass = 1.0\n",
        &["body[0].radius", "fit"],
    );
    refused_scene(
        "[[spawn]]\ncount = 250\nradius = [0.07, 0.07]\n",
        &["spawn[0]", "cannot fit"],
    );
    refused_scene(
        "[[spawn]]\ncount = 500\nradius = [0.1, 0.12]\n",
        &["spawn[0]", "close packing"],
    );
    refused_scene(
        "[[spawn]]\ncount = 5\nradius = [0.05, 0.01]\n",
        &["spawn[0].radius", "min must not exceed max"],
    );
    refused_scene(
        "[[spawn]]\ncount = 5\nradius = [0.01, 0.02]\nmass_law = \"constant\"\n",
        &["spawn[0].mass", "required"],
    );
    refused_scene("[world]\ndt = 0.01\n", &["no bodies"]);
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\nmass = 1e-320\n",
        &[":4:", "body[0].mass", "between"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nvelocity = [1e300, 0.0, 0.0]\nradius = 0.1\nmass = 1.0\n",
        &[":3:", "body[0].velocity", "at most"],
    );
    refused_scene(
        &format!("[world]\ngravity = [0.0, -1e300, 0.0]\n{BODY}"),
        &[":2:", "world.gravity", "at most"],
    );
    refused_scene(
        "[[spawn]]\ncount = 5\nradius = [0.01, 0.02]\ndensity = 1e308\n",
        &[":4:", "spawn[0].density", "mass"],
    );
    refused_scene(
        "[[spawn]]\ncount = 5\nradius = [0.01, 0.02]\nspeed = [0.0, 1e300]\n",
        &[":4:", "spawn[0].speed", "[0, 1e300]"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 1e300]\nradius = 0.1\nmass = 1.0\n",
        &[":2:", "[0.5, 0.5, 1e300] puts the sphere"],
    );
    refused_scene(
        &format!("{BODY}{}", BODY.replace("mass = 1.0", "mass = \"heavy\"")),
        &[":8:", "body[1].mass: invalid type"],
    );
    // A table header inside a multi-line string is text, not a table.
    refused_scene(
        &format!(
            "[lesson]\nidea = \"\"\"\n[[body]]\n\"\"\"\n{}",
            BODY.replace("mass = 1.0", "mass = \"heavy\"")
        ),
        &[":8:", "body[0].mass: invalid type"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, \"a\"]\nradius = 0.1\nmass = 1.0\n",
        &[":2:23:", "body[0].position[2]: invalid type"],
    );
    refused_scene(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.1\n",
        &[":1:", "body[0]: missing field `mass`"],
    );
}

#[test]
fn a_missing_scene_file_is_refused_with_status_3() {
    let o = lerpit(&["run", "--scene", "/nonexistent/scene.toml"]);
    assert_eq!(o.status.code(), Some(3));
    assert!(
        stderr(&o).contains("cannot read the scene file"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn bad_and_contradictory_flags_are_refused_with_status_2() {
    refused_flags(
        &["run", "--lesson", "gravity", "--scene", "x.toml"],
        &["--scene", "cannot be used with"],
    );
    refused_flags(
        &["run", "--steps", "10", "--time", "1"],
        &["--time", "cannot be used with"],
    );
    refused_flags(
        &["run", "--trace", "5", "--format", "csv"],
        &["cannot be used with"],
    );
    refused_flags(
        &["run", "--trajectory", "5", "--format", "text"],
        &["--trajectory", "cannot be used with", "--format"],
    );
    refused_flags(
        &["run", "--trajectory", "5", "--trace", "5"],
        &["--trajectory", "cannot be used with", "--trace"],
    );
    refused_flags(
        &["run", "--trajectory", "0"],
        &["--trajectory", "from 1 to"],
    );
    refused_flags(&["run", "--dt", "-1"], &["--dt", "greater than 0"]);
    refused_flags(&["run", "--dt", "NaN"], &["--dt", "finite"]);
    refused_flags(
        &["run", "--restitution", "2"],
        &["--restitution", "between 0 and 1"],
    );
    refused_flags(
        &["run", "--integrator", "rk9"],
        &["unknown integrator 'rk9'"],
    );
    refused_flags(&["run", "--lesson", "bowling"], &["bowling"]);
    refused_flags(&["run", "--steps", "many"], &["--steps"]);
    refused_flags(&["run", "--trace", "0"], &["--trace"]);
    refused_flags(&["run", "--particles", "0"], &["--particles", "from 1 to"]);
    refused_flags(&["run", "--bogus"], &["--bogus"]);
    // A non-finite negative value is not taken for short flags (-i -n -f).
    refused_flags(&["run", "--steps", "-inf"], &["'-inf' for '--steps"]);
    refused_flags(&["run", "--dt", "-NaN"], &["'-NaN' for '--dt", "finite"]);
    refused_flags(&["run", "--gravity", "1e300"], &["--gravity", "at most"]);
}

#[test]
fn runs_beyond_the_step_limit_are_refused_naming_both_values() {
    refused_flags(
        &["run", "--time", "1e30", "--dt", "1"],
        &["--time 1e30 s", "--dt 1 s", "at most 1e12"],
    );
    refused_flags(
        &["run", "--time", "1e308"],
        &["--time 1e308 s", "the scene's dt", "at most 1e12"],
    );
    refused_flags(
        &["run", "--dt", "1e-300", "--time", "1e300"],
        &["--time 1e300 s", "--dt 1e-300 s", "at most 1e12"],
    );
    refused_flags(
        &["run", "--steps", "18446744073709551615"],
        &[
            "--steps",
            "from 0 to 1000000000000",
            "got 18446744073709551615",
        ],
    );
    refused_flags(
        &["run", "--steps", "1e13"],
        &["--steps", "from 0 to 1000000000000", "got 1e13"],
    );
    // A scene's own dt with the default 1 s: the scene is at fault.
    let file = scene_file(&format!("[world]\ndt = 1e-300\n{BODY}"));
    let o = lerpit(&["run", "--scene", file.path.to_str().unwrap()]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    for needle in [
        "world.dt",
        "1 s (the default --time)",
        "1e-300",
        "at most 1e12",
    ] {
        assert!(err.contains(needle), "lacks {needle:?}: {err}");
    }
}

#[test]
fn whole_numbers_may_be_written_in_exponent_form() {
    let v = json(&lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "1e1",
        "--particles",
        "2.5e1",
        "--substeps",
        "2.0",
        "--seed",
        "7e0",
        "--threads",
        "1E0",
    ]));
    assert_eq!(v["steps"], 10);
    assert_eq!(v["bodies"].as_array().unwrap().len(), 25);
    assert_eq!(v["substeps"], 2);
    assert_eq!(v["seed"], 7);
    let o = lerpit(&[
        "run", "--lesson", "pingpong", "--steps", "3e1", "--trace", "1e1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    let steps: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| &l[..l.find(',').unwrap()])
        .collect();
    assert_eq!(steps, ["0", "10", "20", "30"]);
}

#[test]
fn every_integer_flag_of_run_names_the_flag_the_value_and_the_range() {
    let ranges = [
        ("--steps", "from 0 to 1000000000000"),
        ("--particles", "from 1 to 10000000"),
        ("--substeps", "from 1 to 10000"),
        ("--seed", "from 0 to 18446744073709551615"),
        ("--threads", "from 1 to 256"),
        ("--trace", "from 1 to 1000000000000"),
    ];
    for (flag, range) in ranges {
        for value in ["-5", "2.5", "1e-3"] {
            refused_flags(
                &["run", "--lesson", "gravity", flag, value],
                &[flag, range, &format!("got {value}")],
            );
        }
        refused_flags(
            &["run", "--lesson", "gravity", flag, "many"],
            &[flag, range, "'many'", "1e6"],
        );
    }
    // The visualiser takes the same overrides, checked the same way.
    refused_flags(
        &["--particles", "-5"],
        &["--particles", "from 1 to 10000000", "got -5"],
    );
}

#[test]
fn decimal_flags_name_the_value_as_written() {
    let o = lerpit(&["run", "--gravity", "1e308"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("--gravity") && err.contains("got 1e308"),
        "{err}"
    );
    assert!(!err.contains("got inf"), "{err}");
    refused_flags(
        &["run", "--dt", "-0.001"],
        &["--dt", "greater than 0", "-0.001"],
    );
    refused_flags(
        &["run", "--rest-threshold", "-1"],
        &["--rest-threshold", "0 or more"],
    );
    refused_flags(
        &["run", "--time", "fast"],
        &["--time", "must be a number", "'fast'"],
    );
}

/// The radii of `lesson`'s spheres with `--particles n`, after one step.
fn radii_with_particles(lesson: &str, n: &str) -> Vec<f64> {
    let o = lerpit(&[
        "run",
        "--lesson",
        lesson,
        "--particles",
        n,
        "--steps",
        "1",
        "--format",
        "csv",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(7).unwrap().parse().unwrap())
        .collect()
}

#[test]
fn particles_sizes_the_spheres_to_keep_the_scene_s_solid_fraction() {
    // The gravity lesson's 150 spheres have radii in [0.012, 0.02] m; 15,000
    // of them would fill 27% of the box at that size (and found no room
    // before). As `+` does, the flag scales every radius by cbrt(150/15000).
    let f = (150.0_f64 / 15000.0).cbrt();
    let radii = radii_with_particles("gravity", "15000");
    assert_eq!(radii.len(), 15000);
    for r in radii {
        assert!(
            (0.012 * f * (1.0 - 1e-12)..=0.02 * f * (1.0 + 1e-12)).contains(&r),
            "radius {r} outside [{}, {}]",
            0.012 * f,
            0.02 * f
        );
    }
    // A scene of explicit bodies only (the ping-pong ball): more spheres
    // like it, each sized cbrt(1/5) of it.
    let radii = radii_with_particles("pingpong", "5");
    assert_eq!(radii.len(), 5);
    for r in radii {
        assert!((r - 0.05 * (0.2_f64).cbrt()).abs() < 1e-15, "radius {r}");
    }
}

#[test]
fn a_scene_too_full_for_its_spheres_says_what_to_do() {
    // A scene file's remedy is the file's own field.
    refused_scene(
        "[[spawn]]\ncount = 250\nradius = [0.07, 0.07]\n",
        &["spawn[0]", "cannot fit", "set overlap = true"],
    );
    refused_scene(
        "[[spawn]]\ncount = 300\nradius = [0.07, 0.07]\n",
        &["spawn[0]", "fill 43%", "jam (38.5%", "set overlap = true"],
    );
    // Too many to fit is said before what running them would cost, which
    // no flag could help.
    refused_scene(
        "[[spawn]]\ncount = 100000\nradius = [0.05, 0.05]\n",
        &["spawn[0]", "fill 5236%"],
    );
}

#[test]
fn only_a_regular_scene_file_of_at_most_16_mib_is_read() {
    for (path, kind) in [("/dev/zero", "a character device"), ("/tmp", "a folder")] {
        if !std::path::Path::new(path).exists() {
            continue;
        }
        let o = lerpit(&["run", "--scene", path]);
        assert_eq!(o.status.code(), Some(3), "{path}");
        assert!(
            stderr(&o).contains(&format!("it is {kind}, not a regular file")),
            "{path}: {}",
            stderr(&o)
        );
    }

    // 17 MiB, sparse: nothing is written but its length.
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.toml");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(17 * 1024 * 1024)
        .unwrap();
    let o = lerpit(&["run", "--scene", big.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3));
    let err = stderr(&o);
    assert!(
        err.contains("17825792 bytes") && err.contains("at most 16777216 (16 MiB)"),
        "{err}"
    );

    let bad = dir.path().join("latin1.toml");
    std::fs::write(&bad, b"[world]\ndt = 0.01 # \xe9\n").unwrap();
    let o = lerpit(&["run", "--scene", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains("not UTF-8"), "{}", stderr(&o));
}

#[test]
fn a_named_pipe_is_refused_without_waiting_for_a_writer() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("scene.toml");
    match Command::new("mkfifo").arg(&fifo).status() {
        Ok(s) if s.success() => {}
        _ => {
            eprintln!("skipped: mkfifo is not available");
            return;
        }
    }
    // Were the pipe opened, this would wait for ever: no one writes to it.
    let o = lerpit(&["run", "--scene", fifo.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3));
    assert!(
        stderr(&o).contains("a named pipe (FIFO), not a regular file"),
        "{}",
        stderr(&o)
    );
}

fn many_spheres(count: usize, broad_phase: &str) -> String {
    format!(
        "[world]\npair_collisions = true\nbroad_phase = \"{broad_phase}\"\n\n\
         [[spawn]]\ncount = {count}\nradius = [0.001, 0.001]\noverlap = true\n"
    )
}

/// `run --scene PATH --steps 1` with `more` flags: its JSON.
fn one_step_of(path: &str, more: &[&str]) -> serde_json::Value {
    let mut args = vec!["run", "--scene", path, "--steps", "1"];
    args.extend_from_slice(more);
    json(&lerpit(&args))
}

#[test]
fn a_grid_sized_by_one_large_sphere_needs_allow_slow_as_all_pairs_does() {
    // One sphere of radius 0.3 makes one cell of the box: 6,001 small
    // spheres beside it would be tested every pair with every pair.
    let text = "[world]\npair_collisions = true\nbroad_phase = \"grid\"\n\n[[body]]\n\
                position = [0.5, 0.5, 0.5]\nradius = 0.3\nmass = 1.0\n\n[[spawn]]\n\
                count = 6000\nradius = [0.002, 0.003]\n";
    let file = scene_file(text);
    let path = file.path.to_str().unwrap();
    refused_flags(
        &["run", "--scene", path, "--steps", "1"],
        &[
            "the grid with 6,001 spheres would test about 18,003,000 pairs a step (3,000 a sphere)",
            "largest sphere (radius 0.3 m), so 1x1x1 cells",
            "--allow-slow",
        ],
    );
    let v = one_step_of(path, &["--allow-slow"]);
    assert_eq!(v["pair_tests"], 18_003_000);
    // With 5,000 in all, no more than all-pairs may test: no flag needed.
    let v = one_step_of(path, &["--particles", "5000"]);
    assert_eq!(v["pair_tests"], 12_497_500);
    // The visualiser refuses it the same way.
    let out = lerpit(&["--scene", path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("the grid with 6,001 spheres"));
}

#[test]
fn all_pairs_over_5000_spheres_needs_allow_slow() {
    refused_flags(
        &[
            "run",
            "--lesson",
            "collisions",
            "--particles",
            "5001",
            "--broadphase",
            "all-pairs",
        ],
        &[
            "--broadphase all-pairs",
            "5,001 spheres",
            "12,502,500 pairs",
            "--allow-slow",
        ],
    );
    // From the scene file too, and only when a step will run.
    let file = scene_file(&many_spheres(5001, "all-pairs"));
    let path = file.path.to_str().unwrap();
    refused_flags(
        &["run", "--scene", path, "--steps", "1"],
        &[
            "the scene's broad phase all-pairs",
            "12,502,500 pairs",
            "--allow-slow",
        ],
    );
    let v = json(&lerpit(&["run", "--scene", path, "--steps", "0"]));
    assert_eq!(v["steps"], 0);
    let v = one_step_of(path, &["--allow-slow"]);
    assert_eq!(v["pair_tests"], 12_502_500);
    // At the limit, and with the grid, no flag is needed.
    let file = scene_file(&many_spheres(5000, "all-pairs"));
    let v = one_step_of(file.path.to_str().unwrap(), &[]);
    assert_eq!(v["broad_phase"], "all-pairs");
    let v = one_step_of(path, &["--broadphase", "grid"]);
    assert_eq!(v["broad_phase"], "grid");
}

#[test]
fn a_scene_file_too_large_to_read_in_the_memory_left_is_refused_before_reading() {
    // 3 MB of one array of numbers took 235 MB to read (its bound 399
    // MB): under a 100 MB address-space limit the reader had aborted
    // part-way (status 134); the file is refused as a bad scene, saying
    // why.
    let mut text = String::from("[world]\ngravity = [");
    while text.len() < 3_000_000 {
        text.push_str("0,");
    }
    text.push_str("0]\n");
    let file = scene_file(&text);
    let o = lerpit_within(100_000, &["run", "--scene", file.path.to_str().unwrap()]);
    let said = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{said}");
    assert!(
        said.contains(
            "cannot read the scene file: reading its 3 MB may take up to 399 MB of memory"
        ) && said.contains("(the address-space limit, ulimit -v)")
            && said.trim_end().ends_with("Use a smaller file"),
        "{said}"
    );
}

#[test]
fn spheres_piled_on_one_another_are_the_scenes_fault_before_any_cost() {
    // 40,000 spheres of 5 cm overlapping: the grid would test 23 million
    // pairs a step, and all-pairs 6,000 of radius 0.1 more than allowed,
    // but --allow-slow would not make either run: status 3 at once, with
    // no word of --allow-slow, from run and the visualiser alike.
    for (count, radius, broad_phase) in [(40_000, 0.05, "grid"), (6000, 0.1, "all-pairs")] {
        let text = format!(
            "[world]\npair_collisions = true\nbroad_phase = \"{broad_phase}\"\n\n\
             [[spawn]]\ncount = {count}\nradius = [{radius}, {radius}]\noverlap = true\n"
        );
        let file = scene_file(&text);
        let path = file.path.to_str().unwrap();
        for args in [
            vec!["run", "--scene", path, "--steps", "1"],
            vec!["--scene", path],
        ] {
            let out = lerpit(&args);
            let err = stderr(&out);
            assert_eq!(out.status.code(), Some(3), "{args:?}: {err}");
            assert!(
                err.contains("start piled on one another") && !err.contains("--allow-slow"),
                "{args:?}: {err}"
            );
        }
    }
}

#[test]
fn bodies_piled_at_one_point_are_refused_before_the_first_step() {
    let pile: String = (0..300)
        .map(|_| "[[body]]\nposition = [0.5, 0.5, 0.5]\nradius = 0.01\nmass = 1.0\n")
        .collect();
    refused_scene(
        &pile,
        &[
            "300 spheres start piled on one another",
            "more than 19,200 overlapping pairs",
            "64 a sphere",
            "300 bodies share the point [0.5, 0.5, 0.5]",
        ],
    );
    // The same bodies without pair collisions never collect contacts.
    let v = json(&lerpit(&[
        "run",
        "--scene",
        scene_file(&format!("[world]\npair_collisions = false\n{pile}"))
            .path
            .to_str()
            .unwrap(),
        "--steps",
        "1",
    ]));
    assert_eq!(v["bodies"].as_array().unwrap().len(), 300);
    // A dense but physical start is accepted: spheres may overlap a few
    // neighbours each.
    let v = json(&lerpit(&[
        "run",
        "--scene",
        scene_file(&many_spheres(3000, "grid").replace("0.001, 0.001", "0.03, 0.03"))
            .path
            .to_str()
            .unwrap(),
        "--steps",
        "1",
    ]));
    assert_eq!(v["bodies"].as_array().unwrap().len(), 3000);
}

#[test]
fn a_standard_output_closed_at_the_start_is_status_1_for_every_command() {
    // Closed by the shell that then becomes lerpit: the runtime opens
    // /dev/null in its place, which took everything silently (status 0).
    let closed = |args: &[&str]| {
        Command::new("sh")
            .arg("-c")
            .arg("exec \"$@\" >&-")
            .arg("sh")
            .arg(crate::support::BIN)
            .args(args)
            .output()
            .expect("sh runs")
    };
    for args in [
        &["run", "--steps", "1"][..],
        &["scene", "gravity"],
        &["--help"],
        &["bench", "--particles", "100", "--steps", "1"],
        &["study", "--quick"],
    ] {
        let o = closed(args);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("standard output was closed when lerpit started"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // A bad command line stays a bad command line.
    assert_eq!(closed(&["--bogus"]).status.code(), Some(2));
    // Sent to /dev/null, it runs as ever.
    let o = Command::new(crate::support::BIN)
        .args(["run", "--steps", "1"])
        .stdout(std::process::Stdio::null())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn output_that_cannot_be_written_is_status_1_for_every_command() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("skipped: no /dev/full");
        return;
    };
    for args in [
        &["--help"][..],
        &["--version"],
        &["run", "--help"],
        &["scene", "gravity"],
        &["run", "--steps", "3"],
        &["run", "--steps", "3", "--format", "text"],
        &["run", "--steps", "3", "--format", "csv"],
        &["run", "--steps", "3", "--trace", "1"],
        &["bench", "--particles", "200", "--steps", "1"],
        &[
            "bench",
            "--particles",
            "200",
            "--steps",
            "1",
            "--format",
            "json",
        ],
    ] {
        let o = Command::new(BIN)
            .args(args)
            .stdout(full.try_clone().unwrap())
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert!(
            stderr(&o).contains("cannot write the output"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

/// How `child` ended without its reader: within a minute, or the test
/// fails saying `what` went on.
fn ended_alone(mut child: std::process::Child, what: &str) -> std::process::ExitStatus {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if std::time::Instant::now() > deadline {
            child.kill().unwrap();
            panic!("{what} went on without its reader");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

#[test]
fn a_reader_that_stops_early_is_no_error() {
    use std::io::{BufRead, BufReader};
    // Far more than a pipe holds: the writes after the reader leaves fail.
    let mut child = Command::new(BIN)
        .args([
            "run",
            "--lesson",
            "gravity",
            "--particles",
            "5000",
            "--steps",
            "0",
            "--format",
            "csv",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("index,"), "{first}");
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stderr(&o), "");

    // A trace whose next row is a billion steps away still ends once its
    // reader has gone, as a write would have found: it ran on until then.
    let mut child = Command::new(BIN)
        .args(["run", "--steps", "1e12", "--trace", "1e9"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    let mut reader = BufReader::new(child.stdout.take().unwrap());
    reader.read_line(&mut first).unwrap();
    assert!(first.starts_with("step,time,"), "{first}");
    drop(reader);
    assert_eq!(ended_alone(child, "the run").code(), Some(0));

    // So does a benchmark of a billion steps, which prints only at its end.
    let readerless = |args: &[&str]| {
        let mut child = Command::new(BIN)
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        ended_alone(child, args[0]).code()
    };
    assert_eq!(
        readerless(&["bench", "--particles", "1000", "--steps", "1e9"]),
        Some(0)
    );

    // And the stability study (minutes long), whose tables come at its end.
    assert_eq!(readerless(&["study", "--stability"]), Some(0));

    // One writing files goes on to write them.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().to_str().unwrap();
    assert_eq!(readerless(&["study", "--quick", "--out", out]), Some(0));
    for name in ["sweep.csv", "conservation.csv", "conservation.svg"] {
        assert!(dir.path().join(name).is_file(), "{name} written");
    }
}

#[test]
fn resting_contact_and_projection_passes_are_checked_in_flags_and_scene_files() {
    refused_flags(
        &["run", "--rest-steps", "11"],
        &["--rest-steps", "from 0 (off) to 10", "11"],
    );
    refused_flags(
        &["run", "--projection-passes", "0"],
        &["--projection-passes", "from 1 to 64", "0"],
    );
    refused_scene(
        &format!("[world]\nrest_steps = -1\n\n{BODY}"),
        &["2:14", "world.rest_steps", "from 0 (off) to 10"],
    );
    refused_scene(
        &format!("[world]\nprojection_passes = 65\n\n{BODY}"),
        &["world.projection_passes", "from 1 to 64, got 65"],
    );
    let v = json(&lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--rest-steps",
        "0",
        "--projection-passes",
        "4",
        "--steps",
        "10",
    ]));
    assert_eq!(v["steps"], 10);
    assert_eq!(v["rest_steps"], 0.0, "the report says what ran");
    assert_eq!(v["projection_passes"], 4);
}

#[test]
fn a_spawn_count_may_be_written_in_exponent_form() {
    let file = scene_file("[[spawn]]\ncount = 1.2e2\nradius = [0.01, 0.02]\n");
    let o = lerpit(&[
        "run",
        "--scene",
        file.path.to_str().unwrap(),
        "--steps",
        "1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(json(&o)["bodies"].as_array().map(Vec::len), Some(120));
}

#[test]
fn a_scene_too_large_for_the_memory_limit_is_refused_before_its_spheres_are_placed() {
    // Ten million spheres take about 2.6 GB before any contact; under an
    // address-space limit of 500 MB placing them would abort.
    let scene = scene_file(
        "[world]\nbroad_phase = \"grid\"\n\
         [[spawn]]\ncount = 10000000\nradius = [0.001, 0.001]\noverlap = true\n",
    );
    let o = lerpit_within(
        500000,
        &[
            "run",
            "--scene",
            scene.path.to_str().unwrap(),
            "--steps",
            "1",
        ],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(3), "{err}");
    assert!(
        err.contains("the scene's 10,000,000 spheres need about 2.6 GB of memory")
            && err.contains("(the address-space limit, ulimit -v")
            && err.ends_with("Use fewer spheres\n"),
        "{err}"
    );
}

#[test]
fn drawing_a_settled_pile_too_large_for_the_memory_limit_is_refused_before_it_is_built() {
    // The pile's first step holds its overlapping pairs (about 1.45 GB
    // of the 1.7 GB that drawing a million spheres needs, with the frame
    // and the history), refused at once under a 600 MB limit (ten million
    // took 37 s to build before the world refused them, advising to spread
    // them out).
    let o = lerpit_within(
        600000,
        &[
            "bench",
            "--render",
            "--start",
            "settled",
            "--particles",
            "1000000",
            "--frames",
            "1",
        ],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains(
            "drawing the settled pile of 1,000,000 spheres (its first step holds about \
             23,945,749 overlapping pairs) needs about 1.7 GB of memory"
        ) && err.contains("(the address-space limit, ulimit -v")
            && err.ends_with("Use fewer spheres, or the dilute start\n"),
        "{err}"
    );
}

#[test]
fn memory_that_runs_out_part_way_ends_the_run_with_a_message_and_status_1() {
    // 300,000 spheres fit the first step, and the support pass's pairs
    // then grow with the pile they fall into, past 150 MB (without the
    // limit the run's resident memory reaches 288 MB by step 20). Rust
    // alone would print the size and abort (134).
    let scene = scene_file(
        "[world]\ngravity = [0.0, -9.81, 0.0]\ndt = 0.016666666666666666\n\
         pair_collisions = true\nbroad_phase = \"grid\"\nseed = 3\n\
         [[spawn]]\ncount = 300000\nradius = [0.004, 0.004]\n",
    );
    let path = scene.path.to_str().unwrap();
    let o = lerpit_within(
        150000,
        &["run", "--scene", path, "--support", "--steps", "20"],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(o.stdout.is_empty(), "no half report");
    assert!(
        err.starts_with("lerpit: error: memory ran out: an allocation of ")
            && err.contains(" failed; the address-space limit (ulimit -v) is 154 MB. ")
            && err.ends_with("Use fewer spheres, or raise the limit\n")
            && err.lines().count() == 1,
        "{err}"
    );
}

#[test]
fn output_past_the_file_size_limit_is_said_with_status_1() {
    // Under `ulimit -f 4` (2 or 4 KiB) a run's report fills the file: the write
    // fails and says so, where SIGXFSZ had ended the program (153) with
    // nothing said. A study's files are then not written at all.
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report.json");
    let o = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 4 && exec \"$0\" \"$@\" > \"$REPORT\"")
        .arg(BIN)
        .args(["run", "--lesson", "collisions", "--steps", "1"])
        .env("REPORT", &report)
        .output()
        .expect("sh runs");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.starts_with("lerpit: error: cannot write the output: File too large"),
        "{err}"
    );
    // The limit's blocks are the shell's: 512 or 1024 bytes.
    let written = std::fs::metadata(&report).unwrap().len();
    assert!(written == 2048 || written == 4096, "{written} bytes");
    let out = dir.path().join("study");
    let o = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 4 && exec \"$0\" \"$@\" > /dev/null")
        .arg(BIN)
        .args(["study", "--quick", "--out", out.to_str().unwrap()])
        .output()
        .expect("sh runs");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("File too large"), "{err}");
    assert_eq!(
        std::fs::read_dir(&out).unwrap().count(),
        0,
        "no file of the study"
    );
}

#[test]
fn a_lone_large_sphere_is_placed_and_a_bodies_only_scene_says_where_more_do_not_fit() {
    // One spawned sphere of 0.46 m fills 41% of the box, beyond where many
    // would jam, but alone it fits.
    let lone = scene_file("[[spawn]]\ncount = 1\nradius = [0.46, 0.46]\n");
    let o = lerpit(&[
        "run",
        "--scene",
        lone.path.to_str().unwrap(),
        "--steps",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A scene of one body: --particles adds spheres like it, in a spawn of
    // no line of the file.
    let body = scene_file(
        "[[body]]\nposition = [0.5, 0.5, 0.5]\nvelocity = [0.0, 0.0, 0.0]\nradius = 0.5\nmass = 1.0\n",
    );
    let path = body.path.to_str().unwrap();
    let o = refused(
        &["run", "--scene", path, "--particles", "2"],
        3,
        &[
            "the spheres added like body[0]: cannot fit 1 non-overlapping sphere in the box",
            "or add a [[spawn]] entry with overlap = true to the scene",
        ],
    );
    let err = stderr(&o);
    assert!(!err.contains(":0:") && !err.contains("spawn[0]"), "{err}");
}

#[test]
fn flip_walls_say_a_restitution_they_do_not_use() {
    let flip = scene_file(&format!(
        "[world]\nwall_mode = \"flip\"\nwall_restitution = 0.5\n\n{BODY}"
    ));
    let o = lerpit(&[
        "run",
        "--scene",
        flip.path.to_str().unwrap(),
        "--format",
        "text",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(
            "walls            flip (keep the speed; wall_restitution 0.5 applies to restitution walls only)"
        ),
        "{text}"
    );
}
