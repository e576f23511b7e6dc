//! The named choices: the names scene files, flags and output use, their
//! order, and the refusal of an unknown name (the same in a file and on
//! the command line).

use lerpit::scene::Lesson;
use lerpit::sim::config::{Choice, UnknownChoice};
use lerpit::sim::{BroadPhase, Integrator, MassLawKind, WallMode};
use strum::VariantArray;

fn names<C: Choice>() -> Vec<&'static str> {
    C::VARIANTS.iter().map(|&c| c.name()).collect()
}

#[test]
fn every_choice_keeps_its_names_in_order() {
    assert_eq!(
        names::<Integrator>(),
        [
            "explicit-euler",
            "semi-implicit-euler",
            "velocity-verlet",
            "rk4",
            "continuous"
        ]
    );
    assert_eq!(names::<BroadPhase>(), ["all-pairs", "grid", "auto"]);
    assert_eq!(names::<WallMode>(), ["flip", "restitution"]);
    assert_eq!(names::<MassLawKind>(), ["volume", "constant"]);
    assert_eq!(names::<Lesson>(), ["pingpong", "gravity", "collisions"]);
}

fn round_trips<C: Choice + std::fmt::Debug + std::fmt::Display>() {
    for &c in C::VARIANTS {
        assert_eq!(C::parse(c.name()), Ok(c));
        assert_eq!(c.to_string(), c.name());
    }
    let first = C::VARIANTS[0];
    let mut c = first.next();
    for _ in 1..C::VARIANTS.len() {
        assert_ne!(c, first);
        c = c.next();
    }
    assert_eq!(c, first, "next() wraps around after the last");
}

#[test]
fn names_parse_back_and_next_visits_each_once() {
    round_trips::<Integrator>();
    round_trips::<BroadPhase>();
    round_trips::<WallMode>();
    round_trips::<MassLawKind>();
    round_trips::<Lesson>();
}

#[test]
fn the_constant_lists_follow_the_declaration() {
    assert_eq!(Integrator::ALL.as_slice(), Integrator::VARIANTS);
    assert_eq!(BroadPhase::ALL.as_slice(), BroadPhase::VARIANTS);
    assert_eq!(Lesson::ALL.as_slice(), Lesson::VARIANTS);
    let discrete: Vec<Integrator> = Integrator::ALL
        .into_iter()
        .filter(|m| *m != Integrator::Continuous)
        .collect();
    assert_eq!(Integrator::DISCRETE.to_vec(), discrete);
}

#[test]
fn an_unknown_name_is_refused_with_every_choice() {
    let e: UnknownChoice = Integrator::parse("rk9").unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown integrator 'rk9'; choose one of explicit-euler, semi-implicit-euler, \
         velocity-verlet, rk4, continuous"
    );
    assert_eq!(
        MassLawKind::parse("heavy").unwrap_err().to_string(),
        "unknown mass law 'heavy'; choose one of volume, constant"
    );
}

#[test]
fn serde_uses_the_same_names() {
    #[derive(serde::Deserialize, serde::Serialize, Debug, PartialEq)]
    struct Row {
        integrator: Integrator,
        broad_phase: BroadPhase,
        wall_mode: WallMode,
    }
    let row = Row {
        integrator: Integrator::Rk4,
        broad_phase: BroadPhase::AllPairs,
        wall_mode: WallMode::Flip,
    };
    let json = serde_json::to_string(&row).unwrap();
    assert_eq!(
        json,
        r#"{"integrator":"rk4","broad_phase":"all-pairs","wall_mode":"flip"}"#
    );
    assert_eq!(serde_json::from_str::<Row>(&json).unwrap(), row);
    let e = serde_json::from_str::<Row>(
        r#"{"integrator":"leapfrog","broad_phase":"grid","wall_mode":"flip"}"#,
    )
    .unwrap_err();
    assert!(
        e.to_string().starts_with("unknown integrator 'leapfrog'"),
        "{e}"
    );
}
