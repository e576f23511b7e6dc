//! The study's charts as SVG text (plotters, no system libraries): log-log
//! axes, one line with points per series, a legend. Writing the files is
//! the command line's (`cli::study`), so that none is half written.

use super::charts::{LOG_FLOOR, Series};
use plotters::prelude::*;

/// A log-log chart of `series` (raw, positive values), as SVG.
pub(crate) fn log_log(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
) -> Result<String, String> {
    let mut svg = String::new();
    draw(&mut svg, title, x_desc, y_desc, series)
        .map_err(|e| format!("cannot draw the chart '{title}': {e}"))?;
    Ok(svg)
}

fn draw(
    svg: &mut String,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
) -> Result<(), Box<dyn std::error::Error>> {
    // Values at or below 0 cannot go on a log axis: they are drawn at the
    // text charts' floor.
    let clean = |v: f64| {
        if v.is_finite() && v > LOG_FLOOR {
            v
        } else {
            LOG_FLOOR
        }
    };
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|&(x, y)| (clean(x), clean(y))))
        .collect();
    let (x0, x1) = axis_range(pts.iter().map(|p| p.0));
    let (y0, y1) = axis_range(pts.iter().map(|p| p.1));

    let root = SVGBackend::with_string(svg, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .draw()?;
    for (k, s) in series.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let data: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|&(x, y)| (clean(x), clean(y)))
            .collect();
        chart
            .draw_series(LineSeries::new(data.clone(), color.stroke_width(2)))?
            .label(s.name.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
            });
        chart.draw_series(PointSeries::of_element(
            data,
            4,
            color.filled(),
            &|c, s, st| Circle::new(c, s, st),
        ))?;
    }
    // The legend goes where it hides the least of the lines and points.
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let lines: Vec<Vec<(i32, i32)>> = series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .map(|&(x, y)| {
                    let (px, py) = chart.backend_coord(&(clean(x), clean(y)));
                    (px - xs.start, py - ys.start)
                })
                .collect()
        })
        .collect();
    let names: Vec<&str> = series.iter().map(|s| s.name.as_str()).collect();
    let area = ((xs.end - xs.start).max(0), (ys.end - ys.start).max(0));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .margin(LEGEND_MARGIN)
        .legend_area_size(LEGEND_KEY)
        .label_font(("sans-serif", LEGEND_FONT))
        .position(legend_position(&names, &lines, area))
        .draw()?;
    root.present()?;
    Ok(())
}

/// The range of a log axis over `values`: each end pushed out by a factor
/// of 2, and just beyond whole powers of ten when that holds fewer than two
/// of them, so that at least two labelled powers of ten show.
fn axis_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    if !(lo.is_finite() && hi > lo) {
        return (LOG_FLOOR, 1.0);
    }
    let (lo, hi) = (lo / 2.0, hi * 2.0);
    if hi.log10().floor() - lo.log10().ceil() >= 1.0 {
        (lo, hi)
    } else {
        // Just beyond the powers of ten, so that both are labelled.
        (
            10f64.powf(lo.log10().floor()) * 0.9,
            10f64.powf(hi.log10().ceil()) * 1.1,
        )
    }
}

/// The legend's text size, the width of each series' key and the margin
/// around its entries, px.
const LEGEND_FONT: u32 = 12;
const LEGEND_KEY: u32 = 30;
const LEGEND_MARGIN: u32 = 10;

/// Where the legend of series `names` hides the fewest points of `lines`
/// (each a series' points, in pixels from the top left of a plotting area
/// `area` wide and high): the lines are sampled between their points, and
/// the places are tried from the upper right, the first of the fewest
/// taken.
fn legend_position(
    names: &[&str],
    lines: &[Vec<(i32, i32)>],
    area: (i32, i32),
) -> SeriesLabelPosition {
    use SeriesLabelPosition::*;
    // The box as plotters lays it out, its text estimated generously.
    let widest = names.iter().map(|n| n.chars().count()).max().unwrap_or(0) as i32;
    let size = (
        widest * LEGEND_FONT as i32 * 2 / 3 + (LEGEND_KEY + 2 * LEGEND_MARGIN) as i32,
        names.len() as i32 * (LEGEND_FONT as i32 * 3 / 2) + 2 * LEGEND_MARGIN as i32,
    );
    let samples: Vec<(i32, i32)> = lines
        .iter()
        .flat_map(|points| {
            let single = points.first().map(|&p| (p, p));
            let pairs = points.windows(2).map(|w| (w[0], w[1]));
            single
                .into_iter()
                .chain(pairs)
                .flat_map(|((x0, y0), (x1, y1))| {
                    (0..=SAMPLES)
                        .map(move |k| (x0 + (x1 - x0) * k / SAMPLES, y0 + (y1 - y0) * k / SAMPLES))
                })
        })
        .collect();
    let hidden = |place: &SeriesLabelPosition| {
        let (left, top) = corner(place, size, area);
        let near = 6; // a point's marker and the line's width
        samples
            .iter()
            .filter(|&&(x, y)| {
                x + near >= left
                    && x - near <= left + size.0
                    && y + near >= top
                    && y - near <= top + size.1
            })
            .count()
    };
    let places = [
        UpperRight,
        UpperLeft,
        LowerRight,
        LowerLeft,
        MiddleRight,
        MiddleLeft,
        UpperMiddle,
        LowerMiddle,
    ];
    places
        .into_iter()
        .enumerate()
        .min_by_key(|(k, place)| (hidden(place), *k))
        .map_or(UpperRight, |(_, place)| place)
}

/// Points sampled along each segment of a line.
const SAMPLES: i32 = 24;

/// The top left corner of a legend `size` at `place` in an area `area`
/// (as plotters' layout puts it: 5 px from the edges).
fn corner(place: &SeriesLabelPosition, size: (i32, i32), area: (i32, i32)) -> (i32, i32) {
    use SeriesLabelPosition::*;
    let x = match place {
        UpperLeft | MiddleLeft | LowerLeft => 5,
        UpperMiddle | MiddleMiddle | LowerMiddle => (area.0 - size.0) / 2,
        UpperRight | MiddleRight | LowerRight => area.0 - size.0 - 5,
        Coordinate(x, _) => *x,
    };
    let y = match place {
        UpperLeft | UpperMiddle | UpperRight => 5,
        MiddleLeft | MiddleMiddle | MiddleRight => (area.1 - size.1) / 2,
        LowerLeft | LowerMiddle | LowerRight => area.1 - size.1 - 5,
        Coordinate(_, y) => *y,
    };
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legend_goes_to_a_corner_the_lines_leave_free() {
        let names = ["explicit-euler", "rk4"];
        let area = (800, 500);
        // A line from the upper left to the lower right: the upper right is free.
        let falling = vec![vec![(0, 0), (800, 500)]];
        assert_eq!(
            legend_position(&names, &falling, area),
            SeriesLabelPosition::UpperRight
        );
        // A line rising to the upper right: the upper left is the first free.
        let rising = vec![vec![(0, 500), (400, 250), (800, 0)]];
        assert_eq!(
            legend_position(&names, &rising, area),
            SeriesLabelPosition::UpperLeft
        );
        // Lines through both upper corners and the lower right.
        let busy = vec![vec![(0, 0), (800, 0)], vec![(800, 0), (800, 500)]];
        assert_eq!(
            legend_position(&names, &busy, area),
            SeriesLabelPosition::LowerLeft
        );
        // No free place: the one hiding the fewest samples.
        let everywhere: Vec<Vec<(i32, i32)>> = (0..=50)
            .map(|k| vec![(0, k * 10), (800, k * 10)])
            .chain([vec![(5, 300), (5, 500)], vec![(5, 310), (5, 490)]])
            .collect();
        assert_ne!(
            legend_position(&names, &everywhere, area),
            SeriesLabelPosition::LowerLeft
        );
    }

    #[test]
    fn a_narrow_range_widens_to_whole_decades() {
        assert_eq!(
            axis_range([3e-16, 7e-16].into_iter()),
            (1e-16 * 0.9, 1e-14 * 1.1)
        );
        assert_eq!(axis_range([1e-3, 1.0].into_iter()), (5e-4, 2.0));
        // Over a decade wide, yet holding one power of ten: widened too.
        assert_eq!(
            axis_range([3e-16, 1.5e-15].into_iter()),
            (1e-16 * 0.9, 1e-14 * 1.1)
        );
        assert_eq!(axis_range(std::iter::empty()), (LOG_FLOOR, 1.0));
    }
}
