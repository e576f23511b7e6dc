//! `lerpit bench` and the broad-phase choice from the command line and
//! scene files, through the real binary.

use crate::support::{BODY, json, lerpit, refused_flags, scene_file, stderr, stdout};

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
    assert_eq!(v["steps"], 3);
    assert_eq!(v["threads"], 2);
    assert_eq!(v["broadphase"], "grid");
    for field in [
        "seconds",
        "sphere_steps_per_s",
        "ns_per_sphere_step",
        "pair_tests_per_step",
        "contacts_per_step",
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
    // N = 100 and 316, each with all-pairs, grid and auto.
    assert_eq!(rows.len(), 6, "{out}");
    assert!(out.contains("crossover:"), "{out}");
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
            "from 1 to 1000000000000, got 1.5",
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
            "5001 spheres",
            "12502500 pairs",
            "--allow-slow",
            "--broadphase grid",
        ],
    );
    // The default size, 100,000, is refused the same way.
    refused_flags(
        &["bench", "--broadphase", "all-pairs"],
        &["4999950000 pairs"],
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
