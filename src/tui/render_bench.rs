//! `lerpit bench --render`: the cost of drawing one frame, headless.
//!
//! From the dilute start, the gravity lesson with N spheres (placed with
//! overlaps allowed: drawing cost does not depend on it, and 100,000 of
//! its spheres would not fit otherwise); from the settled start, the
//! benchmark's pile of N equal spheres at rest on the floor
//! (`scene::bench`), as a world under gravity becomes. It is drawn into an
//! off-screen buffer of W x H cells, F times; between frames the world
//! takes one step (not timed), so each frame draws a new state. Two figures per frame: the whole screen (view, panel,
//! chart, footer) and the box view alone. Medians are reported: the
//! machine may be busy. Owns the measurement only.

use super::app::App;
use super::view::render_box;
use crate::scene::bench::{BenchStart, bench_world_from};
use crate::scene::{Lesson, Scene};
use crate::sim::BroadPhase;
use crate::study::metrics::median;
use ratatui::buffer::Buffer;
use ratatui::layout::Rect;
use ratatui::widgets::Widget;
use std::time::Instant;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RenderBench {
    pub particles: usize,
    pub width: u16,
    pub height: u16,
    pub frames: usize,
    pub start: BenchStart,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Figures {
    /// Per-frame wall times, ms, sorted.
    pub frame_ms: Vec<f64>,
    pub box_ms: Vec<f64>,
}

impl RenderBench {
    /// The app to draw: the gravity lesson with `particles` spheres, or
    /// the benchmark's settled pile of them.
    pub fn app(&self) -> Result<App, String> {
        match self.start {
            BenchStart::Dilute => {
                let mut scene = Lesson::Gravity.scene();
                for s in &mut scene.spawns {
                    s.overlap = true;
                }
                scene.set_particles(self.particles)?;
                App::new(scene, Some(Lesson::Gravity)).map_err(|e| e.message)
            }
            BenchStart::Settled => {
                let pile = bench_world_from(BenchStart::Settled, self.particles, BroadPhase::Auto);
                let scene = Scene {
                    name: "benchmark pile".into(),
                    origin: "the benchmark's settled start".into(),
                    info: None,
                    world: pile.config.clone(),
                    seed: 0,
                    bodies: pile.bodies.iter_scene_order().collect(),
                    spawns: Vec::new(),
                    spawn_lines: Vec::new(),
                    sized_for: None,
                };
                App::new(scene, None).map_err(|e| e.message)
            }
        }
    }

    /// Step `app` and time drawing it, [`RenderBench::frames`] times,
    /// telling `drawn` after each frame.
    pub fn draw(&self, mut app: App, mut drawn: impl FnMut()) -> Figures {
        let area = Rect::new(0, 0, self.width, self.height);
        let mut buf = Buffer::empty(area);
        let (mut frame_ms, mut box_ms) = (Vec::new(), Vec::new());
        for _ in 0..self.frames {
            app.step();
            let t = Instant::now();
            buf.reset();
            (&app).render(area, &mut buf);
            frame_ms.push(t.elapsed().as_secs_f64() * 1e3);

            let t = Instant::now();
            buf.reset();
            render_box(&app, area, &mut buf);
            box_ms.push(t.elapsed().as_secs_f64() * 1e3);
            drawn();
        }
        frame_ms.sort_by(f64::total_cmp);
        box_ms.sort_by(f64::total_cmp);
        Figures { frame_ms, box_ms }
    }
}

impl Figures {
    pub(crate) fn report(&self, bench: &RenderBench) -> String {
        let line = |name: &str, v: &[f64]| {
            let m = median(&mut v.to_vec());
            format!(
                "{name:<10} median {m:.3} ms  (min {:.3}, max {:.3})  = {:.0} frames/s\n",
                v.first().copied().unwrap_or(f64::NAN),
                v.last().copied().unwrap_or(f64::NAN),
                1e3 / m
            )
        };
        format!(
            "render benchmark: {}, {}, {}x{} cells, {} frame{}\n{}{}",
            match bench.start {
                BenchStart::Dilute => "gravity lesson",
                BenchStart::Settled => "the benchmark's settled pile",
            },
            crate::scene::spheres(bench.particles),
            bench.width,
            bench.height,
            bench.frames,
            if bench.frames == 1 { "" } else { "s" },
            line("full frame", &self.frame_ms),
            line("box view", &self.box_ms)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bench_draws_the_number_of_frames_asked_for() {
        let bench = RenderBench {
            particles: 300,
            width: 100,
            height: 30,
            frames: 3,
            start: BenchStart::Dilute,
        };
        assert_eq!(bench.app().unwrap().frame.world.bodies.len(), 300);
        let mut drawn = 0;
        let figures = bench.draw(bench.app().unwrap(), || drawn += 1);
        assert_eq!((figures.frame_ms.len(), drawn), (3, 3));
        let report = figures.report(&bench);
        assert!(
            report.contains("gravity lesson, 300 spheres, 100x30 cells"),
            "{report}"
        );
    }

    #[test]
    fn the_settled_start_draws_the_benchmark_s_pile_at_rest_on_the_floor() {
        let bench = RenderBench {
            particles: 5000,
            width: 100,
            height: 30,
            frames: 2,
            start: BenchStart::Settled,
        };
        let app = bench.app().unwrap();
        let world = &app.frame.world;
        let pile = bench_world_from(BenchStart::Settled, 5000, BroadPhase::Auto);
        assert_eq!(world.bodies.len(), 5000);
        // The pile's own spheres, at rest, with its parameters.
        assert_eq!(
            world.bodies.iter_scene_order().collect::<Vec<_>>(),
            pile.bodies.iter_scene_order().collect::<Vec<_>>()
        );
        assert_eq!(world.config, pile.config);
        let report = bench.draw(bench.app().unwrap(), || {}).report(&bench);
        assert!(
            report.contains("the benchmark's settled pile, 5,000 spheres, 100x30 cells, 2 frames"),
            "{report}"
        );
    }
}
