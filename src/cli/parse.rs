//! Parsers for the command line's lists and ranges.

/// Most values a list or range may expand to (a guard against a typo such as a step of 1e-9).
pub const MAX_VALUES: usize = 1_000_000;

/// `X`, `X,Y,...` or `FROM:TO:STEP` (inclusive of TO, within a millionth of a step).
pub fn values(text: &str) -> Result<Vec<f64>, String> {
    let num = |s: &str| -> Result<f64, String> {
        s.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| format!("{s:?} is not a number"))
    };
    if let Some((from, rest)) = text.split_once(':') {
        let (to, step) = rest.split_once(':').ok_or_else(|| format!("{text:?}: a range is FROM:TO:STEP"))?;
        let (from, to, step) = (num(from)?, num(to)?, num(step)?);
        if step <= 0.0 {
            return Err(format!("{text:?}: the step must be positive"));
        }
        if to < from {
            return Err(format!("{text:?}: TO is below FROM"));
        }
        // Counted in f64: a huge span must be refused, not wrap to an empty list.
        let count = ((to - from) / step + 1e-6).floor() + 1.0;
        if count.is_nan() || count > MAX_VALUES as f64 {
            return Err(format!("{text:?} expands to {} values (at most {MAX_VALUES})", crate::error::number(count)));
        }
        let count = count as usize;
        return Ok((0..count).map(|i| from + i as f64 * step).collect());
    }
    text.split(',').map(num).collect()
}

/// A finite number (clap's own f64 parser takes "nan" and "inf").
pub fn finite(text: &str) -> Result<f64, String> {
    text.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| format!("{text:?} is not a finite number"))
}

/// An exposure in stops, within ±[`crate::display::MAX_EXPOSURE_EV`] as a scene's `exposure_ev`.
pub fn exposure(text: &str) -> Result<f64, String> {
    let ev = finite(text)?;
    let max = crate::display::MAX_EXPOSURE_EV;
    if ev.abs() > max {
        return Err(format!("{} stops: an exposure lies within ±{max}", text.trim()));
    }
    Ok(ev)
}

/// A tone curve by name (`display::Tone`): filmic or clip.
pub fn tone(text: &str) -> Result<crate::display::Tone, String> {
    text.trim().parse()
}

/// Samples per pixel: a power of two from 1 to 64 (whether the device has that many is checked later).
pub fn samples(text: &str) -> Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .ok()
        .filter(|&n| n.is_power_of_two() && n <= 64)
        .ok_or_else(|| format!("{text:?}: samples per pixel is a power of two: 1 (no anti-aliasing), 2, 4, 8, …"))
}

/// `THETA,PHI`.
pub fn pair(text: &str) -> Result<(f64, f64), String> {
    match values(text)?.as_slice() {
        [a, b] if !text.contains(':') => Ok((*a, *b)),
        _ => Err(format!("{text:?}: expected THETA,PHI in degrees")),
    }
}

/// `N` or `NX,NY` (positive integers).
pub fn tile(text: &str) -> Result<(usize, usize), String> {
    let parts: Vec<_> = text.split(',').map(|s| s.trim().parse::<usize>()).collect();
    match parts.as_slice() {
        [Ok(n)] if *n > 0 => Ok((*n, *n)),
        [Ok(x), Ok(y)] if *x > 0 && *y > 0 => Ok((*x, *y)),
        _ => Err(format!("{text:?}: expected NX or NX,NY (positive integers)")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_include_their_end() {
        assert_eq!(values("380:400:10").unwrap(), vec![380.0, 390.0, 400.0]);
        assert_eq!(values("0:0.3:0.1").unwrap().len(), 4);
        assert_eq!(values("500").unwrap(), vec![500.0]);
        assert_eq!(values("450,550").unwrap(), vec![450.0, 550.0]);
        assert!(values("1:0:1").is_err() && values("0:1:0").is_err() && values("0:1e9:1e-3").is_err());
        assert!(values("1:1e300:1").is_err(), "a count beyond usize must not wrap to an empty list");
        assert!(values("abc").is_err() && values("nan").is_err());
        assert!(finite("inf").is_err() && finite("NaN").is_err() && finite("-1e300").is_ok());
        assert_eq!(pair("10,180").unwrap(), (10.0, 180.0));
        assert!(pair("10").is_err());
        assert_eq!(tile("3").unwrap(), (3, 3));
        assert_eq!(tile("2,5").unwrap(), (2, 5));
        assert!(tile("0").is_err() && tile("a,b").is_err());
    }
}
