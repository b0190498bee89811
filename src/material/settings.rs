//! The material settings that trade speed for accuracy, declared once: `settings!` below is the only place a
//! setting is named, and from its list come [`Settings`] (every value, with the defaults a user gets),
//! [`SettingsPatch`] (each set or left alone: a scene's material, the command line's flags, a profile's `--sweep`,
//! the viewer's keys), [`Settings::KEYS`] and [`Settings::values`] (the profile's CSV columns) and
//! [`Settings::label`] (its row labels). Adding a setting is one entry here plus its use.
//!
//! An entry reads `KEY: KIND<TYPE> = DEFAULT, check CHECK, flag "--FLAG" …;` where KIND is `value` (always
//! set), `auto` (`None` lets the shading choose; `auto` on the command line) or `switch` (off unless turned on).
//! With `set_in "[light]"` the setting is the light's: a scene sets it once, in that table, for every material.

use crate::error::{Error, Result};
use crate::gpu::interface;
use crate::physics::baked::sample::TableMips;
use crate::physics::baked::DEFAULT_TABLE_TOLERANCE;
use crate::physics::coherence::DEFAULT_COHERENCE_UM;
use crate::physics::illuminant::Illuminant;
use crate::physics::taylor::DEFAULT_TOLERANCE;

/// The thesis's shading approaches (model.md §3.1–§3.4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Approach {
    /// Full λ-space sampling: every wavelength step, the Taylor sum with the Gaussian window (the reference)
    Flss,
    /// One wavelength per DFT bin crossed, with the dλ Jacobian the thesis left out (model.md §3.2)
    Nmm,
    /// The periodic-tiling (Dirichlet) factor with the patch's exact DTFT kernel (model.md §1.11, §1.12)
    Pq,
    /// Stam's analytic grating: only the dominant spacing, no height field (GPU Gems ch. 8)
    Gem,
    /// The spectrally integrated colour baked over (u, v) with its w-dependence as a Chebyshev series, filtered
    /// over each pixel's footprint: a handful of fetches per pixel
    Baked,
}

impl Approach {
    pub const ALL: [Approach; 5] = [Approach::Flss, Approach::Nmm, Approach::Pq, Approach::Gem, Approach::Baked];

    /// The value of the `APPROACH` specialization constant.
    pub fn id(self) -> u32 {
        match self {
            Approach::Flss => interface::APPROACH_FLSS,
            Approach::Nmm => interface::APPROACH_NMM,
            Approach::Pq => interface::APPROACH_PQ,
            Approach::Gem => interface::APPROACH_GEM,
            Approach::Baked => interface::APPROACH_BAKED,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Approach::Flss => "flss",
            Approach::Nmm => "nmm",
            Approach::Pq => "pq",
            Approach::Gem => "gem",
            Approach::Baked => "baked",
        }
    }

    /// Whether the approach samples the Taylor terms (flss, nmm, pq).
    pub fn uses_terms(self) -> bool {
        !matches!(self, Approach::Gem | Approach::Baked)
    }
}

/// Where a frame evaluates the environment's diffraction (the `sky_at` setting).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SkyAt {
    /// The diffracted part at the mesh's vertices, interpolated across each triangle; the specular part per pixel.
    Vertex,
    /// All of it per pixel: the prefiltered model exactly as [`Moments::radiance`](crate::light::prefilter::Moments::radiance) states it.
    Pixel,
}

impl SkyAt {
    pub const ALL: [SkyAt; 2] = [SkyAt::Vertex, SkyAt::Pixel];

    pub fn name(self) -> &'static str {
        match self {
            SkyAt::Vertex => "vertex",
            SkyAt::Pixel => "pixel",
        }
    }

    /// The value of the `SKY_DIFFRACTION` specialization constant for a material with moments.
    pub fn spec(self) -> u32 {
        match self {
            SkyAt::Vertex => interface::SKY_DIFFRACTION_VERTEX,
            SkyAt::Pixel => interface::SKY_DIFFRACTION_PIXEL,
        }
    }
}

/// Largest window radius (taps (2r+1)² per term and wavelength; the shaders' loops are bounded by it).
pub const MAX_WINDOW_RADIUS: u32 = 16;
/// The longest wavelength step, nm (one sample over 380–780 nm).
pub const MAX_LAMBDA_STEP_NM: f64 = 400.0;

/// What a setting's value must satisfy, besides its type (scene files, flags and sweeps are all checked here).
mod check {
    use super::{MAX_LAMBDA_STEP_NM, MAX_WINDOW_RADIUS};

    pub fn any<T>(_: &T) -> Result<(), String> {
        Ok(())
    }

    pub fn positive(v: &f64) -> Result<(), String> {
        match v.is_finite() && *v > 0.0 {
            true => Ok(()),
            false => Err("expected a positive finite number".into()),
        }
    }

    pub fn lambda_step(v: &f64) -> Result<(), String> {
        match v.is_finite() && *v > 0.0 && *v <= MAX_LAMBDA_STEP_NM {
            true => Ok(()),
            false => Err(format!("the wavelength step must lie in (0, {MAX_LAMBDA_STEP_NM}] nm")),
        }
    }

    pub fn table_segments(v: &usize) -> Result<(), String> {
        let most = crate::physics::baked::MAX_SEGMENTS;
        match (1..=most).contains(v) {
            true => Ok(()),
            false => Err(format!("a table has 1 to {most} segments of w")),
        }
    }

    pub fn window_radius(v: &u32) -> Result<(), String> {
        match *v <= MAX_WINDOW_RADIUS {
            true => Ok(()),
            false => Err(format!("the window radius is a whole number of taps from 0 to {MAX_WINDOW_RADIUS}")),
        }
    }
}

/// A setting's value as text: parsed from the command line and sweeps, shown in labels and CSV.
pub trait SettingValue: Copy + Send + Sync + 'static {
    fn parse(text: &str) -> std::result::Result<Self, String>;
    fn show(&self) -> String;
}

/// The one of `all` whose name is `text`, or why none is (`what`: what they are called).
fn parse_named<T: Copy>(text: &str, all: &[T], name: fn(T) -> &'static str, what: &str) -> Result<T, String> {
    all.iter().copied().find(|a| name(*a) == text.trim()).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|a| name(*a)).collect();
        format!("{text:?}: the {what} are {}", names.join(", "))
    })
}

impl SettingValue for Approach {
    fn parse(text: &str) -> std::result::Result<Self, String> {
        parse_named(text, &Approach::ALL, Approach::name, "approaches")
    }
    fn show(&self) -> String {
        self.name().to_string()
    }
}

impl SettingValue for SkyAt {
    fn parse(text: &str) -> std::result::Result<Self, String> {
        parse_named(text, &SkyAt::ALL, SkyAt::name, "choices")
    }
    fn show(&self) -> String {
        self.name().to_string()
    }
}

impl SettingValue for TableMips {
    fn parse(text: &str) -> std::result::Result<Self, String> {
        parse_named(text, &TableMips::ALL, TableMips::name, "choices")
    }
    fn show(&self) -> String {
        self.name().to_string()
    }
}

impl SettingValue for Illuminant {
    /// A name, or a CSV file relative to the working folder (a scene's are relative to the scene).
    fn parse(text: &str) -> std::result::Result<Self, String> {
        Illuminant::parse(text, std::path::Path::new(".")).map_err(|e| e.to_string())
    }
    fn show(&self) -> String {
        self.name.to_string()
    }
}

impl SettingValue for f64 {
    fn parse(text: &str) -> std::result::Result<Self, String> {
        text.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("{text:?} is not a finite number"))
    }
    fn show(&self) -> String {
        self.to_string()
    }
}

macro_rules! integer_setting {
    ($($t:ty),*) => {$(
        impl SettingValue for $t {
            fn parse(text: &str) -> std::result::Result<Self, String> {
                text.trim().parse::<$t>().map_err(|_| format!("{text:?} is not a whole number"))
            }
            fn show(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
integer_setting!(usize, u32);

impl SettingValue for bool {
    fn parse(text: &str) -> std::result::Result<Self, String> {
        match text.trim() {
            "true" | "on" | "yes" => Ok(true),
            "false" | "off" | "no" => Ok(false),
            _ => Err(format!("{text:?}: expected true or false")),
        }
    }
    fn show(&self) -> String {
        self.to_string()
    }
}

/// `text` parsed and checked.
fn parse_checked<T: SettingValue>(
    text: &str,
    check: fn(&T) -> std::result::Result<(), String>,
) -> std::result::Result<T, String> {
    let v = T::parse(text)?;
    check(&v).map_err(|e| format!("{}: {e}", text.trim()))?;
    Ok(v)
}

/// Whether `text` is the word `auto` (an `auto` setting's None), as a flag, a sweep or a scene writes it.
fn is_auto(text: &str) -> bool {
    text.trim() == "auto"
}

/// A scene file's value of an `auto` setting: the value, or None for `"auto"`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoOr<T>(pub Option<T>);

impl<T> Default for AutoOr<T> {
    fn default() -> Self {
        Self(None)
    }
}

impl<'de, T: serde::Deserialize<'de>> serde::Deserialize<'de> for AutoOr<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Written<T> {
            Value(T),
            Word(String),
        }
        match Written::deserialize(d)? {
            Written::Value(v) => Ok(Self(Some(v))),
            Written::Word(w) if is_auto(&w) => Ok(Self(None)),
            Written::Word(w) => Err(serde::de::Error::custom(format!("expected a number or \"auto\", got {w:?}"))),
        }
    }
}

/// What each kind of setting holds, how a patch replaces it, and how it is written.
mod kind {
    /// Always has a value.
    pub mod value {
        use super::super::SettingValue;
        pub type Own<T> = T;
        pub type Patch<T> = Option<T>;
        /// As a scene file writes it.
        pub type FilePatch<T> = Option<T>;
        pub fn from_file<T>(file: Option<T>) -> Option<T> {
            file
        }
        #[cfg(feature = "cli")]
        pub const SHOWS_DEFAULT: bool = true;
        pub fn apply<T: Copy>(patch: Option<T>, own: T) -> T {
            patch.unwrap_or(own)
        }
        pub fn show<T: SettingValue>(own: &T) -> String {
            own.show()
        }
        pub fn is_set<T>(patch: &Option<T>) -> bool {
            patch.is_some()
        }
        pub fn set<T: SettingValue>(
            patch: &mut Option<T>,
            text: &str,
            check: fn(&T) -> Result<(), String>,
        ) -> Result<(), String> {
            *patch = Some(super::super::parse_checked(text, check)?);
            Ok(())
        }
        pub fn checked<T>(patch: &Option<T>, check: fn(&T) -> Result<(), String>) -> Result<(), String> {
            patch.as_ref().map_or(Ok(()), check)
        }
        #[cfg(feature = "cli")]
        pub fn arg<T: SettingValue>(arg: clap::Arg, check: fn(&T) -> Result<(), String>) -> clap::Arg {
            arg.num_args(1).value_parser(move |text: &str| super::super::parse_checked(text, check))
        }
        #[cfg(feature = "cli")]
        pub fn get<T: SettingValue>(m: &clap::ArgMatches, id: &str) -> Option<T> {
            m.get_one::<T>(id).copied()
        }
    }

    /// `None`: the shading chooses.
    pub mod auto {
        use super::super::SettingValue;
        pub type Own<T> = Option<T>;
        pub type Patch<T> = Option<T>;
        /// As a scene file writes it: a value, or `"auto"` (the shading chooses, as where it is left out).
        pub type FilePatch<T> = super::super::AutoOr<T>;
        pub fn from_file<T>(file: super::super::AutoOr<T>) -> Option<T> {
            file.0
        }
        #[cfg(feature = "cli")]
        pub const SHOWS_DEFAULT: bool = true;
        pub fn apply<T: Copy>(patch: Option<T>, own: Option<T>) -> Option<T> {
            patch.or(own)
        }
        pub fn show<T: SettingValue>(own: &Option<T>) -> String {
            own.map_or("auto".to_string(), |v| v.show())
        }
        pub use super::value::{checked, is_set};
        /// `auto` leaves the material's own (which is auto unless it sets one).
        pub fn set<T: SettingValue>(
            patch: &mut Option<T>,
            text: &str,
            check: fn(&T) -> Result<(), String>,
        ) -> Result<(), String> {
            *patch = parse(text, check)?;
            Ok(())
        }
        /// `auto` (None), or a value `check` accepts.
        fn parse<T: SettingValue>(text: &str, check: fn(&T) -> Result<(), String>) -> Result<Option<T>, String> {
            if super::super::is_auto(text) {
                return Ok(None);
            }
            super::super::parse_checked(text, check).map(Some).map_err(|e| format!("{e} (or auto)"))
        }
        /// A flag that takes a value or `auto` (the patch's None: the material's own).
        #[cfg(feature = "cli")]
        pub fn arg<T: SettingValue>(arg: clap::Arg, check: fn(&T) -> Result<(), String>) -> clap::Arg {
            arg.num_args(1).value_parser(move |text: &str| parse(text, check))
        }
        #[cfg(feature = "cli")]
        pub fn get<T: SettingValue>(m: &clap::ArgMatches, id: &str) -> Option<T> {
            m.get_one::<Option<T>>(id).copied().flatten()
        }
    }

    /// Off unless a material or the patch turns it on.
    pub mod switch {
        pub type Own<T> = T;
        pub type Patch<T> = T;
        /// As a scene file writes it.
        pub type FilePatch<T> = T;
        pub fn from_file(file: bool) -> bool {
            file
        }
        #[cfg(feature = "cli")]
        pub const SHOWS_DEFAULT: bool = false;
        pub fn apply(patch: bool, own: bool) -> bool {
            patch || own
        }
        pub fn show(own: &bool) -> String {
            own.to_string()
        }
        pub fn is_set(patch: &bool) -> bool {
            *patch
        }
        pub fn set(patch: &mut bool, text: &str, _: fn(&bool) -> Result<(), String>) -> Result<(), String> {
            *patch = <bool as super::super::SettingValue>::parse(text)?;
            Ok(())
        }
        pub fn checked(_: &bool, _: fn(&bool) -> Result<(), String>) -> Result<(), String> {
            Ok(())
        }
        #[cfg(feature = "cli")]
        pub fn arg<T>(arg: clap::Arg, _: fn(&T) -> Result<(), String>) -> clap::Arg {
            arg.action(clap::ArgAction::SetTrue)
        }
        #[cfg(feature = "cli")]
        #[allow(clippy::extra_unused_type_parameters)] // called as `get::<bool>` like the other kinds
        pub fn get<T>(m: &clap::ArgMatches, id: &str) -> bool {
            m.get_flag(id)
        }
    }
}

/// One setting's description: its key, the flag that sets it and its help.
#[derive(Clone, Copy, Debug)]
pub struct SettingInfo {
    /// The key in scene files, `--sweep` and the CSV.
    pub key: &'static str,
    /// The command-line flag, without its dashes.
    pub flag: &'static str,
    /// Older names still accepted: as keys (scene files, sweeps) and as flags.
    pub aliases: &'static [&'static str],
    pub flag_aliases: &'static [&'static str],
    /// The doc comment: what the setting is.
    pub doc: &'static str,
    /// Its label in a profile row (`N=12`); `None`: shown only where a configuration sets it.
    pub short: Option<&'static str>,
    /// The default as the help states it, where [`Settings::default`]'s value is not the whole story.
    pub default_help: Option<&'static str>,
    /// Where a scene sets it when not in its materials (`"[light]"`).
    pub set_in: Option<&'static str>,
}

macro_rules! settings {
    ($(
        $(#[doc = $doc:literal])+
        $key:ident: $kind:ident<$ty:ty> = $default:expr, check $check:ident,
            flag $flag:literal $(, value_name $value_name:literal)?
            $(, short $short:literal)?
            $(, default_help $default_help:literal)?
            $(, aliases [$($alias:literal),*])?
            $(, flag_aliases [$($flag_alias:literal),*])?
            $(, set_in $set_in:literal)?;
    )+) => {
        /// Every setting that trades speed for accuracy, with the defaults a user gets (declared in
        /// `src/material/settings.rs`).
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct Settings {
            $( $(#[doc = $doc])+ pub $key: kind::$kind::Own<$ty>, )+
        }

        impl Default for Settings {
            fn default() -> Self {
                Self { $( $key: $default, )+ }
            }
        }

        /// Settings that replace a material's own, each set or left alone: a scene's material, the command line's
        /// flags, one configuration of a profile, the viewer's keys.
        #[derive(Clone, Copy, Debug, Default, PartialEq, serde::Deserialize)]
        #[serde(from = "SettingsFile")]
        pub struct SettingsPatch {
            $( $(#[doc = $doc])+ $(#[doc = concat!("(A scene sets it in `", $set_in, "`.)")])?
               pub $key: kind::$kind::Patch<$ty>, )+
        }

        /// [`SettingsPatch`] as a scene file writes it (an `auto` setting may say `"auto"`).
        #[derive(Default, serde::Deserialize)]
        #[serde(default)]
        struct SettingsFile {
            $( $($(#[serde(alias = $alias)])*)? $(#[serde(skip)] #[doc = $set_in])?
               $key: kind::$kind::FilePatch<$ty>, )+
        }

        impl From<SettingsFile> for SettingsPatch {
            fn from(file: SettingsFile) -> Self {
                Self { $( $key: kind::$kind::from_file(file.$key), )+ }
            }
        }

        impl Settings {
            /// Every setting, in declaration order.
            pub const INFO: &'static [SettingInfo] = &[$(
                SettingInfo {
                    key: stringify!($key),
                    flag: $flag,
                    aliases: &[$($($alias),*)?],
                    flag_aliases: &[$($($flag_alias),*)?],
                    doc: concat!($($doc, "\n"),+),
                    short: optional!($($short)?),
                    default_help: optional!($($default_help)?),
                    set_in: optional!($($set_in)?),
                },
            )+];
            /// The settings' keys (the CSV's first columns).
            pub const KEYS: &'static [&'static str] = &[$(stringify!($key)),+];

            /// Each setting's value as text, in [`Settings::KEYS`] order (`auto` where the shading chooses).
            pub fn values(&self) -> Vec<String> {
                vec![$( kind::$kind::show(&self.$key) ),+]
            }
        }

        impl SettingsPatch {
            /// `settings` with this patch in place.
            pub fn apply(&self, settings: Settings) -> Settings {
                Settings { $( $key: kind::$kind::apply(self.$key, settings.$key), )+ }
            }

            /// Sets the setting `key` (or one of its aliases) from text, as `--sweep KEY=VALUE` writes it.
            pub fn set(&mut self, key: &str, text: &str) -> Result<()> {
                let bad = |e: String| Error::setting(key, format!("{key}={text}: {e}"));
                match key {
                    $( stringify!($key) $($(| $alias)*)? => {
                        kind::$kind::set(&mut self.$key, text, check::$check).map_err(bad)
                    } )+
                    _ => Err(Error::setting(key, format!(
                        "unknown setting `{key}` (the settings are {})",
                        Settings::KEYS.join(", ")
                    ))),
                }
            }

            /// The keys this patch sets.
            pub fn keys_set(&self) -> Vec<&'static str> {
                let mut keys = Vec::new();
                $( if kind::$kind::is_set(&self.$key) { keys.push(stringify!($key)); } )+
                keys
            }

            /// Refuses a value out of its setting's range (a scene file's, which no parser has seen): `key: why`.
            pub fn check(&self) -> std::result::Result<(), String> {
                $( kind::$kind::checked(&self.$key, check::$check)
                    .map_err(|e| format!("{}: {e}", stringify!($key)))?; )+
                Ok(())
            }
        }

        #[cfg(feature = "cli")]
        impl clap::FromArgMatches for SettingsPatch {
            fn from_arg_matches(m: &clap::ArgMatches) -> std::result::Result<Self, clap::Error> {
                Ok(Self { $( $key: kind::$kind::get::<$ty>(m, stringify!($key)), )+ })
            }
            fn update_from_arg_matches(&mut self, m: &clap::ArgMatches) -> std::result::Result<(), clap::Error> {
                *self = Self::from_arg_matches(m)?;
                Ok(())
            }
        }

        #[cfg(feature = "cli")]
        impl clap::Args for SettingsPatch {
            fn augment_args(cmd: clap::Command) -> clap::Command {
                let defaults = Settings::default();
                cmd $( .arg(kind::$kind::arg::<$ty>(
                    clap::Arg::new(stringify!($key))
                        .long($flag)
                        $(.value_name($value_name))?
                        .help(help(stringify!($key), kind::$kind::SHOWS_DEFAULT.then(|| kind::$kind::show(&defaults.$key))))
                        $(.aliases([$($flag_alias),*]))?,
                    check::$check,
                )) )+
            }
            fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
                Self::augment_args(cmd)
            }
        }
    };
}
/// `Some(x)` for an entry that gives one, else `None`.
macro_rules! optional {
    () => {
        None
    };
    ($x:literal) => {
        Some($x)
    };
}

settings! {
    /// Shading approach: flss, nmm, pq, gem or baked (docs/approaches.md)
    approach: value<Approach> = Approach::Flss, check any,
        flag "approach", value_name "NAME", short "",
        default_help "baked in a scene, flss for a lone height field (map, profile --heightfield)";
    /// Taylor order N (terms 0..=N); auto: the smallest N that meets the tolerance (`terms`: its first name)
    order: auto<usize> = None, check any,
        flag "order", value_name "N", short "N", aliases ["terms"], flag_aliases ["terms"];
    /// Tolerance on the amplitude |P − P_N| (a flat mirror at specular has |P| = 1)
    tolerance: value<f64> = DEFAULT_TOLERANCE, check positive,
        flag "tolerance", value_name "T";
    /// Wavelength step in nm over 380–780 nm (FLSS and PQ; gem's specular term)
    lambda_step_nm: value<f64> = 5.0, check lambda_step,
        flag "lambda-step-nm", value_name "NM", short "Δλ", aliases ["lambda_step"], flag_aliases ["lambda-step"];
    /// Window taps either side of the nearest bin, at most 16; auto: brdf and terms the full window (weights
    /// ≥ 1e-17), the shaders down to a weight of 1e-3
    window_radius: auto<u32> = None, check window_radius,
        flag "window-radius", value_name "R", short "r";
    /// Coherence length in µm (the Gaussian window has σ_s = L/4)
    coherence_um: value<f64> = DEFAULT_COHERENCE_UM, check positive,
        flag "coherence-um", value_name "L";
    /// Shade even where f32 sums cannot reach the tolerance (the plan's estimate)
    accept_f32_error: switch<bool> = false, check any,
        flag "accept-f32-error";
    /// Baked: tolerance on the table's Chebyshev tail in w, relative to each texel's brightest value (a scene
    /// that sets it turns strict_table on)
    table_tolerance: value<f64> = DEFAULT_TABLE_TOLERANCE, check positive,
        flag "table-tolerance", value_name "T";
    /// Baked: refuse a table whose certified tail exceeds the table tolerance (memory or the term cap kept fewer
    /// terms than it needs) instead of warning
    strict_table: switch<bool> = false, check any,
        flag "strict-table", flag_aliases ["strict"];
    /// The light's spectrum: D65, D50, D55, D75 (`D<N>`: N·100 K daylight), A, E, F1 … F12, or a CSV of nm,relative
    /// power, for every material (a scene under the clear sky, the default, takes its sun's unless one is named)
    illuminant: value<Illuminant> = Illuminant::d65(), check any,
        flag "illuminant", value_name "NAME|FILE.csv", set_in "[light]";
    /// Where a frame evaluates the environment's diffraction: vertex (its broad, diffracted part at the mesh's
    /// vertices, interpolated; the specular part per pixel) or pixel (all of it per pixel)
    sky_at: value<SkyAt> = SkyAt::Vertex, check any,
        flag "sky-at", value_name "WHERE";
    /// Baked: how a frame reads the table between its mip levels: linear (trilinear, two levels blended), nearest
    /// (the nearest level: half the texel reads) or auto (nearest on a CPU device, where it saved a tenth of the
    /// default scene's frame at the same measured error; linear on a GPU)
    table_mips: value<TableMips> = TableMips::Auto, check any,
        flag "table-mips", value_name "FILTER";
    /// Baked: equal segments of w, each with its own Chebyshev series: a read fetches one segment's layers, and a
    /// series over a shorter interval needs fewer terms, for the memory of every segment; auto: two where w spans
    /// more than 1.5 (the tables for any view) and they read fewer layers within twice the memory of one
    table_segments: auto<usize> = None, check table_segments,
        flag "table-segments", value_name "N";
}

/// A flag's help: the setting's doc on one line and its default.
#[cfg(feature = "cli")]
fn help(key: &str, default: Option<String>) -> String {
    let info = Settings::INFO.iter().find(|i| i.key == key).expect("every flag is a setting");
    let doc = info.doc.lines().map(str::trim).collect::<Vec<_>>().join(" ");
    let scene =
        info.set_in.map_or("a scene's material may set its own".to_string(), |t| format!("a scene's {t} may set it"));
    match info.default_help.map(str::to_string).or(default) {
        None => format!("{doc} (a scene's material may turn it on itself)"),
        Some(default) => format!("{doc} [default: {default}; {scene}]"),
    }
}

impl Settings {
    /// The key `name` stands for: a key itself or an older name of one.
    pub fn canonical(name: &str) -> Option<&'static str> {
        Settings::INFO.iter().find(|i| i.key == name || i.aliases.contains(&name)).map(|i| i.key)
    }

    /// A profile row's label: the approach, then `N=… Δλ=… r=…`, then every other setting `patch` sets.
    pub fn label(&self, patch: &SettingsPatch) -> String {
        let values = self.values();
        let set = patch.keys_set();
        let mut parts = Vec::new();
        for (info, value) in Settings::INFO.iter().zip(&values) {
            match info.short {
                Some("") => parts.push(value.clone()),
                Some(short) => parts.push(format!("{short}={value}")),
                None if set.contains(&info.key) => parts.push(format!("{}={value}", info.key)),
                None => {}
            }
        }
        parts.join(" ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_patch_replaces_only_what_it_sets() {
        let own = Settings { order: Some(6), window_radius: Some(3), coherence_um: 20.0, ..Settings::default() };
        assert_eq!(SettingsPatch::default().apply(own), own, "an empty patch changes nothing");
        let patch = SettingsPatch { approach: Some(Approach::Nmm), order: Some(9), ..SettingsPatch::default() };
        let s = patch.apply(own);
        assert_eq!((s.approach, s.order), (Approach::Nmm, Some(9)));
        assert_eq!((s.window_radius, s.coherence_um), (Some(3), 20.0), "what is not set stays the material's");
        assert!(SettingsPatch { strict_table: true, ..SettingsPatch::default() }.apply(own).strict_table);
        assert!(
            SettingsPatch::default().apply(Settings { strict_table: true, ..own }).strict_table,
            "a switch stays on"
        );
    }

    #[test]
    fn keys_and_their_old_names_set_the_same_setting() {
        let mut a = SettingsPatch::default();
        a.set("order", "7").unwrap();
        let mut b = SettingsPatch::default();
        b.set("terms", "7").unwrap();
        assert_eq!((a, a.order), (b, Some(7)));
        a.set("order", "auto").unwrap();
        assert_eq!(a.order, None);
        for (key, text, why) in [
            ("window_radius", "17", "0 to 16"),
            ("lambda_step_nm", "0", "(0, 400]"),
            ("lambda_step_nm", "nan", "finite"),
            ("tolerance", "-1", "positive"),
            ("approach", "magic", "flss, nmm, pq, gem, baked"),
            ("strict_table", "maybe", "true or false"),
            ("speed", "1", "the settings are approach, order"),
        ] {
            let e = SettingsPatch::default().set(key, text).unwrap_err().to_string();
            assert!(e.contains(why), "{key}={text}: {e}");
        }
    }

    #[test]
    fn every_setting_has_a_key_a_flag_and_a_value() {
        let d = Settings::default();
        assert_eq!(Settings::KEYS.len(), Settings::INFO.len());
        assert_eq!(d.values().len(), Settings::KEYS.len());
        for info in Settings::INFO {
            assert_eq!(info.flag, info.key.replace('_', "-"), "a flag is its key in kebab case");
            assert!(!info.doc.trim().is_empty());
            let mut p = SettingsPatch::default();
            // Each key takes its own default's text (auto for auto), so the CSV's values parse back.
            let text = &d.values()[Settings::KEYS.iter().position(|k| *k == info.key).unwrap()];
            p.set(info.key, text).unwrap_or_else(|e| panic!("{}: {e}", info.key));
            for alias in info.aliases {
                SettingsPatch::default().set(alias, text).unwrap();
            }
        }
    }

    #[test]
    fn scene_values_are_checked_as_flags_are() {
        let p = SettingsPatch { window_radius: Some(99), ..SettingsPatch::default() };
        assert!(p.check().unwrap_err().starts_with("window_radius: "));
        let p = SettingsPatch { coherence_um: Some(f64::INFINITY), ..SettingsPatch::default() };
        assert!(p.check().unwrap_err().starts_with("coherence_um: "));
        assert!(SettingsPatch::default().check().is_ok());
    }

    #[test]
    fn labels_show_the_approach_the_shorts_and_what_a_patch_sets() {
        let s = Settings::default();
        assert_eq!(s.label(&SettingsPatch::default()), "flss N=auto Δλ=5 r=auto");
        let patch = SettingsPatch { coherence_um: Some(2.0), ..SettingsPatch::default() };
        assert_eq!(patch.apply(s).label(&patch), "flss N=auto Δλ=5 r=auto coherence_um=2");
    }
}
