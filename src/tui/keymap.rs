//! The key table: which key does what, when, and how it is described.
//!
//! One table drives three things so they cannot drift apart: dispatch
//! ([`dispatch`]), the footer's hints ([`footer`]) and the help overlay
//! (every entry, in order). Owns keys and their meaning; it never changes
//! the app itself.
//!
//! Camera keys and stepping keys share the arrows. The scheme: Left and
//! Right step back and forward while paused and orbit while running; h and
//! l always orbit, so the camera is never out of reach. Up/Down and j/k
//! always tilt.

use super::action::Action;
use super::camera::{ORBIT_STEP, Preset, ZOOM_STEP};
use crate::scene::Lesson;
use ratatui::crossterm::event::{
    KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind,
};

/// A key with the modifiers that matter (Shift is folded into the
/// character for printable keys and into BackTab).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Key {
    pub code: KeyCode,
    pub ctrl: bool,
}

const fn ch(c: char) -> Key {
    Key {
        code: KeyCode::Char(c),
        ctrl: false,
    }
}

const fn code(code: KeyCode) -> Key {
    Key { code, ctrl: false }
}

const fn ctrl(c: char) -> Key {
    Key {
        code: KeyCode::Char(c),
        ctrl: true,
    }
}

/// Ctrl-\, which outside raw mode sends SIGQUIT: the terminal sends it as
/// the byte 0x1c, which crossterm reads as Ctrl-4.
const CTRL_BACKSLASH: Key = ctrl('4');

impl Key {
    /// The key an event names, or `None` with Alt (or Super, Hyper, Meta)
    /// held: no binding uses them, so Alt-q does not quit.
    pub(crate) fn from_event(e: &KeyEvent) -> Option<Self> {
        let unbound =
            KeyModifiers::ALT | KeyModifiers::SUPER | KeyModifiers::HYPER | KeyModifiers::META;
        if e.modifiers.intersects(unbound) {
            return None;
        }
        let code = match e.code {
            KeyCode::Char(c) if e.modifiers.contains(KeyModifiers::CONTROL) => {
                KeyCode::Char(c.to_ascii_lowercase())
            }
            c => c,
        };
        Some(Key {
            code,
            ctrl: e.modifiers.contains(KeyModifiers::CONTROL),
        })
    }

    /// For an event with Alt held (and no other of the unbound
    /// modifiers), the key without it: what Esc and that key typed at once
    /// would have been.
    pub(crate) fn without_alt(e: &KeyEvent) -> Option<Self> {
        let others = KeyModifiers::SUPER | KeyModifiers::HYPER | KeyModifiers::META;
        if !e.modifiers.contains(KeyModifiers::ALT) || e.modifiers.intersects(others) {
            return None;
        }
        let mut plain = *e;
        plain.modifiers.remove(KeyModifiers::ALT);
        Self::from_event(&plain)
    }

    /// How the key is written in the footer and the help.
    pub(crate) fn label(&self) -> String {
        if *self == CTRL_BACKSLASH {
            return "Ctrl-\\".into();
        }
        let base = match self.code {
            KeyCode::Char(' ') => "Space".to_string(),
            KeyCode::Char(c) => c.to_string(),
            KeyCode::Left => "←".into(),
            KeyCode::Right => "→".into(),
            KeyCode::Up => "↑".into(),
            KeyCode::Down => "↓".into(),
            KeyCode::PageUp => "PgUp".into(),
            KeyCode::PageDown => "PgDn".into(),
            KeyCode::Tab => "Tab".into(),
            KeyCode::BackTab => "Shift-Tab".into(),
            KeyCode::Esc => "Esc".into(),
            KeyCode::F(n) => format!("F{n}"),
            other => format!("{other:?}"),
        };
        if self.ctrl {
            format!("Ctrl-{}", base.to_ascii_uppercase())
        } else {
            base
        }
    }
}

/// When an entry applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum When {
    Always,
    Paused,
    Running,
    /// Only while the help overlay is open.
    HelpOpen,
    /// Only while the chart screen is open.
    ChartOpen,
    /// Only while spheres are selected.
    Selected,
    /// Only while the world works on a search for a collision or a step
    /// already asked for (what a newer key stops).
    Working,
}

/// The state dispatch depends on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mode {
    pub paused: bool,
    pub help_open: bool,
    pub chart_open: bool,
    pub selected: bool,
    /// The world works on a search for a collision or a step already
    /// asked for.
    pub working: bool,
    /// The world collides its spheres with one another: the footer then
    /// names the keys of their restitution `e`.
    pub pairs: bool,
}

impl When {
    fn holds(self, mode: Mode) -> bool {
        match self {
            When::Always => true,
            When::Paused => mode.paused,
            When::Running => !mode.paused,
            When::HelpOpen => mode.help_open,
            When::ChartOpen => mode.chart_open,
            When::Selected => mode.selected,
            When::Working => mode.working,
        }
    }

    /// A note for the help overlay.
    pub(crate) fn note(self) -> &'static str {
        match self {
            When::Paused => " (paused)",
            When::Running => " (running)",
            When::HelpOpen => " (in help)",
            When::ChartOpen => " (in the chart)",
            When::Selected => " (with a selection)",
            When::Working => " (during a search or a step)",
            When::Always => "",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Group {
    Time,
    Lesson,
    Parameters,
    View,
    Program,
}

impl Group {
    pub const ALL: [Group; 5] = [
        Group::Time,
        Group::Lesson,
        Group::Parameters,
        Group::View,
        Group::Program,
    ];

    pub(crate) fn title(self) -> &'static str {
        match self {
            Group::Time => "Time",
            Group::Lesson => "Lesson",
            Group::Parameters => "Parameters",
            Group::View => "View",
            Group::Program => "Program",
        }
    }
}

pub struct Binding {
    pub keys: &'static [Key],
    pub action: Action,
    pub when: When,
    pub group: Group,
    /// Shown in the help overlay.
    pub description: &'static str,
    /// Shown in the footer when set.
    pub hint: Option<&'static str>,
}

const O: f64 = ORBIT_STEP;

/// Every key, in help order. Dispatch takes the first entry whose key
/// matches and whose condition holds.
pub const BINDINGS: &[Binding] = &[
    Binding {
        keys: &[ch('?'), code(KeyCode::F(1))],
        action: Action::ToggleHelp,
        when: When::Always,
        group: Group::Program,
        description: "open or close this help",
        hint: Some("help"),
    },
    Binding {
        keys: &[code(KeyCode::Esc)],
        action: Action::CloseHelp,
        when: When::HelpOpen,
        group: Group::Program,
        description: "close the help",
        hint: None,
    },
    Binding {
        keys: &[ch('k'), code(KeyCode::Up)],
        action: Action::ScrollHelp(-1),
        when: When::HelpOpen,
        group: Group::Program,
        description: "scroll the help up",
        hint: None,
    },
    Binding {
        keys: &[ch('j'), code(KeyCode::Down)],
        action: Action::ScrollHelp(1),
        when: When::HelpOpen,
        group: Group::Program,
        description: "scroll the help down",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::PageUp)],
        action: Action::ScrollHelpPage(-1),
        when: When::HelpOpen,
        group: Group::Program,
        description: "scroll the help up a page",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::PageDown)],
        action: Action::ScrollHelpPage(1),
        when: When::HelpOpen,
        group: Group::Program,
        description: "scroll the help down a page",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::Home)],
        action: Action::ScrollHelpTo(false),
        when: When::HelpOpen,
        group: Group::Program,
        description: "the help's top",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::End)],
        action: Action::ScrollHelpTo(true),
        when: When::HelpOpen,
        group: Group::Program,
        description: "the help's end",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::Esc)],
        action: Action::CloseChart,
        when: When::ChartOpen,
        group: Group::Program,
        description: "close the chart",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::Esc)],
        action: Action::ClearSelection,
        when: When::Selected,
        group: Group::View,
        description: "forget the selected spheres (Esc never quits)",
        hint: None,
    },
    Binding {
        keys: &[ch('}')],
        action: Action::PickNext,
        when: When::Always,
        group: Group::View,
        description: "pick the next sphere by number (of a pair, its first)",
        hint: None,
    },
    Binding {
        keys: &[ch('{')],
        action: Action::PickPrevious,
        when: When::Always,
        group: Group::View,
        description: "pick the previous sphere by number (of a pair, its second)",
        hint: None,
    },
    Binding {
        keys: &[ctrl('z')],
        action: Action::Suspend,
        when: When::Always,
        group: Group::Program,
        description: "suspend to the shell (fg resumes)",
        hint: None,
    },
    Binding {
        keys: &[ctrl('l')],
        action: Action::Redraw,
        when: When::Always,
        group: Group::Program,
        description: "draw the whole screen again",
        hint: None,
    },
    Binding {
        keys: &[ch('q'), ctrl('c')],
        action: Action::Quit,
        when: When::Always,
        group: Group::Program,
        description: "quit",
        hint: Some("quit"),
    },
    Binding {
        keys: &[CTRL_BACKSLASH],
        action: Action::Quit,
        when: When::Always,
        group: Group::Program,
        description: "quit, as Ctrl-C",
        hint: None,
    },
    Binding {
        keys: &[ch(' ')],
        action: Action::TogglePause,
        when: When::Always,
        group: Group::Time,
        description: "pause or resume",
        hint: Some("pause"),
    },
    Binding {
        keys: &[ch('n'), ch('.'), code(KeyCode::Right)],
        action: Action::StepForward,
        when: When::Paused,
        group: Group::Time,
        description: "one step forward",
        hint: Some("step"),
    },
    Binding {
        keys: &[ch(','), code(KeyCode::Left)],
        action: Action::StepBack,
        when: When::Paused,
        group: Group::Time,
        description: "one step back (as far as kept)",
        hint: Some("back"),
    },
    Binding {
        keys: &[ch('o')],
        action: Action::NextCollision,
        when: When::Always,
        group: Group::Time,
        description: "run to the next collision (between spheres where they collide, else with a wall; of the picked sphere, with either, when one is), pause on it and select it (none within 10 s, or within 76,800 steps when dt is below 1/7680 s: back where it began)",
        hint: Some("collision"),
    },
    Binding {
        keys: &[code(KeyCode::Esc)],
        action: Action::StopWork,
        when: When::Working,
        group: Group::Time,
        description: "stop what the world works on: a search for a collision goes back where it began, a step not finished is not taken",
        hint: None,
    },
    Binding {
        keys: &[ch('n'), ch('.'), ch(',')],
        action: Action::PauseToStep,
        when: When::Running,
        group: Group::Time,
        description: "pause to step",
        hint: None,
    },
    Binding {
        keys: &[ch('<')],
        action: Action::Slower,
        when: When::Always,
        group: Group::Time,
        description: "slower (down to x1/16)",
        hint: None,
    },
    Binding {
        keys: &[ch('>')],
        action: Action::Faster,
        when: When::Always,
        group: Group::Time,
        description: "faster (up to x4)",
        hint: None,
    },
    Binding {
        keys: &[ch('1')],
        action: Action::Lesson(Lesson::Pingpong),
        when: When::Always,
        group: Group::Lesson,
        description: "ping-pong lesson (own parameters)",
        hint: None,
    },
    Binding {
        keys: &[ch('2')],
        action: Action::Lesson(Lesson::Gravity),
        when: When::Always,
        group: Group::Lesson,
        description: "gravity lesson (own parameters)",
        hint: None,
    },
    Binding {
        keys: &[ch('3')],
        action: Action::Lesson(Lesson::Collisions),
        when: When::Always,
        group: Group::Lesson,
        description: "collisions lesson (own parameters)",
        hint: Some("lessons"),
    },
    Binding {
        keys: &[code(KeyCode::Tab)],
        action: Action::NextLesson,
        when: When::Always,
        group: Group::Lesson,
        description: "next lesson (or the scene file opened)",
        hint: None,
    },
    Binding {
        keys: &[code(KeyCode::BackTab)],
        action: Action::PreviousLesson,
        when: When::Always,
        group: Group::Lesson,
        description: "previous lesson (or the scene file opened)",
        hint: None,
    },
    Binding {
        keys: &[ch('r')],
        action: Action::Restart,
        when: When::Always,
        group: Group::Lesson,
        description: "restart, keeping the parameters",
        hint: None,
    },
    Binding {
        keys: &[ch('R')],
        action: Action::Reseed,
        when: When::Always,
        group: Group::Lesson,
        description: "restart with a new seed",
        hint: None,
    },
    Binding {
        keys: &[ch('+'), ch('=')],
        action: Action::MoreSpheres,
        when: When::Always,
        group: Group::Lesson,
        description: "more spheres (restarts)",
        hint: None,
    },
    Binding {
        keys: &[ch('-')],
        action: Action::FewerSpheres,
        when: When::Always,
        group: Group::Lesson,
        description: "fewer spheres (restarts)",
        hint: None,
    },
    Binding {
        keys: &[ch('p')],
        action: Action::PairRestitutionDown,
        when: When::Always,
        group: Group::Parameters,
        description: "pair restitution e - 0.05",
        hint: None,
    },
    Binding {
        keys: &[ch('P')],
        action: Action::PairRestitutionUp,
        when: When::Always,
        group: Group::Parameters,
        description: "pair restitution e + 0.05",
        hint: Some("e"),
    },
    Binding {
        keys: &[ch('e')],
        action: Action::WallRestitutionDown,
        when: When::Always,
        group: Group::Parameters,
        description: "wall restitution c_r - 0.05",
        hint: None,
    },
    Binding {
        keys: &[ch('E')],
        action: Action::WallRestitutionUp,
        when: When::Always,
        group: Group::Parameters,
        description: "wall restitution c_r + 0.05",
        hint: Some("c_r"),
    },
    Binding {
        keys: &[ch('g')],
        action: Action::GravityDown,
        when: When::Always,
        group: Group::Parameters,
        description: "weaker gravity (down to 0)",
        hint: None,
    },
    Binding {
        keys: &[ch('G')],
        action: Action::GravityUp,
        when: When::Always,
        group: Group::Parameters,
        description: "stronger gravity (up to 20 m/s^2)",
        hint: Some("gravity"),
    },
    Binding {
        keys: &[ch('i')],
        action: Action::NextIntegrator,
        when: When::Always,
        group: Group::Parameters,
        description: "next integrator",
        hint: Some("method"),
    },
    Binding {
        keys: &[ch('b')],
        action: Action::NextBroadPhase,
        when: When::Always,
        group: Group::Parameters,
        description: "next broad phase: all-pairs, grid, auto",
        hint: Some("broad"),
    },
    Binding {
        keys: &[ch('y')],
        action: Action::ToggleResting,
        when: When::Always,
        group: Group::Parameters,
        description: "resting contact on/off (bounces slower than a step of gravity stop)",
        hint: None,
    },
    Binding {
        keys: &[ch('Y')],
        action: Action::ToggleSupport,
        when: When::Always,
        group: Group::Parameters,
        description: "support pass on/off (resting contacts solved together)",
        hint: None,
    },
    Binding {
        keys: &[ch('S')],
        action: Action::ToggleSleep,
        when: When::Always,
        group: Group::Parameters,
        description: "sleeping on/off (spheres at rest for 0.5 s stop until disturbed)",
        hint: None,
    },
    Binding {
        keys: &[ch('[')],
        action: Action::HalveDt,
        when: When::Always,
        group: Group::Parameters,
        description: "halve dt (down to 1/7680 s)",
        hint: None,
    },
    Binding {
        keys: &[ch(']')],
        action: Action::DoubleDt,
        when: When::Always,
        group: Group::Parameters,
        description: "double dt (up to 1/30 s)",
        hint: None,
    },
    Binding {
        keys: &[ch('h'), code(KeyCode::Left)],
        action: Action::Orbit { yaw: O, pitch: 0.0 },
        when: When::Always,
        group: Group::View,
        description: "orbit left (← only while running)",
        hint: None,
    },
    Binding {
        keys: &[ch('l'), code(KeyCode::Right)],
        action: Action::Orbit {
            yaw: -O,
            pitch: 0.0,
        },
        when: When::Always,
        group: Group::View,
        description: "orbit right (→ only while running)",
        hint: None,
    },
    Binding {
        keys: &[ch('k'), code(KeyCode::Up)],
        action: Action::Orbit { yaw: 0.0, pitch: O },
        when: When::Always,
        group: Group::View,
        description: "look from higher",
        hint: None,
    },
    Binding {
        keys: &[ch('j'), code(KeyCode::Down)],
        action: Action::Orbit {
            yaw: 0.0,
            pitch: -O,
        },
        when: When::Always,
        group: Group::View,
        description: "look from lower",
        hint: None,
    },
    Binding {
        keys: &[ch('z')],
        action: Action::Zoom(ZOOM_STEP),
        when: When::Always,
        group: Group::View,
        description: "zoom in (on the selection, if any)",
        hint: None,
    },
    Binding {
        keys: &[ch('Z')],
        action: Action::Zoom(1.0 / ZOOM_STEP),
        when: When::Always,
        group: Group::View,
        description: "zoom out",
        hint: None,
    },
    Binding {
        keys: &[ch('f')],
        action: Action::View(Preset::Front),
        when: When::Always,
        group: Group::View,
        description: "front view",
        hint: None,
    },
    Binding {
        keys: &[ch('s')],
        action: Action::View(Preset::Side),
        when: When::Always,
        group: Group::View,
        description: "side view",
        hint: None,
    },
    Binding {
        keys: &[ch('u')],
        action: Action::View(Preset::Top),
        when: When::Always,
        group: Group::View,
        description: "top view (from up above)",
        hint: None,
    },
    Binding {
        keys: &[ch('a')],
        action: Action::View(Preset::ThreeQuarter),
        when: When::Always,
        group: Group::View,
        description: "three-quarter view",
        hint: None,
    },
    Binding {
        keys: &[ch('0')],
        action: Action::ResetView,
        when: When::Always,
        group: Group::View,
        description: "reset the view",
        hint: None,
    },
    Binding {
        keys: &[ch('v')],
        action: Action::ToggleVectors,
        when: When::Always,
        group: Group::View,
        description: "velocity vectors on/off",
        hint: None,
    },
    Binding {
        keys: &[ch('t')],
        action: Action::ToggleTrails,
        when: When::Always,
        group: Group::View,
        description: "trails on/off",
        hint: None,
    },
    Binding {
        keys: &[ch('#')],
        action: Action::ToggleFloorGrid,
        when: When::Always,
        group: Group::View,
        description: "floor grid on/off",
        hint: None,
    },
    Binding {
        keys: &[ch('m')],
        action: Action::ToggleColouring,
        when: When::Always,
        group: Group::View,
        description: "colour by speed or by depth",
        hint: None,
    },
    Binding {
        keys: &[ch('d')],
        action: Action::ToggleContacts,
        when: When::Always,
        group: Group::View,
        description: "contacts and their normals on/off",
        hint: None,
    },
    Binding {
        keys: &[ch('w')],
        action: Action::TogglePanel,
        when: When::Always,
        group: Group::View,
        description: "hide or show the side panel",
        hint: None,
    },
    Binding {
        keys: &[ch('x')],
        action: Action::ToggleGhost,
        when: When::Always,
        group: Group::View,
        description: "exact reference as a ghost on/off",
        hint: Some("ghost"),
    },
    Binding {
        keys: &[ch('c')],
        action: Action::ToggleChart,
        when: When::Always,
        group: Group::View,
        description: "work-precision chart of the lesson",
        hint: Some("chart"),
    },
];

/// Mouse use, for the help overlay (the terminal reports it, not the table).
pub(crate) const MOUSE_HELP: &[(&str, &str)] = &[
    ("click", "select the sphere under the pointer"),
    ("drag", "orbit the camera"),
    ("wheel", "zoom in and out"),
];

/// The action a key asks for in `mode`, if any. While the help is open
/// its own keys (scrolling, closing) come first; every other key asks for
/// its usual action, which the app then declines, saying so, unless it is
/// a way out (`Action::acts_over_help`).
pub fn dispatch(key: Key, mode: Mode) -> Option<Action> {
    BINDINGS
        .iter()
        .find(|b| b.keys.contains(&key) && b.when.holds(mode))
        .map(|b| b.action)
}

/// What the footer says of a key that does nothing in `mode`. A capital
/// whose small letter acts asks after Caps Lock.
pub(crate) fn unbound(key: Key, mode: Mode) -> String {
    let label = key.label();
    let lower = match key.code {
        KeyCode::Char(c) if !key.ctrl && c.is_uppercase() => Some(ch(c.to_ascii_lowercase()))
            .filter(|&k| {
                dispatch(k, mode).is_some_and(|a| !mode.chart_open || a.acts_over_chart())
            }),
        _ => None,
    };
    match lower {
        Some(k) => format!(
            "{label} does nothing here ({} does: is Caps Lock on?); ? lists the keys",
            k.label()
        ),
        None => format!("{label} does nothing here: ? lists the keys"),
    }
}

/// Radians of orbit per terminal cell of mouse drag.
pub(crate) const DRAG_STEP: f64 = ORBIT_STEP / 2.0;

/// The action a mouse event asks for: a left-button drag orbits (by the
/// cells moved since the last event), a left click (press and release
/// without moving) picks, the wheel zooms. `drag` remembers the button.
pub fn mouse_action(e: &MouseEvent, drag: &mut Option<Drag>) -> Option<Action> {
    match e.kind {
        MouseEventKind::Down(MouseButton::Left) => {
            *drag = Some(Drag {
                at: (e.column, e.row),
                moved: false,
            });
            None
        }
        MouseEventKind::Drag(MouseButton::Left) => {
            let d = drag.as_mut()?;
            let (c0, r0) = std::mem::replace(&mut d.at, (e.column, e.row));
            d.moved = true;
            let dx = f64::from(e.column) - f64::from(c0);
            let dy = f64::from(e.row) - f64::from(r0);
            Some(Action::Orbit {
                yaw: -dx * DRAG_STEP,
                pitch: dy * DRAG_STEP * 2.0,
            })
        }
        MouseEventKind::Up(MouseButton::Left) => match drag.take() {
            Some(d) if !d.moved => Some(Action::Pick {
                column: e.column,
                row: e.row,
            }),
            _ => None,
        },
        MouseEventKind::Up(_) => {
            *drag = None;
            None
        }
        MouseEventKind::ScrollUp => Some(Action::Zoom(ZOOM_STEP)),
        MouseEventKind::ScrollDown => Some(Action::Zoom(1.0 / ZOOM_STEP)),
        _ => None,
    }
}

/// A left button held down: where it was last seen, and whether it has
/// moved since it went down (a drag orbits; a press and release in place
/// is a click).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Drag {
    pub at: (u16, u16),
    pub moved: bool,
}

/// What `action` does, as the help says it: the description of the first
/// key bound to it (`None` for actions no key makes, such as a click).
pub(crate) fn describe(action: Action) -> Option<&'static str> {
    BINDINGS
        .iter()
        .find(|b| b.action == action)
        .map(|b| b.description)
}

/// The key that asks for `action`, as the help writes it: the first
/// bound to it. Messages name keys through this, so that they follow the
/// table.
pub(crate) fn key_of(action: Action) -> String {
    BINDINGS
        .iter()
        .find(|b| b.action == action)
        .map_or_else(String::new, |b| b.keys[0].label())
}

/// `(keys, hint)` pairs for the footer, in table order, for `mode`.
pub(crate) fn footer(mode: Mode) -> Vec<(String, &'static str)> {
    BINDINGS
        .iter()
        .filter(|b| b.when.holds(mode) || b.when == When::Paused)
        .filter(|b| !mode.chart_open || b.action.acts_over_chart())
        .filter(|b| !mode.help_open || b.action.acts_over_help())
        // The spheres' restitution where they collide (`e` the walls'
        // c_r, which a learner of collisions may take for it).
        .filter(|b| mode.pairs || b.action != Action::PairRestitutionUp)
        .filter_map(|b| {
            // Space's hint says what it does now: a paused world runs.
            let hint = match (b.action, b.hint?) {
                (Action::TogglePause, _) if mode.paused => "run",
                (_, hint) => hint,
            };
            let keys = match b.action {
                Action::Lesson(_) => "1-3".to_string(),
                Action::WallRestitutionUp => "e/E".to_string(),
                Action::PairRestitutionUp => "p/P".to_string(),
                Action::GravityUp => "g/G".to_string(),
                _ => b.keys[0].label(),
            };
            Some((keys, hint))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUNNING: Mode = Mode {
        paused: false,
        help_open: false,
        chart_open: false,
        selected: false,
        working: false,
        pairs: false,
    };
    const PAUSED: Mode = Mode {
        paused: true,
        help_open: false,
        chart_open: false,
        selected: false,
        working: false,
        pairs: false,
    };
    const CHART: Mode = Mode {
        paused: false,
        help_open: false,
        chart_open: true,
        selected: false,
        working: false,
        pairs: false,
    };

    #[test]
    fn messages_name_the_first_key_bound_to_an_action() {
        // Stepping is bound to n, '.' and Right, back to ',' and Left:
        // messages name the first of each (the session's write them out,
        // "'n' steps on, ',' back": the session imports nothing of the
        // terminal, and this table's keys are crossterm's), and every key
        // a message names dispatches to its action.
        assert_eq!(key_of(Action::StepForward), "n");
        assert_eq!(key_of(Action::StepBack), ",");
        let picked = Mode {
            selected: true,
            ..PAUSED
        };
        for action in [
            Action::ToggleResting,
            Action::ToggleSupport,
            Action::ToggleSleep,
            Action::ToggleVectors,
            Action::ToggleTrails,
            Action::ToggleFloorGrid,
            Action::ToggleContacts,
            Action::TogglePanel,
            Action::ClearSelection,
            Action::StepBack,
            Action::ToggleGhost,
            Action::ToggleHelp,
            Action::ToggleColouring,
            Action::Quit,
        ] {
            let label = key_of(action);
            let key = BINDINGS
                .iter()
                .flat_map(|b| b.keys)
                .find(|k| k.label() == label)
                .expect("a bound key");
            assert_eq!(dispatch(*key, picked), Some(action), "{label}");
        }
        // The help's title names the key that closes it.
        let help = Mode {
            help_open: true,
            ..picked
        };
        let esc = code(KeyCode::Esc);
        assert_eq!(key_of(Action::CloseHelp), esc.label());
        assert_eq!(dispatch(esc, help), Some(Action::CloseHelp));
        // The footer's note while the world works names the key that stops it.
        let working = Mode {
            working: true,
            ..PAUSED
        };
        assert_eq!(key_of(Action::StopWork), esc.label());
        assert_eq!(dispatch(esc, working), Some(Action::StopWork));
        // A click picks, and no key does.
        assert_eq!(key_of(Action::Pick { column: 0, row: 0 }), "");
    }

    #[test]
    fn o_says_how_far_it_searches() {
        use crate::tui::session::{COLLISION_SEARCH_SECONDS, COLLISION_SEARCH_STEPS, DT_MIN};
        let said = describe(Action::NextCollision).unwrap();
        let limits = format!(
            "(none within {COLLISION_SEARCH_SECONDS} s, or within {} steps when dt is below 1/{} s",
            crate::scene::thousands(COLLISION_SEARCH_STEPS),
            1.0 / DT_MIN
        );
        assert!(said.contains(&limits), "{said}");
    }

    #[test]
    fn the_footer_lists_only_keys_that_act_where_it_shows() {
        let hints = |mode| -> Vec<String> {
            footer(mode)
                .into_iter()
                .map(|(keys, hint)| format!("{keys} {hint}"))
                .collect()
        };
        let help = Mode {
            help_open: true,
            ..RUNNING
        };
        assert_eq!(hints(help), ["? help", "q quit"]);
        assert_eq!(
            hints(CHART),
            ["? help", "q quit", "Space pause", "1-3 lessons", "c chart"]
        );
        assert!(hints(PAUSED).contains(&"n step".to_string()));
        // Space says what it does now.
        assert!(hints(RUNNING).contains(&"Space pause".to_string()));
        assert!(hints(PAUSED).contains(&"Space run".to_string()));
        assert!(!hints(PAUSED).contains(&"Space pause".to_string()));
        // The spheres' restitution is named where they collide, before
        // the walls'.
        let pairs = Mode {
            pairs: true,
            ..RUNNING
        };
        assert!(!hints(RUNNING).iter().any(|h| h.starts_with("p/P")));
        let (p, e) = (hints(pairs), "p/P e".to_string());
        let at = |h: &str| p.iter().position(|x| x == h);
        assert!(at(&e).is_some_and(|k| Some(k) < at("e/E c_r")), "{p:?}");
    }

    #[test]
    fn the_step_keys_pause_a_running_world_and_step_a_paused_one() {
        for key in [ch('n'), ch('.'), ch(',')] {
            assert_eq!(dispatch(key, RUNNING), Some(Action::PauseToStep));
        }
        assert_eq!(dispatch(ch('n'), PAUSED), Some(Action::StepForward));
        assert_eq!(dispatch(ch(','), PAUSED), Some(Action::StepBack));
        assert_eq!(dispatch(ch(' '), RUNNING), Some(Action::TogglePause));
        assert_eq!(describe(Action::PauseToStep), Some("pause to step"));
    }

    #[test]
    fn arrows_step_while_paused_and_orbit_while_running() {
        let right = code(KeyCode::Right);
        assert_eq!(dispatch(right, PAUSED), Some(Action::StepForward));
        assert!(matches!(
            dispatch(right, RUNNING),
            Some(Action::Orbit { .. })
        ));
        assert!(matches!(
            dispatch(ch('l'), PAUSED),
            Some(Action::Orbit { .. })
        ));
        assert_eq!(
            dispatch(code(KeyCode::Left), PAUSED),
            Some(Action::StepBack)
        );
    }

    #[test]
    fn esc_closes_the_help_then_the_selection_and_never_quits() {
        let help = Mode {
            paused: false,
            help_open: true,
            chart_open: false,
            selected: true,
            working: false,
            pairs: false,
        };
        let selected = Mode {
            selected: true,
            ..RUNNING
        };
        assert_eq!(dispatch(code(KeyCode::Esc), help), Some(Action::CloseHelp));
        assert_eq!(
            dispatch(code(KeyCode::Esc), selected),
            Some(Action::ClearSelection)
        );
        assert_eq!(
            dispatch(code(KeyCode::Esc), RUNNING),
            None,
            "Esc never quits"
        );
        assert_eq!(
            dispatch(ch('x'), help),
            Some(Action::ToggleGhost),
            "keys ask for their usual action behind the help"
        );
        assert_eq!(dispatch(ctrl('c'), help), Some(Action::Quit));
        // Ctrl-\ comes as the byte crossterm reads as Ctrl-4.
        assert_eq!(dispatch(CTRL_BACKSLASH, help), Some(Action::Quit));
        assert_eq!(CTRL_BACKSLASH.label(), "Ctrl-\\");
    }

    #[test]
    fn every_key_of_every_entry_reaches_its_action_in_some_mode() {
        let modes = [RUNNING, PAUSED, CHART]
            .into_iter()
            .chain([true, false].map(|paused| Mode {
                paused,
                help_open: true,
                chart_open: false,
                selected: false,
                working: false,
                pairs: false,
            }))
            .chain([Mode {
                selected: true,
                ..RUNNING
            }])
            .chain([Mode {
                working: true,
                ..PAUSED
            }]);
        let modes: Vec<Mode> = modes.collect();
        for b in BINDINGS {
            for &k in b.keys {
                assert!(
                    modes.iter().any(|&m| dispatch(k, m) == Some(b.action)),
                    "key {} never reaches {:?}: an earlier entry shadows it",
                    k.label(),
                    b.action
                );
            }
        }
    }

    #[test]
    fn esc_while_the_world_works_stops_it_and_otherwise_does_what_it_did() {
        let working = Mode {
            working: true,
            ..PAUSED
        };
        assert_eq!(
            dispatch(code(KeyCode::Esc), working),
            Some(Action::StopWork)
        );
        // A selection keeps its Esc first (forgetting it goes to the world,
        // so it stops the work too, as any action for the world does); in
        // the help, Esc closes the help.
        for (mode, action) in [
            (
                Mode {
                    selected: true,
                    ..working
                },
                Action::ClearSelection,
            ),
            (
                Mode {
                    help_open: true,
                    ..working
                },
                Action::CloseHelp,
            ),
        ] {
            assert_eq!(dispatch(code(KeyCode::Esc), mode), Some(action));
        }
        assert_eq!(dispatch(code(KeyCode::Esc), PAUSED), None);
    }

    #[test]
    fn a_key_that_does_nothing_says_so_and_asks_after_caps_lock() {
        assert_eq!(dispatch(ch('Q'), RUNNING), None);
        assert_eq!(
            unbound(ch('Q'), RUNNING),
            "Q does nothing here (q does: is Caps Lock on?); ? lists the keys"
        );
        assert_eq!(
            unbound(ch('9'), PAUSED),
            "9 does nothing here: ? lists the keys"
        );
        // Behind the chart x is declined: no hint that it would act.
        assert_eq!(
            unbound(ch('X'), CHART),
            "X does nothing here: ? lists the keys"
        );
        assert_eq!(
            unbound(ch('C'), CHART),
            "C does nothing here (c does: is Caps Lock on?); ? lists the keys"
        );
        assert_eq!(
            unbound(code(KeyCode::F(5)), RUNNING),
            "F5 does nothing here: ? lists the keys"
        );
        assert_eq!(
            unbound(ctrl('a'), RUNNING),
            "Ctrl-A does nothing here: ? lists the keys"
        );
        // Esc acts only on a selection, the help or the chart.
        assert_eq!(dispatch(code(KeyCode::Esc), RUNNING), None);
        assert_eq!(
            unbound(code(KeyCode::Esc), RUNNING),
            "Esc does nothing here: ? lists the keys"
        );
    }

    #[test]
    fn esc_closes_the_chart_before_quitting_and_c_toggles_it() {
        assert_eq!(
            dispatch(code(KeyCode::Esc), CHART),
            Some(Action::CloseChart)
        );
        assert_eq!(dispatch(ch('c'), CHART), Some(Action::ToggleChart));
        assert_eq!(dispatch(ch('c'), RUNNING), Some(Action::ToggleChart));
        assert_eq!(dispatch(ch('q'), CHART), Some(Action::Quit));
    }

    #[test]
    fn no_key_is_bound_twice_for_all_modes() {
        let always: Vec<(Key, Action)> = BINDINGS
            .iter()
            .filter(|b| b.when == When::Always)
            .flat_map(|b| b.keys.iter().map(|&k| (k, b.action)))
            .collect();
        for (n, (k, a)) in always.iter().enumerate() {
            for (k2, a2) in &always[n + 1..] {
                assert!(k != k2, "key {} means {a:?} and {a2:?}", k.label());
            }
        }
    }

    #[test]
    fn ctrl_letters_are_read_case_blind_and_shift_folds_into_the_character() {
        let e = KeyEvent::new(
            KeyCode::Char('C'),
            KeyModifiers::CONTROL | KeyModifiers::SHIFT,
        );
        assert_eq!(Key::from_event(&e), Some(ctrl('c')));
        let e = KeyEvent::new(KeyCode::Char('E'), KeyModifiers::SHIFT);
        assert_eq!(Key::from_event(&e), Some(ch('E')));
    }

    #[test]
    fn keys_with_alt_are_bound_to_nothing() {
        for modifiers in [
            KeyModifiers::ALT,
            KeyModifiers::ALT | KeyModifiers::CONTROL,
            KeyModifiers::SUPER,
            KeyModifiers::META,
        ] {
            let e = KeyEvent::new(KeyCode::Char('q'), modifiers);
            assert_eq!(Key::from_event(&e), None, "{modifiers:?}-q");
        }
        let e = KeyEvent::new(KeyCode::Char('q'), KeyModifiers::NONE);
        assert_eq!(
            Key::from_event(&e).and_then(|k| dispatch(k, RUNNING)),
            Some(Action::Quit)
        );
        // The key Alt was held with, to say what it would have been.
        let e = KeyEvent::new(KeyCode::Char('r'), KeyModifiers::ALT);
        assert_eq!(Key::without_alt(&e), Some(ch('r')));
        assert_eq!(
            Key::without_alt(&KeyEvent::new(KeyCode::Char('r'), KeyModifiers::NONE)),
            None
        );
        let e = KeyEvent::new(KeyCode::Char('r'), KeyModifiers::ALT | KeyModifiers::SUPER);
        assert_eq!(Key::without_alt(&e), None);
    }

    #[test]
    fn ctrl_l_redraws_in_any_mode() {
        for mode in [RUNNING, PAUSED, CHART] {
            assert_eq!(dispatch(ctrl('l'), mode), Some(Action::Redraw));
        }
        assert!(Action::Redraw.acts_over_help() && Action::Redraw.acts_over_chart());
        // `l` alone still orbits.
        assert!(matches!(
            dispatch(ch('l'), RUNNING),
            Some(Action::Orbit { .. })
        ));
    }

    #[test]
    fn ctrl_z_suspends_in_any_mode_whatever_the_case() {
        for mode in [RUNNING, PAUSED, CHART] {
            assert_eq!(dispatch(ctrl('z'), mode), Some(Action::Suspend));
        }
        let e = KeyEvent::new(KeyCode::Char('Z'), KeyModifiers::CONTROL);
        assert_eq!(Key::from_event(&e), Some(ctrl('z')));
        assert_eq!(dispatch(ch('z'), RUNNING), Some(Action::Zoom(ZOOM_STEP)));
    }
}
