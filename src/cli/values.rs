//! Flag values as typed on the command line: whole numbers and decimal
//! numbers, each checked against its range, with a message that says what
//! was expected and what was given (clap prefixes the flag's name).
//!
//! A whole number may be written with digits (`250000`) or in decimal or
//! scientific notation whose value is exactly whole (`2.5e5`, `1e6`,
//! `1000.0`); the value is read exactly, never through a float. A named
//! choice (`--integrator rk4`) is read by [`choice`], by the names and with
//! the message of scene files.

use crate::sim::config::Choice;
use clap::builder::{PossibleValue, TypedValueParser};
use std::marker::PhantomData;

/// Parse `text` as a whole number in `min..=max`.
pub(crate) fn whole_number<T: TryFrom<u64>>(text: &str, min: u64, max: u64) -> Result<T, String> {
    let range = format!("must be a whole number from {min} to {max}");
    let n = match exact_value(text) {
        Exact::Whole(n) => n,
        Exact::Fraction | Exact::TooLarge => return Err(format!("{range}, got {}", text.trim())),
        Exact::NotANumber => {
            return Err(format!(
                "{range} (digits, or a form such as 1e6), got '{text}'"
            ));
        }
    };
    match u64::try_from(n) {
        Ok(n) if (min..=max).contains(&n) => {
            T::try_from(n).map_err(|_| format!("{range}, got {}", text.trim()))
        }
        _ => Err(format!("{range}, got {}", text.trim())),
    }
}

/// A clap value parser for a whole number in `min..=max`.
pub(crate) fn whole<T: TryFrom<u64> + Clone + Send + Sync + 'static>(
    min: u64,
    max: u64,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static {
    move |s: &str| whole_number(s, min, max)
}

/// A clap value parser for a number that passes `rule` (one of
/// [`crate::scene::rules`], shared with scene files).
pub(crate) fn number(
    rule: fn(f64) -> Result<f64, String>,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |s: &str| {
        let v = decimal_or_fraction(s.trim())
            .ok_or_else(|| format!("must be a number (such as 0.5, 1e-3 or 1/60), got '{s}'"))?;
        // -0 is 0: adding +0 turns it into +0 and leaves every other
        // number as it is. A number beyond the range, read as 0 or as
        // infinity, is refused even where the rule takes what it reads as
        // (`--time 1e-400` ran no step).
        let ruled = rule(v + 0.0);
        match (rounded_away(s.trim(), v), ruled) {
            (Some(why), Err(e)) => Err(format!("{e} ({why})")),
            (Some(why), Ok(_)) => Err(format!("{why}; write 0 if 0 is meant")),
            (None, ruled) => ruled,
        }
    }
}

/// `text` as a decimal number (`0.5`, `1e-3`), or as a fraction of two
/// (`1/60`: the visualiser shows dt that way).
pub(crate) fn decimal_or_fraction(text: &str) -> Option<f64> {
    match text.split_once('/') {
        Some((p, q)) => Some(p.trim().parse::<f64>().ok()? / q.trim().parse::<f64>().ok()?),
        None => text.parse().ok(),
    }
}

/// Why `text`, which parsed as `v`, is not the number typed: beyond the
/// range of 64-bit floating point, it was read as 0 or as infinity. For a
/// fraction, either part, else the quotient.
fn rounded_away(text: &str, v: f64) -> Option<String> {
    if let Some((p, q)) = text.split_once('/') {
        let (p, q) = (p.trim(), q.trim());
        let part = |t: &str| t.parse::<f64>().ok().and_then(|x| rounded_away(t, x));
        if let Some(why) = part(p).or_else(|| part(q)) {
            return Some(why);
        }
        let (p, q) = (p.parse::<f64>().ok()?, q.parse::<f64>().ok()?);
        let rounded = (v == 0.0 && p != 0.0) || (v.is_infinite() && q != 0.0 && p.is_finite());
        return rounded.then(|| read_as(text, v));
    }
    let typed_zero = crate::scene::rules::typed_as_zero(text);
    let typed_infinite = text.to_ascii_lowercase().contains("inf");
    let rounded = (v == 0.0 && !typed_zero) || (v.is_infinite() && !typed_infinite);
    rounded.then(|| read_as(text, v))
}

/// How `text`, beyond 64-bit range, was read: as 0 (`v` is 0) or as
/// infinity.
fn read_as(text: &str, v: f64) -> String {
    if v == 0.0 {
        crate::scene::rules::read_as_zero(text)
    } else {
        format!("{text} is larger than a 64-bit number can hold, so it reads as infinity")
    }
}

/// A clap value parser for a named [`Choice`]: refuses an unknown name as a
/// scene file does (`unknown integrator 'rk9'; choose one of ...`) and
/// lists the names, with each one's doc line, in `--help`.
pub(crate) fn choice<C: Choice + Send + Sync>() -> ChoiceParser<C> {
    ChoiceParser(PhantomData)
}

/// See [`choice`].
pub(crate) struct ChoiceParser<C>(PhantomData<fn() -> C>);

impl<C> Clone for ChoiceParser<C> {
    fn clone(&self) -> Self {
        ChoiceParser(PhantomData)
    }
}

impl<C: Choice + Send + Sync> TypedValueParser for ChoiceParser<C> {
    type Value = C;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<C, clap::Error> {
        // clap's own wording around the message: "invalid value 'rk9' for
        // '--integrator <INTEGRATOR>': ...".
        (|s: &str| C::parse(s)).parse_ref(cmd, arg, value)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(C::VARIANTS.iter().map(|&c| {
            PossibleValue::new(c.name()).help(c.about().unwrap_or_default())
        })))
    }
}

/// What a piece of text is, read exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Exact {
    Whole(i128),
    /// A number with a non-zero fractional part.
    Fraction,
    /// A whole number beyond `i128`.
    TooLarge,
    NotANumber,
}

/// Read `[+-]digits[.digits][(e|E)[+-]digits]` exactly.
fn exact_value(text: &str) -> Exact {
    let s = text.trim();
    let (negative, s) = match s.as_bytes().first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    let (mantissa, exponent) = match s.find(['e', 'E']) {
        Some(k) => (&s[..k], Some(&s[k + 1..])),
        None => (s, None),
    };
    let (int_part, frac_part) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let all_digits = |p: &str| p.bytes().all(|b| b.is_ascii_digit());
    if int_part.len() + frac_part.len() == 0 || !all_digits(int_part) || !all_digits(frac_part) {
        return Exact::NotANumber;
    }
    let exponent: i64 = match exponent {
        None => 0,
        Some(e) => {
            let digits = e.strip_prefix(['+', '-']).unwrap_or(e);
            if digits.is_empty() || !all_digits(digits) {
                return Exact::NotANumber;
            }
            // Beyond this the answer is the same: too large, or a fraction.
            match e.parse::<i64>() {
                Ok(v) => v.clamp(-1_000_000, 1_000_000),
                Err(_) if e.starts_with('-') => -1_000_000,
                Err(_) => 1_000_000,
            }
        }
    };
    let digits: String = format!("{int_part}{frac_part}");
    let digits = digits.trim_start_matches('0');
    if digits.is_empty() {
        return Exact::Whole(0);
    }
    // value = digits * 10^scale
    let scale = exponent - frac_part.len() as i64;
    let significant = if scale < 0 {
        let cut = (-scale) as usize;
        if cut >= digits.len() || digits[digits.len() - cut..].bytes().any(|b| b != b'0') {
            return Exact::Fraction;
        }
        &digits[..digits.len() - cut]
    } else {
        digits
    };
    if significant.len() as i64 + scale.max(0) > 38 {
        return Exact::TooLarge;
    }
    let mut n: i128 = significant.parse().expect("checked digits");
    for _ in 0..scale.max(0) {
        n *= 10;
    }
    Exact::Whole(if negative { -n } else { n })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minus_zero_is_read_as_zero() {
        let read = number(Ok)("-0").unwrap();
        assert_eq!(read.to_bits(), 0.0_f64.to_bits(), "{read}");
        assert_eq!(number(Ok)("-0.5"), Ok(-0.5));
    }

    #[test]
    fn whole_numbers_are_read_exactly_in_any_notation() {
        assert_eq!(exact_value("250000"), Exact::Whole(250_000));
        assert_eq!(exact_value(" +7 "), Exact::Whole(7));
        assert_eq!(exact_value("-5"), Exact::Whole(-5));
        assert_eq!(exact_value("1e6"), Exact::Whole(1_000_000));
        assert_eq!(exact_value("2.5E3"), Exact::Whole(2_500));
        assert_eq!(exact_value("1000.000"), Exact::Whole(1_000));
        assert_eq!(exact_value("120e-1"), Exact::Whole(12));
        assert_eq!(exact_value("-0.0"), Exact::Whole(0));
        assert_eq!(
            exact_value("18446744073709551615"),
            Exact::Whole(u64::MAX.into())
        );
        assert_eq!(exact_value("2.5"), Exact::Fraction);
        assert_eq!(exact_value("1e-3"), Exact::Fraction);
        assert_eq!(exact_value("125e-1"), Exact::Fraction);
        assert_eq!(exact_value("1e30"), Exact::Whole(10i128.pow(30)));
        assert_eq!(exact_value("1e39"), Exact::TooLarge);
        assert_eq!(exact_value("1e99999999999999999999"), Exact::TooLarge);
        assert_eq!(exact_value("1e-99999999999999999999"), Exact::Fraction);
        for bad in [
            "", "many", "1e", "e5", ".", "inf", "NaN", "0x10", "1_000", "1e+",
        ] {
            assert_eq!(exact_value(bad), Exact::NotANumber, "{bad:?}");
        }
    }

    #[test]
    fn a_whole_number_out_of_range_names_the_range_and_the_value() {
        assert_eq!(whole_number::<usize>("1e6", 1, 10_000_000), Ok(1_000_000));
        let e = whole_number::<usize>("-5", 1, 1000).unwrap_err();
        assert_eq!(e, "must be a whole number from 1 to 1000, got -5");
        let e = whole_number::<u32>("2.5", 1, 10).unwrap_err();
        assert_eq!(e, "must be a whole number from 1 to 10, got 2.5");
        let e = whole_number::<u64>("lots", 0, 9).unwrap_err();
        assert!(e.contains("such as 1e6") && e.contains("'lots'"), "{e}");
        let e = whole_number::<u64>("1e30", 0, 1_000_000_000_000).unwrap_err();
        assert!(e.ends_with("got 1e30"), "{e}");
    }

    #[test]
    fn a_number_beyond_floating_point_says_how_it_was_read() {
        let dt = number(crate::scene::rules::dt);
        assert_eq!(
            dt("1e-400").unwrap_err(),
            "must be greater than 0, got 0 (1e-400 is closer to 0 than a 64-bit \
             number can hold, so it reads as 0)"
        );
        assert_eq!(
            dt("1e400").unwrap_err(),
            "must be a finite number, got inf (1e400 is larger than a 64-bit number \
             can hold, so it reads as infinity)"
        );
        // Where the rule takes 0, it is still not what was typed:
        // `--time 1e-400` ran no step.
        let time = number(crate::scene::rules::non_negative);
        assert_eq!(
            time("1e-400").unwrap_err(),
            "1e-400 is closer to 0 than a 64-bit number can hold, so it reads as 0; \
             write 0 if 0 is meant"
        );
        assert_eq!(time("0e-400"), Ok(0.0));
        assert_eq!(time("1e-320"), Ok(1e-320));
        // Typed as 0 or infinity: the value is what was typed.
        assert_eq!(dt("0.0e-400").unwrap_err(), "must be greater than 0, got 0");
        assert_eq!(dt("-inf").unwrap_err(), "must be a finite number, got -inf");
        assert_eq!(dt("0.5"), Ok(0.5));
    }

    #[test]
    fn a_number_may_be_a_fraction_as_the_visualiser_shows_dt() {
        let dt = number(crate::scene::rules::dt);
        assert_eq!(dt("1/60"), Ok(1.0 / 60.0));
        assert_eq!(dt(" 1 / 240 "), Ok(1.0 / 240.0));
        assert_eq!(dt("1/0").unwrap_err(), "must be a finite number, got inf");
        assert_eq!(dt("0/0").unwrap_err(), "must be a finite number, got NaN");
        // A part, or the quotient, beyond 64-bit range says so.
        assert_eq!(
            dt("1e-400/1").unwrap_err(),
            "must be greater than 0, got 0 (1e-400 is closer to 0 than a 64-bit \
             number can hold, so it reads as 0)"
        );
        assert_eq!(
            dt("1/1e400").unwrap_err(),
            "must be greater than 0, got 0 (1e400 is larger than a 64-bit number \
             can hold, so it reads as infinity)"
        );
        assert_eq!(
            dt("1e-200/1e200").unwrap_err(),
            "must be greater than 0, got 0 (1e-200/1e200 is closer to 0 than a \
             64-bit number can hold, so it reads as 0)"
        );
        assert_eq!(
            dt("1e200/1e-200").unwrap_err(),
            "must be a finite number, got inf (1e200/1e-200 is larger than a 64-bit \
             number can hold, so it reads as infinity)"
        );
        assert_eq!(
            dt("-1/60").unwrap_err(),
            format!("must be greater than 0, got {}", -1.0 / 60.0)
        );
        for bad in ["1/", "/60", "1/60/2", "a/b"] {
            assert!(
                dt(bad).unwrap_err().contains("such as 0.5, 1e-3 or 1/60"),
                "{bad}"
            );
        }
    }
}
