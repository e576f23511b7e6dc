//! Flag values as typed on the command line: whole numbers and decimal
//! numbers, each checked against its range, with a message that says what
//! was expected and what was given (clap prefixes the flag's name).
//!
//! A whole number is read exactly ([`crate::scene::whole_number`], as
//! scene files read theirs): digits, or a notation whose value is exactly
//! whole (`1e6`). A named
//! choice (`--integrator rk4`) is read by [`choice`], by the names and with
//! the message of scene files.

pub(crate) use crate::scene::whole_number::whole_number;
use crate::sim::config::Choice;
use clap::builder::{PossibleValue, TypedValueParser};
use std::marker::PhantomData;

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
