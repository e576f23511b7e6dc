//! Random key sequences, mouse events and terminal sizes driven through the
//! visualiser's state machine and drawing: nothing panics and every
//! invariant holds after every event.

use crate::support::draw;
use lerpit::scene::Lesson;
use lerpit::tui::App;
use lerpit::tui::action::Action;
use lerpit::tui::app::TIME_SCALES;
use lerpit::tui::camera::{PITCH_LIMIT, ZOOM_MAX, ZOOM_MIN};
use lerpit::tui::keymap::{BINDINGS, Key, dispatch, mouse_action};
use lerpit::tui::selection::Selection;
use lerpit::tui::session::Session;
use lerpit::tui::session::{DT_MAX, DT_MIN, GRAVITY_MAX};
use proptest::prelude::*;
use ratatui::crossterm::event::{KeyCode, KeyModifiers, MouseButton, MouseEvent, MouseEventKind};

#[derive(Clone, Debug)]
enum Input {
    Key(Key),
    Mouse(MouseEventKind, u16, u16),
    Draw(u16, u16),
}

fn bound_keys() -> Vec<Key> {
    let mut keys: Vec<Key> = BINDINGS
        .iter()
        .flat_map(|b| b.keys.iter().copied())
        .collect();
    keys.dedup();
    keys
}

fn input() -> impl Strategy<Value = Input> {
    let keys = bound_keys();
    prop_oneof![
        6 => proptest::sample::select(keys).prop_map(Input::Key),
        1 => (any::<char>(), any::<bool>())
            .prop_map(|(c, ctrl)| Input::Key(Key { code: KeyCode::Char(c), ctrl })),
        1 => (
            proptest::sample::select(vec![
                MouseEventKind::Down(MouseButton::Left),
                MouseEventKind::Drag(MouseButton::Left),
                MouseEventKind::Up(MouseButton::Left),
                MouseEventKind::ScrollUp,
                MouseEventKind::ScrollDown,
            ]),
            any::<u16>(),
            any::<u16>(),
        )
            .prop_map(|(k, c, r)| Input::Mouse(k, c, r)),
        2 => (0u16..=200, 0u16..=70).prop_map(|(w, h)| Input::Draw(w, h)),
    ]
}

fn check_invariants(app: &App) -> Result<(), TestCaseError> {
    let session = app.session().expect("the tests own the session");
    let frame = &app.frame;
    let c = &session.world.config;
    prop_assert!(
        (0.0..=1.0).contains(&c.wall_restitution),
        "wall restitution {}",
        c.wall_restitution
    );
    prop_assert!(
        (0.0..=1.0).contains(&c.pair_restitution),
        "pair restitution {}",
        c.pair_restitution
    );
    prop_assert!(
        (0.0..=GRAVITY_MAX).contains(&session.gravity()),
        "gravity {}",
        session.gravity()
    );
    prop_assert!((DT_MIN..=DT_MAX).contains(&c.dt), "dt {}", c.dt);
    let s = app.time_scale();
    prop_assert!(
        s >= TIME_SCALES[0] && s <= *TIME_SCALES.last().unwrap(),
        "time scale {s}"
    );
    prop_assert!(
        app.camera.pitch.abs() <= PITCH_LIMIT,
        "pitch {}",
        app.camera.pitch
    );
    prop_assert!(
        (ZOOM_MIN..=ZOOM_MAX).contains(&app.camera.zoom),
        "zoom {}",
        app.camera.zoom
    );
    prop_assert!(
        !session.history.is_empty() && session.history.len() <= session.history.capacity()
    );
    prop_assert!(
        session.history.steps_back() as u64 <= session.world.steps,
        "history beyond step 0"
    );
    prop_assert_eq!(
        session.energy.samples().last().unwrap().steps,
        session.world.steps
    );
    prop_assert_eq!(
        session.world.bodies.len(),
        session.scene.body_count(),
        "scene and world agree"
    );
    prop_assert!(session.world.bodies.len() <= session.max_spheres().max(1));
    if let Some(g) = session.ghost.as_ref() {
        prop_assert!(session.show_ghost, "a ghost only while it is on");
        if g.unavailable.is_none() {
            prop_assert_eq!(g.positions.len(), session.world.bodies.len());
            prop_assert!(g.rms.is_some_and(f64::is_finite), "ghost RMS {:?}", g.rms);
        }
    }
    let b = &session.world.bodies;
    for i in 0..b.len() {
        let (p, r) = (b.position[i], b.radius[i]);
        prop_assert!(
            p.to_array()
                .iter()
                .all(|&x| x >= r - 1e-12 && x <= 1.0 - r + 1e-12),
            "sphere {i} at {p} (radius {r}) is outside the box"
        );
    }
    prop_assert_eq!(
        frame.world.state_hash(),
        session.world.state_hash(),
        "the frame shows the session's state"
    );
    Ok(())
}

/// The chart screen shows these rows (a sweep per case would be slow):
/// every method at three time steps, one of them with zero error (drawn at
/// the log floor).
fn no_sweep(lesson: Lesson) -> Result<Vec<lerpit::study::Row>, String> {
    let mut rows = Vec::new();
    for (k, &method) in lerpit::sim::Integrator::ALL.iter().enumerate() {
        for dt in [1.0 / 30.0, 1.0 / 300.0, 1.0 / 3000.0] {
            rows.push(lerpit::study::Row {
                lesson,
                method,
                dt,
                steps: 1,
                bodies: 1,
                horizon: 0.5,
                wall_time: 1e-6 / dt,
                cost_per_second: (1.0 + k as f64) * 1e-6 / dt,
                ns_per_body_step: 10.0,
                rms_error: if k == 4 { 0.0 } else { dt },
                bounce_time_error: None,
                apex_ratio_error: None,
                energy_error: dt,
                event_cap_reached: false,
            });
        }
    }
    Ok(rows)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn no_input_sequence_at_any_size_panics_or_breaks_an_invariant(
        lesson in proptest::sample::select(Lesson::ALL.to_vec()),
        inputs in proptest::collection::vec(input(), 1..60),
    ) {
        let mut app = App::lesson(lesson).with_chart_source(no_sweep);
        // Charts known up front: the chart screen is drawn at every size
        // without waiting on a thread.
        for l in Lesson::ALL {
            app.charts.insert(l, no_sweep(l).unwrap());
        }
        let mut drag = None;
        for input in inputs {
            match input {
                Input::Key(key) => {
                    if let Some(action) = dispatch(key, app.mode()) {
                        app.apply(action);
                    }
                }
                Input::Mouse(kind, column, row) => {
                    let e = MouseEvent { kind, column, row, modifiers: KeyModifiers::NONE };
                    if let Some(action) = mouse_action(&e, &mut drag) {
                        app.apply(action);
                    }
                }
                Input::Draw(w, h) => {
                    draw(&app, w, h);
                }
            }
            // A quit ends the real loop; carry on to reach more states.
            check_invariants(&app)?;
        }
    }
}

/// Step the collisions lesson (seed `seed`, pair restitution `e`) until a
/// contact of a pair that meets nothing else in that step; select it.
fn a_lone_contact(seed: u64, e: f64) -> Option<Session> {
    let mut scene = Lesson::Collisions.scene();
    scene.seed = seed;
    scene.world.pair_restitution = e;
    let mut session = Session::new(scene, Some(Lesson::Collisions)).ok()?;
    for _ in 0..2000 {
        session.step();
        let w = &session.world;
        let contacts = w.contacts();
        let alone = |c: &lerpit::sim::Contact| {
            contacts
                .iter()
                .filter(|d| [d.i, d.j].iter().any(|s| *s == c.i || *s == c.j))
                .count()
                == 1
        };
        if let Some(c) = contacts.iter().find(|c| alone(c)) {
            let (a, b) = (w.bodies.id[c.i as usize], w.bodies.id[c.j as usize]);
            session.apply(Action::Select(Some(Selection::pair(a, b))));
            return Some(session);
        }
    }
    None
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// The panel's V1 and V2 for a selected pair are the normal speeds the
    /// step produced, and follow the lesson's formula from the panel's own
    /// m, v and e.
    #[test]
    fn a_selected_pairs_v1_and_v2_are_what_the_step_produced(
        seed in 0u64..10_000,
        e in 0u32..=100,
    ) {
        let e = f64::from(e) / 100.0;
        let session = a_lone_contact(seed, e).expect("the lesson's spheres collide");
        let inspection = session.inspection().expect("a selection");
        let pair = inspection.pair.clone().expect("numbers for a pair in contact");
        let Selection::Pair(a, b) = inspection.selection else { panic!("a pair") };
        let b_ = &session.world.bodies;
        let slot = |id: u32| b_.id.iter().position(|&s| s == id).unwrap();
        let (s1, s2) = (slot(a), slot(b));
        let inside = |p: lerpit::sim::Vec3, r: f64| p.to_array().iter().all(|&x| x > r && x < 1.0 - r);
        // The wall stage runs after the contacts; where it leaves the pair
        // alone, the step's result is the contact's.
        if inside(pair.after[0], b_.radius[s1]) && inside(pair.after[1], b_.radius[s2]) {
            prop_assert_eq!(pair.after, [b_.position[s1], b_.position[s2]]);
            let n = pair.normal;
            let tol = |v: f64| 1e-12 * (1.0 + v.abs());
            match pair.v_after {
                Some([v1, v2]) => {
                    prop_assert!((b_.velocity[s1].dot(n) - v1).abs() <= tol(v1));
                    prop_assert!((b_.velocity[s2].dot(n) - v2).abs() <= tol(v2));
                    let [m1, m2] = pair.mass;
                    let [u1, u2] = pair.v_normal;
                    let e = pair.e;
                    let lesson_v1 = (m1 * u1 + m2 * u2 - m2 * (u1 - u2) * e) / (m1 + m2);
                    let lesson_v2 = (m1 * u1 + m2 * u2 - m1 * (u2 - u1) * e) / (m1 + m2);
                    prop_assert!((lesson_v1 - v1).abs() <= tol(v1));
                    prop_assert!((lesson_v2 - v2).abs() <= tol(v2));
                    // Momentum is conserved; kinetic energy never grows.
                    prop_assert!((pair.momentum[1] - pair.momentum[0]).length()
                        <= 1e-12 * (1.0 + pair.momentum[0].length()));
                    prop_assert!(pair.kinetic[1] <= pair.kinetic[0] * (1.0 + 1e-12));
                }
                None => prop_assert!(pair.v_normal[0] <= pair.v_normal[1], "separating"),
            }
        }
    }
}

/// With the support pass on, a pair the lesson's pass struck still shows
/// its V1 and V2 by the lesson's formula, and where it ended the step;
/// a resting pair says that the support pass holds it.
#[test]
fn with_the_support_pass_a_struck_pair_shows_its_numbers_and_a_resting_one_says_why() {
    use lerpit::sim::{Body, Vec3};
    let r = 0.05;
    let body = |position: Vec3, velocity: Vec3, mass: f64| Body {
        position,
        velocity,
        radius: r,
        mass,
    };
    let scene_with = |support: bool| {
        let mut scene = Lesson::Collisions.scene();
        scene.spawns.clear();
        scene.spawn_lines.clear();
        scene.world.support = support;
        scene.bodies = vec![
            // A column of two at rest on the floor.
            body(Vec3::new(0.2, r, 0.2), Vec3::ZERO, 1.0),
            body(Vec3::new(0.2, 3.0 * r - 1e-4, 0.2), Vec3::ZERO, 1.0),
            // Two in mid-air, overlapping as they close fast.
            body(Vec3::new(0.6, 0.6, 0.6), Vec3::new(1.0, 0.0, 0.0), 1.0),
            body(
                Vec3::new(0.6 + 2.0 * r - 1e-3, 0.6, 0.6),
                Vec3::new(-2.0, 0.0, 0.0),
                3.0,
            ),
            // Two in mid-air, overlapping as they fly apart.
            body(Vec3::new(0.3, 0.6, 0.3), Vec3::new(-1.0, 0.0, 0.0), 1.0),
            body(
                Vec3::new(0.3 + 2.0 * r - 0.02, 0.6, 0.3),
                Vec3::new(1.0, 0.0, 0.0),
                1.0,
            ),
            // Two parting slower than the panel's figures show.
            body(Vec3::new(0.3, 0.3, 0.7), Vec3::new(-1e-4, 0.0, 0.0), 1.0),
            body(
                Vec3::new(0.3 + 2.0 * r - 1e-3, 0.3, 0.7),
                Vec3::new(1e-4, 0.0, 0.0),
                1.0,
            ),
        ];
        scene
    };
    let mut session =
        Session::new(scene_with(true), Some(Lesson::Collisions)).expect("a valid scene");
    assert_eq!(session.world.config.support_idle(), None, "the pass runs");
    session.step();

    session.apply(Action::Select(Some(Selection::pair(2, 3))));
    let inspection = session.inspection().expect("a selection");
    let pair = inspection.pair.expect("numbers for the struck pair");
    let [m1, m2] = pair.mass;
    let [u1, u2] = pair.v_normal;
    let e = pair.e;
    assert_eq!(e, session.world.config.pair_restitution, "a fast impact");
    let [v1, v2] = pair.v_after.expect("an impulse");
    let tol = |v: f64| 1e-12 * (1.0 + v.abs());
    assert!((v1 - (m1 * u1 + m2 * u2 - m2 * (u1 - u2) * e) / (m1 + m2)).abs() <= tol(v1));
    assert!((v2 - (m1 * u1 + m2 * u2 - m1 * (u2 - u1) * e) / (m1 + m2)).abs() <= tol(v2));
    // Sphere 2 is the lighter one, from whose side n points.
    assert!(u1 > u2 && (pair.normal - Vec3::X).length() < 1e-12);
    // The support pass leaves a pair flying apart in mid-air alone: the
    // step ends with the lesson's V1 and V2.
    let [end1, end2] = pair.step_end.expect("the support pass ran");
    let b = &session.world.bodies;
    let slot = |id: u32| b.id.iter().position(|&s| s == id).unwrap();
    assert_eq!(end1, b.velocity[slot(2)].dot(pair.normal));
    assert_eq!(end2, b.velocity[slot(3)].dot(pair.normal));
    assert!((end1 - v1).abs() <= tol(v1) && (end2 - v2).abs() <= tol(v2));

    session.apply(Action::Select(Some(Selection::pair(0, 1))));
    let inspection = session.inspection().expect("a selection");
    assert_eq!(inspection.pair, None);
    let note = inspection.pair_note.expect("a note for the resting pair");
    assert!(
        note.contains("resting contact") && note.contains("support pass"),
        "{note}"
    );
    // A pair flying apart is not resting contact, though the lesson's pass
    // leaves it to the support pass too.
    session.apply(Action::Select(Some(Selection::pair(4, 5))));
    let note = session
        .inspection()
        .and_then(|i| i.pair_note)
        .expect("a note for the separating pair");
    assert!(note.starts_with("separating at 2.000 m/s"), "{note}");
    // One parting at 0.0002 m/s reads as at rest along n, not as
    // "separating at 0.000 m/s".
    session.apply(Action::Select(Some(Selection::pair(6, 7))));
    let note = session
        .inspection()
        .and_then(|i| i.pair_note)
        .expect("a note for the pair at rest along n");
    assert!(
        note.starts_with("resting contact: closing at 0.000 m/s along n"),
        "{note}"
    );

    // With the pass off the same impact has no step-end row.
    let mut session = Session::new(scene_with(false), Some(Lesson::Collisions)).expect("valid");
    session.step();
    session.apply(Action::Select(Some(Selection::pair(2, 3))));
    let pair = session.inspection().and_then(|i| i.pair).expect("numbers");
    assert_eq!(pair.step_end, None);
    assert_eq!(pair.v_after, Some([v1, v2]), "the same lesson's impact");
}
