//! Whole numbers as a person writes them, on the command line or in a
//! scene file: with digits (`250000`) or in decimal or scientific notation
//! whose value is exactly whole (`2.5e5`, `1e6`, `1000.0`). The value is
//! read from the text exactly, never through a float, and checked against
//! its range with a message that says what was expected and what was
//! given.

/// Parse `text` as a whole number in `min..=max`.
pub(crate) fn whole_number<T: TryFrom<u64>>(text: &str, min: u64, max: u64) -> Result<T, String> {
    whole_number_written(text, text.trim(), min, max)
}

/// [`whole_number`] of `text`, a form of the number `written` (a scene's
/// `0x10` as `16`, `1_000.0` as `1000.0`), which the message quotes.
pub(crate) fn whole_number_written<T: TryFrom<u64>>(
    text: &str,
    written: &str,
    min: u64,
    max: u64,
) -> Result<T, String> {
    let range = format!("must be a whole number from {min} to {max}");
    let n = match exact_value(text) {
        Exact::Whole(n) => n,
        Exact::Fraction | Exact::TooLarge => return Err(format!("{range}, got {written}")),
        Exact::NotANumber => {
            return Err(format!(
                "{range} (digits, or a form such as 1e6), got '{written}'"
            ));
        }
    };
    match u64::try_from(n) {
        Ok(n) if (min..=max).contains(&n) => {
            T::try_from(n).map_err(|_| format!("{range}, got {written}"))
        }
        _ => Err(format!("{range}, got {written}")),
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
}
