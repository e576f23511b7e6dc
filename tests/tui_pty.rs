//! End to end: the real binary in a pseudo-terminal. Open the visualiser,
//! switch to the gravity lesson, raise the wall restitution, pause, step,
//! quit; check the screen along the way, the exit status, and that the
//! terminal is left as it was (main screen, no mouse reporting).
#![cfg(feature = "tui")]

use portable_pty::{CommandBuilder, PtySize, native_pty_system};
use std::io::{Read, Write};
use std::sync::mpsc;
use std::time::{Duration, Instant};

const ROWS: u16 = 40;
const COLS: u16 = 120;
const PATIENCE: Duration = Duration::from_secs(30);

struct Screen {
    parser: vt100::Parser,
    output: mpsc::Receiver<Vec<u8>>,
}

impl Screen {
    fn pump(&mut self, wait: Duration) {
        if let Ok(bytes) = self.output.recv_timeout(wait) {
            self.parser.process(&bytes);
        }
        while let Ok(bytes) = self.output.try_recv() {
            self.parser.process(&bytes);
        }
    }

    /// Wait until the screen satisfies `ok`; panic with the screen if not.
    fn wait_for(&mut self, what: &str, ok: impl Fn(&str) -> bool) -> String {
        let deadline = Instant::now() + PATIENCE;
        loop {
            let text = self.parser.screen().contents();
            if ok(&text) {
                return text;
            }
            assert!(
                Instant::now() < deadline,
                "the screen never showed {what}; it shows:\n{text}"
            );
            self.pump(Duration::from_millis(50));
        }
    }
}

/// The step number the readouts show ("step N").
fn shown_step(screen: &str) -> Option<u64> {
    let at = screen.find(" s, step ")?;
    let rest = &screen[at + " s, step ".len()..];
    rest.split(|c: char| !c.is_ascii_digit())
        .next()?
        .parse()
        .ok()
}

#[test]
fn a_person_switches_lesson_tunes_steps_and_quits() {
    let pty = native_pty_system()
        .openpty(PtySize {
            rows: ROWS,
            cols: COLS,
            pixel_width: 0,
            pixel_height: 0,
        })
        .expect("a pseudo-terminal opens");
    let mut cmd = CommandBuilder::new(env!("CARGO_BIN_EXE_lerpit"));
    cmd.env("TERM", "xterm-256color");
    cmd.env_remove("NO_COLOR");
    let mut child = pty.slave.spawn_command(cmd).expect("lerpit starts");
    drop(pty.slave);

    let mut reader = pty.master.try_clone_reader().unwrap();
    let mut keys = pty.master.take_writer().unwrap();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let mut buf = [0u8; 8192];
        while let Ok(n) = reader.read(&mut buf) {
            if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                break;
            }
        }
    });
    let mut screen = Screen {
        parser: vt100::Parser::new(
            std::num::NonZeroU16::new(ROWS).unwrap(),
            std::num::NonZeroU16::new(COLS).unwrap(),
            0,
        ),
        output: rx,
    };
    let mut press = |k: &str| {
        keys.write_all(k.as_bytes()).unwrap();
        keys.flush().unwrap();
    };

    screen.wait_for("the ping-pong lesson", |s| s.contains("lerpit: Ping-pong"));
    assert!(screen.parser.screen().alternate_screen(), "full screen");

    press("2");
    screen.wait_for("the gravity lesson", |s| {
        s.contains("lerpit: Gravity") && s.contains("c_r = 0.95")
    });
    press("E");
    screen.wait_for("the raised restitution", |s| s.contains("c_r = 1.00"));
    press(" ");
    let paused = screen.wait_for("the pause", |s| {
        s.contains(" paused ") && s.contains("paused, x1")
    });
    let step = shown_step(&paused).expect("the readouts show the step");
    // The pause may land between a frame's steps and its drawing: settle.
    std::thread::sleep(Duration::from_millis(200));
    screen.pump(Duration::from_millis(50));
    let step = shown_step(&screen.parser.screen().contents()).unwrap_or(step);
    press("n");
    screen.wait_for("one step more", |s| shown_step(s) == Some(step + 1));
    press("q");

    let deadline = Instant::now() + PATIENCE;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "lerpit did not quit on q");
        screen.pump(Duration::from_millis(50));
    };
    screen.pump(Duration::from_millis(100));
    assert!(status.success(), "exit status {status:?}");
    let s = screen.parser.screen();
    assert!(!s.alternate_screen(), "the main screen is back");
    assert_eq!(
        s.mouse_protocol_mode(),
        vt100::MouseProtocolMode::None,
        "mouse reporting is off again"
    );
}
