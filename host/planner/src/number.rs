//! Numbers in the CSVs as plain decimals (`0.465`, not `4.65e-1`): spreadsheets and readers see
//! the value at a glance, and every CSV reader still parses it.

/// Significant digits of the plan CSVs: the IK meets targets to about 1e-9 of the leg length, so
/// ten digits keep everything the planner resolves.
pub const SIGNIFICANT: usize = 10;

/// `x` with `sig` significant digits as a plain decimal, trailing zeros dropped; magnitudes below
/// 1e-20 (far under any quantity of either organism, nano N m torques included) are written `0`.
pub fn plain(x: f64, sig: usize) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x.abs() < 1e-20 {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor() as i64;
    let decimals = (sig as i64 - 1 - magnitude).clamp(0, 40) as usize;
    let mut s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.truncate(s.trim_end_matches('0').trim_end_matches('.').len());
    }
    if s == "-0" { "0".into() } else { s }
}

#[cfg(test)]
mod tests {
    use super::plain;

    #[test]
    fn plain_decimals_with_significant_digits() {
        assert_eq!(plain(0.465, 10), "0.465");
        assert_eq!(plain(4.65e-1, 3), "0.465");
        assert_eq!(plain(-1234.5678, 6), "-1234.57");
        assert_eq!(plain(1.25e-9, 3), "0.00000000125");
        assert_eq!(plain(2.0, 10), "2");
        assert_eq!(plain(0.0, 10), "0");
        assert_eq!(plain(-1e-30, 10), "0");
        assert_eq!(plain(-0.0000004, 1), "-0.0000004");
        assert_eq!(plain(123456.0, 3), "123456");
        // Round trip to the digits kept.
        let x = 0.123_456_789_012_345;
        assert!((plain(x, 10).parse::<f64>().unwrap() - x).abs() < 1e-10);
    }
}
