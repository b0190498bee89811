//! diffract used from another crate: the exact BRDF of a flat mirror (all of the light in the mirror direction)
//! and of a sinusoidal grating (its first order where the grating equation puts it). Exits non-zero if either is
//! wrong.

use diffract::material::Settings;
use diffract::physics::exact::{Method, Query};
use diffract::physics::heightfield::HeightField;
use diffract::reference::brdf::{evaluate, Evaluator};

fn main() -> diffract::Result<()> {
    let accuracy = Settings { tolerance: 1e-4, coherence_um: 6.4, ..Settings::default() };
    let exact = Evaluator::Cpu(Method::Exact);
    let mirror = HeightField::new(64, 64, 0.1, 0.1, vec![0.0; 64 * 64])?;
    let specular = Query { lambda_nm: 550.0, theta_i: 30.0, phi_i: 0.0, theta_r: 30.0, phi_r: 180.0 };
    let p = evaluate(&mirror, &[specular], exact, &accuracy, None)?.samples[0].power;
    assert!((p - 1.0).abs() < 1e-9, "a mirror's specular |P|² is 1, got {p}");
    // A grating of period 1.6 µm along x, 20 nm deep: at normal incidence its first order leaves at
    // sin θ = λ/d (the grating equation), far brighter than 10° beside it.
    let (n, period_px) = (64, 16);
    let heights =
        (0..n * n).map(|i| 0.02 * (std::f64::consts::TAU * (i % n) as f64 / period_px as f64).cos()).collect();
    let grating = HeightField::new(n, n, 0.1, 0.1, heights)?;
    let theta = (0.55_f64 / 1.6).asin().to_degrees();
    let order = Query { lambda_nm: 550.0, theta_i: 0.0, phi_i: 0.0, theta_r: theta, phi_r: 0.0 };
    let off = Query { theta_r: theta + 10.0, ..order };
    let s = evaluate(&grating, &[order, off], exact, &accuracy, None)?.samples;
    assert!(
        s[0].power > 1e3 * s[1].power,
        "the first order at {theta:.2}° ({}) outshines 10° beside it ({})",
        s[0].power,
        s[1].power
    );
    println!(
        "mirror: |P|² = {p:.9} at specular; grating: first order at {theta:.2}°, {:.3e} × the light 10° beside it",
        s[0].power / s[1].power
    );
    Ok(())
}
