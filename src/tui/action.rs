//! What a person can ask the visualiser to do. Keys and mouse events turn
//! into actions (see `keymap`); `App::apply` carries them out. An action
//! says what is wanted, never which key asked for it.

use super::camera::Preset;
use super::selection::Selection;
use crate::scene::Lesson;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    Quit,
    TogglePause,
    /// Pause a running world so that the step keys step it (`n`, `.` and
    /// `,` while running): unlike `TogglePause`, a way into stepping, so
    /// what covers the view declines it as it declines the steps.
    PauseToStep,
    StepForward,
    StepBack,
    Lesson(Lesson),
    /// The scene opened from a file at the start, afresh (Tab and
    /// Shift-Tab reach it among the lessons).
    OpenedScene,
    NextLesson,
    PreviousLesson,
    WallRestitutionDown,
    WallRestitutionUp,
    PairRestitutionDown,
    PairRestitutionUp,
    GravityDown,
    GravityUp,
    NextIntegrator,
    /// The next broad phase: all-pairs, grid, auto.
    NextBroadPhase,
    HalveDt,
    DoubleDt,
    MoreSpheres,
    FewerSpheres,
    Slower,
    Faster,
    Restart,
    Reseed,
    ToggleVectors,
    ToggleTrails,
    /// Draw a grid on the floor, or stop.
    ToggleFloorGrid,
    ToggleColouring,
    /// Draw the exact reference as a ghost over the spheres, or stop.
    ToggleGhost,
    /// Open or close the work-precision chart of the lesson.
    ToggleChart,
    CloseChart,
    /// Turn the camera by these angles, rad.
    Orbit {
        yaw: f64,
        pitch: f64,
    },
    /// Multiply the zoom by this factor.
    Zoom(f64),
    View(Preset),
    ResetView,
    ToggleHelp,
    CloseHelp,
    /// Scroll the help by this many lines (negative: up).
    ScrollHelp(i16),
    /// Scroll the help by this many pages of what it shows (negative: up).
    ScrollHelpPage(i16),
    /// Scroll the help to its top (false) or its end (true).
    ScrollHelpTo(bool),
    /// A click at this terminal cell: select the sphere nearest to it.
    Pick {
        column: u16,
        row: u16,
    },
    /// Select spheres (or nothing).
    Select(Option<Selection>),
    /// Forget the selection.
    ClearSelection,
    /// Pick the sphere numbered after the one picked (the first of a pair
    /// picked; sphere 0 when none is), or before it (the second of a pair).
    PickNext,
    PickPrevious,
    /// Run to the next collision, pause on it and select it.
    NextCollision,
    /// Stop what the world works on: a search for a collision or a long
    /// step gives way to it, as to any action for the world; it changes
    /// nothing itself, and says what the search it stopped said.
    StopWork,
    /// Mark the contacts of the step and draw their normals, or stop.
    ToggleContacts,
    /// Show or hide the side panel.
    TogglePanel,
    /// Resting contact on or off: impacts slower than one step of gravity
    /// keep no normal speed.
    ToggleResting,
    /// The support pass on or off: resting contacts solved together.
    ToggleSupport,
    /// Sleeping on or off: spheres at rest stop costing anything until
    /// disturbed.
    ToggleSleep,
    /// Hand the terminal back to the shell and stop (Ctrl-Z); `fg`
    /// resumes. The event loop carries it out: it owns the terminal.
    Suspend,
    /// Draw every cell of the screen again (Ctrl-L), as after another
    /// program wrote over it. The event loop carries it out too.
    Redraw,
}

impl Action {
    /// Whether the action acts while the help covers the view: the help's
    /// own (scrolling, closing) and the ways out. Anything else would
    /// change what the help hides, unseen.
    pub fn acts_over_help(self) -> bool {
        matches!(
            self,
            Action::Quit
                | Action::Suspend
                | Action::Redraw
                | Action::ToggleHelp
                | Action::CloseHelp
                | Action::ScrollHelp(_)
                | Action::ScrollHelpPage(_)
                | Action::ScrollHelpTo(_)
        )
    }

    /// Whether the action only moves the camera: it changes nothing the
    /// footer's word on the last action speaks of, which it leaves (a
    /// learner turns and zooms to look at the collision it describes).
    pub fn moves_the_camera(self) -> bool {
        matches!(
            self,
            Action::Orbit { .. } | Action::Zoom(_) | Action::View(_) | Action::ResetView
        )
    }

    /// Whether the action acts while the work-precision chart covers the
    /// view and the panel: the chart's own keys, the help, a lesson (whose
    /// chart then shows), pausing and the ways out. Anything else would
    /// change what the chart hides, unseen.
    pub fn acts_over_chart(self) -> bool {
        self.acts_over_help()
            || matches!(
                self,
                Action::ToggleChart
                    | Action::CloseChart
                    | Action::TogglePause
                    | Action::Lesson(_)
                    | Action::OpenedScene
                    | Action::NextLesson
                    | Action::PreviousLesson
            )
    }
}
