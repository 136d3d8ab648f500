//! The command line. Flags are a contract with users' scripts: rename nothing.
//!
//! Rendering is the default: `ppm scene.yml -n 100` and `ppm render scene.yml -n 100` are the
//! same. A scene file named like a subcommand (`compare`, `converge`, `convert`, `merge`, `render`) can
//! still be rendered as `ppm ./compare`.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, Parser, Subcommand, ValueEnum};
use ppm_core::camera::MAX_RESOLUTION;
use ppm_core::integrator::{Algorithm, Aov, DirectMode, LightStrategy, Radius};
use std::path::PathBuf;

const AFTER_HELP: &str = "\
Output: a PNG (8-bit sRGB) and a linear float EXR with the same stem are always both written.

Exit status: 0 on success, 1 on an error, 2 on bad command-line usage, 130 when a render was
stopped by Ctrl-C, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2 or SIGXCPU (the iteration in progress is abandoned and the image of
all finished iterations written; with none finished nothing is written; a second signal, a
second or more after the first, quits at once without writing).";

/// Progressive photon mapping and path tracing renderer.
#[derive(Parser, Debug)]
#[command(
    name = "ppm",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true,
    // `--seed -1` is a value out of range, reported as such, not an unknown option `-1`.
    allow_negative_numbers = true,
    // Bare `ppm` prints the help, which lists the subcommands, not only `Usage: ppm <SCENE>`.
    arg_required_else_help = true,
    after_help = AFTER_HELP
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub render: RenderArgs,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (the default when no subcommand is given).
    Render(RenderArgs),
    /// Compare two images: relMSE, RMSE and trimmed relMSE of A against the reference B.
    Compare(CompareArgs),
    /// Run algorithms for the same time budget and plot relMSE against time.
    Converge(ConvergeArgs),
    /// Print what an EXR image records: size, channels and every header attribute.
    Info(InfoArgs),
    /// Join the EXRs of shards (or consecutive slices) of one render into the image of the
    /// whole render, bit for bit.
    Merge(MergeArgs),
    /// Write a scene (YAML, Mitsuba XML or pbrt-v4) as scene format v1: what ppm understood
    /// of it, to read and edit; meshes and images go to `<OUT stem>_files/` beside it.
    Convert(ConvertArgs),
}

/// Iterations rendered when neither `-n` nor `--time-limit` is given.
pub const DEFAULT_ITERATIONS: u64 = 32;

#[derive(Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file (YAML); when not found as given, looked up in ./scenes, $PPM_SCENES, the
    /// scenes installed beside the binary and the source tree's scenes/.
    #[arg(required_unless_present = "resume")]
    pub scene: Option<PathBuf>,
    /// Iterations to render [default: 32, or unlimited with --time-limit]. Each iteration
    /// traces one camera path per pixel (pt: one sample per pixel; ppm: plus a photon pass).
    #[arg(short = 'n', long, value_parser = clap::value_parser!(u64).range(1..), allow_negative_numbers = true)]
    pub iterations: Option<u64>,
    /// Path tracing: samples per pixel, the same as -n (one sample per pixel per iteration);
    /// refused for ppm, where an iteration is more than a sample (use -n).
    #[arg(long, value_name = "N", conflicts_with = "iterations", value_parser = clap::value_parser!(u64).range(1..), allow_negative_numbers = true)]
    pub spp: Option<u64>,
    /// Output image: out.png, out.exr or out all write out.png + out.exr; a missing folder
    /// is created [default: <scene stem>.png/.exr in the current folder]. `--outfile`
    /// (pbrt's name) is the same flag.
    #[arg(short, long, value_name = "PATH", alias = "outfile")]
    pub output: Option<PathBuf>,
    /// Integrator [default: the scene's `render.algorithm`, else ppm].
    #[arg(short, long, value_parser = algorithm_parser())]
    pub algorithm: Option<Algorithm>,
    #[command(flatten)]
    pub settings: SettingsArgs,
    /// Stop after the iteration that crosses this much render time (seconds).
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds, allow_negative_numbers = true)]
    pub time_limit: Option<f64>,
    /// Also write the current image every this many seconds.
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds, allow_negative_numbers = true)]
    pub checkpoint: Option<f64>,
    /// Reference image (EXR, HDR, or PNG decoded from sRGB) to measure the error against;
    /// sets the default resolution.
    #[arg(long, value_name = "REF.exr")]
    pub reference: Option<PathBuf>,
    /// CSV of iteration,seconds,relmse,rmse, written during the render (needs --reference).
    #[arg(long, value_name = "CSV", requires = "reference")]
    pub error_log: Option<PathBuf>,
    /// Render only this window, in fractions of the image from the top-left corner (pbrt's
    /// convention); the output image is the window's size.
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"], allow_negative_numbers = true, conflicts_with_all = ["pixelbounds", "reference"])]
    pub cropwindow: Option<Vec<f64>>,
    /// Render only pixels X0..X1 by Y0..Y1 (half-open, from the top-left corner); the output
    /// image is the window's size.
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"], conflicts_with = "reference")]
    pub pixelbounds: Option<Vec<u32>>,
    /// Stream the image to a tev viewer listening at HOST:PORT (tev's default port is 14158).
    #[arg(long, value_name = "HOST:PORT")]
    pub display_server: Option<String>,
    /// Print only warnings and errors (no progress bar, no summary).
    #[arg(short, long, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Also print the settings used before rendering and where the scene was found.
    #[arg(short, long)]
    pub verbose: bool,
    /// Extra images written next to the render (photon mapping): `radius` writes
    /// <output>.radius.exr, each pixel's gather radius in the last iteration (scene units);
    /// `photons` writes <output>.photons.exr, how many photons each pixel's estimate rests on
    /// (sppm: its accumulated count N; ppm: the last iteration's photons in its radius).
    #[arg(long, value_enum, value_name = "NAME")]
    pub aov: Vec<AovArg>,
    /// Render only slice I (0-based) of K equal slices of the -n iterations; join the K
    /// EXRs with `ppm merge`.
    #[arg(long, value_name = "I/K", allow_hyphen_values = true, value_parser = crate::provenance::parse_shard_arg, requires = "iterations")]
    pub shard: Option<(u64, u64)>,
    /// Continue the render saved in this EXR (a finished image or a checkpoint) for -n more
    /// iterations; the scene and settings not given are the file's (those given must agree).
    #[arg(long, value_name = "FILE.exr")]
    pub resume: Option<PathBuf>,
}

/// `NAME=VALUE` of `-D`: a parameter name as Mitsuba's `$name` spells it, and any value.
fn parse_define(s: &str) -> Result<(String, String), String> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| format!("`{s}` is not NAME=VALUE"))?;
    let valid = !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !valid {
        return Err(format!(
            "`{name}` is not a parameter name (letters, digits and _)"
        ));
    }
    Ok((name.to_string(), value.to_string()))
}

/// Extra images (arbitrary output variables) a render can write.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovArg {
    /// Each pixel's gather radius in the last iteration, in scene units (grey EXR).
    Radius,
    /// How many photons each pixel's estimate rests on (grey EXR): sppm's accumulated count
    /// N, or for ppm the last iteration's photons within the pixel's radius at its first
    /// diffuse visible point.
    Photons,
}

impl AovArg {
    /// The image it names.
    pub fn aov(self) -> Aov {
        match self {
            AovArg::Radius => Aov::Radius,
            AovArg::Photons => Aov::Photons,
        }
    }

    /// The tag in the file name: `<output>.<name>.exr`.
    pub fn name(self) -> &'static str {
        match self {
            AovArg::Radius => "radius",
            AovArg::Photons => "photons",
        }
    }
}

#[derive(Args, Debug, Clone)]
pub struct InfoArgs {
    /// The EXR image.
    pub image: PathBuf,
}

/// Settings shared by `render` and `converge`; unset ones come from the scene file.
#[derive(Args, Debug, Clone, Default)]
pub struct SettingsArgs {
    /// Image width (without --height the scene's aspect ratio is kept).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_RESOLUTION as i64), allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Image height (without --width the scene's aspect ratio is kept).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_RESOLUTION as i64), allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// Seed of all random numbers (converge: the first of --seeds consecutive seeds)
    /// [default: 0, or the --resume file's].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Mitsuba XML scenes: give the scene's parameter `$NAME` this value, over its
    /// `<default>` (as `mitsuba -D NAME=VALUE`); repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Worker threads [default: all cores] (-t is threads, as in Mitsuba, not a time limit).
    #[arg(short = 't', long, value_parser = clap::value_parser!(u64).range(1..=4096), allow_negative_numbers = true)]
    pub threads: Option<u64>,
    /// ppm and sppm: light paths per iteration [default: scene file, else 200000 for ppm
    /// and one per pixel for sppm].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..), allow_negative_numbers = true)]
    pub photons: Option<u32>,
    /// ppm, sppm and vcm: initial gather radius in scene units, or `photons` (each pixel's
    /// distance to its 32nd nearest photon of a pilot photon map), or `footprint` = `auto`
    /// (2 pixel widths at its first diffuse visible point) [default: scene file, or photons].
    #[arg(long, value_name = "R|photons|footprint|auto", value_parser = gather_radius, allow_negative_numbers = true)]
    pub radius: Option<Radius>,
    /// ppm, sppm and vcm: radius reduction alpha in (0, 1].
    #[arg(long, value_parser = unit_interval, allow_negative_numbers = true)]
    pub alpha: Option<f32>,
    /// Most bounces between camera and light, for every algorithm (0: only light seen
    /// directly; Mitsuba's max_depth minus 1; above 1024 used as 1024).
    #[arg(long, value_parser = depth, allow_negative_numbers = true)]
    pub max_depth: Option<u32>,
    /// ppm and sppm: direct light from photons or by light sampling [default: sampled, the
    /// lower equal-time error measured on the Cornell box scenes]
    #[arg(long, value_enum)]
    pub direct: Option<DirectArg>,
    /// pt: how light is found (only mis is meant for production).
    #[arg(long, value_enum)]
    pub light_strategy: Option<LightStrategyArg>,
}

#[derive(Args, Debug, Clone)]
pub struct CompareArgs {
    /// The image to measure (EXR, or PNG decoded to linear).
    pub a: PathBuf,
    /// The reference image.
    pub b: PathBuf,
}

#[derive(Args, Debug, Clone)]
pub struct ConvergeArgs {
    /// Scene file (YAML); looked up in scenes/ when not found as given.
    pub scene: PathBuf,
    /// Reference image (EXR, HDR, or PNG decoded from sRGB); the renders use its resolution. Render it with a seed outside
    /// the ones used here (--seed .. --seed + --seeds - 1): a shared seed correlates its
    /// noise with the runs' and understates their error.
    #[arg(long, value_name = "REF.exr")]
    pub reference: PathBuf,
    /// Render time per algorithm and seed, in seconds.
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds, allow_negative_numbers = true)]
    pub time_limit: f64,
    /// Algorithms to run, comma-separated.
    #[arg(short, long, value_parser = algorithm_parser(), value_delimiter = ',', default_values_t = [Algorithm::Path, Algorithm::Ppm])]
    pub algorithm: Vec<Algorithm>,
    /// Seeds per algorithm (K > 1 draws the min/max band over seeds).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000), allow_negative_numbers = true)]
    pub seeds: u32,
    /// Folder for <scene stem>_convergence.csv and .png.
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub out: PathBuf,
    #[command(flatten)]
    pub settings: SettingsArgs,
}

#[derive(Args, Debug, Clone)]
pub struct MergeArgs {
    /// The EXRs of the parts (`--shard` renders or consecutive `--resume` slices), any order.
    #[arg(required = true, value_name = "PART.exr")]
    pub parts: Vec<PathBuf>,
    /// Output image: out.png, out.exr or out all write out.png + out.exr; a missing folder
    /// is created. `--outfile` (pbrt's name) is the same flag.
    #[arg(short, long, value_name = "PATH", required = true, alias = "outfile")]
    pub output: PathBuf,
}

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The scene to convert: .xml (Mitsuba), .pbrt (pbrt-v4) or .yml; looked up as a
    /// render's scene is.
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The YAML file to write; its meshes and images go to the folder `<OUT stem>_files/`
    /// beside it.
    #[arg(short, long, value_name = "OUT.yml", required = true)]
    pub output: PathBuf,
    /// Mitsuba XML scenes: give the scene's parameter `$NAME` this value, over its
    /// `<default>` (as `mitsuba -D NAME=VALUE`); repeatable.
    #[arg(short = 'D', value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
}

/// The `-a` values: every name and alias of [`Algorithm::TABLE`], each name with its line of
/// description in `--help`.
fn algorithm_parser() -> impl TypedValueParser<Value = Algorithm> {
    let values = Algorithm::TABLE.iter().map(|entry| {
        PossibleValue::new(entry.name)
            .aliases(entry.aliases.iter().copied())
            .help(entry.description)
    });
    PossibleValuesParser::new(values).map(|name| match name.parse() {
        Ok(algorithm) => algorithm,
        Err(_) => unreachable!("the possible values are the table's names"),
    })
}

/// The algorithm a render uses: `-a` if given, else the scene's `render.algorithm`, else
/// [`Algorithm::DEFAULT`].
pub fn resolve_algorithm(given: Option<Algorithm>, scene: Option<Algorithm>) -> Algorithm {
    given.or(scene).unwrap_or(Algorithm::DEFAULT)
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectArg {
    /// Direct light by density estimation of first-bounce photons.
    Photons,
    /// Direct light by light sampling at the gather point.
    Sampled,
}

impl From<DirectArg> for DirectMode {
    fn from(d: DirectArg) -> Self {
        match d {
            DirectArg::Photons => DirectMode::Photons,
            DirectArg::Sampled => DirectMode::Sampled,
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightStrategyArg {
    /// Light and BSDF sampling combined by the power heuristic.
    Mis,
    /// Light sampling only.
    Light,
    /// BSDF sampling only.
    Bsdf,
}

impl From<LightStrategyArg> for LightStrategy {
    fn from(s: LightStrategyArg) -> Self {
        match s {
            LightStrategyArg::Mis => LightStrategy::Mis,
            LightStrategyArg::Light => LightStrategy::LightOnly,
            LightStrategyArg::Bsdf => LightStrategy::BsdfOnly,
        }
    }
}

fn parse_f64(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| format!("'{s}' is not a number"))
}

/// A duration in seconds: finite and > 0.
fn positive_seconds(s: &str) -> Result<f64, String> {
    let v = parse_f64(s)?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s} is not a positive number of seconds"))
    }
}

/// A finite value > 0.
fn positive_finite(s: &str) -> Result<f32, String> {
    let v = parse_f64(s)? as f32;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("{s} must be a finite number > 0"))
    }
}

/// `photons`, `footprint` or its older name `auto`, or a finite number > 0.
pub(crate) fn gather_radius(s: &str) -> Result<Radius, String> {
    match s {
        "photons" => return Ok(Radius::Photons),
        "auto" | "footprint" => return Ok(Radius::Auto),
        _ => {}
    }
    positive_finite(s)
        .map(Radius::World)
        .map_err(|_| format!("{s} must be a finite number > 0, `photons`, `footprint` or `auto`"))
}

/// A value in (0, 1].
/// A number of bounces: any whole number from 0 on; one above what a `u32` holds is kept as
/// `u32::MAX`, which the render lowers to the supported maximum with a warning.
fn depth(s: &str) -> Result<u32, String> {
    use ppm_core::integrator::MAX_DEPTH;
    match s.trim().parse::<u128>() {
        Ok(n) => Ok(n.min(u32::MAX.into()) as u32),
        Err(_) => Err(format!(
            "{s} is not a number of bounces: expected a whole number >= 0 (above {MAX_DEPTH} \
             used as {MAX_DEPTH})"
        )),
    }
}

fn unit_interval(s: &str) -> Result<f32, String> {
    let v = parse_f64(s)? as f32;
    if v > 0.0 && v <= 1.0 {
        Ok(v)
    } else {
        Err(format!("{s} must be in (0, 1]"))
    }
}

#[cfg(test)]
mod tests;
