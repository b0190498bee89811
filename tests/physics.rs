//! The CPU reference against closed-form optics (no GPU): Jacobi–Anger orders of a sinusoidal phase grating,
//! the grating equation for a blazed grating, a flat mirror, and the Taylor series against the exact method.

use diffract::physics::coherence::{CoherenceWindow, Lookup};
use diffract::physics::exact::window_gain;
use diffract::physics::exact::{Method, Query, Reference};
use diffract::physics::heightfield::HeightField;
use diffract::physics::taylor::{HeightStats, TaylorPlan};

#[path = "common/place.rs"]
mod place;

/// Bessel J_m(x) = (1/2π)∫₀^{2π} cos(mτ − x sin τ) dτ; the trapezoid rule on a periodic integrand converges
/// geometrically, so 512 points are exact to rounding for |x| < 30.
fn bessel_j(m: i32, x: f64) -> f64 {
    const STEPS: usize = 512;
    (0..STEPS)
        .map(|i| {
            let t = i as f64 / STEPS as f64 * std::f64::consts::TAU;
            (m as f64 * t - x * t.sin()).cos()
        })
        .sum::<f64>()
        / STEPS as f64
}

/// h = a·cos(2πx/d) along x, one row (a 1D grating: the window in y is then the coherence limit itself).
fn sinusoid(a_um: f64, period_px: usize, periods: usize, dx_um: f64) -> HeightField {
    let n = period_px * periods;
    let h = (0..n).map(|x| a_um * (std::f64::consts::TAU * x as f64 / period_px as f64).cos()).collect();
    HeightField::new(n, 1, dx_um, dx_um, h).unwrap()
}

fn reference(hf: &HeightField, method: Method, queries: &[Query], order: Option<usize>) -> Reference {
    let (lx, ly) = hf.size_um();
    let window = CoherenceWindow::new(lx, ly, 65.0, None).unwrap();
    let plan = match method {
        Method::Exact => None,
        _ => Some(Reference::plan_for(hf, &window, queries, 1e-8, order).unwrap()),
    };
    Reference::new(hf, window, method, plan).unwrap()
}

/// Views of orders m = 0..=3 at normal incidence: u = mλ/d, so sin θ_r = mλ/d with φ_r = 180°.
fn order_queries(lambda_nm: f64, d_um: f64) -> Vec<(i32, Query)> {
    (0..=3)
        .filter_map(|m| {
            let s = m as f64 * lambda_nm * 1e-3 / d_um;
            (s < 0.999).then(|| {
                let theta_r = s.asin().to_degrees();
                (m, Query { lambda_nm, theta_i: 0.0, phi_i: 0.0, theta_r, phi_r: 180.0 })
            })
        })
        .collect()
}

#[test]
fn sinusoidal_grating_orders_have_bessel_powers() {
    let (a, d_px, dx) = (0.1, 32, 0.05);
    let hf = sinusoid(a, d_px, 20, dx);
    let d_um = d_px as f64 * dx;
    for lambda_nm in [450.0, 550.0, 650.0] {
        let orders = order_queries(lambda_nm, d_um);
        let queries: Vec<Query> = orders.iter().map(|o| o.1).collect();
        for method in [Method::Exact, Method::Taylor] {
            let samples = reference(&hf, method, &queries, None).evaluate(&queries).unwrap();
            for ((m, _), s) in orders.iter().zip(&samples) {
                let k = std::f64::consts::TAU / (lambda_nm * 1e-3);
                let expected = bessel_j(*m, k * s.uvw.z * a).powi(2);
                let rel = (s.power - expected).abs() / expected;
                assert!(rel < 5e-3, "{method:?} λ={lambda_nm} m={m}: power {} vs J_m² {expected} ({rel:.2e})", s.power);
            }
        }
    }
}

#[test]
fn sinusoidal_grating_is_dark_between_orders() {
    let hf = sinusoid(0.1, 32, 20, 0.05);
    let q = Query { lambda_nm: 550.0, theta_i: 0.0, phi_i: 0.0, theta_r: 12.0, phi_r: 180.0 };
    let s = reference(&hf, Method::Exact, &[q], None).evaluate(&[q]).unwrap();
    assert!(s[0].power < 1e-12, "{}", s[0].power);
}

#[test]
fn flat_mirror_is_one_at_specular_and_dark_elsewhere() {
    let hf = HeightField::new(64, 64, 0.1, 0.1, vec![0.2; 64 * 64]).unwrap();
    for (theta_i, phi_i) in [(0.0, 0.0), (30.0, 0.0), (60.0, 45.0)] {
        let specular = Query { lambda_nm: 500.0, theta_i, phi_i, theta_r: theta_i, phi_r: phi_i + 180.0 };
        let off = Query { theta_r: theta_i + 5.0, ..specular };
        for method in [Method::Exact, Method::Taylor] {
            let s = reference(&hf, method, &[specular, off], None).evaluate(&[specular, off]).unwrap();
            assert!((s[0].power - 1.0).abs() < 1e-12, "{method:?} θ_i={theta_i}: {}", s[0].power);
            assert!(s[1].power < 1e-12, "{method:?}: {}", s[1].power);
        }
    }
    let normal = Query { lambda_nm: 500.0, theta_i: 0.0, phi_i: 0.0, theta_r: 0.0, phi_r: 0.0 };
    let s = reference(&hf, Method::Exact, &[normal], None).evaluate(&[normal]).unwrap();
    assert!((s[0].reflectance - 1.0).abs() < 1e-12, "a mirror at normal incidence reflects 1");
}

/// h = H·frac(x/d): a blazed grating.
fn sawtooth(h_um: f64, period_px: usize, periods: usize, dx_um: f64) -> HeightField {
    let n = period_px * periods;
    let h = (0..n).map(|x| h_um * (x % period_px) as f64 / period_px as f64).collect();
    HeightField::new(n, 1, dx_um, dx_um, h).unwrap()
}

/// The θ_r of the power maximum near `theta0`, from a fine sweep and a parabola through ln(power) (exact for a
/// Gaussian peak).
fn peak_theta(r: &Reference, base: Query, theta0: f64, half_width: f64, step: f64) -> f64 {
    let n = (2.0 * half_width / step).round() as usize;
    let qs: Vec<Query> = (0..=n).map(|i| Query { theta_r: theta0 - half_width + i as f64 * step, ..base }).collect();
    let s = r.evaluate(&qs).unwrap();
    let i = (1..n).max_by(|&a, &b| s[a].power.total_cmp(&s[b].power)).unwrap();
    let (l, c, rr) = (s[i - 1].power.ln(), s[i].power.ln(), s[i + 1].power.ln());
    qs[i].theta_r + 0.5 * step * (l - rr) / (l - 2.0 * c + rr)
}

#[test]
fn blazed_grating_first_order_gives_back_its_period() {
    // The thesis's test (model.md §6.1): 2.5 µm period, 65 µm patch; light at θ_i = 30°, views at φ_r = 180°.
    let (d_px, dx) = (50, 0.05);
    let d_um = d_px as f64 * dx;
    let hf = sawtooth(0.3, d_px, 26, dx);
    let r = reference(&hf, Method::Exact, &[], None);
    let theta_i: f64 = 30.0;
    let mut estimates = Vec::new();
    for lambda_nm in [420.0, 480.0, 540.0, 600.0, 660.0] {
        let base = Query { lambda_nm, theta_i, phi_i: 0.0, theta_r: 0.0, phi_r: 180.0 };
        // Coarse sweep, then the local maxima; the first order is the one with the smallest non-zero |u|.
        let coarse: Vec<Query> = (0..1700).map(|i| Query { theta_r: i as f64 * 0.05, ..base }).collect();
        let s = r.evaluate(&coarse).unwrap();
        let maxima: Vec<usize> = (1..s.len() - 1)
            .filter(|&i| s[i].power > s[i - 1].power && s[i].power >= s[i + 1].power && s[i].power > 1e-4)
            .collect();
        let first = maxima
            .iter()
            .copied()
            .filter(|&i| s[i].uvw.x.abs() > 0.05)
            .min_by(|&a, &b| s[a].uvw.x.abs().total_cmp(&s[b].uvw.x.abs()))
            .expect("a first order");
        let theta = peak_theta(&r, base, coarse[first].theta_r, 0.2, 0.002);
        // Grating equation in this frame: u = −sin θ_i cos φ_i − sin θ_r cos φ_r = m λ / d with m = ±1.
        let u = -(theta_i.to_radians().sin()) + theta.to_radians().sin();
        estimates.push(lambda_nm * 1e-3 / u.abs());
    }
    for d in &estimates {
        assert!((d / d_um - 1.0).abs() < 2e-4, "period {d} µm from {estimates:?}, true {d_um}");
    }
}

#[test]
fn grazing_angles_stay_finite() {
    let hf = sinusoid(0.1, 32, 4, 0.05);
    let qs: Vec<Query> = [89.0, 89.9, 89.99]
        .iter()
        .flat_map(|&t| {
            [
                Query { lambda_nm: 500.0, theta_i: t, phi_i: 0.0, theta_r: t, phi_r: 180.0 },
                Query { lambda_nm: 500.0, theta_i: t, phi_i: 0.0, theta_r: t, phi_r: 0.0 },
            ]
        })
        .collect();
    for method in [Method::Exact, Method::Taylor] {
        for s in reference(&hf, method, &qs, None).evaluate(&qs).unwrap() {
            assert!(s.power.is_finite() && s.reflectance.is_finite(), "{s:?}");
        }
    }
    let below = Query { lambda_nm: 500.0, theta_i: 0.0, phi_i: 0.0, theta_r: 90.0, phi_r: 0.0 };
    assert!(reference(&hf, Method::Exact, &[], None).evaluate(&[below]).is_err());
}

fn elaphe(tile: usize) -> HeightField {
    let scale = diffract::physics::formats::png::PngScale { pixel_size_um: 0.065, height_um: 0.375 };
    diffract::physics::formats::load(&place::afm("elaphe-100px.png"), Some(scale)).unwrap().tiled(tile, tile).unwrap()
}

/// Lookups on and between bins, over the spectrum's busy part, for a few wavelengths and |w|.
fn probe_points(hf: &HeightField) -> Vec<(Lookup, f64)> {
    let (lx, ly) = hf.size_um();
    let mut out = Vec::new();
    for (u, v, w, lambda_um) in
        [(0.0, 0.0, -2.0, 0.38), (0.0, 0.12, -1.9, 0.45), (0.03, 0.35, -1.5, 0.55), (-0.2, 0.6, -1.2, 0.7)]
    {
        let k = std::f64::consts::TAU / lambda_um;
        out.push((Lookup::new(u, v, lambda_um, lx, ly), k * w));
    }
    out
}

#[test]
fn taylor_error_falls_with_n_within_the_bound() {
    let hf = elaphe(2);
    let (lx, ly) = hf.size_um();
    let window = CoherenceWindow::new(lx, ly, 65.0, None).unwrap();
    let exact = Reference::new(&hf, window, Method::Exact, None).unwrap();
    let points = probe_points(&hf);
    let truth: Vec<_> = points.iter().map(|&(at, kw)| exact.amplitude(at, kw)).collect();
    let gain = window_gain(&window, &hf);
    let mut last = f64::INFINITY;
    for order in [6, 10, 14, 18, 22, 26] {
        // x_max for λ = 380 nm, |w| = 2: a bound for every probe point.
        let plan = TaylorPlan::new(0.38, 2.0, &HeightStats::of(&hf), gain, 1e-4, Some(order)).unwrap();
        let taylor = Reference::new(&hf, window, Method::Taylor, Some(plan)).unwrap();
        let err =
            points.iter().zip(&truth).map(|(&(at, kw), t)| (taylor.amplitude(at, kw) - t).norm()).fold(0.0, f64::max);
        assert!(
            err <= plan.truncation_bound + 1e-14,
            "N={order}: error {err:.3e} above the bound {:.3e}",
            plan.truncation_bound
        );
        assert!(err < last || err < 1e-13, "N={order}: error {err:.3e} did not fall (was {last:.3e})");
        last = err;
    }
    assert!(last < 1e-10);
}

#[test]
fn the_f32_estimate_tracks_the_observed_f32_error() {
    // The Elaphe patch at 1×..4× its height: f32 sums degrade as x_max grows, and the plan's estimate stays
    // above the observed error without being uselessly pessimistic.
    let base = elaphe(2);
    let k = std::f64::consts::TAU / 0.38;
    for scale in [1.0, 2.0, 3.0, 4.0] {
        let heights = base.heights_um.iter().map(|h| scale * h).collect();
        let hf = HeightField::new(base.nx, base.ny, base.dx_um, base.dy_um, heights).unwrap();
        let (lx, ly) = hf.size_um();
        let window = CoherenceWindow::new(lx, ly, 65.0, None).unwrap();
        let plan = TaylorPlan::new(0.38, 2.0, &HeightStats::of(&hf), window_gain(&window, &hf), 1e-4, None).unwrap();
        let f32 = Reference::new(&hf, window, Method::TaylorF32, Some(plan)).unwrap();
        let exact = Reference::new(&hf, window, Method::Exact, None).unwrap();
        let mut worst: f64 = 0.0;
        for i in 0..30 {
            for j in 0..4 {
                let at = Lookup { sx: i as f64 * 0.5, sy: j as f64 * 0.37 };
                worst = worst.max((f32.amplitude(at, -2.0 * k) - exact.amplitude(at, -2.0 * k)).norm());
            }
        }
        let d = plan.describe();
        assert!(
            worst <= plan.f32_error + plan.truncation_bound,
            "×{scale}: observed {worst:.3e} above the estimate: {d}"
        );
        assert!(plan.f32_error <= 30.0 * worst, "×{scale}: estimate far above the observed {worst:.3e}: {d}");
        if scale == 1.0 {
            assert!(plan.f32_suffices() && worst <= plan.tolerance, "the measured patch fits f32: {d}");
        }
        if scale == 4.0 {
            assert!(!plan.f32_suffices() && worst > plan.tolerance, "4× the height is beyond f32 ({worst:.3e}): {d}");
        }
    }
}

/// ∫ f cos θ_r dω_r over the (u, v) square of half-width `half` around `centre`, in sr⁻¹·sr: (u, v) are the
/// projected solid angle's coordinates (ω_r,xy = −(u, v) − ω_i,xy), so the integral is Σ f·du·dv on a grid
/// (the midpoint rule; views below the horizon reflect nothing).
fn reflected_fraction(r: &Reference, lambda_nm: f64, omega_i: glam::DVec3, centre: (f64, f64), half: f64) -> f64 {
    const STEPS: usize = 121;
    let du = 2.0 * half / STEPS as f64;
    let mut queries = Vec::with_capacity(STEPS * STEPS);
    for j in 0..STEPS {
        for i in 0..STEPS {
            let u = centre.0 - half + (i as f64 + 0.5) * du;
            let v = centre.1 - half + (j as f64 + 0.5) * du;
            let (x, y) = (-u - omega_i.x, -v - omega_i.y);
            let z2 = 1.0 - x * x - y * y;
            if z2 <= 1e-6 {
                continue;
            }
            let (theta_i, phi_i) = (omega_i.z.acos().to_degrees(), omega_i.y.atan2(omega_i.x).to_degrees());
            let (theta_r, phi_r) = (z2.sqrt().acos().to_degrees(), y.atan2(x).to_degrees());
            queries.push(Query { lambda_nm, theta_i, phi_i, theta_r, phi_r });
        }
    }
    r.evaluate(&queries).unwrap().iter().map(|s| s.brdf_sr).sum::<f64>() * du * du
}

/// The BRDF in sr⁻¹ is energy-conserving in the coherence length: a flat mirror reflects Fresnel's R(θ_i) of
/// the incident flux (∫ f cos θ_r dω_r) at coherence lengths from 4 µm to 1 mm, while its peak grows as
/// (k σ_s)². (The peak-normalised `reflectance` is 1 at the mirror whatever the coherence: its lobe's energy
/// falls as 1/coherence².) The scale is exact for a narrow lobe; a wide one (k σ_s ≈ 9 at 4 µm and 700 nm: ±6°)
/// sees the gain and Fresnel change across it and, near grazing, loses part of itself below the horizon: the
/// deviation falls as 1/(k σ_s)² (measured: 65 µm ≤ 2.2e-3, 1 mm ≤ 9.2e-6 at 70°; 4 µm 2.0e-2 at 40°, −12 % at 70°).
#[test]
fn a_flat_mirror_reflects_its_fresnel_fraction_at_every_coherence_length() {
    let tolerance = |k_sigma: f64, theta_i: f64| match (k_sigma, theta_i) {
        (ks, _) if ks > 100.0 => 5e-3,
        (_, t) if t <= 45.0 => 3e-2,
        _ => 0.15,
    };
    let hf = HeightField::new(16, 16, 0.1, 0.1, vec![0.0; 256]).unwrap();
    let (lx, ly) = hf.size_um();
    let r0 = diffract::physics::optics::normal_reflectance(diffract::physics::optics::SKIN_INDEX);
    for coherence in [4.0, 65.0, 1000.0] {
        let r =
            Reference::new(&hf, CoherenceWindow::new(lx, ly, coherence, None).unwrap(), Method::Exact, None).unwrap();
        for lambda_nm in [400.0, 700.0] {
            let k_sigma = std::f64::consts::TAU / (lambda_nm * 1e-3) * coherence / 4.0;
            for theta_i in [0.0f64, 40.0, 70.0] {
                let omega_i = diffract::physics::optics::direction(theta_i, 30.0);
                let fraction = reflected_fraction(&r, lambda_nm, omega_i, (0.0, 0.0), 5.0 / k_sigma);
                // Exact Fresnel (Born & Wolf's sine and tangent forms; R₀ at normal incidence).
                let fresnel = if theta_i == 0.0 {
                    r0
                } else {
                    let (t, n) = (theta_i.to_radians(), diffract::physics::optics::SKIN_INDEX);
                    let tt = (t.sin() / n).asin();
                    0.5 * (((t - tt).sin() / (t + tt).sin()).powi(2) + ((t - tt).tan() / (t + tt).tan()).powi(2))
                };
                let rel = fraction / fresnel - 1.0;
                assert!(
                    rel.abs() < tolerance(k_sigma, theta_i),
                    "coherence {coherence} µm, λ {lambda_nm} nm, θ_i {theta_i}°: reflects {fraction:.5}, R = \
                     {fresnel:.5} ({rel:+.2e})"
                );
            }
        }
    }
}

/// A sinusoidal phase grating's order m carries R₀·C_m·J_m(k·w·a)² of the flux at normal incidence (C_m the gain
/// at the order's direction) — the same at every coherence length, though its lobe's width follows 1/coherence
/// (measured within 4.9e-3 at 16 µm, 3.0e-4 at 65 µm: the narrow-lobe limit again).
#[test]
fn grating_orders_carry_bessel_energy_whatever_the_coherence() {
    let (a, d_px, dx) = (0.1, 32, 0.05);
    let hf = sinusoid(a, d_px, 20, dx);
    let (lx, ly) = hf.size_um();
    let d_um = d_px as f64 * dx;
    let lambda_nm = 550.0;
    let k = std::f64::consts::TAU / (lambda_nm * 1e-3);
    let normal = diffract::physics::optics::direction(0.0, 0.0);
    let r0 = diffract::physics::optics::normal_reflectance(diffract::physics::optics::SKIN_INDEX);
    for coherence in [16.0, 32.0, 65.0] {
        let r =
            Reference::new(&hf, CoherenceWindow::new(lx, ly, coherence, None).unwrap(), Method::Exact, None).unwrap();
        let k_sigma = k * coherence / 4.0;
        for m in 0..=2 {
            let u = m as f64 * lambda_nm * 1e-3 / d_um;
            let energy = reflected_fraction(&r, lambda_nm, normal, (u, 0.0), 5.0 / k_sigma);
            let omega_m = glam::DVec3::new(-u, 0.0, (1.0 - u * u).sqrt());
            let w = -(normal.z + omega_m.z);
            let gain = diffract::physics::optics::gain_factor(normal, omega_m);
            let expected = r0 * gain * bessel_j(m, k * w * a).powi(2);
            let rel = energy / expected - 1.0;
            assert!(
                rel.abs() < 0.02,
                "coherence {coherence} µm, order {m}: {energy:.5e} vs {expected:.5e} ({rel:+.2e})"
            );
        }
    }
}

/// Errors come in kinds a caller can match, and read as one line a user can act on.
#[test]
fn errors_are_typed_and_say_what_is_wrong() {
    use diffract::Error;
    let e = HeightField::new(2, 2, 0.1, 0.1, vec![0.0; 3]).unwrap_err();
    assert!(matches!(e, Error::HeightField(_)), "{e:?}");
    let e = CoherenceWindow::new(6.4, 6.4, -1.0, None).unwrap_err();
    assert!(matches!(&e, Error::Setting { name, .. } if name == "coherence_um"), "{e:?}");
    assert!(e.to_string().starts_with("the coherence length must lie between"), "{e}");
    let scene = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nfov_deg = 40\n\n[light]\ndirection = [0, 0, 0]\n";
    let e = diffract::scene::Scene::parse(scene, "s.toml", std::path::Path::new(".")).unwrap_err();
    assert!(matches!(&e, Error::Scene { file, line: Some(_), .. } if file == "s.toml"), "{e:?}");
    assert!(e.to_string().starts_with("s.toml:"), "{e}");
}
