//! The visualiser's command line, run as a person would from a script.

use crate::support::{lerpit, scene_file};

#[test]
fn without_a_terminal_the_visualiser_points_to_run_and_exits_1() {
    let out = lerpit(&["--lesson", "gravity", "--restitution", "0.8"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(err.contains("not a terminal"), "stderr: {err}");
    assert!(err.contains("lerpit run"), "stderr: {err}");
}

#[test]
fn without_a_terminal_the_scene_is_not_placed() {
    // Spheres that cannot fit, though they fill less of the box than the
    // check before placing refuses, fail only once placing them has been
    // tried (exit 3 on a terminal); without one the visualiser stops first.
    let scene = scene_file("[[spawn]]\ncount = 250\nradius = [0.07, 0.07]\n");
    let out = lerpit(&["--scene", scene.path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(err.contains("not a terminal"), "stderr: {err}");
    let run = lerpit(&["run", "--scene", scene.path.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(3), "the same scene, placed by run");
}

#[test]
fn a_bad_override_is_a_usage_error_before_the_terminal_matters() {
    let out = lerpit(&["--restitution", "1.5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("between 0 and 1"));
}

#[test]
fn visualiser_flags_do_not_mix_with_a_command() {
    let out = lerpit(&["--lesson", "gravity", "run"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_flag_of_run_given_to_the_visualiser_points_to_run() {
    for args in [
        &["--steps", "5"][..],
        &["--lesson", "gravity", "--time=3"],
        &["--threads", "2"],
    ] {
        let out = lerpit(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("is for `lerpit run`, which simulates without the visualiser"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("--substeps"), "{args:?}: {err}");
    }
    // Within a command, clap's own message.
    let out = lerpit(&["run", "--stepz", "5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unexpected argument '--stepz'"));
}

#[test]
fn bench_render_takes_no_simulation_flags_and_draws_frames() {
    let out = lerpit(&["bench", "--render", "--sweep"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--sweep"));
    let out = lerpit(&[
        "bench",
        "--render",
        "--particles",
        "200",
        "--width",
        "90",
        "--height",
        "30",
        "--frames",
        "2",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("200 spheres, 90x30 cells, 2 frames"),
        "{text}"
    );
    assert!(
        text.contains("full frame") && text.contains("median"),
        "{text}"
    );
    // From the settled start it draws the benchmark's pile.
    let out = lerpit(&[
        "bench",
        "--render",
        "--start",
        "settled",
        "--particles",
        "300",
        "--frames",
        "1",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("the benchmark's settled pile, 300 spheres, 200x60 cells, 1 frame\n"),
        "{text}"
    );
}

#[test]
fn the_visualiser_refuses_all_pairs_above_its_limit_as_run_does() {
    let scene = scene_file(
        "[world]\npair_collisions = true\n\n[[spawn]]\ncount = 6000\nradius = [0.004, 0.004]\n",
    );
    let path = scene.path.to_str().unwrap();
    let out = lerpit(&["--scene", path]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    assert!(
        err.contains("the scene's broad phase all-pairs with 6,000 spheres")
            && err.contains("--broadphase grid")
            && err.contains("--allow-slow"),
        "stderr: {err}"
    );
    for fix in ["--broadphase=grid", "--allow-slow"] {
        let out = lerpit(&["--scene", path, fix]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{fix}: {err}");
        assert!(err.contains("not a terminal"), "{fix}: {err}");
    }
}
