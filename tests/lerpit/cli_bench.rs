//! `lerpit bench` and the broad-phase choice from the command line and
//! scene files, through the real binary.

use crate::support::{
    BODY, json, lerpit, lerpit_within, refused_flags, scene_file, stderr, stdout,
};

#[test]
fn bench_json_reports_every_field() {
    let o = lerpit(&[
        "bench",
        "--particles",
        "2000",
        "--steps",
        "3",
        "--threads",
        "2",
        "--broadphase",
        "grid",
        "--format",
        "json",
    ]);
    let v = json(&o);
    assert_eq!(v["particles"], 2000);
    assert_eq!(v["start"], "dilute");
    assert_eq!(v["warmup"], 0);
    assert_eq!(v["steps"], 3);
    assert_eq!(v["threads"], 2);
    assert_eq!(v["broadphase"], "grid");
    for field in [
        "seconds",
        "sphere_steps_per_s",
        "ns_per_sphere_step",
        "pair_tests_per_step",
        "contacts_per_step",
        "contacts_per_sphere",
    ] {
        assert!(
            v[field].as_f64().is_some_and(|x| x >= 0.0),
            "{field}: {}",
            v[field]
        );
    }
    if cfg!(target_os = "linux") {
        assert!(v["peak_rss_bytes"].as_u64().is_some_and(|b| b > 0));
    }
    // Each stage is timed inside the timed steps: the stages a grid world
    // without the continuous method runs (each over a microsecond, so more
    // than 0 s on a clock that sees microseconds), none of those it does
    // not run, and together no more than the whole (but for the rounding
    // of their sum, far below a nanosecond).
    let stages = &v["stage_seconds"];
    let fine = crate::support::stage_clock_is_fine();
    let mut sum = 0.0;
    for (stage, ran) in [
        ("integrate", true),
        ("broad_phase", true),
        ("narrow_phase", true),
        ("solve_contacts", true),
        // 2,000 spheres: a small world, so the two stages, not the sweep.
        ("narrow_and_solve", false),
        ("walls", true),
        ("events", false),
    ] {
        let t = stages[stage].as_f64().expect(stage);
        if ran {
            assert!(t > 0.0 || (!fine && t == 0.0), "{stage}: {t}");
        } else {
            assert_eq!(t, 0.0, "{stage}");
        }
        sum += t;
    }
    let whole = v["seconds"].as_f64().unwrap();
    assert!(sum <= whole * (1.0 + 1e-9), "{stages}");
    assert_eq!(v["support_unsettled_per_step"], 0.0, "no support pass");
    let per_sphere = v["contacts_per_step"].as_f64().unwrap() / 2000.0;
    assert!((v["contacts_per_sphere"].as_f64().unwrap() - per_sphere).abs() < 1e-12);
    // The run's description first, in this order.
    let text = stdout(&o);
    let at: Vec<usize> = ["particles", "start", "warmup", "steps", "runs"]
        .iter()
        .map(|k| text.find(&format!("\"{k}\":")).expect(k))
        .collect();
    assert!(at.is_sorted(), "{text}");
}

/// `lerpit bench` with `extra` flags at 3,000 spheres, 2 timed steps.
fn bench_json(extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["bench", "--particles", "3000", "--steps", "2"];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["--format", "json"]);
    let o = lerpit(&args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    serde_json::from_str(&stdout(&o)).expect("JSON output")
}

#[test]
fn a_large_bench_world_finds_and_solves_its_contacts_in_one_sweep() {
    // From `SPATIAL_ORDER_MIN_BODIES` spheres the benchmark times the sweep
    // instead of the two stages, in the steps where nothing reads the
    // contacts before they are all resolved; with `--keep-contacts` too
    // (the sweep lists them as it goes, after the untimed first step ran
    // the two stages to size the list), with the same bits.
    let n = lerpit::sim::large::SPATIAL_ORDER_MIN_BODIES.to_string();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "bench",
            "--particles",
            &n,
            "--steps",
            "2",
            "--start",
            "settled",
            "--awake",
            "--format",
            "json",
        ];
        args.extend_from_slice(extra);
        let o = lerpit(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str::<serde_json::Value>(&stdout(&o)).expect("JSON output")
    };
    let (swept, listed) = (run(&[]), run(&["--keep-contacts"]));
    assert_eq!(swept["keep_contacts"], false);
    assert_eq!(listed["keep_contacts"], true);
    for v in [&swept, &listed] {
        let stages = &v["stage_seconds"];
        let ran = |stage: &str| stages[stage].as_f64().unwrap() > 0.0;
        // The sweep takes milliseconds: on a clock that sees them, more
        // than 0 s. The two stages never ran in a timed step: exactly 0 s.
        if crate::support::stage_clock_is_fine() {
            assert!(ran("narrow_and_solve"), "{stages}");
        }
        assert!(!ran("narrow_phase") && !ran("solve_contacts"), "{stages}");
        assert!(v["contacts_per_sphere"].as_f64().unwrap() > 1.0, "{v}");
    }
    for field in ["state_hash", "contacts_per_step", "pair_tests_per_step"] {
        assert_eq!(swept[field], listed[field], "{field}");
    }
}

#[test]
fn bench_starts_settled_with_several_times_the_contacts() {
    let dilute = bench_json(&[]);
    let settled = bench_json(&["--start", "settled"]);
    assert_eq!(settled["start"], "settled");
    let contacts = |v: &serde_json::Value| v["contacts_per_sphere"].as_f64().unwrap();
    assert!(
        contacts(&settled) > 3.0 * contacts(&dilute),
        "settled {} against dilute {}",
        contacts(&settled),
        contacts(&dilute)
    );
    assert_ne!(settled["state_hash"], dilute["state_hash"]);
    assert_eq!(
        bench_json(&["--start", "settled"])["state_hash"],
        settled["state_hash"]
    );

    // Untimed steps move the timed ones on: 2 warm-up then 2 timed steps
    // end where 4 timed steps do.
    let warm = bench_json(&["--start", "settled", "--warmup", "2"]);
    assert_eq!(warm["warmup"], 2);
    assert_eq!(warm["steps"], 2);
    let o = lerpit(&[
        "bench",
        "--particles",
        "3e3",
        "--steps",
        "4",
        "--start",
        "settled",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let four: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
    assert_eq!(warm["state_hash"], four["state_hash"]);
}

#[test]
fn bench_text_names_the_start_and_the_contacts_per_sphere() {
    let o = lerpit(&[
        "bench",
        "--particles",
        "500",
        "--steps",
        "1",
        "--start",
        "settled",
        "--warmup",
        "3",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    for needle in [
        "start                settled",
        "(after 4 untimed: 1 + --warmup 3)",
        "contacts per sphere  ",
    ] {
        assert!(out.contains(needle), "lacks {needle:?}: {out}");
    }
    assert!(!out.contains("support pass"), "{out}");
}

#[test]
fn bench_text_says_the_settled_start_is_not_the_support_pass_pile() {
    let run = |start: &str| {
        let o = lerpit(&[
            "bench",
            "--particles",
            "300",
            "--steps",
            "1",
            "--support",
            "--start",
            start,
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    let note = "--start dilute --warmup 600 times the pass's own pile";
    let settled = run("settled");
    assert!(settled.contains("support pass         on"), "{settled}");
    assert!(settled.contains(note), "{settled}");
    let dilute = run("dilute");
    assert!(dilute.contains("support pass         on"), "{dilute}");
    assert!(!dilute.contains(note), "{dilute}");
}

#[test]
fn bench_state_is_the_same_for_one_and_three_threads() {
    let hash = |threads: &str| {
        let o = lerpit(&[
            "bench",
            "--particles",
            "5000",
            "--steps",
            "4",
            "--threads",
            threads,
            "--format",
            "json",
        ]);
        let v = json(&o);
        v["state_hash"].as_str().expect("a hash").to_string()
    };
    assert_eq!(hash("1"), hash("3"));
}

#[test]
fn a_small_sweep_prints_the_table_and_the_crossover() {
    let o = lerpit(&["bench", "--sweep", "--sweep-max", "400", "--steps", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit()))
        .collect();
    // N = 100 and 316, each dilute with all-pairs, grid and auto, and
    // settled with auto.
    assert_eq!(rows.len(), 8, "{out}");
    let starts: Vec<&str> = rows
        .iter()
        .map(|r| r.split_whitespace().nth(1).unwrap())
        .collect();
    assert_eq!(
        starts,
        ["dilute", "dilute", "dilute", "settled"].repeat(2),
        "{out}"
    );
    assert!(out.contains("crossover:"), "{out}");
    assert!(
        out.contains("auto time per step at N = 316, settled start over dilute start:"),
        "{out}"
    );

    let o = lerpit(&[
        "bench",
        "--sweep",
        "--sweep-max",
        "100",
        "--steps",
        "1",
        "--format",
        "json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON output");
    let starts: Vec<&str> = v["results"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["start"].as_str().unwrap())
        .collect();
    assert_eq!(starts, ["dilute", "dilute", "dilute", "settled"]);
    assert!(v["settled_time_ratio"].as_f64().is_some_and(|x| x > 0.0));
}

#[test]
fn bad_bench_flags_exit_2_naming_the_flag() {
    for (args, needle) in [
        (&["bench", "--threads", "0"][..], "--threads"),
        (
            &["bench", "--broadphase", "octree"],
            "unknown broad phase 'octree'",
        ),
        (&["bench", "--particles", "0"], "--particles"),
        (&["bench", "--steps", "0"], "--steps"),
        (&["bench", "--sweep", "--particles", "10"], "--particles"),
        (
            &["bench", "--particles", "-5"],
            "from 1 to 10000000, got -5",
        ),
        (&["bench", "--particles", "2.5"], "--particles"),
        (&["bench", "--steps", "-1"], "--steps"),
        (
            &["bench", "--steps", "1.5"],
            "from 1 to 999999999999, got 1.5",
        ),
        (&["bench", "--threads", "-2"], "from 1 to 256, got -2"),
        (&["bench", "--threads", "two"], "'two'"),
        (
            &["bench", "--sweep", "--sweep-max", "50"],
            "from 100 to 10000000, got 50",
        ),
        (&["bench", "--render", "--width", "-1"], "--width"),
        (
            &["bench", "--render", "--height", "1e4"],
            "from 1 to 1000, got 1e4",
        ),
        (&["bench", "--render", "--frames", "0.5"], "--frames"),
        (
            &["bench", "--width", "10"],
            "--width sizes the drawing that --render times",
        ),
        (
            &["bench", "--frames", "3", "--particles", "100"],
            "--frames sizes the drawing that --render times",
        ),
        (
            &["bench", "--start", "pile"],
            "unknown start state 'pile'; choose one of dilute, settled",
        ),
        (
            &["bench", "--steps", "1", "--sweep-max", "1000"],
            "--sweep-max sizes the largest run of --sweep",
        ),
        (
            &["bench", "--sleep", "--particles", "100"],
            "--sleep would change nothing: bench sleeps spheres unless --awake",
        ),
        (&["bench", "--sweep", "--start", "settled"], "--start"),
        (
            &["bench", "--warmup", "-1"],
            "from 0 to 999999999998, got -1",
        ),
        (&["bench", "--warmup", "2.5"], "--warmup"),
        (&["bench", "--warmup", "many"], "'many'"),
        (
            &["bench", "--warmup", "1e12", "--steps", "1"],
            "from 0 to 999999999998, got 1e12",
        ),
        (
            &["bench", "--steps", "1e12"],
            "from 1 to 999999999999, got 1e12",
        ),
        (
            &["bench", "--warmup", "999999999998", "--steps", "2"],
            "make 1000000000001 steps with the first untimed one; at most 1000000000000 are \
             allowed",
        ),
    ] {
        refused_flags(args, &[needle]);
    }
}

#[test]
fn bench_takes_whole_numbers_in_exponent_form() {
    let o = lerpit(&[
        "bench",
        "--particles",
        "2e2",
        "--steps",
        "2e0",
        "--format",
        "json",
    ]);
    let v = json(&o);
    assert_eq!(v["particles"], 200);
    assert_eq!(v["steps"], 2);
}

#[test]
fn bench_all_pairs_over_5000_spheres_needs_allow_slow() {
    refused_flags(
        &["bench", "--particles", "5001", "--broadphase", "all-pairs"],
        &[
            "5,001 spheres",
            "12,502,500 pairs",
            "--allow-slow",
            "--broadphase grid",
        ],
    );
    // The default size, 100,000, is refused the same way.
    refused_flags(
        &["bench", "--broadphase", "all-pairs"],
        &["4,999,950,000 pairs"],
    );

    let o = lerpit(&[
        "bench",
        "--particles",
        "5001",
        "--broadphase",
        "all-pairs",
        "--allow-slow",
        "--steps",
        "1",
        "--format",
        "json",
    ]);
    let v = json(&o);
    assert_eq!(v["broadphase"], "all-pairs");
    assert_eq!(v["pair_tests_per_step"].as_f64(), Some(12_502_500.0));
}

#[test]
fn run_takes_the_broad_phase_from_the_flag_and_the_scene_file() {
    let o = lerpit(&[
        "run",
        "--lesson",
        "collisions",
        "--steps",
        "10",
        "--broadphase",
        "grid",
        "--threads",
        "2",
    ]);
    let v = json(&o);
    assert_eq!(v["broad_phase"], "grid");
    assert!(v["pair_tests"].as_u64().is_some_and(|t| t < 4950));

    let good = scene_file(&format!("[world]\nbroad_phase = \"auto\"\n{BODY}"));
    let bad = scene_file(&format!("[world]\nbroad_phase = \"octree\"\n{BODY}"));

    let o = lerpit(&[
        "run",
        "--scene",
        good.path.to_str().unwrap(),
        "--steps",
        "1",
    ]);
    let v = json(&o);
    assert_eq!(v["broad_phase"], "auto");

    let o = lerpit(&["run", "--scene", bad.path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(3));
    assert!(stderr(&o).contains(":2:"), "{}", stderr(&o));
}

#[test]
fn bench_under_an_address_space_limit_refuses_what_cannot_fit_with_status_1() {
    // Ten million spheres do not fit under 2 GB: refused before they are
    // placed, not aborted. The drawing bench counts the visualiser's frame
    // and history the same way, and a refusal for memory is status 1
    // there too (it was 2).
    for args in [
        "bench --particles 1e7 --steps 1 --threads 64",
        "bench --render --particles 1e7 --frames 1",
    ] {
        let o = lerpit_within(2000000, &args.split(' ').collect::<Vec<_>>());
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args}: {err}");
        assert!(
            err.contains("(the address-space limit, ulimit -v")
                && err.ends_with("Use fewer spheres\n"),
            "{args}: {err}"
        );
    }
}

#[test]
fn a_small_run_under_a_tight_address_space_limit_runs_on_any_thread_count() {
    // 60 MB of address space hold the collisions lesson; the check had
    // withheld 132 MB for two threads' allocation ranges and refused it
    // ("needs about 0 MB ... 0 MB are available"), which glibc reserves
    // only as far as there is room.
    // Under such a limit every thread allocates from one range: each had
    // reserved 64 MiB of its own as it started, and 32 threads under
    // 200 MB then found no room for the later ones' stacks ("cannot start
    // 32 threads", most runs).
    let mut hashes = Vec::new();
    for threads in ["1", "2", "32"] {
        let limit = if threads == "32" { 200000 } else { 60000 };
        let args = [
            "run",
            "--lesson",
            "collisions",
            "--time",
            "2",
            "--threads",
            threads,
        ];
        let o = lerpit_within(limit, &args);
        assert!(o.status.success(), "{threads} threads: {}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        hashes.push(v["state_hash"].clone());
    }
    assert!(hashes.iter().all(|h| *h == hashes[0]), "{hashes:?}");
}
