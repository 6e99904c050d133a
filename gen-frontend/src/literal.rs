//! Exact conversion of literal text: durations to integer nanoseconds
//! (decimal arithmetic, no floating point), sizes to bytes, numbers and
//! string escapes.

use crate::ast::Number;

/// Why a duration or size literal has no value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LiteralError {
    /// Not a whole number of nanoseconds.
    NotWholeNs,
    /// Too large.
    Overflow,
    /// Not a number at all (cannot happen on grammar-checked text).
    Malformed,
}

/// Nanoseconds per unit.
pub(crate) fn unit_ns(unit: &str) -> Option<u128> {
    Some(match unit {
        "ns" => 1,
        "us" => 1_000,
        "ms" => 1_000_000,
        "s" => 1_000_000_000,
        "min" => 60_000_000_000,
        _ => return None,
    })
}

/// Splits `-1.5e-3ms` into its number part and unit.
fn split_unit(text: &str) -> Option<(&str, &str)> {
    let unit_start = text.rfind(|c: char| c.is_ascii_digit() || c == '.')? + 1;
    Some((&text[..unit_start], &text[unit_start..]))
}

/// A decimal number as an exact fraction: `mantissa * 10^exp10`, with sign.
struct Decimal {
    negative: bool,
    mantissa: u128,
    exp10: i64,
}

fn parse_decimal(text: &str) -> Result<Decimal, LiteralError> {
    let (negative, body) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    let (digits, exponent) = match body.find(['e', 'E']) {
        Some(i) => (
            &body[..i],
            body[i + 1..]
                .parse::<i64>()
                .map_err(|_| LiteralError::Malformed)?,
        ),
        None => (body, 0),
    };
    let (int_part, frac_part) = digits.split_once('.').unwrap_or((digits, ""));
    let all = format!("{int_part}{frac_part}");
    let trimmed = all.trim_start_matches('0');
    if trimmed.len() > 36 {
        return Err(LiteralError::Overflow);
    }
    let mantissa = if trimmed.is_empty() {
        0
    } else {
        trimmed
            .parse::<u128>()
            .map_err(|_| LiteralError::Malformed)?
    };
    let frac_len = i64::try_from(frac_part.len()).map_err(|_| LiteralError::Overflow)?;
    Ok(Decimal {
        negative,
        mantissa,
        exp10: exponent - frac_len,
    })
}

/// Converts a duration literal (`10ms`, `0.5s`, `1.5e-3s`) to nanoseconds.
pub fn duration_ns(text: &str) -> Result<i64, LiteralError> {
    let (number, unit) = split_unit(text).ok_or(LiteralError::Malformed)?;
    let factor = unit_ns(unit).ok_or(LiteralError::Malformed)?;
    let d = parse_decimal(number)?;
    let mut value = d
        .mantissa
        .checked_mul(factor)
        .ok_or(LiteralError::Overflow)?;
    if d.exp10 >= 0 {
        for _ in 0..d.exp10 {
            if value == 0 {
                break;
            }
            value = value.checked_mul(10).ok_or(LiteralError::Overflow)?;
        }
    } else {
        for _ in 0..d.exp10.unsigned_abs() {
            if value == 0 {
                break;
            }
            if value % 10 != 0 {
                return Err(LiteralError::NotWholeNs);
            }
            value /= 10;
        }
    }
    let value = i64::try_from(value).map_err(|_| LiteralError::Overflow)?;
    Ok(if d.negative { -value } else { value })
}

/// Converts a size literal (`64k`, `1M`, `8192`) to bytes.
pub fn size_bytes(text: &str) -> Result<u64, LiteralError> {
    let (digits, factor) = match text.as_bytes().last() {
        Some(b'k' | b'K') => (&text[..text.len() - 1], 1024),
        Some(b'M') => (&text[..text.len() - 1], 1024 * 1024),
        _ => (text, 1),
    };
    let n = digits.parse::<u64>().map_err(|_| LiteralError::Overflow)?;
    n.checked_mul(factor).ok_or(LiteralError::Overflow)
}

/// Converts a numeric literal. Integers that overflow `i128` become floats.
pub fn number(text: &str) -> Number {
    let (negative, body) = match text.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, text),
    };
    let sign = if negative { -1 } else { 1 };
    if let Some(hex) = body.strip_prefix("0x").or_else(|| body.strip_prefix("0X")) {
        if let Ok(v) = i128::from_str_radix(hex, 16) {
            return Number::Int(sign * v);
        }
    } else if !body.contains(['.', 'e', 'E']) {
        if let Ok(v) = body.parse::<i128>() {
            return Number::Int(sign * v);
        }
    }
    Number::Float(text.parse::<f64>().unwrap_or(f64::INFINITY))
}

/// Resolves `\"` and `\\`; any other backslash sequence is kept as written.
pub fn unescape(raw: &str) -> String {
    let mut out = String::with_capacity(raw.len());
    let mut chars = raw.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some(e @ ('"' | '\\')) => out.push(e),
            Some(other) => {
                out.push('\\');
                out.push(other);
            }
            None => out.push('\\'),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_are_exact_nanoseconds() {
        assert_eq!(duration_ns("1s"), Ok(1_000_000_000));
        assert_eq!(duration_ns("10ms"), Ok(10_000_000));
        assert_eq!(duration_ns("0.5s"), Ok(500_000_000));
        assert_eq!(duration_ns("250us"), Ok(250_000));
        assert_eq!(duration_ns("1.5e-3s"), Ok(1_500_000));
        assert_eq!(duration_ns("2min"), Ok(120_000_000_000));
        assert_eq!(duration_ns("7ns"), Ok(7));
        assert_eq!(duration_ns("0s"), Ok(0));
        assert_eq!(duration_ns("-1ms"), Ok(-1_000_000));
        assert_eq!(duration_ns(".25ms"), Ok(250_000));
        assert_eq!(duration_ns("1e3us"), Ok(1_000_000));
    }

    #[test]
    fn fractions_of_a_nanosecond_and_overflow_are_errors() {
        assert_eq!(duration_ns("0.5ns"), Err(LiteralError::NotWholeNs));
        assert_eq!(duration_ns("1e-10s"), Err(LiteralError::NotWholeNs));
        assert_eq!(duration_ns("1e30s"), Err(LiteralError::Overflow));
        assert_eq!(
            duration_ns("99999999999999999999min"),
            Err(LiteralError::Overflow)
        );
    }

    #[test]
    fn sizes_use_binary_multiples() {
        assert_eq!(size_bytes("64k"), Ok(65_536));
        assert_eq!(size_bytes("64K"), Ok(65_536));
        assert_eq!(size_bytes("2M"), Ok(2 * 1024 * 1024));
        assert_eq!(size_bytes("8192"), Ok(8192));
        assert_eq!(
            size_bytes("99999999999999999999M"),
            Err(LiteralError::Overflow)
        );
    }

    #[test]
    fn numbers_keep_integers_exact() {
        assert_eq!(number("-3"), Number::Int(-3));
        assert_eq!(number("0x1F"), Number::Int(31));
        assert_eq!(number("1.5e-3"), Number::Float(1.5e-3));
        assert_eq!(number("0.0"), Number::Float(0.0));
    }

    #[test]
    fn escapes() {
        assert_eq!(unescape(r#"a \"b\" c\\d \n"#), "a \"b\" c\\d \\n");
    }
}
