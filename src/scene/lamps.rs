//! The `[[lamp]]` entries checked and made [`Lamp`]s: a kind, a position, an intensity in candela, a disc's radius,
//! and a spot's axis, cone and soft edge. Every mistake names its line and what was expected.

use glam::DVec3;
use toml::Spanned;

use crate::error::Result;
use crate::gpu::interface::MAX_LAMPS;
use crate::light::lamp::{Lamp, Spot};
use crate::scene::checks::{check_coords, triple};
use crate::scene::file::{LampDef, Locator};

/// The brightest lamp a scene may hold, cd (a stadium floodlight's beam is about 10⁶).
pub const MAX_INTENSITY_CD: f64 = 1e9;
/// A lamp's disc when the scene gives no `radius_m`, m: a bulb 2 cm across.
pub const DEFAULT_RADIUS_M: f64 = 0.01;
/// The largest disc, m.
pub const MAX_RADIUS_M: f64 = 100.0;
/// A spot's cone and soft edge when the scene gives none, degrees.
pub const DEFAULT_CONE_DEG: f64 = 30.0;
pub const DEFAULT_SOFT_DEG: f64 = 5.0;

/// Every `[[lamp]]`, checked.
pub(super) fn lamps(loc: &Locator<'_>, defs: &[Spanned<LampDef>]) -> Result<Vec<Lamp>> {
    if let Some(extra) = defs.get(MAX_LAMPS as usize) {
        return Err(loc.at(extra.span(), format!("a scene holds at most {MAX_LAMPS} lamps")));
    }
    defs.iter().map(|d| lamp(loc, d.get_ref())).collect()
}

/// A number in `range` (its text for the message), or the line that says so for `what`.
fn within(loc: &Locator<'_>, v: &Spanned<f64>, what: &str, ok: bool, expected: &str) -> Result<f64> {
    match ok && v.get_ref().is_finite() {
        true => Ok(*v.get_ref()),
        false => Err(loc.at(v.span(), format!("{what} = {}: expected {expected}", crate::error::number(*v.get_ref())))),
    }
}

fn lamp(loc: &Locator<'_>, d: &LampDef) -> Result<Lamp> {
    check_coords(loc, d.position.span(), "[[lamp]] position", d.position.get_ref())?;
    let position = DVec3::from(*d.position.get_ref());
    let i = *d.intensity_cd.get_ref();
    let intensity_cd = within(
        loc,
        &d.intensity_cd,
        "intensity_cd",
        i > 0.0 && i <= MAX_INTENSITY_CD,
        &format!("a luminous intensity in candela above 0 and at most {MAX_INTENSITY_CD:e}"),
    )?;
    let radius_m = match &d.radius_m {
        Some(r) => within(
            loc,
            r,
            "radius_m",
            *r.get_ref() > 0.0 && *r.get_ref() <= MAX_RADIUS_M,
            &format!("the emitting disc's radius in metres, above 0 and at most {MAX_RADIUS_M}"),
        )?,
        None => DEFAULT_RADIUS_M,
    };
    let spot = match d.kind.get_ref().as_str() {
        "point" => {
            let spot_key = [d.cone_deg.as_ref().map(|c| c.span()), d.soft_deg.as_ref().map(|s| s.span())]
                .into_iter()
                .flatten()
                .chain(d.direction.as_ref().map(|x| x.span()))
                .next();
            if let Some(span) = spot_key {
                return Err(loc.at(span, "direction, cone_deg and soft_deg belong to kind = \"spot\""));
            }
            None
        }
        "spot" => Some(spot(loc, d)?),
        other => {
            return Err(loc.at(d.kind.span(), format!("kind = {other:?}: expected \"point\" or \"spot\"")));
        }
    };
    Ok(Lamp { position, intensity_cd, radius_m, spot })
}

fn spot(loc: &Locator<'_>, d: &LampDef) -> Result<Spot> {
    let Some(dir) = &d.direction else {
        return Err(loc.at(d.kind.span(), "a spot needs its direction = [x, y, z] (its axis, from the lamp)"));
    };
    let direction = DVec3::from(*dir.get_ref())
        .try_normalize()
        .filter(|v| v.is_finite() && dir.get_ref().iter().all(|x| x.abs() <= crate::scene::checks::MAX_COORDINATE))
        .ok_or_else(|| {
            loc.at(dir.span(), format!("direction = {}: expected a finite, non-zero vector", triple(dir.get_ref())))
        })?;
    let cone_deg = match &d.cone_deg {
        Some(c) => within(loc, c, "cone_deg", *c.get_ref() > 0.0 && *c.get_ref() <= 90.0, "a half-angle in (0°, 90°]")?,
        None => DEFAULT_CONE_DEG,
    };
    let soft_deg = match &d.soft_deg {
        Some(s) => within(
            loc,
            s,
            "soft_deg",
            (0.0..=cone_deg).contains(s.get_ref()),
            &format!("an edge between 0° and the cone's {}°", crate::error::number(cone_deg)),
        )?,
        None => DEFAULT_SOFT_DEG.min(cone_deg),
    };
    Ok(Spot { direction, cone_deg, soft_deg })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::scene::Scene;

    const HEAD: &str = r#"
[camera]
position = [0.0, 0.5, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 30.0

[[object]]
shape = "ground"
material = "soil"

[material.soil]
pigment = [0.5, 0.5, 0.5]
"#;
    const POINT: &str = "\n[[lamp]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity_cd = 10.0\n";
    const NONE: &str = "\n[light]\nenvironment = \"none\"\n";

    fn parse(text: &str) -> crate::error::Result<Scene> {
        Scene::parse(text, "s.toml", Path::new("."))
    }

    fn error_of(text: &str) -> String {
        parse(text).expect_err("refused").to_string()
    }

    #[test]
    fn lamps_light_a_scene_alone_in_candela_or_beside_the_sun_in_its_units() {
        let alone = parse(&format!("{HEAD}{NONE}{POINT}")).unwrap();
        // Lit by its lamp alone, over a ground: the lamp casts shadows (the sun's map is skipped: no sun).
        assert!(!alone.sun && alone.shadows && alone.sun_strength() == 0.0);
        let unshadowed = parse(&format!("{HEAD}{NONE}shadows = false\n{POINT}")).unwrap();
        assert!(!unshadowed.shadows, "[light] shadows = false turns the lamps' shadows off");
        assert_eq!(alone.unit_luminance(alone.light_dir), 1.0, "the frame in cd/m²");
        let lamp = alone.lamps[0];
        assert_eq!((lamp.position.y, lamp.intensity_cd, lamp.radius_m, lamp.spot), (1.0, 10.0, 0.01, None));
        assert!(alone.illuminant.physical, "lamps put the frame in physical units");
        // Beside a sun (here without an environment) the frame is in units of that sun's luminance: the sky model's.
        let sunny = parse(&format!("{HEAD}{NONE}direction = [0.0, 1.0, 1.0]\n{POINT}")).unwrap();
        let unit = sunny.unit_luminance(sunny.light_dir);
        assert!(sunny.sun && (1e8..1e10).contains(&unit), "the sun at 45°: {unit} cd/m²");
        assert!(sunny.illuminant.physical);
        // Without lamps the sun alone stays in relative units, and a scene without a light is refused.
        assert!(!parse(&format!("{HEAD}{NONE}direction = [0.0, 1.0, 1.0]\n")).unwrap().illuminant.physical);
        assert!(error_of(&format!("{HEAD}{NONE}")).contains("with [[lamp]]s, which then light it alone"));
        let spot = parse(&format!(
            "{HEAD}{NONE}\n[[lamp]]\nkind = \"spot\"\nposition = [0.0, 2.0, 0.0]\nintensity_cd = 5.0\n\
             direction = [0.0, -2.0, 0.0]\nradius_m = 0.05\n"
        ))
        .unwrap();
        let s = spot.lamps[0].spot.unwrap();
        assert_eq!((s.direction.y, s.cone_deg, s.soft_deg, spot.lamps[0].radius_m), (-1.0, 30.0, 5.0, 0.05));
    }

    #[test]
    fn a_lamp_that_cannot_be_lit_is_refused_at_its_line() {
        let with = |lamp: &str| error_of(&format!("{HEAD}{NONE}\n[[lamp]]\n{lamp}\n"));
        let point = "kind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity_cd = 1.0";
        let spot = "kind = \"spot\"\nposition = [0.0, 1.0, 0.0]\nintensity_cd = 1.0\ndirection = [0.0, -1.0, 0.0]";
        for (lamp, expected) in [
            (point.replace("point", "area"), "s.toml:18: kind = \"area\": expected \"point\" or \"spot\""),
            (
                point.replace("intensity_cd = 1.0", "intensity_cd = 0.0"),
                "intensity_cd = 0: expected a luminous intensity",
            ),
            (point.replace("intensity_cd = 1.0", "intensity_cd = 1e12"), "at most 1e9"),
            (point.replace("intensity_cd = 1.0", "intensity_cd = nan"), "intensity_cd = NaN"),
            (format!("{point}\nradius_m = 0.0"), "radius_m = 0: expected the emitting disc's radius"),
            (point.replace("[0.0, 1.0, 0.0]", "[0.0, 1e7, 0.0]"), "within ±1e6"),
            (format!("{point}\ncone_deg = 20.0"), "belong to kind = \"spot\""),
            (format!("{point}\ndirection = [0.0, -1.0, 0.0]"), "belong to kind = \"spot\""),
            (spot.replace("direction = [0.0, -1.0, 0.0]", ""), "a spot needs its direction"),
            (spot.replace("[0.0, -1.0, 0.0]", "[0.0, 0.0, 0.0]"), "direction = [0, 0, 0]: expected a finite, non-zero"),
            (format!("{spot}\ncone_deg = 95.0"), "cone_deg = 95: expected a half-angle in (0°, 90°]"),
            (
                format!("{spot}\ncone_deg = 20.0\nsoft_deg = 25.0"),
                "soft_deg = 25: expected an edge between 0° and the cone's 20°",
            ),
            (format!("{point}\ncolour = [1.0, 0.0, 0.0]"), "unknown field `colour`"),
        ] {
            let e = with(&lamp);
            assert!(e.contains(expected), "{lamp:?}: {e}");
        }
        let nine = (0..9).map(|_| format!("\n[[lamp]]\n{point}\n")).collect::<String>();
        assert!(error_of(&format!("{HEAD}{NONE}{nine}")).contains("at most 8 lamps"));
    }
}
