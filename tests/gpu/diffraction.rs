//! Diffraction shading on the GPU against the CPU reference and against closed forms.

use diffract::material::{Approach, Settings};
use diffract::material::{Material, Reach};
use diffract::physics::baked::sample::{MipFilter, TableMips};
use diffract::physics::coherence::CoherenceWindow;
use diffract::physics::colour::xyz_to_linear_srgb;
use diffract::physics::exact::{Method, Query, Reference};
use diffract::physics::formats::png::PngScale;
use diffract::physics::heightfield::HeightField;
use diffract::physics::optics::{direction, gain_factor, shadow_mask};
use diffract::physics::spectrum::Sampling;
use diffract::render::diffraction::evaluate_brdf;
use diffract::render::map::{render_map, render_map_with, MapImage, MapShader, MapSpec};
use glam::DVec3;

use crate::golden;
use crate::harness::gpu_test;

/// A blazed grating: h = H·frac(x/d), `rows` identical rows.
pub fn blazed(period_px: usize, periods: usize, rows: usize, dx_um: f64, h_um: f64) -> HeightField {
    let n = period_px * periods;
    let h = (0..n * rows).map(|i| h_um * ((i % n) % period_px) as f64 / period_px as f64).collect();
    HeightField::new(n, rows, dx_um, dx_um, h).unwrap()
}

fn elaphe(tile: usize) -> HeightField {
    let scale = PngScale { pixel_size_um: 0.065, height_um: 0.375 };
    diffract::physics::formats::load(&crate::harness::place::afm("elaphe-100px.png"), Some(scale))
        .unwrap()
        .tiled(tile, tile)
        .unwrap()
}

fn flat(n: usize, dx_um: f64) -> HeightField {
    HeightField::new(n, n, dx_um, dx_um, vec![0.1; n * n]).unwrap()
}

/// ω_r of map pixel (x, y), as glsl/map.frag.glsl computes it.
fn map_direction(size: u32, x: u32, y: u32) -> Option<DVec3> {
    let half = f64::from(size) / 2.0;
    let (px, py) = ((f64::from(x) + 0.5 - half) / half, -((f64::from(y) + 0.5 - half) / half));
    let r2 = px * px + py * py;
    (r2 < 1.0).then(|| DVec3::new(px, py, (1.0 - r2).sqrt()))
}

fn map(hf: &HeightField, settings: Settings, size: u32, light: DVec3) -> (Material, MapImage) {
    let material = Material::prepare(hf, settings, &Reach::Map { light, size, filtered: false }).unwrap();
    let image = gpu_test(|ctx| render_map(ctx, &material, size, light, false).unwrap());
    assert_eq!(image.non_finite(), 0);
    (material, image)
}

#[test]
fn gpu_power_matches_the_cpu_taylor_sum() {
    // Elaphe diffracts along y, the blazed grating along x: light and views in those planes.
    for (hf, theta_i, phi_i, phi_r) in
        [(elaphe(3), 20.0, 270.0, 90.0), (blazed(50, 26, 4, 0.05, 0.25), 30.0, 0.0, 180.0)]
    {
        let queries: Vec<Query> = [450.0, 550.0, 650.0]
            .iter()
            .flat_map(|&lambda_nm| {
                (0..400).map(move |i| Query { lambda_nm, theta_i, phi_i, theta_r: i as f64 * 0.2, phi_r })
            })
            .collect();
        let (lx, ly) = hf.size_um();
        let window = CoherenceWindow::new(lx, ly, 65.0, None).unwrap();
        let plan = Reference::plan_for(&hf, &window, &queries, 1e-4, None).unwrap();
        let cpu = Reference::new(&hf, window, Method::Taylor, Some(plan)).unwrap().evaluate(&queries).unwrap();
        let radius = window.radius_x.max(window.radius_y) as u32;
        let settings = Settings { order: Some(plan.order), window_radius: Some(radius), ..Settings::default() };
        let material = Material::prepare(&hf, settings, &Reach::ANY).unwrap();
        let gpu = gpu_test(|ctx| evaluate_brdf(ctx, &material, &queries).unwrap());
        let mut compared = 0;
        for (c, (power, reflectance)) in cpu.iter().zip(&gpu) {
            if c.power > 1e-4 {
                compared += 1;
                let rel = (power - c.power).abs() / c.power;
                assert!(rel < 1e-3, "{:?}: GPU {power} vs CPU {} ({rel:.1e})", c.query, c.power);
                assert!((reflectance - c.reflectance).abs() / c.reflectance < 1e-3);
            }
        }
        assert!(compared > 50, "only {compared} samples above 1e-4");
    }
}

#[test]
fn flat_patch_map_is_white_at_specular_and_black_elsewhere() {
    let size = 65;
    let centre = size / 2;
    for approach in Approach::ALL {
        let (_, image) = map(&flat(64, 0.1), Settings { approach, ..Settings::default() }, size, DVec3::Z);
        let white = image.pixel(centre, centre);
        let mean = (white.x + white.y + white.z) / 3.0;
        assert!((mean - 1.0).abs() < 0.01, "{approach:?}: specular {white}");
        for c in white.to_array() {
            assert!((c - mean).abs() / mean < 0.01, "{approach:?}: specular {white} is not D65 white");
        }
        // Everything two or more pixels from specular is black (PQ's finite number of periods leaves sidelobes).
        let limit = if approach == Approach::Pq { 1e-2 } else { 1e-6 };
        for y in 0..size {
            for x in 0..size {
                if x.abs_diff(centre).max(y.abs_diff(centre)) >= 2 {
                    let p = image.pixel(x, y);
                    assert!(p.max_element() < limit, "{approach:?}: pixel ({x}, {y}) is {p}");
                }
            }
        }
    }
}

/// The positions (sin θ_r along +x or −x) where the blue and the red channel of the first order peak.
fn first_order_peaks(image: &MapImage, side: f64) -> (f64, f64) {
    let size = image.size;
    let row = size / 2;
    let mut blue = (0.0, 0.0);
    let mut red = (0.0, 0.0);
    for x in 0..size {
        let s = (f64::from(x) + 0.5 - f64::from(size) / 2.0) / (f64::from(size) / 2.0) * side;
        // The first order of a 2.5 µm grating at normal incidence spans sin θ = 0.38/2.5 .. 0.78/2.5.
        if !(0.14..=0.30).contains(&s) {
            continue;
        }
        let p = image.pixel(x, row);
        if p.z > blue.1 {
            blue = (s, p.z);
        }
        if p.x > red.1 {
            red = (s, p.x);
        }
    }
    (blue.0, red.0)
}

#[test]
fn blazed_map_shows_the_first_order_spectrum_in_order() {
    let hf = blazed(50, 26, 4, 0.05, 0.25);
    for approach in [Approach::Flss, Approach::Nmm, Approach::Pq, Approach::Baked] {
        let settings = Settings { approach, lambda_step_nm: 5.0, ..Settings::default() };
        let (_, image) = map(&hf, settings, 129, DVec3::Z);
        let row_energy = |side: f64| {
            (0..129)
                .filter(|&x| (f64::from(x) - 64.0) * side > 0.0)
                .map(|x| image.pixel(x, 64).element_sum())
                .sum::<f64>()
        };
        let side = if row_energy(1.0) > row_energy(-1.0) { 1.0 } else { -1.0 };
        let (blue, red) = first_order_peaks(&image, side);
        assert!(blue > 0.0 && red > 0.0, "{approach:?}: no first order ({blue}, {red})");
        assert!(blue < red, "{approach:?}: blue at sin θ = {blue} should be nearer the centre than red at {red}");
        // Nothing along the perpendicular axis, away from specular (PQ's hard-edged period window leaves
        // sinc sidelobes, below one 8-bit step of sRGB).
        let limit = if approach == Approach::Pq { 1e-4 } else { 1e-6 };
        for y in (0..129u32).filter(|y| y.abs_diff(64) >= 3) {
            let p = image.pixel(64, y);
            assert!(p.max_element() < limit, "{approach:?}: light along y at row {y}: {p}");
        }
    }
}

#[test]
fn baked_map_pixels_are_the_tables_values_read_as_the_cpu_twin_reads_them() {
    // The GPU's reads, LOD and Chebyshev sum against `BakedTable::xyz_filtered` (the shader's CPU twin), at the
    // table's finest level (pixel centres are texel centres) and filtered over each pixel's footprint, between the
    // mip levels (trilinear) and from the nearest one; with w in one segment and in two or three (each read from
    // its own layers, the segment chosen per pixel).
    let hf = elaphe(3);
    let light = direction(20.0, 0.0);
    let size = 49;
    let cases = [
        (false, TableMips::Linear, 1),
        (true, TableMips::Linear, 1),
        (true, TableMips::Nearest, 1),
        (false, TableMips::Linear, 2),
        (true, TableMips::Nearest, 3),
    ];
    for (footprint, table_mips, segments) in cases {
        let filter = table_mips.filter(true);
        let table_segments = Some(segments);
        let settings = Settings { approach: Approach::Baked, table_mips, table_segments, ..Settings::default() };
        let material = Material::prepare(&hf, settings, &Reach::Map { light, size, filtered: footprint }).unwrap();
        assert_eq!(material.table.as_ref().unwrap().grid.segments, segments);
        let (image, bits) = gpu_test(|ctx| {
            let limits = &ctx.info.limits;
            let bits = (limits.sub_texel_precision_bits, limits.mipmap_precision_bits);
            (render_map(ctx, &material, size, light, footprint).unwrap(), bits)
        });
        let table = material.table.as_ref().unwrap();
        let lod = if footprint { table.lod(2.0 / f64::from(size)) } else { 0.0 };
        assert!(!footprint || lod > 0.5, "the footprint of a {size}² map spans several texels: lod {lod}");
        // A LOD halfway between two levels may round either way to the nearest one: this one is not.
        assert!((lod.fract() - 0.5).abs() > 0.05, "lod {lod}");
        let mut compared = 0;
        for y in 0..size {
            for x in 0..size {
                let Some(omega_r) = map_direction(size, x, y) else { continue };
                let g = gain_factor(light, omega_r) * shadow_mask(light, omega_r);
                let uvw = -light - omega_r;
                let srgb = |uvw: DVec3, lod: f64| xyz_to_linear_srgb(table.xyz_filtered(uvw, lod, filter) * g);
                let cpu = srgb(uvw, lod);
                let gpu = image.pixel(x, y);
                // A device computes the filter's weights in fixed point (the two axes' each): the bilinear weights to
                // `subTexelPrecisionBits` and the blend of two mip levels to `mipmapPrecisionBits` (Vulkan's limits;
                // lavapipe 8 and 4, an H100 8 and 8, rounded its own way). A weight off by one step 2^-bits moves
                // the colour by that much of the difference it weighs: between the two levels, or between a texel
                // and its neighbours (one texel of the level away along u or v).
                let slack_at = |level: f64, bits: u32| {
                    let texel = table.grid.texel * level.exp2();
                    let centre = srgb(uvw, level);
                    let contrast = [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
                        .map(|(du, dv)| {
                            (srgb(uvw + DVec3::new(du, dv, 0.0) * texel, level) - centre).abs().max_element()
                        })
                        .into_iter()
                        .fold(0.0, f64::max);
                    2.0 * contrast * 0.5f64.powi(bits as i32)
                };
                let (lo, hi) = match filter {
                    MipFilter::Linear => (lod.floor(), (lod.floor() + 1.0).min(lod.ceil())),
                    MipFilter::Nearest => (lod.round(), lod.round()),
                };
                let between_levels = (srgb(uvw, lo) - srgb(uvw, hi)).abs().max_element();
                let slack =
                    slack_at(lo, bits.0).max(slack_at(hi, bits.0)) + between_levels * 0.5f64.powi(bits.1 as i32);
                let scale = cpu.abs().max_element();
                let err = (gpu - cpu).abs().max_element();
                if scale > 1e-4 {
                    compared += 1;
                    assert!(
                        err < 2e-3 * scale + slack,
                        "footprint {footprint}, {filter:?}, pixel ({x}, {y}): GPU {gpu} vs CPU {cpu} (slack {slack:.2e}, \
                         bits {bits:?})"
                    );
                } else {
                    assert!(gpu.abs().max_element() < 2e-4 + slack, "pixel ({x}, {y}): GPU {gpu} vs CPU {cpu}");
                }
            }
        }
        assert!(compared > 30, "{compared}");
    }
}

#[test]
fn map_pixels_match_the_cpu_colour_reference() {
    let hf = elaphe(3);
    let light = direction(20.0, 0.0);
    let settings = Settings { lambda_step_nm: 10.0, ..Settings::default() };
    let (material, image) = map(&hf, settings, 49, light);
    let plan = material.plan.unwrap();
    let reference = Reference::new(&hf, material.window, Method::Taylor, Some(plan)).unwrap();
    let sampling: Sampling = material.sampling;
    let mut compared = 0;
    for y in 0..49 {
        for x in 0..49 {
            let Some(omega_r) = map_direction(49, x, y) else { continue };
            let cpu = xyz_to_linear_srgb(reference.flss_xyz(light, omega_r, &sampling));
            let gpu = image.pixel(x, y);
            let scale = cpu.abs().max_element();
            if scale > 1e-4 {
                compared += 1;
                assert!((gpu - cpu).abs().max_element() / scale < 2e-3, "pixel ({x}, {y}): GPU {gpu} vs CPU {cpu}");
            } else {
                assert!(gpu.abs().max_element() < 2e-4, "pixel ({x}, {y}): GPU {gpu} vs CPU {cpu}");
            }
        }
    }
    assert!(compared > 30, "{compared}");
}

#[test]
fn compute_and_fragment_maps_are_the_same_pixels() {
    // `diffract map` and the profiler draw maps with a compute shader, the viewer with a full-screen triangle: the
    // two run the same per-pixel code (glsl/include/map_pixel.glsl), so every approach's pixels agree to f32
    // rounding, point-sampled and over each pixel's footprint, on a map that is not a multiple of the
    // workgroup's 8 pixels and spans two bands of rows.
    let hf = elaphe(2);
    let light = direction(25.0, 10.0);
    let size = 45;
    for approach in Approach::ALL {
        for footprint in [false, true] {
            let settings = Settings { approach, lambda_step_nm: 10.0, coherence_um: 8.0, ..Settings::default() };
            let reach = Reach::Map { light, size, filtered: footprint };
            let material = Material::prepare(&hf, settings, &reach).unwrap();
            let [compute, fragment] = [MapShader::Compute, MapShader::Fragment].map(|shader| {
                let spec = MapSpec { material: &material, size, light, footprint, shader };
                gpu_test(|ctx| render_map_with(ctx, &spec).unwrap())
            });
            let peak = fragment.rgba.iter().fold(0.0f32, |m, &v| m.max(v.abs()));
            assert!(peak > 0.0, "{approach:?}: a black map");
            let worst = compute.rgba.iter().zip(&fragment.rgba).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
            assert!(worst <= 1e-5 * peak, "{approach:?}, footprint {footprint}: differ by {worst} (peak {peak})");
        }
    }
}

#[test]
fn golden_maps_per_approach() {
    // An 8 µm coherence length widens every order to about a pixel at this size, so the golden images hold
    // smooth colour rather than a few undersampled dots.
    let hf = elaphe(2);
    let light = direction(15.0, 0.0);
    for approach in Approach::ALL {
        let settings = Settings { approach, lambda_step_nm: 10.0, coherence_um: 8.0, ..Settings::default() };
        let (_, image) = map(&hf, settings, 48, light);
        golden::check(
            &format!("map_elaphe_{}_48", approach.name()),
            48,
            48,
            &image.to_rgba8(3.0, diffract::display::Tone::Clip),
        );
    }
}
