//! The profile's picture: time against error, one point per configuration (the mean ΔE₀₀, with a line up to
//! the 99th percentile), coloured by approach, both axes logarithmic. Drawn with `plotters` into a bitmap and
//! written as PNG; text needs a TrueType font, found among the usual system fonts or given with `--plot-font`.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::error::{Error, Result};
use crate::material::Approach;
use crate::reference::exact_image::ImageError;
use crate::reference::profiler::Row;

/// Where the plot looks for a font when none is given (Debian's fonts-dejavu-core first).
const FONT_CANDIDATES: [&str; 5] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/Library/Fonts/Arial.ttf",
];

/// The largest font file read (a TrueType font with every script is a few tens of MiB).
const MAX_FONT_BYTES: u64 = 64 << 20;

/// The font registered with plotters (once per process).
static FONT: OnceLock<std::result::Result<PathBuf, String>> = OnceLock::new();

/// Finds and registers the plot's font (`explicit`, else a system font); call it before long work so that a
/// missing font is reported at once.
pub fn register_font(explicit: Option<&Path>) -> Result<()> {
    let found = FONT.get_or_init(|| {
        let path = match explicit {
            Some(p) => p.to_path_buf(),
            None => FONT_CANDIDATES.iter().map(PathBuf::from).find(|p| p.is_file()).ok_or_else(|| {
                "no TrueType font for the plot's text: install fonts-dejavu-core or pass --plot-font FILE.ttf"
                    .to_string()
            })?,
        };
        // A font file is read like every user file: a regular file, bounded (a FIFO would block, /dev/zero never
        // end).
        let bytes = crate::io::input::read(&path, MAX_FONT_BYTES, "font")
            .map_err(|e| format!("the plot's font (--plot-font): {e}"))?;
        // plotters keeps fonts for the life of the process.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| format!("{} is not a TrueType font plotters can read", path.display()))?;
        Ok(path)
    });
    found.as_ref().map(|_| ()).map_err(|e| Error::Invalid(e.clone()))
}

fn colour(approach: Approach) -> RGBColor {
    match approach {
        Approach::Flss => RGBColor(31, 119, 180),
        Approach::Nmm => RGBColor(255, 127, 14),
        Approach::Pq => RGBColor(44, 160, 44),
        Approach::Gem => RGBColor(214, 39, 40),
        Approach::Baked => RGBColor(148, 103, 189),
    }
}

/// The smallest error drawn: exact zeros sit on this floor of the log axis.
const ERROR_FLOOR: f64 = 1e-4;

/// Draws `rows` (GPU ms, or CPU ms where the device has no timestamps) against their ΔE₀₀ into `out` (PNG).
pub fn plot(out: &Path, title: &str, rows: &[Row], font: Option<&Path>) -> Result<()> {
    register_font(font)?;
    if rows.is_empty() {
        return Err(Error::Invalid("nothing to plot".into()));
    }
    let (w, h) = (1000u32, 700u32);
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    let gpu = rows.iter().all(|r| r.gpu_ms.is_some());
    let time = |r: &Row| if gpu { r.gpu_ms.map_or(r.cpu_ms.median, |s| s.median) } else { r.cpu_ms.median };
    let (t_min, t_max) = bounds(rows.iter().map(time));
    let (e_min, e_max) =
        bounds(rows.iter().flat_map(|r| r.error.map(|e| [e.mean_de, e.p99_de])).flatten().map(|e| e.max(ERROR_FLOOR)));
    let drawn = (|| -> std::result::Result<(), Box<dyn std::error::Error>> {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((t_min..t_max).log_scale(), (e_min..e_max).log_scale())?;
        chart
            .configure_mesh()
            .x_desc(if gpu { "GPU ms per frame (median)" } else { "CPU ms per frame (median; no GPU timestamps)" })
            .y_desc("CIEDE2000 vs exact reference (dot: mean, bar: to p99)")
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .draw()?;
        for approach in Approach::ALL {
            // Rows without a reference (`--no-reference`) have no error to plot.
            let mine: Vec<(&Row, ImageError)> =
                rows.iter().filter(|r| r.settings.approach == approach).filter_map(|r| Some((r, r.error?))).collect();
            if mine.is_empty() {
                continue;
            }
            let c = colour(approach);
            for &(r, e) in &mine {
                let (t, mean, p99) = (time(r), e.mean_de.max(ERROR_FLOOR), e.p99_de.max(ERROR_FLOOR));
                chart.draw_series(LineSeries::new([(t, mean), (t, p99)], c.stroke_width(2)))?;
                let label = point_label(r, rows);
                chart.draw_series(std::iter::once(Text::new(label, (t, mean), ("sans-serif", 13).into_font())))?;
            }
            chart
                .draw_series(
                    mine.iter().map(|&(r, e)| Circle::new((time(r), e.mean_de.max(ERROR_FLOOR)), 6, c.filled())),
                )?
                .label(approach.name())
                .legend(move |(x, y)| Circle::new((x, y), 6, c.filled()));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .draw()?;
        root.present()?;
        Ok(())
    })();
    drawn.map_err(|e| Error::Invalid(format!("drawing the plot: {e}")))?;
    let rgba: Vec<u8> = buffer.chunks(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    crate::io::output::write_png_rgba8(out, w, h, &rgba)
}

/// The settings that tell the points apart (those that vary across `rows`).
fn point_label(r: &Row, rows: &[Row]) -> String {
    // A baked row's settings are its table's: its terms in w (the Taylor order and Δλ are not its own).
    if let Some(t) = &r.table {
        return format!(" w:{}", t.terms);
    }
    let varies = |f: &dyn Fn(&Row) -> String| rows.iter().any(|o| f(o) != f(r));
    let mut parts = vec![String::new()];
    if let Some(n) = r.order.filter(|_| varies(&|o| format!("{:?}", o.order))) {
        parts.push(format!("N={n}"));
    }
    if !matches!(r.settings.approach, Approach::Nmm | Approach::Gem) && varies(&|o| o.lambda_count.to_string()) {
        parts.push(format!("Δλ={}", r.settings.lambda_step_nm));
    }
    if varies(&|o| o.taps.to_string()) {
        parts.push(format!("{}² taps", r.taps));
    }
    if varies(&|o| format!("{}x{}", o.width, o.height)) {
        parts.push(format!("{}×{}", r.width, r.height));
    }
    parts.join(" ")
}

/// A log axis's range around the values, with room for labels.
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    (lo / 1.6, (hi * 2.5).max(lo * 10.0))
}
