//! `lerpit study` end to end: the quick sweep, the files it writes, the
//! stability table, and bad input.

use std::process::Command;

fn lerpit(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lerpit"))
        .args(args)
        .output()
        .expect("the binary runs")
}

#[test]
fn the_quick_study_prints_the_charts_and_writes_csv_and_svg() {
    let dir = std::env::temp_dir().join(format!("lerpit-study-{}", std::process::id()));
    let out = lerpit(&["study", "--quick", "--out", dir.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    for lesson in ["pingpong", "gravity", "collisions"] {
        assert!(
            text.contains(&format!("=== {lesson} lesson")),
            "no {lesson} section"
        );
        for chart in ["work-precision", "convergence"] {
            let svg = std::fs::read_to_string(dir.join(format!("{chart}-{lesson}.svg"))).unwrap();
            assert!(
                svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
                "{chart}-{lesson}.svg"
            );
        }
    }
    assert!(
        text.contains("fitted order"),
        "the convergence legend gives the orders"
    );
    assert!(
        text.contains("bounce-time error") && text.contains("energy drift"),
        "the goals"
    );
    let csv = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("lesson,method,dt,"), "{}", lines[0]);
    assert_eq!(
        lines.len(),
        1 + 3 * 5 * 8,
        "a row per lesson, method and dt"
    );
    let columns = lines[0].split(',').count();
    assert!(
        lines.iter().all(|l| l.split(',').count() == columns),
        "every row complete"
    );
    assert!(dir.join("conservation.csv").exists() && dir.join("conservation.svg").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_quick_sweep_meets_the_gravity_goal_for_the_continuous_method() {
    let rows = lerpit::study::work_precision(lerpit::scene::Lesson::Gravity).unwrap();
    let continuous: Vec<_> = rows
        .iter()
        .filter(|r| r.method == lerpit::sim::Integrator::Continuous)
        .collect();
    assert_eq!(continuous.len(), 8);
    for r in continuous {
        assert!(
            r.bounce_time_error.unwrap() <= 1e-12,
            "dt {}: {:?}",
            r.dt,
            r.bounce_time_error
        );
        assert!(
            r.apex_ratio_error.unwrap() <= 1e-12,
            "dt {}: {:?}",
            r.dt,
            r.apex_ratio_error
        );
    }
}

#[test]
fn the_stability_table_names_failures_and_remedies() {
    let out = lerpit(&["study", "--stability", "--quick"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    for check in [
        "energy",
        "rest",
        "tunnelling",
        "piles",
        "critical dt",
        "extremes",
    ] {
        assert!(
            text.lines().any(|l| l.starts_with(check)),
            "no {check} rows"
        );
    }
    assert!(text.contains("FAILS") && text.contains("holds"));
}

#[test]
fn bad_study_flags_exit_with_status_2() {
    let out = lerpit(&["study", "--quik"]);
    assert_eq!(out.status.code(), Some(2));
    let out = lerpit(&["run", "--substeps", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("from 1 to"));
    let out = lerpit(&["run", "--rest-threshold", "-1"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn an_unwritable_out_folder_is_a_runtime_failure() {
    let file = std::env::temp_dir().join(format!("lerpit-study-file-{}", std::process::id()));
    std::fs::write(&file, "not a folder").unwrap();
    let out = lerpit(&["study", "--quick", "--out", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot create the folder"));
    let _ = std::fs::remove_file(&file);
}
