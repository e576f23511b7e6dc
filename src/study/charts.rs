//! Plain-text charts for the terminal: a grid of characters, one marker
//! per series, axes labelled with their range, and a legend. No terminal
//! library: the text goes to standard output like any other.

use super::sweep::Row;
use crate::sim::Integrator;
use std::fmt::Write;

/// One series: a name for the legend, its marker, and `(x, y)` points.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Series {
    pub name: String,
    pub marker: char,
    pub points: Vec<(f64, f64)>,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TextChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Plot area in characters.
    pub width: usize,
    pub height: usize,
}

/// The marker of a method, in these charts and the visualiser's chart
/// screen: a new method chooses its own here.
pub(crate) fn marker(m: Integrator) -> char {
    match m {
        Integrator::ExplicitEuler => 'e',
        Integrator::SemiImplicitEuler => 's',
        Integrator::VelocityVerlet => 'v',
        Integrator::Rk4 => 'r',
        Integrator::Continuous => 'C',
    }
}

/// The marker of a cell that holds points of more than one series, in
/// these charts and the visualiser's chart screen.
pub(crate) const SHARED: char = '*';

/// Errors and costs below this are drawn at it on log scales (an exact
/// method's error can be 0).
pub(crate) const LOG_FLOOR: f64 = 1e-17;

/// `log10 v`, with `v` raised to [`LOG_FLOOR`] first.
pub(crate) fn log10(v: f64) -> f64 {
    v.max(LOG_FLOOR).log10()
}

/// One series per method, `(x, y)` from each of its rows, in row order.
pub(crate) fn series_by_method(rows: &[&Row], point: impl Fn(&Row) -> (f64, f64)) -> Vec<Series> {
    Integrator::ALL
        .iter()
        .filter_map(|&m| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.method == m)
                .map(|r| point(r))
                .collect();
            (!points.is_empty()).then(|| Series {
                name: m.name().to_string(),
                marker: marker(m),
                points,
            })
        })
        .collect()
}

/// The work-precision series of `rows`: `log10` cost per simulated second
/// against `log10` RMS position error, per method.
pub(crate) fn work_precision_series(rows: &[&Row]) -> Vec<Series> {
    series_by_method(rows, |r| (log10(r.cost_per_second), log10(r.error())))
}

impl TextChart {
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            series: Vec::new(),
            width: 64,
            height: 18,
        }
    }

    pub(crate) fn render(&self) -> String {
        let finite = |&(x, y): &(f64, f64)| x.is_finite() && y.is_finite();
        let pts: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(finite)
            .collect();
        let mut out = String::new();
        let _ = writeln!(out, "{}", self.title);
        if pts.is_empty() {
            let _ = writeln!(out, "  (no data)");
            return out;
        }
        let span = |v: &mut dyn Iterator<Item = f64>| {
            let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
            if hi - lo < 1e-9 {
                (lo - 0.5, hi + 0.5)
            } else {
                (lo, hi)
            }
        };
        let (x0, x1) = span(&mut pts.iter().map(|p| p.0));
        let (y0, y1) = span(&mut pts.iter().map(|p| p.1));
        let (w, h) = (self.width.max(8), self.height.max(4));
        // Each cell: the index of the one series whose points fall in it,
        // or `SHARED` where several series' do.
        let mut grid = vec![vec![' '; w]; h];
        let mut owner = vec![vec![None; w]; h];
        let mut shared = false;
        for (k, s) in self.series.iter().enumerate() {
            for &(x, y) in s.points.iter().filter(|p| finite(p)) {
                let c = ((x - x0) / (x1 - x0) * (w - 1) as f64).round() as usize;
                let r = ((y1 - y) / (y1 - y0) * (h - 1) as f64).round() as usize;
                let (r, c) = (r.min(h - 1), c.min(w - 1));
                match owner[r][c] {
                    Some(other) if other != k => {
                        grid[r][c] = SHARED;
                        shared = true;
                    }
                    Some(_) => {}
                    None => {
                        owner[r][c] = Some(k);
                        grid[r][c] = s.marker;
                    }
                }
            }
        }
        let _ = writeln!(out, "  {}", self.y_label);
        for (r, row) in grid.iter().enumerate() {
            let label = if r == 0 {
                format!("{y1:7.2}")
            } else if r == h - 1 {
                format!("{y0:7.2}")
            } else if r == h / 2 {
                format!("{:7.2}", 0.5 * (y0 + y1))
            } else {
                " ".repeat(7)
            };
            let _ = writeln!(out, "{label} |{}", row.iter().collect::<String>());
        }
        let _ = writeln!(out, "{} +{}", " ".repeat(7), "-".repeat(w));
        let left = format!("{x0:.2}");
        let mid = format!("{:.2}", 0.5 * (x0 + x1));
        let right = format!("{x1:.2}");
        let mut axis = vec![' '; w + 2];
        for (text, at) in [
            (&left, 0),
            (&mid, w / 2 - mid.len() / 2),
            (&right, w - right.len()),
        ] {
            for (k, ch) in text.chars().enumerate() {
                if let Some(slot) = axis.get_mut(at + k + 1) {
                    *slot = ch;
                }
            }
        }
        let _ = writeln!(out, "{}{}", " ".repeat(7), axis.iter().collect::<String>());
        let _ = writeln!(out, "{}{:^w$}", " ".repeat(9), self.x_label);
        for s in &self.series {
            let _ = writeln!(out, "    {}  {}", s.marker, s.name);
        }
        if shared {
            let _ = writeln!(out, "    {SHARED}  more than one method");
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::{SHARED, Series, TextChart};

    fn series(name: &str, marker: char, points: &[(f64, f64)]) -> Series {
        Series {
            name: name.into(),
            marker,
            points: points.to_vec(),
        }
    }

    /// The plot rows of a rendered chart: what lies right of the axis.
    fn plot(text: &str) -> Vec<String> {
        text.lines()
            .filter_map(|l| l.split_once(" |").map(|(_, row)| row.to_string()))
            .collect()
    }

    #[test]
    fn a_cell_two_series_share_shows_the_shared_marker_and_the_legend_says_so() {
        let mut chart = TextChart::new("t", "x", "y");
        (chart.width, chart.height) = (8, 4);
        chart.series = vec![
            series("a", 'a', &[(0.0, 0.0), (1.0, 1.0)]),
            series("b", 'b', &[(1.0, 1.0), (0.0, 1.0)]),
        ];
        let text = chart.render();
        assert_eq!(
            plot(&text),
            ["b      *", "        ", "        ", "a       "],
            "{text}"
        );
        assert!(
            text.ends_with(&format!(
                "    a  a\n    b  b\n    {SHARED}  more than one method\n"
            )),
            "{text}"
        );
    }

    #[test]
    fn a_series_meeting_itself_in_a_cell_keeps_its_marker() {
        let mut chart = TextChart::new("t", "x", "y");
        (chart.width, chart.height) = (8, 4);
        chart.series = vec![
            series("a", 'a', &[(0.0, 0.0), (0.0, 0.01), (1.0, 1.0)]),
            series("b", 'b', &[(0.0, 1.0)]),
        ];
        let text = chart.render();
        assert_eq!(
            plot(&text),
            ["b      a", "        ", "        ", "a       "],
            "{text}"
        );
        assert!(!text.contains(SHARED), "{text}");
    }
}
