//! The exact BRDF of a height field, evaluated on the CPU: a sinusoidal phase grating (period 2 µm, 0.2 µm deep)
//! lit at normal incidence, swept across the views in its plane of diffraction at 550 nm. The brightest view
//! off the mirror direction is the first diffraction order, where the grating equation sin θ = λ/d puts it.
//!
//! Run: `cargo run --release --example exact_brdf`

use diffract::material::Settings;
use diffract::physics::exact::{Method, Query};
use diffract::physics::generate::{generate, PatchKind, PatchSpec};
use diffract::reference::brdf::{evaluate, Evaluator};

fn main() -> diffract::Result<()> {
    // A 16 µm square of the grating, 0.1 µm pixels: its grooves run along y, so it diffracts along x (φ = 0°).
    let spec = PatchSpec::new(PatchKind::Sinusoidal, 16.0, 0.1);
    let grating = generate(&spec)?;
    let lambda_nm = 550.0;
    // θ_r from −40° to 40° in 0.5° steps (negative θ: the view at φ = 180°).
    let queries: Vec<Query> = (-80..=80)
        .map(|i| {
            let theta = f64::from(i) * 0.5;
            Query {
                lambda_nm,
                theta_i: 0.0,
                phi_i: 0.0,
                theta_r: theta.abs(),
                phi_r: if theta < 0.0 { 180.0 } else { 0.0 },
            }
        })
        .collect();
    // The exact evaluation: exp(i·k·w·h) summed directly in f64, under a Gaussian coherence window of 16 µm.
    let accuracy = Settings { tolerance: 1e-4, coherence_um: 16.0, ..Settings::default() };
    let evaluation = evaluate(&grating, &queries, Evaluator::Cpu(Method::Exact), &accuracy, None)?;

    println!("theta_r_deg,reflectance");
    for s in evaluation.samples.iter().step_by(4) {
        let signed = if s.query.phi_r > 90.0 { -s.query.theta_r } else { s.query.theta_r };
        println!("{signed:.2},{:.6}", s.reflectance);
    }
    // The first order: the brightest view beyond 5° of the mirror direction, on the positive side.
    let first = evaluation
        .samples
        .iter()
        .filter(|s| s.query.phi_r < 90.0 && s.query.theta_r > 5.0)
        .max_by(|a, b| a.reflectance.total_cmp(&b.reflectance))
        .expect("views beyond 5°");
    let predicted = (lambda_nm * 1e-3 / spec.period_um).asin().to_degrees();
    println!(
        "first order at θ_r = {:.2}° (grating equation: {predicted:.2}°), reflectance {:.4} of the mirror's",
        first.query.theta_r, first.reflectance
    );
    assert!((first.query.theta_r - predicted).abs() <= 0.5, "the first order is where the grating equation says");
    Ok(())
}
