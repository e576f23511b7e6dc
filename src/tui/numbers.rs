//! The plain text of the quantities the visualiser shows: numbers to a
//! number of significant digits, energies, time steps, the broad phase's
//! name. Owns formatting only; nothing here draws, so the session (state)
//! and the panel (view) both write their figures with it.

use crate::scene::rules::unsigned_zero;
use crate::sim::BroadPhase;

/// A number to four significant digits (a mass or a radius, so that the
/// lesson's formulas can be checked from the panel), in exponent form when
/// very small or large.
pub fn format_significant(v: f64) -> String {
    format_significant_to(v, 4)
}

/// A number to `digits` significant digits (at least 1), as
/// [`format_significant`] writes it.
pub fn format_significant_to(v: f64, digits: usize) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return unsigned_zero(format!("{v}"));
    }
    let digits = digits.max(1);
    if !(1e-4..1e5).contains(&a) {
        let decimals = digits - 1;
        return format!("{v:.decimals$e}");
    }
    let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$}")
}

/// An energy in joules, about four significant digits.
pub(crate) fn format_energy(v: f64) -> String {
    energy_at_scale(v, v.abs(), 0)
}

/// Two energies to compare (before and after), in one format: the one
/// [`format_energy`] gives the larger, so that `0.0101 J -> 0.0099 J`
/// does not read `0.0101 J -> 9.921e-3 J`.
///
/// Two energies that differ get the figures that show it (up to six
/// more), so that a collision's loss never reads as none.
pub(crate) fn format_energies(a: f64, b: f64) -> (String, String) {
    let larger = a.abs().max(b.abs());
    let at = |more| {
        (
            energy_at_scale(a, larger, more),
            energy_at_scale(b, larger, more),
        )
    };
    // Two that differ by rounding alone (an elastic collision's) read as
    // equal, to the usual figures.
    (0..=MORE_FIGURES)
        .map(at)
        .find(|(x, y)| x != y)
        .unwrap_or_else(|| at(0))
}

/// Figures [`format_energies`] may add to tell two energies apart.
const MORE_FIGURES: usize = 6;

/// `v` in joules, in the format [`format_energy`] gives an energy of size
/// `scale` (with `more` figures): decimals for everyday sizes, else
/// exponent form.
fn energy_at_scale(v: f64, scale: f64, more: usize) -> String {
    if v == 0.0 {
        "0 J".into()
    } else if (0.01..1e4).contains(&scale) {
        let digits = (3 - scale.log10().floor() as i32).clamp(0, 4) as usize + more;
        format!("{v:.digits$} J")
    } else {
        let digits = 3 + more;
        format!("{v:.digits$e} J")
    }
}

/// `1/120 s` when dt is a whole fraction of a second, else milliseconds.
pub(crate) fn format_dt(dt: f64) -> String {
    let per_second = 1.0 / dt;
    // Three decimals of a millisecond, or four figures below them.
    let ms = dt * 1e3;
    let ms = if ms >= 0.01 {
        format!("{ms:.3}")
    } else {
        format_significant(ms)
    };
    if whole_per_second(per_second) {
        format!("1/{per_second:.0} s ({ms} ms)")
    } else {
        format!("{ms} ms")
    }
}

/// Whether a step of `1 / per_second` s reads as the fraction `1/n`: a
/// whole `n` (to a millionth), of at most [`MOST_STEPS_A_SECOND`] (a dt of
/// 1e-300 s had read 1/99999999999999990380306940...).
pub(crate) fn whole_per_second(per_second: f64) -> bool {
    per_second <= MOST_STEPS_A_SECOND && (per_second - per_second.round()).abs() < 1e-6 * per_second
}

const MOST_STEPS_A_SECOND: f64 = 1e9;

/// The broad phase chosen, with what `auto` runs.
pub(crate) fn broad_phase_name(b: BroadPhase, n: usize) -> String {
    match b {
        BroadPhase::Auto => format!("auto: {}", b.resolve(n).name()),
        other => other.name().to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn energies_compared_share_one_format() {
        assert_eq!(
            format_energies(0.0101, 0.009921),
            ("0.0101 J".to_string(), "0.0099 J".to_string())
        );
        assert_eq!(
            format_energies(3.137, 3.088),
            ("3.137 J".to_string(), "3.088 J".to_string())
        );
        assert_eq!(
            format_energies(1.482, 0.0),
            ("1.482 J".to_string(), "0 J".to_string())
        );
        assert_eq!(
            format_energies(2e-3, 1e-3),
            ("2.000e-3 J".to_string(), "1.000e-3 J".to_string())
        );
        // A loss below the usual figures still shows.
        assert_eq!(
            format_energies(0.036012, 0.035982),
            ("0.03601 J".to_string(), "0.03598 J".to_string())
        );
        assert_eq!(
            format_energies(0.0360121, 0.0360118),
            ("0.0360121 J".to_string(), "0.0360118 J".to_string())
        );
        assert_eq!(
            format_energies(2.0e-3, 2.0000004e-3),
            ("2.0000000e-3 J".to_string(), "2.0000004e-3 J".to_string())
        );
        assert_eq!(
            format_energies(1.0, 1.0),
            ("1.000 J".to_string(), "1.000 J".to_string())
        );
        // An elastic collision's: equal but for rounding.
        assert_eq!(
            format_energies(3.137, 3.137 + 4.5e-16),
            ("3.137 J".to_string(), "3.137 J".to_string())
        );
    }

    #[test]
    fn energies_read_with_four_significant_digits() {
        assert_eq!(format_energy(0.5), "0.5000 J");
        assert_eq!(format_energy(12.634), "12.63 J");
        assert_eq!(format_energy(1234.4), "1234 J");
        assert_eq!(format_energy(-0.0012345), "-1.234e-3 J");
        assert_eq!(format_energy(0.0), "0 J");
    }
}
