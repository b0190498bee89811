//! The sun in an environment map, found by its energy (model.md §3.12, "A map's own sun"): about the brightest
//! texel a cap of [`cap_radius`] and a ring as wide beyond it; the sun is the cap's light above the ring's mean
//! (its irradiance, the centroid of the excess as its direction, the disc with the excess's second moment as its
//! size), and it is a sun where it holds at least [`MIN_SHARE`] of the irradiance the whole map gives a surface
//! facing it. Taking it out fills the cap with the ring's mean, which removes exactly the light the sun is given;
//! a second compact sun in what remains is reported and left in the map.

use glam::DVec3;

use crate::light::environment::{direction_at, texel_solid_angle, EnvironmentMap};
use crate::physics::colour::luminance;

/// The smallest share of the irradiance on a surface facing it that makes a compact cap a sun.
pub const MIN_SHARE: f64 = 0.25;
/// The smallest cap around a sun, degrees: its disc, its aureole, and the texels a camera's optics spread it over.
pub const MIN_CAP_DEG: f64 = 2.5;
/// The widest cap a sun is looked for in, degrees: a photographed sun with its glare and bloom is often 1–3°
/// across, and its cap must hold it whole wherever in it the brightest texel lies.
pub const MAX_CAP_DEG: f64 = 12.0;
/// How much wider each cap tried is than the one before.
const CAP_STEP: f64 = 1.5;
/// A wider cap is taken where it adds more than this share to the sun's light (its ring still held some of it):
/// a disc the cap cut adds tens of percent; a photographed sun's aureole, a few (at 0.5 % the Polyhaven map's
/// sun grew from 1.6° to 3.1° across, 74 % to 78 % of the light, and moved 0.07°).
const CAP_GROWTH: f64 = 0.05;

/// A sun found in a map, in the map's own frame (before any turn) and units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoundSun {
    /// Unit vector towards it (+y up, the map's layout).
    pub direction: DVec3,
    /// Its irradiance on a surface facing it, linear RGB in the map's radiance units times sr.
    pub irradiance: DVec3,
    /// Its share of the irradiance the whole map gives a surface facing it (luminance).
    pub share: f64,
    /// The angular radius of a uniform disc with the excess light's spread, rad (an upper bound where the texels
    /// are coarser than the disc).
    pub angular_radius: f64,
    /// The cap's centre (the brightest texel's), its radius (rad) and its texels.
    pub cap_centre: DVec3,
    pub cap_radius: f64,
    pub cap_texels: usize,
    /// A texel's width at the map's equator, rad.
    pub texel: f64,
}

impl FoundSun {
    /// Its luminance irradiance (Y of [`Self::irradiance`]), in the map's luminance units times sr.
    pub fn illuminance(&self) -> f64 {
        luminance(self.irradiance)
    }

    /// Its elevation and azimuth in degrees (the map's layout: azimuth 0 along +z, 90 along +x).
    pub fn elevation_azimuth_deg(&self) -> (f64, f64) {
        let d = self.direction;
        (d.y.clamp(-1.0, 1.0).asin().to_degrees(), d.x.atan2(d.z).to_degrees())
    }

    /// One line: where it is, its share of the light and its size.
    pub fn describe(&self) -> String {
        let (elevation, azimuth) = self.elevation_azimuth_deg();
        let size = if self.angular_radius >= self.texel {
            format!("about {:.2}° across", 2.0 * self.angular_radius.to_degrees())
        } else {
            format!("within a texel ({:.3}°: its size is not resolved)", self.texel.to_degrees())
        };
        format!(
            "a sun at {elevation:.2}° elevation, {azimuth:.2}° azimuth holding {:.0} % of the irradiance on a surface \
             facing it, {size}",
            self.share * 100.0
        )
    }
}

/// What a search found: the sun (if any), the map without it, and a second compact sun left in that (if any).
#[derive(Clone, Debug, PartialEq)]
pub struct SunSearch {
    pub sun: Option<FoundSun>,
    /// The map with the sun taken out ([`without`]), where there is one.
    pub rest: Option<TakenOut>,
    pub second: Option<FoundSun>,
}

/// A map with its sun taken out, and the texels that held it as they were (index, radiance).
#[derive(Clone, Debug, PartialEq)]
pub struct TakenOut {
    pub map: EnvironmentMap,
    pub texels: Vec<(usize, [f32; 3])>,
}

fn rgb_at(map: &EnvironmentMap, i: usize) -> DVec3 {
    DVec3::from(map.rgb[i].map(f64::from))
}

/// The cap's angular radius for a map `width` texels wide, rad: [`MIN_CAP_DEG`], or 1.5 texels where they are
/// wider.
pub fn cap_radius(width: u32) -> f64 {
    let texel = 360.0 / f64::from(width);
    MIN_CAP_DEG.max(1.5 * texel).to_radians()
}

/// The texels within `radius` of `centre`: (index, direction, solid angle).
fn texels_within(map: &EnvironmentMap, centre: DVec3, radius: f64) -> Vec<(usize, DVec3, f64)> {
    let (w, h) = (map.width, map.height);
    let elevation = centre.y.clamp(-1.0, 1.0).asin();
    let azimuth = centre.x.atan2(centre.z);
    let per_row = f64::from(h) / std::f64::consts::PI;
    // Rows whose band meets [elevation − radius, elevation + radius] (one texel of margin).
    let top = ((std::f64::consts::FRAC_PI_2 - (elevation + radius)) * per_row).floor() - 1.0;
    let bottom = ((std::f64::consts::FRAC_PI_2 - (elevation - radius)) * per_row).ceil() + 1.0;
    let (top, bottom) = (top.max(0.0) as u32, (bottom.max(0.0) as u32).min(h - 1));
    let cos_radius = radius.cos();
    let mut out = Vec::new();
    for row in top..=bottom {
        let omega = texel_solid_angle(row, w);
        let row_elevation = std::f64::consts::FRAC_PI_2 - (f64::from(row) + 0.5) / per_row;
        // The azimuths within reach on this row (all of them near a pole).
        let (lo, hi) = {
            let c = row_elevation.cos().min(elevation.cos());
            let span = if c < 1e-6 || radius / c >= std::f64::consts::PI {
                std::f64::consts::PI
            } else {
                (radius / c).min(std::f64::consts::PI)
            };
            let per_col = f64::from(w) / std::f64::consts::TAU;
            let centre_col = (azimuth + std::f64::consts::PI) * per_col;
            ((centre_col - span * per_col).floor() as i64 - 1, (centre_col + span * per_col).ceil() as i64 + 1)
        };
        let cols = if hi - lo >= i64::from(w) { 0..i64::from(w) } else { lo..hi + 1 };
        for col in cols {
            let x = col.rem_euclid(i64::from(w)) as u32;
            let dir = direction_at(f64::from(x) + 0.5, f64::from(row) + 0.5, w);
            if dir.dot(centre) >= cos_radius {
                out.push(((row * w + x) as usize, dir, omega));
            }
        }
    }
    out.sort_unstable_by_key(|t| t.0);
    out.dedup_by_key(|t| t.0);
    out
}

/// The luminance irradiance the whole of `map` gives a surface facing `normal` (every texel at its centre): rows
/// in parallel, each texel's cosine from its row's and column's sines and cosines.
pub fn facing_irradiance(map: &EnvironmentMap, normal: DVec3) -> f64 {
    use rayon::prelude::*;
    let w = map.width;
    let columns: Vec<(f64, f64)> = (0..w)
        .map(|x| ((f64::from(x) + 0.5) / f64::from(w) * std::f64::consts::TAU - std::f64::consts::PI).sin_cos())
        .collect();
    (0..map.height)
        .into_par_iter()
        .map(|row| {
            let elevation =
                std::f64::consts::FRAC_PI_2 - (f64::from(row) + 0.5) / f64::from(map.height) * std::f64::consts::PI;
            let (sin_e, cos_e) = elevation.sin_cos();
            let texels = &map.rgb[(row * w) as usize..((row + 1) * w) as usize];
            let sum: f64 = texels
                .iter()
                .zip(&columns)
                .map(|(c, &(sin_a, cos_a))| {
                    let cos = cos_e * (sin_a * normal.x + cos_a * normal.z) + sin_e * normal.y;
                    if cos > 0.0 {
                        crate::physics::spectrum::luminance(*c) * cos
                    } else {
                        0.0
                    }
                })
                .sum();
            sum * texel_solid_angle(row, w)
        })
        .sum()
}

/// The cap of `radius` about `centre` and the mean radiance of the ring of the same width around it.
fn cap_and_background(map: &EnvironmentMap, centre: DVec3, radius: f64) -> (Vec<(usize, DVec3, f64)>, DVec3) {
    let cap = texels_within(map, centre, radius);
    let ring: Vec<_> =
        texels_within(map, centre, 2.0 * radius).into_iter().filter(|(_, d, _)| d.dot(centre) < radius.cos()).collect();
    let ring_area: f64 = ring.iter().map(|t| t.2).sum();
    let background = if ring_area > 0.0 {
        ring.iter().map(|&(i, _, omega)| rgb_at(map, i) * omega).sum::<DVec3>() / ring_area
    } else {
        DVec3::ZERO
    };
    (cap, background)
}

/// A cap's light above the mean of the ring around it.
struct Cap {
    /// On a surface facing it, linear RGB in the map's units times sr.
    irradiance: DVec3,
    /// Towards the centroid of the excess.
    direction: DVec3,
    /// The cap's texels (index, direction, solid angle) and the ring's mean radiance.
    texels: Vec<(usize, DVec3, f64)>,
    background: DVec3,
}

/// The light of a cap of `radius` about `centre` above the mean of the ring around it; None where it has none.
fn excess(map: &EnvironmentMap, centre: DVec3, radius: f64) -> Option<Cap> {
    let (texels, background) = cap_and_background(map, centre, radius);
    let mut irradiance = DVec3::ZERO;
    let mut centroid = DVec3::ZERO;
    for &(i, dir, omega) in &texels {
        let excess = rgb_at(map, i) - background;
        irradiance += excess * omega;
        centroid += dir * (luminance(excess).max(0.0) * omega);
    }
    Some(Cap { irradiance, direction: centroid.try_normalize()?, texels, background })
}

/// The sun of `map` around its brightest texel; None where the cap's light is not a sun. The cap starts at
/// [`cap_radius`] and, centred each time on the light it found, grows by half until the sun's light stops
/// growing (by less than [`CAP_GROWTH`]): a photographed sun with its glare, or a disc wider than the first cap,
/// is taken whole, where a first cap cut it and its ring counted the rest as sky.
fn sun_at_brightest(map: &EnvironmentMap) -> Option<FoundSun> {
    use rayon::prelude::*;
    let (brightest, _) = map
        .rgb
        .par_iter()
        .enumerate()
        .map(|(i, c)| (i, luminance(DVec3::from(c.map(f64::from)))))
        .filter(|(_, y)| y.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let mut centre = direction_at(
        f64::from(brightest as u32 % map.width) + 0.5,
        f64::from(brightest as u32 / map.width) + 0.5,
        map.width,
    );
    let mut radius = cap_radius(map.width);
    let mut cap = excess(map, centre, radius)?;
    while radius * CAP_STEP <= MAX_CAP_DEG.to_radians() {
        let Some(wider) = excess(map, cap.direction, radius * CAP_STEP) else { break };
        if luminance(wider.irradiance) <= luminance(cap.irradiance) * (1.0 + CAP_GROWTH) {
            break;
        }
        (centre, radius) = (cap.direction, radius * CAP_STEP);
        cap = wider;
    }
    // The final cap centred on the sun itself (the brightest texel of a uniform disc may lie at its edge).
    if radius > cap_radius(map.width) {
        centre = cap.direction;
        cap = excess(map, centre, radius)?;
    }
    let (irradiance, direction) = (cap.irradiance.max(DVec3::ZERO), cap.direction);
    // The second moment of the excess about its centroid: a uniform disc of radius ρ has ⟨α²⟩ = ρ²/2.
    let (mut spread, mut weight) = (0.0, 0.0);
    for &(i, dir, omega) in &cap.texels {
        let w = luminance(rgb_at(map, i) - cap.background).max(0.0) * omega;
        spread += w * dir.dot(direction).clamp(-1.0, 1.0).acos().powi(2);
        weight += w;
    }
    let total = facing_irradiance(map, direction);
    let share = if total > 0.0 { luminance(irradiance) / total } else { 0.0 };
    let sun = FoundSun {
        direction,
        irradiance,
        share,
        angular_radius: if weight > 0.0 { (2.0 * spread / weight).sqrt() } else { 0.0 },
        cap_centre: centre,
        cap_radius: radius,
        cap_texels: cap.texels.len(),
        texel: std::f64::consts::TAU / f64::from(map.width),
    };
    (share >= MIN_SHARE && luminance(irradiance) > 0.0).then_some(sun)
}

/// Searches `map` for its sun, takes it out, and searches what remains for a second one.
pub fn find(map: &EnvironmentMap) -> SunSearch {
    let Some(sun) = sun_at_brightest(map) else { return SunSearch { sun: None, rest: None, second: None } };
    let rest = without(map, &sun);
    let second = sun_at_brightest(&rest.map);
    SunSearch { sun: Some(sun), rest: Some(rest), second }
}

/// `map` with `sun` taken out: its cap filled with the mean of the ring around it (what the sun's light was
/// measured above), so that the light removed is the sun's irradiance; and the cap's texels as they were.
pub fn without(map: &EnvironmentMap, sun: &FoundSun) -> TakenOut {
    let (cap, background) = cap_and_background(map, sun.cap_centre, sun.cap_radius);
    let mut out = map.clone();
    let fill = background.max(DVec3::ZERO).as_vec3().to_array();
    let texels = cap.iter().map(|&(i, _, _)| (i, std::mem::replace(&mut out.rgb[i], fill))).collect();
    TakenOut { map: out, texels }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::optics::SUN_SOLID_ANGLE;

    /// A relative-unit sky (radiance ~1, brighter towards the zenith and round the sun) with a sun of known
    /// direction and irradiance spread over the texels its disc covers, at `width`.
    fn sky_with_sun(width: u32, sun: DVec3, sun_irradiance: f64) -> EnvironmentMap {
        let sky = |dir: DVec3| {
            if dir.y > 0.0 {
                DVec3::new(0.6, 0.8, 1.0) * (0.5 + dir.y) + DVec3::splat(0.3 * dir.dot(sun).max(0.0).powi(8))
            } else {
                DVec3::splat(0.15)
            }
        };
        sky_with_disc(width, &sky, (sun, crate::physics::sky::sun_angular_radius()), sun_irradiance)
    }

    /// `sky` at every texel's centre, and a uniform disc of angular `radius` (rad) about `sun` whose irradiance on
    /// a surface facing it is `sun_irradiance`, spread over the texels it covers by sub-samples.
    pub(crate) fn sky_with_disc(
        width: u32,
        sky: &dyn Fn(DVec3) -> DVec3,
        (sun, radius): (DVec3, f64),
        sun_irradiance: f64,
    ) -> EnvironmentMap {
        let height = width / 2;
        let sub = 8u32;
        let mut rgb = Vec::with_capacity((width * height) as usize);
        for row in 0..height {
            for x in 0..width {
                let dir = direction_at(f64::from(x) + 0.5, f64::from(row) + 0.5, width);
                rgb.push(sky(dir).as_vec3().to_array());
            }
        }
        // The disc's coverage of each texel by sub-samples (exact in the limit), its energy normalised to the
        // requested irradiance.
        let mut cover = Vec::new();
        let mut total = 0.0;
        for i in texels_within(
            &EnvironmentMap { width, height, rgb: rgb.clone() },
            sun,
            radius + 3.0 * std::f64::consts::PI / f64::from(width),
        ) {
            let (x, row) = (i.0 as u32 % width, i.0 as u32 / width);
            let inside = (0..sub * sub)
                .filter(|k| {
                    let (sx, sy) = (f64::from(k % sub) + 0.5, f64::from(k / sub) + 0.5);
                    direction_at(f64::from(x) + sx / f64::from(sub), f64::from(row) + sy / f64::from(sub), width)
                        .dot(sun)
                        >= radius.cos()
                })
                .count() as f64
                / f64::from(sub * sub);
            if inside > 0.0 {
                cover.push((i.0, inside * i.2));
                total += inside * i.2;
            }
        }
        if cover.is_empty() {
            let x = ((sun.x.atan2(sun.z) / std::f64::consts::TAU + 0.5) * f64::from(width)) as u32;
            let row = ((0.5 - sun.y.asin() / std::f64::consts::PI) * f64::from(height)) as u32;
            let i = (row * width + x.min(width - 1)) as usize;
            cover.push((i, texel_solid_angle(row, width)));
            total = texel_solid_angle(row, width);
        }
        let sun_rgb = DVec3::new(1.0, 0.95, 0.85);
        let scale = sun_irradiance / luminance(sun_rgb);
        for (i, area) in cover {
            let omega = texel_solid_angle(i as u32 / width, width);
            let add = sun_rgb * (scale * area / total / omega);
            for (c, a) in rgb[i].iter_mut().zip(add.to_array()) {
                *c += a as f32;
            }
        }
        EnvironmentMap { width, height, rgb }
    }

    /// A sun of known direction and irradiance is found at 64, 512 and 4096 texels wide: its direction within
    /// half a texel, its irradiance within 2 %; taking it out removes that irradiance and leaves no sun.
    #[test]
    fn a_sun_of_known_direction_and_irradiance_is_found_at_every_size() {
        let sun = crate::physics::sky::direction(37.3, 61.7);
        // A relative sky (~1) with a sun 10⁵ times as bright per solid angle as the sky: ~7 units of irradiance.
        let e_sun = 1e5 * SUN_SOLID_ANGLE;
        for width in [64u32, 512, 4096] {
            let map = sky_with_sun(width, sun, e_sun);
            let search = find(&map);
            let found = search.sun.unwrap_or_else(|| panic!("{width}: no sun"));
            let off = found.direction.dot(sun).clamp(-1.0, 1.0).acos();
            let texel = std::f64::consts::TAU / f64::from(width);
            let rel = found.illuminance() / e_sun - 1.0;
            eprintln!(
                "{width} wide: {} — off by {:.3} texel, irradiance {rel:+.4}, second: {:?}",
                found.describe(),
                off / texel,
                search.second.map(|s| s.share)
            );
            assert!(off < 0.5 * texel, "{width}: {:.3}°", off.to_degrees());
            assert!(rel.abs() < 0.02, "{width}: {rel}");
            assert!(search.second.is_none());
            let rest = without(&map, &found).map;
            let facing = |m: &EnvironmentMap| -> f64 {
                (0..m.rgb.len())
                    .map(|i| {
                        let (x, row) = (i as u32 % width, i as u32 / width);
                        let d = direction_at(f64::from(x) + 0.5, f64::from(row) + 0.5, width);
                        luminance(rgb_at(m, i)) * d.dot(found.direction).max(0.0) * texel_solid_angle(row, width)
                    })
                    .sum()
            };
            let removed = facing(&map) - facing(&rest);
            assert!((removed / found.illuminance() - 1.0).abs() < 1e-3, "{width}: removed {removed}");
            assert!(find(&rest).sun.is_none(), "{width}: a sun left");
        }
    }

    /// A uniform sky of 1 over a black ground, and a uniform disc of 0.5° to 3° radius holding 8 times the sky's
    /// light on a horizontal plane, 25° high at azimuth 120°, 1024 wide (issue 62's maps): the sun is taken whole,
    /// its direction within 0.05° and its irradiance within 1 %, and nothing of it is left in the map.
    #[test]
    fn a_large_sun_is_taken_whole() {
        let sun = crate::physics::sky::direction(25.0, 120.0);
        let uniform = |d: DVec3| if d.y > 0.0 { DVec3::ONE } else { DVec3::ZERO };
        // The sky's irradiance on a horizontal plane is π; the sun's on it E·sin 25°.
        let e_sun = 8.0 * std::f64::consts::PI / 25f64.to_radians().sin();
        for radius_deg in [0.5, 1.0, 1.5, 2.5, 3.0] {
            let map = sky_with_disc(1024, &uniform, (sun, f64::to_radians(radius_deg)), e_sun);
            let search = find(&map);
            let found = search.sun.unwrap_or_else(|| panic!("{radius_deg}°: no sun"));
            let off = found.direction.dot(sun).clamp(-1.0, 1.0).acos().to_degrees();
            let rel = found.illuminance() / e_sun - 1.0;
            eprintln!("{radius_deg}°: {} — {off:.4}° off, irradiance {rel:+.5}", found.describe());
            assert!(off < 0.05, "{radius_deg}°: {off}° off");
            assert!(rel.abs() < 0.01, "{radius_deg}°: irradiance {rel:+}");
            assert!((found.angular_radius.to_degrees() / radius_deg - 1.0).abs() < 0.1, "{radius_deg}°: {found:?}");
            assert!(search.second.is_none(), "{radius_deg}°: a second sun {:?}", search.second);
            let rest = search.rest.unwrap().map;
            let brightest = rest.rgb.iter().flatten().fold(0.0f32, |m, &c| m.max(c));
            assert!(brightest <= 1.0 + 1e-6, "{radius_deg}°: a texel of {brightest} left of the sun");
        }
    }

    /// The cost on the largest map a scene loads (8192×4096): printed, not asserted (the machine is shared).
    #[test]
    #[ignore = "a benchmark: cargo test --release --lib light::sun -- --ignored --nocapture"]
    fn the_search_on_an_8192_map_takes_under_a_second() {
        let map = sky_with_sun(8192, crate::physics::sky::direction(20.0, -40.0), 1e5 * SUN_SOLID_ANGLE);
        let mut times = Vec::new();
        for _ in 0..5 {
            let t = std::time::Instant::now();
            let search = find(&map);
            times.push(t.elapsed().as_secs_f64());
            assert!(search.sun.is_some());
        }
        times.sort_by(f64::total_cmp);
        eprintln!("sun search on 8192×4096: median {:.3} s of 5 (min {:.3})", times[2], times[0]);
    }

    /// An overcast map (bright towards the zenith, no compact sun) has none; of two suns the brighter is taken
    /// and the other reported.
    #[test]
    fn an_overcast_map_has_no_sun_and_of_two_the_brighter_is_taken() {
        let (width, height) = (256u32, 128u32);
        let overcast = EnvironmentMap {
            width,
            height,
            rgb: (0..width * height)
                .map(|i| {
                    let d = direction_at(f64::from(i % width) + 0.5, f64::from(i / width) + 0.5, width);
                    let l = if d.y > 0.0 { (1.0 + 2.0 * d.y) / 3.0 } else { 0.1 } as f32;
                    [l, l, l]
                })
                .collect(),
        };
        assert_eq!(find(&overcast), SunSearch { sun: None, rest: None, second: None });
        let (a, b) = (crate::physics::sky::direction(50.0, 0.0), crate::physics::sky::direction(20.0, 150.0));
        let one = sky_with_sun(width, a, 2e5 * SUN_SOLID_ANGLE);
        let two = sky_with_sun(width, b, 1.4e5 * SUN_SOLID_ANGLE);
        let both = EnvironmentMap {
            width,
            height,
            rgb: one.rgb.iter().zip(&two.rgb).map(|(p, q)| [0, 1, 2].map(|k| p[k] + q[k])).collect(),
        };
        let search = find(&both);
        let (first, second) = (search.sun.unwrap(), search.second.unwrap());
        assert!(first.direction.dot(a) > 0.999 && second.direction.dot(b) > 0.999, "{search:?}");
    }
}
