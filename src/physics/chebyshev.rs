//! Chebyshev series on an interval: the nodes a function is sampled at, the coefficients of its interpolant,
//! their evaluation, and the bound that sizes a series for a band-limited function.
//!
//! The baked table ([`crate::physics::baked`]) stores each colour's dependence on w as Σ_d a_d·T_d(t), t the position
//! in the table's w-interval mapped to [−1, 1]: every quantity diffract integrates is a sum of pure frequencies
//! e^{i·ω·w} with |ω| ≤ Ω = 2π·(h_max − h_min)/λ_min, whose Chebyshev coefficients fall like J_d(Ωρ) (Jacobi–Anger),
//! super-exponentially once d > Ωρ (model.md §3.5 says why this and not slices in w).

/// The `count` Chebyshev points of the first kind on [−1, 1]: t_c = cos(π(c + ½)/count), largest first.
pub fn nodes(count: usize) -> Vec<f64> {
    (0..count).map(|c| (std::f64::consts::PI * (c as f64 + 0.5) / count as f64).cos()).collect()
}

/// The coefficients a_0..a_{n−1} of the polynomial of degree n − 1 that interpolates `values` (taken at
/// [`nodes`]`(n)`, in that order): a_d = (2 − δ_d0)/n · Σ_c f(t_c)·cos(πd(c + ½)/n) (a discrete cosine
/// transform).
pub fn coefficients(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    (0..n)
        .map(|d| {
            let sum: f64 = values
                .iter()
                .enumerate()
                .map(|(c, f)| f * (std::f64::consts::PI * d as f64 * (c as f64 + 0.5) / n as f64).cos())
                .sum();
            sum * if d == 0 { 1.0 } else { 2.0 } / n as f64
        })
        .collect()
}

/// The matrix of [`coefficients`]: `coefficients(f)[d] = Σ_c m[d][c]·f[c]` (applied to many functions at once).
pub(crate) fn coefficient_matrix(n: usize) -> Vec<Vec<f64>> {
    (0..n)
        .map(|d| {
            let scale = if d == 0 { 1.0 } else { 2.0 } / n as f64;
            (0..n).map(|c| scale * (std::f64::consts::PI * d as f64 * (c as f64 + 0.5) / n as f64).cos()).collect()
        })
        .collect()
}

/// T_0(t)..T_{n−1}(t) by the three-term recurrence T_{d+1} = 2t·T_d − T_{d−1} (the shader's way; stable on
/// [−1, 1], where |T_d| ≤ 1).
pub fn polynomials(t: f64, n: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(n);
    for d in 0..n {
        out.push(match d {
            0 => 1.0,
            1 => t,
            _ => 2.0 * t * out[d - 1] - out[d - 2],
        });
    }
    out
}

/// Σ_d a_d·T_d(t) by Clenshaw's recurrence.
pub fn evaluate(a: &[f64], t: f64) -> f64 {
    let (mut b1, mut b2) = (0.0, 0.0);
    for &c in a.iter().skip(1).rev() {
        let b0 = 2.0 * t * b1 - b2 + c;
        b2 = b1;
        b1 = b0;
    }
    a.first().copied().unwrap_or(0.0) + t * b1 - b2
}

/// An upper bound on Σ_{d ≥ n} |J_d(x)| for |x| ≤ `x` (from |J_d(x)| ≤ (|x|/2)^d/d!, summed as a geometric
/// series once the ratio x/(2(d + 1)) is below 1): the Chebyshev tail of e^{ixt} beyond degree n − 1, halved.
pub(crate) fn bessel_tail(x: f64, n: usize) -> f64 {
    let half = 0.5 * x.abs();
    if half == 0.0 {
        return if n == 0 { 1.0 } else { 0.0 };
    }
    let ratio = half / (n as f64 + 1.0);
    if ratio >= 1.0 {
        return f64::INFINITY;
    }
    // (x/2)^n / n! in logs, finite for large n.
    let log_term = n as f64 * half.ln() - (1..=n).map(|k| (k as f64).ln()).sum::<f64>();
    log_term.exp() / (1.0 - ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_reproduces_a_polynomial_and_its_values_at_the_nodes() {
        // 3 − 2t + 5t³ = 3·T0 + (−2 + 15/4)·T1 + (5/4)·T3.
        let f = |t: f64| 3.0 - 2.0 * t + 5.0 * t * t * t;
        let t = nodes(6);
        let a = coefficients(&t.iter().map(|&x| f(x)).collect::<Vec<_>>());
        let expected = [3.0, 1.75, 0.0, 1.25, 0.0, 0.0];
        for (got, want) in a.iter().zip(expected) {
            assert!((got - want).abs() < 1e-13, "{a:?}");
        }
        for x in [-1.0, -0.3, 0.2, 0.9] {
            assert!((evaluate(&a, x) - f(x)).abs() < 1e-12);
            let p = polynomials(x, a.len());
            let by_recurrence: f64 = a.iter().zip(&p).map(|(c, t)| c * t).sum();
            assert!((by_recurrence - f(x)).abs() < 1e-12);
        }
        let m = coefficient_matrix(6);
        let values: Vec<f64> = t.iter().map(|&x| f(x)).collect();
        for (row, want) in m.iter().zip(&a) {
            let got: f64 = row.iter().zip(&values).map(|(m, v)| m * v).sum();
            assert!((got - want).abs() < 1e-13);
        }
    }

    #[test]
    fn cosine_coefficients_are_bessel_values() {
        // cos(x t) = J0(x) + 2 Σ_k (−1)^k J_{2k}(x) T_{2k}(t) (Jacobi–Anger): for x = 2.5, J0 = −0.0483837764681979,
        // J2 = 0.446059058439617, J4 = 0.0737818800542552 (Abramowitz & Stegun table 9.1 to 10 digits; these
        // from SciPy's jv).
        let x = 2.5;
        let t = nodes(24);
        let a = coefficients(&t.iter().map(|&s| (x * s).cos()).collect::<Vec<_>>());
        assert!((a[0] - -0.0483837764681979).abs() < 1e-14, "{}", a[0]);
        assert!((a[2] - -2.0 * 0.446059058439617).abs() < 1e-14, "{}", a[2]);
        assert!((a[4] - 2.0 * 0.0737818800542552).abs() < 1e-14, "{}", a[4]);
        // The bound holds for every tail.
        for n in 2..20 {
            let tail: f64 = a[n..].iter().map(|c| c.abs()).sum();
            // Past n ≈ 16 both are at the rounding floor of the 24-point DCT (a few 1e-15).
            assert!(tail <= 2.0 * bessel_tail(x, n) + 1e-14, "n = {n}: {tail} > {}", 2.0 * bessel_tail(x, n));
        }
    }
}
