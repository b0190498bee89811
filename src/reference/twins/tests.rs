//! Every twin of ARCHITECTURE.md's table set against each other on the test device, at points that cover its range
//! (edges, grazing angles, knees, seams, segment boundaries); one test per pair, each failing when one side
//! changes alone.

use glam::{DMat3, DVec3};

use super::{evaluate, Point, Resources, Twin};
use crate::gpu::interface::SurfaceUniforms;
use crate::gpu::vk::tests::gpu_test;

/// `twin`'s GLSL at `points` on the test device.
fn gpu(twin: Twin, points: &[Point], resources: Resources<'_>) -> Vec<[f32; 4]> {
    gpu_test(|ctx| evaluate(ctx, twin, points, resources).unwrap())
}

/// A point of these vec4s (the rest zero).
fn point(vectors: &[[f32; 4]]) -> Point {
    let mut p = [[0.0; 4]; 4];
    p[..vectors.len()].copy_from_slice(vectors);
    p
}

/// A vector's f32 components and `w`.
fn v4(v: DVec3, w: f64) -> [f32; 4] {
    [v.x as f32, v.y as f32, v.z as f32, w as f32]
}

/// The f64 value of an f32 vector the GPU was given (what the Rust twin must see).
fn d3(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0].into(), v[1].into(), v[2].into())
}

/// Directions over the whole sphere (seeded), with the poles, the horizon and grazing ones among them.
fn directions(n: usize, seed: u64) -> Vec<DVec3> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let mut out = vec![DVec3::Z, DVec3::NEG_Z, DVec3::X, DVec3::new(0.0, -1.0, 1e-4).normalize()];
    out.extend([89.0f64, 89.9, 60.0, 1e-3].map(|deg| crate::physics::optics::direction(deg, 37.0 * deg.sqrt())));
    while out.len() < n {
        let (z, phi) = (2.0 * rng.f64() - 1.0, std::f64::consts::TAU * rng.f64());
        let r = (1.0 - z * z).sqrt();
        out.push(DVec3::new(r * phi.cos(), r * phi.sin(), z));
    }
    out
}

/// Asserts that each GPU value is within `rel` of the CPU's (relative to its size, or to 1 below it) — the f32
/// arithmetic of the GPU against the f64 of the CPU.
fn assert_close(what: &str, gpu: &[[f32; 4]], cpu: &[[f64; 4]], channels: usize, rel: f64) {
    assert_eq!(gpu.len(), cpu.len());
    for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        for k in 0..channels {
            let (g, c) = (f64::from(g[k]), c[k]);
            assert!((g - c).abs() <= rel * c.abs().max(1.0), "{what}, point {i}, channel {k}: GPU {g} vs CPU {c}");
        }
    }
}

/// The pairs of directions the BRDF's factors are tried at: every pair of `directions`' first 24.
fn direction_pairs() -> Vec<(DVec3, DVec3)> {
    let d = directions(24, 7);
    d.iter().flat_map(|&a| d.iter().map(move |&b| (a, b))).collect()
}

#[test]
fn fresnel_reflectance_is_its_twin() {
    let cosines: Vec<f64> = (0..=100).map(|k| f64::from(k) / 100.0).chain([-0.2, 1e-4, 0.999_999, 1.3]).collect();
    let mut points = Vec::new();
    for n in [1.000_01, 1.33, 1.5, 2.4] {
        points.extend(cosines.iter().map(|&c| point(&[[c as f32, n as f32, 0.0, 0.0]])));
    }
    let cpu: Vec<[f64; 4]> = points
        .iter()
        .map(|p| [crate::physics::optics::fresnel_reflectance(p[0][0].into(), p[0][1].into()), 0.0, 0.0, 0.0])
        .collect();
    assert_close("fresnel_reflectance", &gpu(Twin::FresnelReflectance, &points, Resources::default()), &cpu, 1, 2e-5);
}

#[test]
fn fresnel_ratio_is_its_twin() {
    let pairs = direction_pairs();
    let points: Vec<Point> = pairs.iter().map(|&(i, r)| point(&[v4(i, 1.5), v4(r, 0.0)])).collect();
    let cpu: Vec<[f64; 4]> = points
        .iter()
        .map(|p| [crate::physics::optics::fresnel_ratio(d3(p[0]), d3(p[1]), p[0][3].into()), 0.0, 0.0, 0.0])
        .filter(|_| true)
        .collect();
    // Where ω_i + ω_r vanishes (opposite directions) the half vector is undefined on both sides.
    let keep: Vec<usize> =
        (0..points.len()).filter(|&k| (d3(points[k][0]) + d3(points[k][1])).length() > 1e-3).collect();
    let values = gpu(Twin::FresnelRatio, &points, Resources::default());
    let pick = |v: &[[f32; 4]]| keep.iter().map(|&k| v[k]).collect::<Vec<_>>();
    let cpu: Vec<[f64; 4]> = keep.iter().map(|&k| cpu[k]).collect();
    assert_close("fresnel_ratio", &pick(&values), &cpu, 1, 5e-5);
}

#[test]
fn gain_factor_and_shadow_mask_are_their_twins() {
    let pairs: Vec<(DVec3, DVec3)> = direction_pairs().into_iter().filter(|(i, r)| (*i + *r).length() > 1e-3).collect();
    let points: Vec<Point> = pairs.iter().map(|&(i, r)| point(&[v4(i, 0.0), v4(r, 0.0)])).collect();
    let gain: Vec<[f64; 4]> =
        points.iter().map(|p| [crate::physics::optics::gain_factor(d3(p[0]), d3(p[1])), 0.0, 0.0, 0.0]).collect();
    // The gain grows as 1/(cos θ_r w²) towards grazing: compared relative to its size.
    assert_close("gain_factor", &gpu(Twin::GainFactor, &points, Resources::default()), &gain, 1, 1e-4);
    let mask: Vec<[f64; 4]> =
        points.iter().map(|p| [crate::physics::optics::shadow_mask(d3(p[0]), d3(p[1])), 0.0, 0.0, 0.0]).collect();
    assert_close("shadow_mask", &gpu(Twin::ShadowMask, &points, Resources::default()), &mask, 1, 5e-5);
}

#[test]
fn transmittance_is_its_twin() {
    let points: Vec<Point> = (0..=200).map(|k| point(&[[k as f32 / 200.0, 0.0, 0.0, 0.0]])).collect();
    let cpu: Vec<[f64; 4]> =
        points.iter().map(|p| [crate::physics::optics::transmittance(p[0][0].into()), 0.0, 0.0, 0.0]).collect();
    assert_close("transmittance", &gpu(Twin::Transmittance, &points, Resources::default()), &cpu, 1, 2e-5);
}

#[test]
fn the_pigments_are_their_twins() {
    use crate::physics::optics::{pigment_rgb, pigment_sky_rgb, Lit};
    let d = directions(12, 11);
    let mut rng = fastrand::Rng::with_seed(3);
    let (mut lit, mut sky) = (Vec::new(), Vec::new());
    for (k, (&i, &r)) in d.iter().zip(d.iter().rev()).enumerate() {
        for coated in [true, false] {
            let (up, ambient, visible) = (2.0 * rng.f64() - 1.0, rng.f64(), f64::from(k as u32 % 3) / 2.0);
            let albedo = DVec3::new(rng.f64(), rng.f64(), rng.f64());
            let flag = if coated { 1.0 } else { 0.0 };
            lit.push(point(&[v4(i, up), v4(r, ambient), v4(albedo, visible), [flag, 0.0, 0.0, 0.0]]));
            sky.push(point(&[v4(r, 0.0), v4(albedo, 0.0), v4(DVec3::new(0.3, 0.5, 0.9) * rng.f64(), 0.0), [flag; 4]]));
        }
    }
    let cpu_lit: Vec<[f64; 4]> = lit
        .iter()
        .map(|p| {
            let l = Lit { sun_visible: p[2][3].into(), coated: p[3][0] > 0.5 };
            let rgb = pigment_rgb(d3(p[0]), d3(p[1]), p[0][3].into(), d3(p[2]), p[1][3].into(), l);
            v4(rgb, 0.0).map(f64::from)
        })
        .collect();
    let cpu_sky: Vec<[f64; 4]> = sky
        .iter()
        .map(|p| v4(pigment_sky_rgb(d3(p[0]), d3(p[1]), d3(p[2]), p[3][0] > 0.5), 0.0).map(f64::from))
        .collect();
    assert_close("pigment_rgb", &gpu(Twin::PigmentRgb, &lit, Resources::default()), &cpu_lit, 3, 1e-5);
    assert_close("pigment_sky_rgb", &gpu(Twin::PigmentSkyRgb, &sky, Resources::default()), &cpu_sky, 3, 1e-5);
}

/// An irradiance of random coefficients (negative ones too, so that the clamp at zero is reached).
fn irradiance(seed: u64) -> crate::physics::sh::Irradiance {
    let mut rng = fastrand::Rng::with_seed(seed);
    let coefficients = std::array::from_fn(|k| {
        let scale = if k == 0 { 1.0 } else { 0.8 };
        DVec3::new(rng.f64() - 0.3, rng.f64() - 0.3, rng.f64() - 0.3) * scale
    });
    crate::physics::sh::Irradiance { coefficients }
}

#[test]
fn the_skys_irradiance_is_its_twin() {
    let sky = irradiance(5);
    let frame = SurfaceUniforms { sky_sh: sky.to_vec4s(), ..bytemuck::Zeroable::zeroed() };
    let points: Vec<Point> = directions(200, 9).iter().map(|&n| point(&[v4(n, 0.0)])).collect();
    // The GPU reads the coefficients as f32: the CPU gets the same.
    let f32_sky = crate::physics::sh::Irradiance { coefficients: frame.sky_sh.map(d3) };
    let cpu: Vec<[f64; 4]> = points.iter().map(|p| v4(f32_sky.over_pi(d3(p[0])), 0.0).map(f64::from)).collect();
    let resources = Resources { frame: Some(&frame), ..Resources::default() };
    assert_close("sky_over_pi", &gpu(Twin::SkyOverPi, &points, resources), &cpu, 3, 2e-5);
}

#[test]
fn the_tone_curves_are_their_twins() {
    use crate::display::tone::{agx, Tone};
    // Channels from far below black to far above white, grey and saturated, across AgX's log range.
    let mut colours = vec![DVec3::ZERO, DVec3::ONE, DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.0, 0.2, 1.0)];
    for ev in -18..=8 {
        let y = f64::from(ev).exp2();
        colours.extend([DVec3::splat(y), DVec3::new(y, 0.3 * y, 0.05 * y), DVec3::new(0.01 * y, y, 0.5 * y)]);
    }
    let oetf: Vec<Point> = (-20..=240)
        .map(|k| point(&[[k as f32 / 200.0, 0.0, 0.0, 0.0]]))
        .chain([0.003_130_7f32, 0.003_130_9, 0.0031308].map(|c| point(&[[c, 0.0, 0.0, 0.0]])))
        .collect();
    let cpu: Vec<[f64; 4]> =
        oetf.iter().map(|p| [crate::physics::spectrum::srgb_oetf(p[0][0].into()), 0.0, 0.0, 0.0]).collect();
    assert_close("srgb_oetf", &gpu(Twin::SrgbOetf, &oetf, Resources::default()), &cpu, 1, 2e-5);
    let points: Vec<Point> = colours.iter().map(|&c| point(&[v4(c, 0.0)])).collect();
    let cpu: Vec<[f64; 4]> = points.iter().map(|p| v4(agx(d3(p[0])), 0.0).map(f64::from)).collect();
    // AgX's sigmoid is a 7th-order polynomial with coefficients near 100: f32 keeps it to a few 1e-5.
    assert_close("agx", &gpu(Twin::Agx, &points, Resources::default()), &cpu, 3, 1e-4);
    let mut encode = Vec::new();
    for (k, &c) in colours.iter().enumerate() {
        for tone in Tone::ALL {
            let scale = f64::from(k as i32 % 7 - 3).exp2();
            encode.push(point(&[v4(c, scale), [tone.gpu(), 0.0, 0.0, 0.0]]));
        }
    }
    let cpu: Vec<[f64; 4]> = encode
        .iter()
        .map(|p| {
            let tone = if p[1][0] > 0.5 { Tone::Filmic } else { Tone::Clip };
            v4(tone.encode(d3(p[0]) * f64::from(p[0][3])), 0.0).map(f64::from)
        })
        .collect();
    assert_close("display_encode", &gpu(Twin::DisplayEncode, &encode, Resources::default()), &cpu, 3, 1e-4);
}

#[test]
fn the_spectrum_and_the_colour_matrix_are_their_twins() {
    use crate::physics::illuminant::Illuminant;
    use crate::physics::spectrum::Sampling;
    let mut rng = fastrand::Rng::with_seed(13);
    let xyz: Vec<Point> =
        (0..100).map(|_| point(&[v4(DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 2.0, 0.0)])).collect();
    let cpu: Vec<[f64; 4]> =
        xyz.iter().map(|p| v4(crate::physics::colour::xyz_to_linear_srgb(d3(p[0])), 0.0).map(f64::from)).collect();
    assert_close("xyz_to_linear_srgb", &gpu(Twin::XyzToLinearSrgb, &xyz, Resources::default()), &cpu, 3, 1e-5);
    // The table's rows at 1 nm: at a step of 1 nm the GPU's interpolation between rows is the CPU's at any λ; at
    // coarser steps (the illuminant averaged over each step) the shaders read it at the sampled wavelengths, whole
    // nanometres. Outside 380–780 nm both are zero.
    for (step, illuminant, fractional) in
        [(1.0, Illuminant::d65(), true), (5.0, Illuminant::named("F11").unwrap(), false)]
    {
        let sampling = Sampling::visible_under(step, illuminant);
        let lambdas: Vec<f64> = match fractional {
            true => (0..900).map(|k| 370.0 + f64::from(k) * 0.467).collect(),
            false => (370..=790).map(f64::from).collect(),
        };
        let points: Vec<Point> = lambdas.iter().map(|&l| point(&[[l as f32, 0.0, 0.0, 0.0]])).collect();
        let cpu: Vec<[f64; 4]> = points.iter().map(|p| sampling.weights_at(p[0][0].into())).collect();
        let resources = Resources { sampling: Some(&sampling), ..Resources::default() };
        assert_close(&format!("spectrum_at, step {step}"), &gpu(Twin::SpectrumAt, &points, resources), &cpu, 4, 2e-5);
    }
}

#[test]
fn the_panoramas_coordinates_are_their_twin() {
    let mut rng = fastrand::Rng::with_seed(17);
    let points: Vec<Point> = directions(300, 19).iter().map(|&d| point(&[v4(d, 6.0 * rng.f64() - 3.0)])).collect();
    let values = gpu(Twin::PanoramaUv, &points, Resources::default());
    for (p, g) in points.iter().zip(&values) {
        let [u, v] = crate::light::environment::panorama_uv(d3(p[0]), p[0][3].into());
        // u wraps: across the map's seam (atan2 at ±π) the two may differ by a whole turn, which a sampler ignores.
        // Vulkan lets atan be 4096 ULP off, and asin inherits it: up to 4.9e-4 rad at π/2 and 9.8e-4 at π, 1.6e-4
        // of the map either way (0.03°, a tenth of its finest texels); lavapipe's asin was 3.9e-4 rad off at 0.95.
        let tolerance = 4096.0 * f64::from(f32::EPSILON) / std::f64::consts::PI;
        let du = (f64::from(g[0]) - u).rem_euclid(1.0);
        let dv = (f64::from(g[1]) - v).abs();
        assert!(du.min(1.0 - du) < tolerance && dv < tolerance, "{p:?}: GPU {g:?} vs CPU {u} {v}");
    }
}

#[test]
fn a_maps_views_are_their_twin() {
    for size in [7u32, 64, 255] {
        let pixels: Vec<(u32, u32)> = (0..size).flat_map(|y| (0..size).map(move |x| (x, y))).collect();
        let points: Vec<Point> = pixels
            .iter()
            .map(|&(x, y)| point(&[[x as f32 + 0.5, y as f32 + 0.5, 0.0, 0.0], [size as f32, size as f32, 0.0, 0.0]]))
            .collect();
        let values = gpu(Twin::MapView, &points, Resources::default());
        for (&(x, y), g) in pixels.iter().zip(&values) {
            let cpu = crate::light::sampling::map_view(size, x, y);
            // On the disk's rim f32 and f64 may place a pixel either side.
            let half = f64::from(size) / 2.0;
            let r2 = ((f64::from(x) + 0.5 - half).powi(2) + (f64::from(y) + 0.5 - half).powi(2)) / (half * half);
            match cpu {
                Some(d) => assert!(
                    (g[3] == 1.0 && (d3(*g) - d).abs().max_element() < 2e-6) || (r2 - 1.0).abs() < 1e-5,
                    "map {size}, pixel ({x}, {y}): GPU {g:?} vs CPU {d}"
                ),
                None => assert!(g[3] == 0.0 || (r2 - 1.0).abs() < 1e-5, "map {size}, pixel ({x}, {y}): GPU {g:?}"),
            }
        }
    }
}

#[test]
fn the_moments_grid_and_the_skys_quadratic_are_their_twins() {
    use crate::light::prefilter::{grid_of_view, Quadratic};
    let views: Vec<DVec3> = directions(200, 23).into_iter().filter(|d| d.z >= 0.0).collect();
    let points: Vec<Point> = views.iter().map(|&d| point(&[v4(d, 0.0)])).collect();
    let cpu: Vec<[f64; 4]> = points
        .iter()
        .map(|p| {
            let (x, y) = grid_of_view(d3(p[0]));
            [x, y, 0.0, 0.0]
        })
        .collect();
    assert_close("moment_grid_of_view", &gpu(Twin::MomentGridOfView, &points, Resources::default()), &cpu, 2, 2e-5);
    // The quadratic form of a random irradiance, seen in random orthonormal frames: all nine coefficients.
    let quadratic = Quadratic::of_irradiance(&irradiance(29));
    let frame = SurfaceUniforms { sky_quadratic: quadratic.to_vec4s(true), ..bytemuck::Zeroable::zeroed() };
    let gpu_quadratic = {
        let q = frame.sky_quadratic.map(d3);
        Quadratic { c0: q[0], c: [q[1], q[2], q[3]], q: [[q[4], q[7], q[8]], [q[7], q[5], q[9]], [q[8], q[9], q[6]]] }
    };
    let mut points = Vec::new();
    let mut cpu = Vec::new();
    for (k, &n) in directions(20, 31).iter().enumerate() {
        let x = n.any_orthonormal_vector();
        let axes = DMat3::from_cols(x, n.cross(x), n);
        let (x, y) = (d3(v4(axes.x_axis, 0.0)), d3(v4(axes.y_axis, 0.0)));
        let a = gpu_quadratic.coefficients(DMat3::from_cols(x, y, d3(v4(n, 0.0))));
        for (j, a) in a.iter().enumerate() {
            points.push(point(&[v4(x, 0.0), v4(y, 0.0), v4(n, 0.0), [j as f32, k as f32, 0.0, 0.0]]));
            cpu.push(v4(*a, 0.0).map(f64::from));
        }
    }
    let resources = Resources { frame: Some(&frame), ..Resources::default() };
    assert_close("sky_coefficients", &gpu(Twin::SkyCoefficients, &points, resources), &cpu, 3, 5e-5);
}

#[test]
fn drawing_from_a_distribution_is_its_twin() {
    use crate::light::sampling::{r2, tent, Distribution2D};
    // 13 × 7 cells with an empty row and empty cells, of measures varying by row.
    let mut rng = fastrand::Rng::with_seed(37);
    let weights: Vec<f64> =
        (0..13 * 7).map(|i| if i / 13 == 3 || i % 5 == 0 { 0.0 } else { rng.f64() * rng.f64() }).collect();
    let distribution = Distribution2D::new(&weights, 13, 7, |i| 1.0 + (i / 13) as f64).unwrap();
    let size = [13u32, 7].map(f32::from_bits);
    let mut xis: Vec<[f32; 2]> = (0..1000).map(|_| [rng.f32(), rng.f32()]).collect();
    xis.extend([[0.0, 0.0], [0.999_999_94, 0.999_999_94]]);
    // Exactly on the CDF's steps, where the search must take the same side.
    xis.extend(distribution.cdf[..8].iter().map(|&c| [c.min(0.999_999_94), c.min(0.999_999_94)]));
    let points: Vec<Point> =
        xis.iter().map(|xi| point(&[[xi[0], xi[1], 0.0, 0.0], [size[0], size[1], 0.0, 0.0]])).collect();
    let resources = Resources { distribution: Some(&distribution), ..Resources::default() };
    let values = gpu(Twin::SampleCell, &points, resources);
    for (xi, g) in xis.iter().zip(&values) {
        let (col, row, fx, fy) = distribution.sample([xi[0].into(), xi[1].into()]);
        assert!(
            g[0] == col as f32
                && g[1] == row as f32
                && (f64::from(g[2]) - fx).abs() < 1e-5
                && (f64::from(g[3]) - fy).abs() < 1e-5,
            "xi {xi:?}: GPU {g:?} vs CPU ({col}, {row}, {fx}, {fy})"
        );
    }
    let mut rng = fastrand::Rng::with_seed(41);
    let r2_points: Vec<[u32; 3]> =
        (0..500).map(|k| [k * 977, rng.u32(..), rng.u32(..)]).chain([[u32::MAX, 0, u32::MAX]]).collect();
    let points: Vec<Point> = r2_points
        .iter()
        .map(|r| point(&[[f32::from_bits(r[0]), f32::from_bits(r[1]), f32::from_bits(r[2]), 0.0]]))
        .collect();
    for (r, g) in r2_points.iter().zip(gpu(Twin::R2, &points, Resources::default())) {
        let [x, y] = r2(r[0], [r[1], r[2]]);
        // Integer arithmetic on both sides, then 24 bits: exact.
        assert!(f64::from(g[0]) == x && f64::from(g[1]) == y, "r2 {r:?}: GPU {g:?} vs CPU {x} {y}");
    }
    let points: Vec<Point> =
        (0..=400).map(|k| point(&[[(k as f32 / 400.0).min(0.999_999_94), 0.0, 0.0, 0.0]])).collect();
    let cpu: Vec<[f64; 4]> = points.iter().map(|p| [tent(p[0][0].into()), 0.0, 0.0, 0.0]).collect();
    assert_close("tent", &gpu(Twin::Tent, &points, Resources::default()), &cpu, 1, 2e-5);
}

/// A baked material of `segments` segments in w: a blazed grating's table for a small map (a few mip levels).
fn baked(segments: usize) -> crate::material::Material {
    use crate::material::{Approach, Material, Reach, Settings};
    use crate::physics::generate::{generate, PatchKind, PatchSpec};
    let hf = generate(&PatchSpec::new(PatchKind::Blazed, 6.5, 0.065)).unwrap();
    let settings = Settings { approach: Approach::Baked, table_segments: Some(segments), ..Settings::default() };
    let light = crate::physics::optics::direction(25.0, 10.0);
    Material::prepare(&hf, settings, &Reach::Map { light, size: 65, filtered: true }).unwrap()
}

#[test]
fn the_baked_tables_lod_and_segments_are_their_twins() {
    for segments in [1, 3] {
        let material = baked(segments);
        let table = material.table.as_ref().unwrap();
        let texel = table.grid.texel;
        let footprints: Vec<f64> =
            (-20..=60).map(|k| texel * (f64::from(k) / 8.0).exp2()).chain([0.0, -1.0, texel, f64::NAN]).collect();
        let points: Vec<Point> = footprints.iter().map(|&f| point(&[[f as f32, 0.0, 0.0, 0.0]])).collect();
        let cpu: Vec<[f64; 4]> = points.iter().map(|p| [table.lod(p[0][0].into()), 0.0, 0.0, 0.0]).collect();
        let resources = Resources { material: Some(&material), ..Resources::default() };
        assert_close("table_lod", &gpu(Twin::TableLod, &points, resources), &cpu, 1, 2e-5);
        let (w0, w1) = table.grid.w;
        let ws: Vec<f64> = (-20..=220).map(|k| w0 + (w1 - w0) * f64::from(k) / 200.0).collect();
        let points: Vec<Point> = ws.iter().map(|&w| point(&[[w as f32, 0.0, 0.0, 0.0]])).collect();
        let values = gpu(Twin::TableSegment, &points, resources);
        for (p, g) in points.iter().zip(&values) {
            let (segment, t) = table.grid.segment_of(p[0][0].into());
            // On a boundary f32 may take either neighbour, at t = ±1 of each: the same point of the series.
            let same = g[0] == segment as f32 && (f64::from(g[1]) - t).abs() < 1e-4;
            let boundary = (f64::from(g[1]).abs() - 1.0).abs() < 1e-4 && (t.abs() - 1.0).abs() < 1e-4;
            assert!(same || boundary, "{segments} segments, w {}: GPU {g:?} vs CPU ({segment}, {t})", p[0][0]);
        }
    }
}

#[test]
fn a_baked_tables_read_is_its_twin() {
    use crate::physics::baked::sample::MipFilter;
    let material = baked(2);
    let table = material.table.as_ref().unwrap();
    let grid = &table.grid;
    let mut rng = fastrand::Rng::with_seed(43);
    let mut points = Vec::new();
    // Texel centres of levels 0, 1 and 2 read at their own level (the filter's weights there are 0 and 1: no
    // fixed-point rounding), at random w across both segments.
    for level in 0..table.levels.len().min(3) {
        let texel = grid.texel * f64::from(1u32 << level);
        let (nu, nv) = (grid.nu >> level, grid.nv >> level);
        for _ in 0..300 {
            let (a, b) = (rng.usize(..nu.max(1)), rng.usize(..nv.max(1)));
            let u = grid.u0 + (a as f64 + 0.5) * texel;
            let v = grid.v0 + (b as f64 + 0.5) * texel;
            let w = grid.w.0 + (grid.w.1 - grid.w.0) * rng.f64();
            points.push(point(&[[u as f32, v as f32, w as f32, level as f32]]));
        }
    }
    let resources = Resources { material: Some(&material), ..Resources::default() };
    let values = gpu(Twin::BakedXyz, &points, resources);
    let brightest = values.iter().map(|v| v[1].abs()).fold(0.0f32, f32::max);
    assert!(brightest > 0.0, "the points see the grating's light");
    for (p, g) in points.iter().zip(&values) {
        let cpu = table.xyz_filtered(d3(p[0]), p[0][3].into(), MipFilter::Linear);
        // The Chebyshev sum in f32 over coefficients of the table's own f32 texels, against the CPU's f64 sum.
        let err = (d3(*g) - cpu).abs().max_element();
        assert!(err <= 1e-4 * cpu.abs().max_element() + 1e-6 * f64::from(brightest), "{p:?}: GPU {g:?} vs CPU {cpu}");
    }
}

#[test]
fn the_table_of_twins_in_architecture_md_is_the_list_here() {
    let doc = include_str!("../../../ARCHITECTURE.md");
    let table = doc.split("## Twins").nth(1).expect("ARCHITECTURE.md has a section \"Twins\"");
    for twin in Twin::ALL {
        let (glsl, rust) = twin.names();
        let row = format!("| `{glsl}` | `{rust}` |");
        assert!(table.contains(&row), "ARCHITECTURE.md's table of twins lacks the row {row}");
    }
    let rows = table.lines().filter(|l| l.starts_with("| `") && l.contains(".glsl: ")).count();
    assert!(rows >= Twin::ALL.len(), "{rows} rows");
}

#[test]
fn the_lamps_are_their_twins() {
    use crate::light::lamp::{spot_factor, Lamp, Spot};
    // Across the edge, inside, beyond, a hard edge and a point lamp's 360° cone.
    let cases: Vec<[f32; 3]> = (0..=60)
        .map(|k| [k as f32, 30.0, 10.0])
        .chain([[29.0, 30.0, 0.0], [31.0, 30.0, 0.0], [180.0, 360.0, 0.0], [0.0, 90.0, 90.0]])
        .collect();
    let points: Vec<Point> = cases.iter().map(|c| point(&[[c[0], c[1], c[2], 0.0]])).collect();
    let cpu: Vec<[f64; 4]> =
        cases.iter().map(|c| [spot_factor(c[0].into(), c[1].into(), c[2].into()), 0.0, 0.0, 0.0]).collect();
    assert_close("spot_factor", &gpu(Twin::SpotFactor, &points, Resources::default()), &cpu, 1, 1e-5);
    // A point lamp and a spot, seen from points near and far, inside the beam, on its edge and outside it.
    let spot = Spot { direction: DVec3::new(0.3, -1.0, 0.2).normalize(), cone_deg: 35.0, soft_deg: 12.0 };
    let lamps = [
        Lamp { position: DVec3::new(0.5, 2.0, -1.0), intensity_cd: 80.0, radius_m: 0.02, spot: None },
        Lamp { position: DVec3::new(-1.0, 1.5, 0.5), intensity_cd: 250.0, radius_m: 0.1, spot: Some(spot) },
    ];
    let unit = 3.0;
    let uniforms = crate::light::lamp::LampUniforms::new(&lamps, unit);
    let frame = SurfaceUniforms { lamp_count: uniforms.count, lamps: uniforms.lamps, ..bytemuck::Zeroable::zeroed() };
    let (mut points, mut cpu, mut beams) = (Vec::new(), Vec::new(), Vec::new());
    // The spot's beam swept from its axis across its edge, besides directions all round.
    let side = spot.direction.any_orthonormal_vector();
    let beam = (0..=40).map(|deg| DMat3::from_axis_angle(side, f64::from(deg).to_radians()) * spot.direction);
    for (k, lamp) in lamps.iter().enumerate() {
        let sweep: Vec<DVec3> = if k == 1 { beam.clone().collect() } else { Vec::new() };
        for p in directions(40, 11 + k as u64).into_iter().chain(sweep) {
            let at = lamp.position + p * (0.01 + 3.0 * (p.x * 0.5 + 0.5));
            let given = point(&[v4(at, k as f64)]);
            let (l, e) = lamp.light_at(d3(given[0]));
            let full = lamp.intensity_cd / ((lamp.position - d3(given[0])).length_squared() + lamp.radius_m.powi(2));
            points.push(given);
            cpu.push([l.x, l.y, l.z, e / unit]);
            beams.push(full / unit);
        }
    }
    let resources = Resources { frame: Some(&frame), ..Resources::default() };
    let gpu = gpu(Twin::LampLight, &points, resources);
    assert_close("lamp_light's direction", &gpu, &cpu, 3, 1e-5);
    // The irradiance to 1e-5 of itself where the beam is full; on a spot's edge the smoothstep's slope (1/8 per
    // degree at most here) turns the GPU's acos (llvmpipe's, good to about 1e-4 rad) into up to 1e-3 of the beam's
    // full irradiance there.
    for (i, ((g, c), full)) in gpu.iter().zip(&cpu).zip(&beams).enumerate() {
        let off = (f64::from(g[3]) - c[3]).abs();
        assert!(off <= 1e-5 * c[3] + 1e-3 * full, "lamp_light, point {i}: GPU {} vs CPU {} (full {full})", g[3], c[3]);
    }
    assert!(gpu.iter().zip(&cpu).any(|(g, c)| g[3] == 0.0 && c[3] == 0.0), "some points lie outside the beam");
    let lit = cpu[40..].iter().filter(|c| c[3] > 0.0).count();
    assert!(lit >= 20, "and some inside it: {lit} of 81");
}

#[test]
fn a_lamps_coherence_and_the_widened_read_are_their_twins() {
    use crate::light::lamp::{widen_steps, widening_variance, Lamp};
    // A lamp's coherence from near its disc (clamped at 1 µm) to far beyond it.
    let lamp = Lamp { position: DVec3::new(0.2, 1.0, -0.4), intensity_cd: 10.0, radius_m: 0.01, spot: None };
    let uniforms = crate::light::lamp::LampUniforms::new(&[lamp], 1.0);
    let frame = SurfaceUniforms { lamp_count: uniforms.count, lamps: uniforms.lamps, ..bytemuck::Zeroable::zeroed() };
    let resources = Resources { frame: Some(&frame), ..Resources::default() };
    let points: Vec<Point> =
        [1e-4, 0.003, 0.01, 0.1, 0.5, 1.0, 3.0, 30.0].map(|d| point(&[v4(lamp.position - DVec3::Y * d, 0.0)])).to_vec();
    let cpu: Vec<[f64; 4]> = points.iter().map(|p| [lamp.coherence_at(d3(p[0])), 0.0, 0.0, 0.0]).collect();
    // llvmpipe's atan is good to a few 1e-5.
    assert_close("lamp_coherence_um", &gpu(Twin::LampCoherence, &points, resources), &cpu, 1, 1e-4);
    assert!(cpu[0][0] == 1.0 && (cpu[5][0] - 65.0 * 0.2666 / 0.5729).abs() < 0.1, "{cpu:?}");
    // The widening from lamps far shorter than the material's to its own, and none from a longer one.
    let lengths: Vec<[f32; 2]> = [(1.0, 65.0), (17.3, 65.0), (64.9, 65.0), (65.0, 65.0), (120.0, 65.0), (5.0, 20.0)]
        .map(|(l, m)| [l as f32, m as f32])
        .to_vec();
    let points: Vec<Point> = lengths.iter().map(|l| point(&[[l[0], l[1], 0.0, 0.0]])).collect();
    let cpu: Vec<[f64; 4]> =
        lengths.iter().map(|l| [widening_variance(l[0].into(), l[1].into()), 0.0, 0.0, 0.0]).collect();
    assert_close("widening_variance", &gpu(Twin::WideningVariance, &points, Resources::default()), &cpu, 1, 1e-6);
    assert!(cpu[3][0] == 0.0 && cpu[4][0] == 0.0 && cpu[1][0] > 0.0);
    // Steps of every shape (a pixel's, elongated, turned, zero) widened by variances small and large beside them.
    let mut rng = fastrand::Rng::with_seed(5);
    let mut cases: Vec<([f32; 4], f32)> =
        vec![([0.0; 4], 1e-4), ([0.01, 0.0, 0.0, 0.01], 0.0), ([0.02, 0.0, 0.0, 0.0], 1e-5)];
    for _ in 0..60 {
        let s = [rng.f32() - 0.5, rng.f32() - 0.5, rng.f32() - 0.5, rng.f32() - 0.5].map(|x| x * 0.1);
        cases.push((s, 10f32.powf(-7.0 + 5.0 * rng.f32())));
    }
    let points: Vec<Point> = cases.iter().map(|(s, v)| point(&[*s, [*v, 0.0, 0.0, 0.0]])).collect();
    let gpu_steps = gpu(Twin::WidenSteps, &points, Resources::default());
    for (i, ((s, v), g)) in cases.iter().zip(&gpu_steps).enumerate() {
        let c = widen_steps(s.map(f64::from), f64::from(*v));
        // The footprint is its covariance: compare a·aᵀ + b·bᵀ (the axes' signs and order are free).
        let cov = |x: [f64; 4]| [x[0] * x[0] + x[2] * x[2], x[0] * x[1] + x[2] * x[3], x[1] * x[1] + x[3] * x[3]];
        let (gc, cc) = (cov(g.map(f64::from)), cov(c));
        let scale = cc[0].abs().max(cc[2].abs()).max(1e-12);
        assert!(gc.iter().zip(&cc).all(|(a, b)| (a - b).abs() <= 1e-4 * scale), "point {i}: GPU {gc:?} vs CPU {cc:?}");
        // And the widening adds 12·v to each of the covariance's two diagonal terms.
        let trace = |x: [f64; 3]| x[0] + x[2];
        let before = cov(s.map(f64::from));
        assert!((trace(cc) - trace(before) - 24.0 * f64::from(*v)).abs() <= 1e-9 + 1e-6 * trace(cc), "point {i}");
    }
}
