//! Numbers for people: one readable style everywhere (titles, axis labels, tables).
//!
//! * Values between 10⁻³ and 10⁵ in decimal form, others as `3.0×10⁻⁶`; a minus sign is `−`.
//! * A value without an uncertainty has four significant digits, trailing zeros dropped:
//!   [`fmt_value`]`(0.009650, "")` is `0.00965`, `fmt_value(3e-6, "/µm")` is `3×10⁻⁶ /µm`.
//! * A value with an uncertainty is rounded where its two-digit uncertainty ends:
//!   [`fmt_with_err`]`(0.009653, 0.000123, "")` is `0.00965 ± 0.00012`,
//!   `fmt_with_err(2.8331e-6, 1.2e-8, "/µm")` is `(2.833 ± 0.012)×10⁻⁶ /µm`.
//! * Tick labels of one axis share the number of decimals that keeps them exact and distinct
//!   ([`tick_labels`]).
//!
//! Units are appended after a no-break space (`µm`, `µm/s`, `/µm`, `s`); friction has none.

/// Significant digits of a value shown without an uncertainty.
pub const SIG: usize = 4;

/// Decimal form is used for magnitudes 10^MIN_EXP ≤ |x| < 10^MAX_EXP.
const MIN_EXP: i32 = -3;
const MAX_EXP: i32 = 5;

/// `e` as Unicode superscript digits (`-6` → `⁻⁶`).
pub fn superscript(e: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if e < 0 {
        s.push('⁻');
    }
    for c in e.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// Decimal exponent of `x` after rounding to `sig` significant digits (0 for 0).
fn exponent(x: f64, sig: usize) -> i32 {
    if x == 0.0 || !x.is_finite() {
        return 0;
    }
    let s = format!("{:.*e}", sig.saturating_sub(1), x.abs());
    s.rsplit('e').next().and_then(|e| e.parse().ok()).unwrap_or(0)
}

/// Uses the typographic minus and never prints `−0`.
fn tidy(s: String) -> String {
    let s = if s.starts_with('-') && s.chars().all(|c| matches!(c, '-' | '0' | '.')) { s[1..].to_string() } else { s };
    s.replacen('-', "−", 1)
}

fn trim_zeros(s: String) -> String {
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

/// The value and its unit, joined by a no-break space (a table cell never wraps between them).
fn with_unit(s: String, unit: &str) -> String {
    if unit.is_empty() { s } else { format!("{s}\u{a0}{unit}") }
}

/// `x` with `sig` significant digits, trailing zeros dropped: decimal between 10⁻³ and 10⁵,
/// else `m×10ⁿ`. Non-finite values print as `–`.
pub fn fmt_num(x: f64, sig: usize) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let sig = sig.max(1);
    let e = exponent(x, sig);
    if (MIN_EXP..MAX_EXP).contains(&e) {
        let d = (sig as i32 - 1 - e).max(0) as usize;
        tidy(trim_zeros(format!("{x:.d$}")))
    } else {
        let m = x / 10f64.powi(e);
        tidy(format!("{}×10{}", trim_zeros(format!("{:.*}", sig - 1, m)), superscript(e)))
    }
}

/// `x` with four significant digits and its unit: `0.00965`, `8.12 µm`, `3×10⁻⁶ /µm`.
pub fn fmt_value(x: f64, unit: &str) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    with_unit(fmt_num(x, SIG), unit)
}

/// `x ± err` rounded where the two-digit uncertainty ends, with its unit: `0.00965 ± 0.00012`,
/// `12.3 ± 1.4 µm`, `(2.833 ± 0.012)×10⁻⁶ /µm`. Without a usable uncertainty (non-finite or not
/// positive), as [`fmt_value`].
pub fn fmt_with_err(x: f64, err: f64, unit: &str) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if !(err > 0.0 && err.is_finite()) {
        return fmt_value(x, unit);
    }
    // exponent of the last digit shown: the second significant digit of the uncertainty
    let last = exponent(err, 2) - 1;
    let ex = exponent(x.abs().max(err), SIG);
    if (MIN_EXP..MAX_EXP).contains(&ex) {
        let d = (-last).max(0) as usize;
        // an uncertainty of tens or more: both rounded to its second digit (`1230 ± 450`)
        let (x, err) = if last > 0 {
            let q = 10f64.powi(last);
            ((x / q).round() * q, (err / q).round() * q)
        } else {
            (x, err)
        };
        with_unit(format!("{} ± {err:.d$}", tidy(format!("{x:.d$}"))), unit)
    } else {
        let s = 10f64.powi(ex);
        let d = (ex - last).max(0) as usize;
        with_unit(format!("({} ± {:.d$})×10{}", tidy(format!("{:.d$}", x / s)), err / s, superscript(ex)), unit)
    }
}

/// Numbers shown side by side (a table column, a change), `sig` significant digits each, all in
/// one form: decimal, or all `m×10ⁿ` when any needs it; trailing zeros kept.
pub fn fmt_common(xs: &[f64], sig: usize) -> Vec<String> {
    let sig = sig.max(1);
    let decimal = |x: f64| x == 0.0 || !x.is_finite() || (MIN_EXP..MAX_EXP).contains(&exponent(x, sig));
    let all_decimal = xs.iter().all(|&x| decimal(x));
    xs.iter()
        .map(|&x| {
            if !x.is_finite() {
                "–".to_string()
            } else if x == 0.0 {
                "0".into()
            } else if all_decimal {
                let d = (sig as i32 - 1 - exponent(x, sig)).max(0) as usize;
                tidy(format!("{x:.d$}"))
            } else {
                let e = exponent(x, sig);
                tidy(format!("{:.*}×10{}", sig - 1, x / 10f64.powi(e), superscript(e)))
            }
        })
        .collect()
}

/// A change `a → b` in one form ([`fmt_common`]): `0.00110 → 0.000826` with three digits is
/// `1.10×10⁻³ → 8.26×10⁻⁴`.
pub fn fmt_pair(a: f64, b: f64, sig: usize) -> String {
    let v = fmt_common(&[a, b], sig);
    format!("{} → {}", v[0], v[1])
}

/// Decimal places at which evenly spaced ticks (as plotters places them: multiples of 1, 2 or
/// 5 × 10ⁿ) print exactly and all distinct.
pub fn tick_decimals(ticks: &[f64]) -> usize {
    let step = ticks.windows(2).map(|w| (w[1] - w[0]).abs()).filter(|d| *d > 0.0).fold(f64::INFINITY, f64::min);
    let mut d = if step.is_finite() { (-step.log10() - 1e-9).ceil().max(0.0) as usize } else { 0 };
    let distinct = |d: usize| {
        let l: Vec<String> = ticks.iter().map(|t| tidy(format!("{t:.d$}"))).collect();
        l.windows(2).all(|w| w[0] != w[1])
    };
    while d < 15 && !distinct(d) {
        d += 1;
    }
    d
}

/// Labels of the ticks `ticks` with the decimals of [`tick_decimals`]: exact and distinct.
pub fn tick_labels(ticks: &[f64]) -> Vec<String> {
    let d = tick_decimals(ticks);
    ticks.iter().map(|t| tidy(format!("{t:.d$}"))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_well() {
        assert_eq!(fmt_value(0.00965, ""), "0.00965");
        assert_eq!(fmt_value(0.009650001, ""), "0.00965");
        assert_eq!(fmt_value(8.123456, "µm"), "8.123\u{a0}µm");
        assert_eq!(fmt_value(3e-6, "/µm"), "3×10⁻⁶\u{a0}/µm");
        assert_eq!(fmt_value(2.833121483939129e-6, "/µm"), "2.833×10⁻⁶\u{a0}/µm");
        assert_eq!(fmt_value(0.0073043904924411174, "/µm"), "0.007304\u{a0}/µm");
        assert_eq!(fmt_value(-1.5e-4, ""), "−1.5×10⁻⁴");
        assert_eq!(fmt_value(123456.0, "s"), "1.235×10⁵\u{a0}s");
        assert_eq!(fmt_value(0.0, ""), "0");
        assert_eq!(fmt_value(f64::NAN, "µm"), "–");
        // rounding that carries into the next power of ten
        assert_eq!(fmt_value(9.99999e-4, ""), "0.001");
    }

    #[test]
    fn values_with_errors_round_where_the_error_ends() {
        assert_eq!(fmt_with_err(0.009653, 0.000123, ""), "0.00965 ± 0.00012");
        assert_eq!(fmt_with_err(12.34, 1.4, "µm"), "12.3 ± 1.4\u{a0}µm");
        assert_eq!(fmt_with_err(1234.0, 56.0, "s"), "1234 ± 56\u{a0}s");
        assert_eq!(fmt_with_err(12.8, 18997.0, ""), "0 ± 19000");
        assert_eq!(fmt_with_err(1234.0, 456.0, ""), "1230 ± 460");
        assert_eq!(fmt_with_err(2.8331e-6, 1.2e-8, "/µm"), "(2.833 ± 0.012)×10⁻⁶\u{a0}/µm");
        assert_eq!(fmt_with_err(-0.0021, 0.0004, ""), "−0.00210 ± 0.00040");
        assert_eq!(fmt_with_err(0.5, f64::NAN, ""), "0.5");
        assert_eq!(fmt_with_err(0.5, 0.0, ""), "0.5");
    }

    #[test]
    fn changes_share_one_form() {
        assert_eq!(fmt_pair(0.0011, 0.000826, 3), "1.10×10⁻³ → 8.26×10⁻⁴");
        assert_eq!(fmt_pair(0.0104, 0.00968, 3), "0.0104 → 0.00968");
        assert_eq!(fmt_pair(2.0, f64::NAN, 3), "2.00 → –");
        assert_eq!(fmt_common(&[0.00104, 0.000968, 0.0], 3), ["1.04×10⁻³", "9.68×10⁻⁴", "0"]);
    }

    #[test]
    fn tick_labels_are_distinct_and_exact() {
        let t = [0.6056, 0.6058, 0.606, 0.6062, 0.6064];
        assert_eq!(tick_labels(&t), ["0.6056", "0.6058", "0.6060", "0.6062", "0.6064"]);
        assert_eq!(tick_labels(&[0.0, 0.5, 1.0, 1.5]), ["0.0", "0.5", "1.0", "1.5"]);
        assert_eq!(tick_labels(&[-10.0, -5.0, 0.0, 5.0]), ["−10", "−5", "0", "5"]);
        // plotters' key points carry rounding noise
        assert_eq!(tick_labels(&[0.1, 0.30000000000000004, 0.5]), ["0.1", "0.3", "0.5"]);
    }
}
