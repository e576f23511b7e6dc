//! `lerpit study` end to end: the quick sweep, the files it writes, the
//! stability table, and bad input.

use crate::support::{BIN, lerpit, lerpit_within, refused, refused_flags, stderr};

#[test]
fn the_quick_study_prints_the_charts_and_writes_csv_and_svg() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("results");
    // A file of an earlier study, replaced as --force asks.
    std::fs::create_dir(&dir).unwrap();
    std::fs::write(dir.join("sweep.csv"), "an earlier study\n").unwrap();
    let out = lerpit(&[
        "study",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
        "--force",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
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
    // Only the study's files: no temporary file is left behind.
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 9, "{names:?}");
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
    assert!(
        text.contains("wrote ") && text.contains("sweep.csv"),
        "{text}"
    );
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
    assert!(out.status.success(), "{}", stderr(&out));
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
    refused_flags(&["study", "--quik"], &[]);
    refused_flags(&["run", "--substeps", "0"], &["from 1 to"]);
    refused_flags(&["run", "--rest-threshold", "-1"], &[]);
}

#[test]
fn an_out_path_that_is_a_file_is_a_bad_command_line() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("results");
    std::fs::write(&file, "not a folder").unwrap();
    let args = ["study", "--quick", "--out", file.to_str().unwrap()];
    refused(&args, 2, &["it is not a folder"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "not a folder");
}

#[test]
fn a_folder_under_a_file_is_a_bad_command_line_and_a_stopped_study_makes_no_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("results");
    std::fs::write(&file, "not a folder").unwrap();
    let under = file.join("deeper");
    let args = ["study", "--quick", "--out", under.to_str().unwrap()];
    refused(&args, 2, &["results is not a folder"]);
    // A study killed before it writes leaves no folder behind.
    let new = tmp.path().join("new").join("deeper");
    let mut child = std::process::Command::new(BIN)
        .args(["study", "--out", new.to_str().unwrap()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Well into the sweep, which takes minutes of work: past its start and
    // the check of the folder, far from its files.
    wait_until_worked(&mut child, 0.5);
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!tmp.path().join("new").exists(), "an empty folder was left");
}

/// Wait until `child`, still running, has used `seconds` of processor
/// time (its threads' user and system time together).
#[cfg(target_os = "linux")]
fn wait_until_worked(child: &mut std::process::Child, seconds: f64) {
    use std::time::{Duration, Instant};
    let patience = Instant::now() + Duration::from_secs(300);
    loop {
        assert!(child.try_wait().unwrap().is_none(), "it ended first");
        if processor_seconds(child.id()).is_some_and(|s| s >= seconds) {
            return;
        }
        assert!(Instant::now() < patience, "it never worked {seconds} s");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Where the processor time is not read here, as long on the clock.
#[cfg(not(target_os = "linux"))]
fn wait_until_worked(_child: &mut std::process::Child, seconds: f64) {
    std::thread::sleep(std::time::Duration::from_secs_f64(seconds));
}

/// The processor time process `pid` has used, seconds.
#[cfg(target_os = "linux")]
fn processor_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // After the name: the state (field 3), ..., utime and stime (14, 15).
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    // SAFETY: sysconf takes a plain integer.
    let per_second = unsafe { libc::sysconf(libc::_SC_CLK_TCK) };
    (per_second > 0).then(|| ticks as f64 / per_second as f64)
}

#[test]
fn an_out_path_through_a_link_to_nowhere_is_refused_before_the_study() {
    // The folder itself, or one on its way, a symbolic link whose target
    // is missing: creating the folder would fail, so the study must not
    // start. Nothing is printed, and the link stays as it was.
    let tmp = tempfile::tempdir().unwrap();
    let link = tmp.path().join("results");
    std::os::unix::fs::symlink(tmp.path().join("nowhere"), &link).unwrap();
    for out in [link.clone(), link.join("deeper")] {
        let args = ["study", "--quick", "--out", out.to_str().unwrap()];
        let refusal = refused(&args, 2, &["results is a symbolic link to", "nowhere"]);
        assert!(refusal.stdout.is_empty(), "the study ran first");
    }
    assert!(link.symlink_metadata().unwrap().file_type().is_symlink());
    assert!(!tmp.path().join("nowhere").exists());
    // Two links to each other: a loop, said so.
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    std::os::unix::fs::symlink(&b, &a).unwrap();
    std::os::unix::fs::symlink(&a, &b).unwrap();
    let args = ["study", "--quick", "--out", a.to_str().unwrap()];
    refused(&args, 2, &["leads back to itself"]);
}

#[test]
fn study_files_already_there_are_kept_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("sweep.csv"), "an earlier study\n").unwrap();
    // Refused before the sweep starts: nothing is printed or written.
    let args = ["study", "--quick", "--out", dir.to_str().unwrap()];
    let out = refused(&args, 2, &["sweep.csv is already there", "--force"]);
    assert!(out.stdout.is_empty());
    assert_eq!(
        std::fs::read_to_string(dir.join("sweep.csv")).unwrap(),
        "an earlier study\n"
    );
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 1);
}

#[test]
fn a_study_that_cannot_write_one_file_replaces_none() {
    // The study's files already there, each "an earlier study"; the new
    // study may write files of at most 8 KB (RLIMIT_FSIZE, with SIGXFSZ
    // ignored so that the write fails instead): its CSV files fit, its
    // charts do not. With --force, it replaces none.
    use std::os::unix::process::CommandExt;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let first = lerpit(&["study", "--quick", "--out", dir.to_str().unwrap()]);
    assert!(first.status.success(), "{}", stderr(&first));
    let names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(names.len() > 5, "{names:?}");
    let sizes: Vec<u64> = names
        .iter()
        .map(|n| std::fs::metadata(dir.join(n)).unwrap().len())
        .collect();
    assert!(
        sizes.iter().any(|&b| b < 8192) && sizes.iter().any(|&b| b > 8192),
        "some files fit the limit, some do not: {sizes:?}"
    );
    for name in &names {
        std::fs::write(dir.join(name), "an earlier study\n").unwrap();
    }
    let mut study = std::process::Command::new(BIN);
    study.args([
        "study",
        "--quick",
        "--force",
        "--out",
        dir.to_str().unwrap(),
    ]);
    // SAFETY: between fork and exec, only `setrlimit` and `signal`, which
    // are async-signal-safe.
    unsafe {
        study.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: 8192,
                rlim_max: 8192,
            };
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) == 0 {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        });
    }
    let out = study.output().unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let message = stderr(&out);
    assert!(
        message.contains("cannot write")
            && message.contains("no file of the study was written or replaced"),
        "{message}"
    );
    assert!(
        !message.contains(".lerpit-"),
        "no temporary file's name: {message}"
    );
    let mut left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    left.sort();
    let mut expected = names.clone();
    expected.sort();
    assert_eq!(left, expected, "no temporary file is left");
    for name in &names {
        assert_eq!(
            std::fs::read_to_string(dir.join(name)).unwrap(),
            "an earlier study\n",
            "{name:?} was replaced"
        );
    }
}

#[test]
fn a_folder_that_cannot_be_written_is_refused_before_the_sweep() {
    let tmp = tempfile::tempdir().unwrap();
    let locked = tmp.path().join("locked");
    std::fs::create_dir(&locked).unwrap();
    let mut dir = locked.clone();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o555)).unwrap();
        // Root writes anyway: use a folder no one can write files in.
        if std::fs::write(locked.join("probe"), "").is_ok() {
            dir = std::path::PathBuf::from("/proc/self");
        }
    }
    if !dir.is_dir() {
        eprintln!("skipped: no folder that refuses files");
        return;
    }
    let args = ["study", "--quick", "--out", dir.to_str().unwrap()];
    let out = refused(&args, 1, &["cannot write in the folder"]);
    assert!(out.stdout.is_empty(), "refused before the sweep");
    // The reason names the folder asked for, never the probe's own file.
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains(".lerpit-"), "{err}");
    // /proc has the folder, yet "no such file" for a new one: said so.
    if dir.starts_with("/proc") {
        assert!(err.contains("it takes no new files"), "{err}");
    }
    let sub = dir.join("sub");
    let args = ["study", "--quick", "--out", sub.to_str().unwrap()];
    let out = refused(&args, 1, &["cannot create the folder"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !err.contains(".lerpit-") && !err.contains("at path"),
        "{err}"
    );
}

#[test]
fn a_folder_where_the_stability_table_goes_is_refused_before_the_suite_and_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("stability.txt")).unwrap();
    std::fs::write(dir.join("stability.txt").join("keep"), "kept").unwrap();
    let args = [
        "study",
        "--stability",
        "--quick",
        "--out",
        dir.to_str().unwrap(),
        "--force",
    ];
    let out = refused(&args, 2, &["stability.txt is a folder"]);
    assert!(out.stdout.is_empty(), "refused before the suite");
    assert_eq!(
        std::fs::read_to_string(dir.join("stability.txt").join("keep")).unwrap(),
        "kept"
    );
}

#[test]
fn a_folder_where_a_study_file_goes_is_refused_before_the_sweep_even_with_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("sweep.csv")).unwrap();
    let args = [
        "study",
        "--quick",
        "--force",
        "--out",
        dir.to_str().unwrap(),
    ];
    let out = refused(
        &args,
        2,
        &["sweep.csv is a folder, where the study writes a file"],
    );
    assert!(out.stdout.is_empty(), "refused before the sweep");
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 1);
}

/// Whatever the moment a study is stopped, its folder holds all of its
/// files or none, and no temporary file.
#[cfg(unix)]
#[test]
fn a_study_stopped_at_any_moment_leaves_all_its_files_or_none_and_no_temporary_file() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let tmp = tempfile::tempdir().unwrap();
    let run = |dir: &std::path::Path, stdout: Stdio| {
        std::process::Command::new(BIN)
            .args(["study", "--quick", "--out", dir.to_str().unwrap()])
            .stdout(stdout)
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    // How long a whole quick study takes here, files included.
    let start = Instant::now();
    let whole = tmp.path().join("whole");
    assert!(run(&whole, Stdio::null()).wait().unwrap().success());
    let took = start.elapsed();
    let files = std::fs::read_dir(&whole).unwrap().count();
    assert!(files >= 9, "{files} files");
    let all_or_none = |dir: &std::path::Path, at: Duration| {
        let names: Vec<String> = match std::fs::read_dir(dir) {
            Ok(entries) => entries
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect(),
            Err(_) => Vec::new(),
        };
        assert!(
            !names.iter().any(|n| n.ends_with(".tmp")),
            "stopped after {at:?}: {names:?}"
        );
        assert!(
            names.is_empty() || names.len() == files,
            "stopped after {at:?}: {names:?}"
        );
    };
    // Halfway through the sweep the signal ends the study at once. Halfway
    // by the clock is not always so (this run may be faster than the one
    // timed): the study is stopped there (SIGSTOP), and only if it has not
    // printed its tables, which it does once the sweep is done and before
    // it writes a file, is it in the sweep. Then SIGTERM and SIGCONT. A
    // study that had printed them is tried again, stopped sooner.
    let mut at = took / 2;
    for attempt in 0.. {
        let dir = tmp.path().join(format!("halfway-{attempt}"));
        let status = terminated_in_the_sweep(run(&dir, Stdio::piped()), at);
        all_or_none(&dir, at);
        if let Some(status) = status {
            assert_eq!(status.signal(), Some(libc::SIGTERM), "{status:?}");
            break;
        }
        assert!(
            !at.is_zero(),
            "the study printed its tables before it could be stopped"
        );
        at = if at > Duration::from_millis(20) {
            at / 4
        } else {
            Duration::ZERO
        };
    }
    // Stop it at moments spread over the rest of that, where the files
    // are written.
    let tries = 12;
    for k in 1..tries {
        let dir = tmp.path().join(format!("stopped-{k}"));
        let mut child = run(&dir, Stdio::null());
        let at = took.mul_f64(0.5 + 0.6 * f64::from(k) / f64::from(tries));
        std::thread::sleep(at);
        unsafe {
            libc::kill(child.id() as i32, libc::SIGTERM);
        }
        child.wait().unwrap();
        all_or_none(&dir, at);
    }
}

/// Stop `study` (SIGSTOP) after `at`; if it has not yet printed anything
/// to its standard output (a pipe), send it SIGTERM and SIGCONT and return
/// how it ended. `None` when it had printed, or ended, by then.
#[cfg(unix)]
fn terminated_in_the_sweep(
    mut study: std::process::Child,
    at: std::time::Duration,
) -> Option<std::process::ExitStatus> {
    use std::os::fd::AsRawFd;
    std::thread::sleep(at);
    let pid = study.id() as libc::pid_t;
    // SAFETY: kill takes plain integers; waitpid writes the status it is
    // given.
    unsafe {
        assert_eq!(libc::kill(pid, libc::SIGSTOP), 0);
        let mut status = 0;
        assert_eq!(libc::waitpid(pid, &mut status, libc::WUNTRACED), pid);
        if !libc::WIFSTOPPED(status) {
            // It ended before the stop (and was reaped here).
            return None;
        }
    }
    // Stopped, it prints nothing more: the pipe holds all it printed.
    let mut out = libc::pollfd {
        fd: study.stdout.as_ref().unwrap().as_raw_fd(),
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: poll reads and writes the one descriptor it is given.
    let printed = unsafe { libc::poll(&mut out, 1, 0) } != 0;
    // SAFETY: kill takes plain integers.
    unsafe {
        assert_eq!(libc::kill(pid, libc::SIGTERM), 0);
        assert_eq!(libc::kill(pid, libc::SIGCONT), 0);
    }
    let status = study.wait().unwrap();
    (!printed).then_some(status)
}

#[test]
fn a_study_that_an_address_space_limit_cannot_hold_is_refused_before_it_starts() {
    // Under 10 MB the threads' stacks do not fit: status 1, naming the
    // limit (the study's threads, one a core, had panicked at starting,
    // status 101, or hung). Under 60 MB they do, and the sweep runs, but
    // not the stability suite's 100,000 spheres.
    let o = lerpit_within(10000, &["study", "--quick"]);
    let said = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{said}");
    assert!(
        said.starts_with("lerpit: error: the address-space limit (ulimit -v) leaves ")
            && said.contains("stack")
            && said.trim_end().ends_with("Raise the limit"),
        "{said}"
    );
    let o = lerpit_within(60000, &["study", "--quick"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = lerpit_within(60000, &["study", "--stability"]);
    let said = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{said}");
    assert!(
        said.contains("and the study (about 150 MB). Raise the limit"),
        "{said}"
    );
}
