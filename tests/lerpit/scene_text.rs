//! Any text a scene file may hold, through the real binary: the lessons'
//! own files and the README's example, cut, repeated, spliced with hostile
//! lines and numbers, or replaced by arbitrary text. Whatever the file
//! holds, `lerpit run --scene` either runs it (one JSON object out) or
//! refuses it with exit 3 and a message naming the file, never a panic,
//! a signal or a hang; a message that places the problem places it on a
//! line the file has.

use crate::support::{BIN, README, scene_file, stderr};
use proptest::prelude::*;
use std::io::{Read, Seek, SeekFrom};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The texts the mutations start from: every lesson's file and the
/// README's example scene.
fn seeds() -> Vec<String> {
    let start = README.find("```toml\n").expect("README has a toml example") + 8;
    let example = &README[start..];
    let example = &example[..example.find("```").expect("the example ends")];
    vec![
        include_str!("../../src/scene/lessons/pingpong.toml").to_string(),
        include_str!("../../src/scene/lessons/gravity.toml").to_string(),
        include_str!("../../src/scene/lessons/collisions.toml").to_string(),
        example.to_string(),
    ]
}

/// Numbers a hostile file puts where a field's value goes.
const NUMBERS: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e308",
    "-1e308",
    "nan",
    "+inf",
    "-inf",
    "1e-320",
    "0.5",
    "3",
    "2.5e3",
    "1_000",
    "18446744073709551616",
    "4294967297",
    "0x10",
    "\"7\"",
    "[]",
    "[1, 2]",
    "{}",
    "true",
];

/// Lines a hostile file adds.
const LINES: &[&str] = &[
    "[world]",
    "[lesson]",
    "[[body]]",
    "[[spawn]]",
    "[world.extra]",
    "count = 5000",
    "count = 10000000000",
    "radius = [0.5, 0.1]",
    "radius = 0.6",
    "position = [nan, 0.5, 0.5]",
    "position = [0.5, 0.5]",
    "velocity = [1e300, 0, 0]",
    "mass = 0",
    "dt = 1e-300",
    "dt = 1",
    "substeps = 4294967296",
    "projection_passes = 65",
    "integrator = \"rk5\"",
    "broad_phase = \"grid\"",
    "support = true",
    "sleep = true",
    "overlap = true",
    "title = \"\u{202e}evil\u{0}\"",
    "contacts = \"yes\"",
    "gravity = [0, -1e6, 0]",
    "seed = -1",
    "= 1",
    "\"unterminated",
    "\u{feff}",
];

/// One change to a scene's text.
#[derive(Clone, Debug)]
enum Cut {
    /// Replace the `k`th number in the text with one of [`NUMBERS`].
    Number(usize, usize),
    /// Remove a line.
    Drop(usize),
    /// Repeat a line.
    Repeat(usize),
    /// Add one of [`LINES`] before a line.
    Add(usize, usize),
    /// Keep only the text before a point (a fraction of its length).
    Truncate(f64),
}

fn cut() -> impl Strategy<Value = Cut> {
    prop_oneof![
        (any::<usize>(), 0..NUMBERS.len()).prop_map(|(k, n)| Cut::Number(k, n)),
        any::<usize>().prop_map(Cut::Drop),
        any::<usize>().prop_map(Cut::Repeat),
        (any::<usize>(), 0..LINES.len()).prop_map(|(k, l)| Cut::Add(k, l)),
        (0.0..1.0f64).prop_map(Cut::Truncate),
    ]
}

fn apply(text: &str, cut: &Cut) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let line = |k: usize| k % lines.len().max(1);
    match *cut {
        Cut::Number(k, n) => {
            let numbers: Vec<(usize, usize)> = number_spans(text);
            if numbers.is_empty() {
                return text.to_string();
            }
            let (start, end) = numbers[k % numbers.len()];
            return format!("{}{}{}", &text[..start], NUMBERS[n], &text[end..]);
        }
        Cut::Drop(k) if !lines.is_empty() => {
            lines.remove(line(k));
        }
        Cut::Repeat(k) if !lines.is_empty() => {
            let at = line(k);
            lines.insert(at, lines[at].clone());
        }
        Cut::Add(k, l) => {
            let at = line(k);
            lines.insert(at.min(lines.len()), LINES[l].to_string());
        }
        Cut::Truncate(f) => {
            let mut end = (text.len() as f64 * f) as usize;
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            return text[..end].to_string();
        }
        _ => {}
    }
    lines.join("\n") + "\n"
}

/// The byte ranges of the numbers written in `text`, in comments and
/// strings too (which a change there leaves harmless): each a run of
/// digits with its sign, point and exponent, not part of a name.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if starts {
            let start = if i > 0 && bytes[i - 1] == b'-' {
                i - 1
            } else {
                i
            };
            let mut end = i;
            while end < bytes.len()
                && (bytes[end].is_ascii_digit() || b".eE_+-".contains(&bytes[end]))
            {
                end += 1;
            }
            spans.push((start, end));
            i = end;
        } else {
            i += 1;
        }
    }
    spans
}

/// Longest a run may take before it counts as a hang: far beyond what
/// five steps of any scene the rules let through need, even in a debug build.
const HANG: Duration = Duration::from_secs(300);

/// `lerpit run --scene` on `text`, for five steps (`--allow-slow`: a
/// scene of a few thousand spheres on all-pairs runs them). Its output
/// goes to files, which never fill up as a pipe does while it is waited
/// on.
fn run_scene(text: &str) -> Output {
    let file = scene_file(text);
    let path = file.path.to_str().unwrap();
    let (mut out, mut err) = (tempfile::tempfile().unwrap(), tempfile::tempfile().unwrap());
    let mut child = Command::new(BIN)
        .args(["run", "--scene", path, "--steps", "5", "--format", "json"])
        .arg("--allow-slow")
        .stdin(Stdio::null())
        .stdout(out.try_clone().unwrap())
        .stderr(err.try_clone().unwrap())
        .spawn()
        .expect("the lerpit binary runs");
    let began = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("the child can be waited on") {
            break status;
        }
        if began.elapsed() > HANG {
            child.kill().ok();
            panic!("lerpit hung on this scene:\n{text}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let read = |f: &mut std::fs::File| {
        let mut bytes = Vec::new();
        f.seek(SeekFrom::Start(0)).unwrap();
        f.read_to_end(&mut bytes).unwrap();
        bytes
    };
    Output {
        status,
        stdout: read(&mut out),
        stderr: read(&mut err),
    }
}

/// What every run must be, whatever `text` held; its exit status.
fn check_run(text: &str) -> Result<Option<i32>, TestCaseError> {
    let o = run_scene(text);
    let err = stderr(&o);
    prop_assert!(
        !err.contains("panicked") && !err.contains("RUST_BACKTRACE"),
        "a panic on\n{text}\n{err}"
    );
    match o.status.code() {
        Some(0) => {
            let out: serde_json::Value = serde_json::from_slice(&o.stdout)
                .map_err(|e| TestCaseError::fail(format!("stdout is no JSON ({e}) for\n{text}")))?;
            prop_assert!(out.is_object(), "{out}");
        }
        Some(3) => {
            prop_assert!(
                err.starts_with("lerpit: error: ") && err.contains("scene.toml"),
                "the message names the file:\n{err}"
            );
            let place = err
                .lines()
                .next()
                .and_then(|l| l.split("scene.toml:").nth(1))
                .and_then(|rest| rest.split(':').next())
                .and_then(|line| line.parse::<usize>().ok());
            if let Some(line) = place {
                let lines = text.lines().count().max(1);
                prop_assert!(
                    (1..=lines + 1).contains(&line),
                    "placed on line {line} of {lines}:\n{err}\n{text}"
                );
            }
        }
        other => prop_assert!(false, "exit {other:?} on\n{text}\n{err}"),
    }
    Ok(o.status.code())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn a_cut_or_spliced_scene_runs_or_is_refused_by_name(
        seed in 0..4usize,
        cuts in prop::collection::vec(cut(), 1..5),
    ) {
        let text = cuts.iter().fold(seeds()[seed].clone(), |t, c| apply(&t, c));
        check_run(&text)?;
    }

}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Text at random holds no sphere the rules accept (a `[[body]]` needs
    /// its centre, radius and mass), so it is always refused.
    #[test]
    fn arbitrary_text_is_refused_by_name(text in "\\PC{0,200}") {
        prop_assert_eq!(check_run(&text)?, Some(3));
    }
}

#[test]
fn the_seeds_run_and_a_cut_number_an_added_line_and_garbage_are_refused() {
    // The seeds run unchanged; a number cut to NaN, a line without a key
    // and control characters are each refused: the properties above meet
    // both outcomes.
    for seed in seeds() {
        assert_eq!(run_scene(&seed).status.code(), Some(0), "{seed}");
    }
    let gravity = &seeds()[1];
    // A thousand spheres write more than a pipe holds: all of it is read.
    let thousand = gravity.replace("count = 150", "count = 1_000");
    let o = run_scene(&thousand);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(o.stdout.len() > 1 << 16, "{} bytes", o.stdout.len());
    let at = gravity.find("dt = ").expect("the lesson sets dt") + 5;
    let nan = apply(gravity, &Cut::Number(number_spans(&gravity[..at]).len(), 5));
    assert!(nan.contains("dt = nan"), "{nan}");
    assert_eq!(run_scene(&nan).status.code(), Some(3), "{nan}");
    let added = apply(gravity, &Cut::Add(0, LINES.len() - 3));
    assert_eq!(run_scene(&added).status.code(), Some(3), "{added}");
    assert_eq!(run_scene("\u{0}\u{1}").status.code(), Some(3));
}
