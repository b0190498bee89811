//! `diffract profile`: the speed/accuracy trade of the shading settings, measured.
//!
//! A profile runs a list of [`Config`]s (the cross product of each `--sweep`'s items; several sweeps add their
//! lists) over one workload (a BRDF map or a scene) and reports for each: GPU time per frame from timestamps
//! (median, 10th and 90th percentiles), CPU wall time per frame, Taylor-term texel fetches per pixel (counted by
//! the shaders' counting variants), their rate against the device's measured peak (`--roofline`), and the
//! image's error against an exact reference ([`crate::reference::exact_image`]).
//!
//! - [`run`]: the loop over configurations: the subject (a map or a scene), its materials, frames and reference.
//! - [`plot`]: time against error as a picture.
//! - here: the configurations and sweeps, the rows and their CSV and markdown.

pub mod plot;
pub mod run;

use std::fmt::Write as _;

use crate::error::{Error, Result};
use crate::io::stats::Spread;
use crate::material::{Approach, Settings, SettingsPatch};
use crate::render::diffraction::Upload;
use crate::render::map::MapShader;
use crate::render::offscreen::FrameTarget;
use crate::render::pass;
use crate::render::visibility::ShadingPath;

/// One configuration of a profile: the settings it sets for every material (the rest are each material's own;
/// a BRDF map's are [`Settings::default`]'s with the command line's tolerance and coherence) and the image size.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Config {
    pub overrides: SettingsPatch,
    /// Image width (maps: the side) in pixels.
    pub size: u32,
    /// Samples per pixel of a scene's frames (None: the profile's `--samples`, else the scene's).
    pub samples: Option<u32>,
    /// The pipeline that draws a BRDF map (None: the device's, `MapShader::for_device`).
    pub shader: Option<MapShader>,
    /// What a scene's frames are drawn into (None: linear, as `render` reads them back).
    pub target: Option<FrameTarget>,
    /// How a scene's frames are shaded (None: forward, as `render` draws them).
    pub path: Option<ShadingPath>,
}

/// The keys a sweep may vary besides the material settings ([`Settings::KEYS`]).
pub const FRAME_KEYS: [&str; 5] = ["size", "samples", "shader", "target", "path"];
/// Largest image side a profile renders (the reference is a CPU computation).
pub const MAX_SIZE: u32 = 4096;

/// Every key a sweep may vary: the material settings, then the frame's.
pub fn sweep_keys() -> Vec<&'static str> {
    Settings::KEYS.iter().chain(&FRAME_KEYS).copied().collect()
}

impl Config {
    /// Sets `key` to `value` (as written on the command line).
    pub fn set(&mut self, key: &str, value: &str) -> Result<()> {
        let bad = |what: &str| Error::setting("sweep", format!("--sweep {key}={value}: {what}"));
        match key {
            "size" => {
                let v: u32 = value.parse().map_err(|_| bad("the size is a pixel count"))?;
                if !(1..=MAX_SIZE).contains(&v) {
                    return Err(bad(&format!("the size must lie in 1..={MAX_SIZE} pixels")));
                }
                self.size = v;
            }
            "samples" => {
                let v: u32 = value.parse().map_err(|_| bad("samples per pixel are a count"))?;
                if !(v.is_power_of_two() && v <= 64) {
                    return Err(bad("samples per pixel are 1, 2, 4, 8, 16, 32 or 64"));
                }
                self.samples = Some(v);
            }
            "shader" => {
                let names = MapShader::NAMES.join(" or ");
                self.shader = Some(MapShader::parse(value).ok_or_else(|| bad(&format!("a map's shader is {names}")))?);
            }
            "target" => {
                let names = FrameTarget::NAMES.join(" or ");
                let target =
                    FrameTarget::parse(value).ok_or_else(|| bad(&format!("a scene's frame target is {names}")))?;
                self.target = Some(target);
            }
            "path" => {
                let names = ShadingPath::NAMES.join(" or ");
                let path =
                    ShadingPath::parse(value).ok_or_else(|| bad(&format!("a scene's shading path is {names}")))?;
                self.path = Some(path);
            }
            _ if Settings::canonical(key).is_some() => {
                self.overrides.set(key, value).map_err(|e| Error::setting("sweep", format!("--sweep {e}")))?
            }
            _ => {
                return Err(Error::setting(
                    "sweep",
                    format!("--sweep: unknown key `{key}` (the keys are {})", sweep_keys().join(", ")),
                ))
            }
        }
        Ok(())
    }

    /// A short label, e.g. `flss N=12 Δλ=5 r=2 256px`: `own` where each material keeps its own setting, `auto`
    /// where the shading chooses.
    pub fn label(&self) -> String {
        let own = |key: &str| !self.overrides.keys_set().contains(&key);
        let parts: Vec<String> = Settings::INFO
            .iter()
            .zip(self.overrides.apply(Settings::default()).values())
            .filter_map(|(info, value)| {
                let value = if own(info.key) && info.short.is_some() && value != "auto" { "own".into() } else { value };
                match info.short {
                    Some("") => Some(value),
                    Some(short) => Some(format!("{short}={value}")),
                    None if !own(info.key) => Some(format!("{}={value}", info.key)),
                    None => None,
                }
            })
            .collect();
        self.with_frame(format!("{} {}px", parts.join(" "), self.size))
    }

    /// `label` with the samples per pixel, map shader and frame target a sweep set (`… 800px 4spp display`).
    fn with_frame(&self, label: String) -> String {
        let mut label = label;
        let parts = [
            self.samples.map(|n| format!("{n}spp")),
            self.shader.map(|s| s.name().to_string()),
            self.target.map(|t| t.name().to_string()),
            self.path.map(|p| p.name().to_string()),
        ];
        for part in parts.into_iter().flatten() {
            label += " ";
            label += &part;
        }
        label
    }
}

/// One `--sweep`: items `KEY=V1,V2,...` whose cross product it stands for.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    pub items: Vec<(String, Vec<String>)>,
}

impl Sweep {
    /// Parses the items of one `--sweep` (each `KEY=V1,V2,...`), checking every value.
    pub fn parse(items: &[String]) -> Result<Self> {
        let mut parsed: Vec<(String, Vec<String>)> = Vec::new();
        for item in items {
            let (key, values) = item.split_once('=').ok_or_else(|| {
                Error::setting("sweep", format!("--sweep {item}: expected KEY=V1,V2,... (e.g. order=4,8,16)"))
            })?;
            let asked = key.trim().replace('-', "_");
            let key = Settings::canonical(&asked).map_or(asked.clone(), str::to_string);
            if parsed.iter().any(|(k, _)| *k == key) {
                return Err(Error::setting("sweep", format!("--sweep: `{key}` appears twice in one sweep")));
            }
            let values: Vec<String> =
                values.split(',').map(|v| v.trim().to_string()).filter(|v| !v.is_empty()).collect();
            if values.is_empty() {
                return Err(Error::setting("sweep", format!("--sweep {item}: no values")));
            }
            let mut probe = Config::default();
            for v in &values {
                probe.set(&asked, v)?;
            }
            parsed.push((key, values));
        }
        Ok(Self { items: parsed })
    }

    /// The configurations: `base` with every combination of the items' values (the first item varies slowest).
    pub fn configs(&self, base: Config) -> Result<Vec<Config>> {
        let mut out = vec![base];
        for (key, values) in &self.items {
            let mut next = Vec::with_capacity(out.len() * values.len());
            for c in &out {
                for v in values {
                    let mut c = *c;
                    c.set(key, v)?;
                    next.push(c);
                }
            }
            out = next;
        }
        Ok(out)
    }
}

/// Every configuration of `sweeps` in order (each sweep's cross product, then the next sweep's), duplicates
/// dropped; no sweep: `base` alone.
pub fn configurations(base: Config, sweeps: &[Sweep]) -> Result<Vec<Config>> {
    if sweeps.is_empty() {
        return Ok(vec![base]);
    }
    let mut out: Vec<Config> = Vec::new();
    for sweep in sweeps {
        for c in sweep.configs(base)? {
            if !out.contains(&c) {
                out.push(c);
            }
        }
    }
    Ok(out)
}

/// What one configuration measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub config: Config,
    /// The first material's settings under the configuration (the approach, order and step it ran with).
    pub settings: Settings,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the frames.
    pub samples: u32,
    /// The pipeline that drew a BRDF map's frames (None for a scene).
    pub map_shader: Option<MapShader>,
    /// What a scene's frames were drawn into (None for a map).
    pub frame_target: Option<FrameTarget>,
    /// How a scene's frames were shaded (None for a map).
    pub shading_path: Option<ShadingPath>,
    /// The Taylor order used (None for gem), wavelengths sampled (FLSS, PQ; NMM's vary) and taps per axis.
    pub order: Option<usize>,
    pub lambda_count: usize,
    pub taps: u32,
    pub frames: usize,
    pub precompute_ms: f64,
    pub gpu_ms: Option<Spread>,
    /// Each pass's GPU time over the frames ([`crate::render::pass`] names), in frame order; their medians sum
    /// to about the frame's (exactly, frame by frame).
    pub passes: Vec<(String, Spread)>,
    /// What uploading the materials' tables or Taylor terms cost (all materials together).
    pub upload: Option<Upload>,
    pub cpu_ms: Spread,
    /// Fragment-shader invocations of the shading pass by pipeline statistics (llvmpipe counts 16 per rasterised
    /// 4×4 block, before the depth test).
    pub fragment_invocations: Option<u64>,
    /// Invocations that shaded a pixel (counted by the counting shaders after the early depth test), per pixel
    /// that shows the surface.
    pub shaded_per_pixel: f64,
    /// Counted Taylor-term fetches per image pixel.
    pub fetches_per_pixel: f64,
    /// Counted fetches / median GPU time.
    pub fetches_per_s: Option<f64>,
    /// `fetches_per_s` over the probe's peak (with `--roofline`; not for baked, whose filtered reads the probe does
    /// not measure).
    pub roofline_fraction: Option<f64>,
    /// Against the exact reference (None with `--no-reference`).
    pub error: Option<crate::reference::exact_image::ImageError>,
    /// The baked approach's table (of the first material).
    pub table: Option<TableSummary>,
}

/// What a baked table costs: its Chebyshev terms in w, its level-0 texels, its GPU memory and how long it took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableSummary {
    pub terms: usize,
    pub texels: (usize, usize),
    pub mib: f64,
    pub ms: f64,
    pub cached: bool,
}

impl TableSummary {
    pub fn of(material: &crate::material::Material) -> Option<Self> {
        let table = material.table.as_ref()?;
        Some(Self {
            terms: table.terms,
            texels: (table.grid.nu, table.grid.nv),
            mib: table.bytes() as f64 / (1u64 << 20) as f64,
            ms: material.table_ms,
            cached: material.table_cached,
        })
    }
}

/// How a row writes one CSV field.
type Field = fn(&Row) -> String;

/// The CSV's columns after the settings' ([`Settings::KEYS`]: what each row ran with): what it measured, each
/// with how a row writes it (empty where the device cannot measure).
const MEASURED: [(&str, Field); 38] = [
    ("order_used", |r| opt(r.order)),
    ("lambda_count", |r| r.lambda_count.to_string()),
    ("taps", |r| r.taps.to_string()),
    ("width", |r| r.width.to_string()),
    ("height", |r| r.height.to_string()),
    ("samples", |r| r.samples.to_string()),
    ("map_shader", |r| r.map_shader.map_or(String::new(), |s| s.name().to_string())),
    ("frame_target", |r| r.frame_target.map_or(String::new(), |t| t.name().to_string())),
    ("shading_path", |r| r.shading_path.map_or(String::new(), |p| p.name().to_string())),
    ("frames", |r| r.frames.to_string()),
    ("precompute_ms", |r| format!("{:.3}", r.precompute_ms)),
    ("gpu_ms_median", |r| opt(r.gpu_ms.map(|s| format!("{:.4}", s.median)))),
    ("gpu_ms_p10", |r| opt(r.gpu_ms.map(|s| format!("{:.4}", s.p10)))),
    ("gpu_ms_p90", |r| opt(r.gpu_ms.map(|s| format!("{:.4}", s.p90)))),
    ("depth_ms_median", |r| opt(r.pass_ms(pass::DEPTH).map(|v| format!("{v:.4}")))),
    ("visibility_ms_median", |r| opt(r.pass_ms(pass::VISIBILITY).map(|v| format!("{v:.4}")))),
    ("shading_ms_median", |r| opt(r.pass_ms(pass::SHADING).map(|v| format!("{v:.4}")))),
    ("edges_ms_median", |r| opt(r.pass_ms(pass::EDGES).map(|v| format!("{v:.4}")))),
    ("resolve_ms_median", |r| opt(r.pass_ms(pass::RESOLVE).map(|v| format!("{v:.4}")))),
    ("copy_ms_median", |r| opt(r.pass_ms(pass::COPY).map(|v| format!("{v:.4}")))),
    ("cpu_ms_median", |r| format!("{:.4}", r.cpu_ms.median)),
    ("fragment_invocations", |r| opt(r.fragment_invocations)),
    ("shaded_per_covered_pixel", |r| format!("{:.3}", r.shaded_per_pixel)),
    ("fetches_per_pixel", |r| format!("{:.1}", r.fetches_per_pixel)),
    ("fetches_per_s", |r| opt(r.fetches_per_s.map(|v| format!("{v:.4e}")))),
    ("roofline_fraction", |r| opt(r.roofline_fraction.map(|v| format!("{v:.4}")))),
    ("mean_de2000", |r| opt(r.error.map(|e| format!("{:.5}", e.mean_de)))),
    ("p99_de2000", |r| opt(r.error.map(|e| format!("{:.5}", e.p99_de)))),
    ("mean_de2000_se", |r| opt(r.error.and_then(|e| e.mean_de_se).map(|v| format!("{v:.5}")))),
    ("mean_de2000_half_positions", |r| opt(r.error.and_then(|e| e.mean_de_half_positions).map(|v| format!("{v:.5}")))),
    ("de_pixels", |r| opt(r.error.map(|e| e.pixels))),
    ("rel_xyz_rmse", |r| opt(r.error.map(|e| format!("{:.5e}", e.rel_rmse)))),
    ("table_terms", |r| opt(r.table.map(|t| t.terms))),
    ("table_texels", |r| opt(r.table.map(|t| format!("{}x{}", t.texels.0, t.texels.1)))),
    ("table_mib", |r| opt(r.table.map(|t| format!("{:.2}", t.mib)))),
    ("upload_bytes", |r| opt(r.upload.map(|u| u.bytes))),
    ("upload_gpu_ms", |r| opt(r.upload.and_then(|u| u.gpu_ms).map(|v| format!("{v:.4}")))),
    ("label", |r| r.label()),
];

/// The CSV's column header (the schema a test checks): the settings, then what was measured.
pub fn csv_columns() -> Vec<&'static str> {
    Settings::KEYS.iter().copied().chain(MEASURED.iter().map(|(name, _)| *name)).collect()
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

impl Row {
    /// The label of what ran, e.g. `flss N=12 Δλ=5 r=2 256px` (`auto`: the order or radius was not forced).
    pub fn label(&self) -> String {
        self.config.with_frame(format!("{} {}px", self.settings.label(&self.config.overrides), self.config.size))
    }

    /// The median GPU time of the pass `name` over the frames (None where the frames had no such pass).
    pub fn pass_ms(&self, name: &str) -> Option<f64> {
        self.passes.iter().find(|(n, _)| n == name).map(|(_, s)| s.median)
    }

    /// The row's CSV fields, in [`csv_columns`] order (empty where the device cannot measure).
    pub fn csv_fields(&self) -> Vec<String> {
        let mut fields = self.settings.values();
        fields.extend(MEASURED.iter().map(|(_, field)| field(self)));
        fields
    }
}

/// The CSV: `#` comment lines (`comments`, one per entry), the header, one row per configuration.
pub fn csv(comments: &[String], rows: &[Row]) -> String {
    let mut out = String::new();
    for c in comments {
        for line in c.lines() {
            let _ = writeln!(out, "# {line}");
        }
    }
    let _ = writeln!(out, "{}", csv_columns().join(","));
    for row in rows {
        let fields: Vec<String> = row.csv_fields().into_iter().map(|f| csv_escape(&f)).collect();
        let _ = writeln!(out, "{}", fields.join(","));
    }
    out
}

fn csv_escape(field: &str) -> String {
    if field.contains([',', '"', '\n']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

/// The markdown table printed at the end of a profile.
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::from(
        "| approach | N | Δλ nm | taps | size | GPU ms median [p10, p90] | CPU ms | fetches/px | of peak | \
         ΔE00 mean | ΔE00 p99 | rel. XYZ RMSE |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n",
    );
    for r in rows {
        let s = &r.settings;
        let gpu = r.gpu_ms.map_or("n/a".to_string(), |s| format!("{} [{}, {}]", ms(s.median), ms(s.p10), ms(s.p90)));
        let lambda = match (s.approach, &r.table) {
            (Approach::Nmm, _) => "per bin".to_string(),
            (Approach::Baked, _) => "1 (baked)".to_string(),
            _ => format!("{} ({})", s.lambda_step_nm, r.lambda_count),
        };
        // A baked row's "N" is its table's Chebyshev terms in w and its "taps" the table's texels and memory.
        let (order, taps) = match &r.table {
            Some(t) => (format!("w: {}", t.terms), format!("{}×{} texels, {:.0} MiB", t.texels.0, t.texels.1, t.mib)),
            None => (r.order.map_or("–".to_string(), |n| n.to_string()), format!("{}²", r.taps)),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {}×{}{} | {} | {} | {} | {} | {} | {} | {} |",
            s.approach.name(),
            order,
            lambda,
            taps,
            r.width,
            r.height,
            frame_suffix(r),
            gpu,
            ms(r.cpu_ms.median),
            si(r.fetches_per_pixel),
            r.roofline_fraction.map_or("–".to_string(), |f| format!("{:.0} %", 100.0 * f)),
            r.error.map_or("–".into(), |e| mean_de(&e)),
            r.error.map_or("–".into(), |e| format!("{:.3}", e.p99_de)),
            r.error.map_or("–".into(), |e| format!("{:.2e}", e.rel_rmse))
        );
    }
    out
}

/// What a markdown row's size says besides the pixels: the samples per pixel (` ×4`), a map's shader, a scene's
/// display target.
fn frame_suffix(r: &Row) -> String {
    let samples = if r.samples > 1 { format!(" ×{}", r.samples) } else { String::new() };
    let shader = r.config.shader.map_or(String::new(), |s| format!(" {}", s.name()));
    let display = if r.config.target == Some(FrameTarget::Display) { " display" } else { "" };
    let path = if r.config.path == Some(ShadingPath::Visibility) { " visibility" } else { "" };
    format!("{samples}{shader}{display}{path}")
}

/// The second table printed at the end of a profile: where each configuration's frame time goes, pass by pass
/// (medians over the frames), and what uploading its textures cost once. Empty where the device has no
/// timestamps.
pub fn markdown_passes(rows: &[Row]) -> String {
    if rows.iter().all(|r| r.passes.is_empty()) {
        return String::new();
    }
    let mut out = String::from("| configuration |");
    let mut rule = String::from("|---|");
    for name in pass::ALL {
        out += &format!(" {name} ms |");
        rule += "--:|";
    }
    out += " frame ms | passes, of frame | upload (once) |\n";
    rule += "--:|--:|--:|\n";
    out += &rule;
    for r in rows {
        let cells: Vec<String> = pass::ALL.iter().map(|&n| r.pass_ms(n).map_or("–".into(), ms)).collect();
        let sum: f64 = r.passes.iter().map(|(_, s)| s.median).sum();
        let frame = r.gpu_ms.map(|s| s.median);
        let share = frame.filter(|&f| f > 0.0).map_or("–".into(), |f| format!("{:.1} %", 100.0 * sum / f));
        let upload = r.upload.map_or("–".into(), |u| {
            let gpu = u.gpu_ms.map_or(String::new(), |g| format!(", GPU {}", ms(g)));
            format!("{:.1} MiB{gpu} ms", u.bytes as f64 / (1u64 << 20) as f64)
        });
        let _ = writeln!(
            out,
            "| {} | {} | {} | {share} | {upload} |",
            r.label(),
            cells.join(" | "),
            frame.map_or("–".into(), ms)
        );
    }
    out
}

/// Milliseconds with three significant digits.
/// A mean ΔE00 as printed: with its standard error where the reference holds random pixels only.
pub fn mean_de(e: &crate::reference::exact_image::ImageError) -> String {
    match e.mean_de_se {
        Some(se) => format!("{:.3} ± {se:.3}", e.mean_de),
        None => format!("{:.3}", e.mean_de),
    }
}

pub fn ms(v: f64) -> String {
    if v >= 100.0 {
        format!("{v:.0}")
    } else if v >= 10.0 {
        format!("{v:.1}")
    } else if v >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// A count with an SI suffix (k, M, G).
pub(crate) fn si(v: f64) -> String {
    match v {
        v if v >= 1e9 => format!("{:.2}G", v / 1e9),
        v if v >= 1e6 => format!("{:.2}M", v / 1e6),
        v if v >= 1e3 => format!("{:.1}k", v / 1e3),
        v => format!("{v:.0}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> Config {
        let overrides =
            SettingsPatch { approach: Some(Approach::Flss), lambda_step_nm: Some(5.0), ..SettingsPatch::default() };
        Config { overrides, size: 64, samples: None, shader: None, target: None, path: None }
    }

    #[test]
    fn a_sweep_is_the_cross_product_of_its_items_and_sweeps_add_up() {
        let a = Sweep::parse(&["approach=flss,pq".into(), "order=4,8,auto".into()]).unwrap();
        let b = Sweep::parse(&["lambda-step=10,5".into()]).unwrap();
        let configs = configurations(base(), &[a, b]).unwrap();
        // 2 × 3 from the first sweep; the second adds Δλ = 10 (Δλ = 5 is the base, already listed).
        assert_eq!(configs.len(), 7);
        assert_eq!(configs[0].overrides.order, Some(4));
        assert_eq!(configs[2].overrides.order, None);
        let old = configurations(base(), &[Sweep::parse(&["terms=3".into()]).unwrap()]).unwrap();
        assert_eq!(old[0].overrides.order, Some(3), "the key's first name is still accepted");
        assert_eq!(configs[3].overrides.approach, Some(Approach::Pq));
        assert_eq!(configs[6].overrides.lambda_step_nm, Some(10.0));
        let samples = configurations(base(), &[Sweep::parse(&["samples=1,4".into()]).unwrap()]).unwrap();
        assert_eq!(samples.iter().map(|c| c.samples).collect::<Vec<_>>(), [Some(1), Some(4)]);
        assert!(samples[1].label().ends_with("64px 4spp"), "{}", samples[1].label());
        let shaders = configurations(base(), &[Sweep::parse(&["shader=fragment,compute".into()]).unwrap()]).unwrap();
        assert_eq!(
            shaders.iter().map(|c| c.shader).collect::<Vec<_>>(),
            [Some(MapShader::Fragment), Some(MapShader::Compute)]
        );
        assert!(shaders[1].label().ends_with("64px compute"), "{}", shaders[1].label());
        let sweep = Sweep::parse(&["samples=4".into(), "target=linear,display".into()]).unwrap();
        let targets = configurations(base(), &[sweep]).unwrap();
        assert_eq!(
            targets.iter().map(|c| c.target).collect::<Vec<_>>(),
            [Some(FrameTarget::Linear), Some(FrameTarget::Display)]
        );
        assert!(targets[1].label().ends_with("64px 4spp display"), "{}", targets[1].label());
    }

    #[test]
    fn bad_sweeps_are_refused_with_the_item() {
        for (item, needle) in [
            ("speed=1", "unknown key"),
            ("coherence_um=0", "positive"),
            ("order", "KEY=V1"),
            ("order=", "no values"),
            ("order=x", "order=x"),
            ("approach=fast", "flss, nmm"),
            ("lambda_step_nm=0", "(0, 400]"),
            ("window_radius=99", "0 to 16"),
            ("size=0", "1..="),
            ("samples=3", "1, 2, 4"),
            ("samples=128", "1, 2, 4"),
            ("shader=vertex", "compute or fragment"),
            ("target=srgb", "linear or display"),
        ] {
            let e = Sweep::parse(&[item.to_string()]).unwrap_err().to_string();
            assert!(e.contains(needle), "{item}: {e}");
        }
    }
}
