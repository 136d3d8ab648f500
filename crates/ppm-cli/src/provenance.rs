//! Where an image came from: the header attributes every EXR of a render carries (as pbrt-v4
//! records its settings), and the rule that decides whether two images are renders of the
//! same thing (`--resume`, `ppm merge`).

use crate::camera_matrices::CameraMatrices;
use anyhow::{bail, Context, Result};
use ppm_core::integrator::{Algorithm, DirectMode, LightStrategy, RenderSettings, Setting};
use std::collections::BTreeMap;
use std::fmt;

/// The version of the saved render state (attributes and channels): bumped when their meaning
/// changes, so that a file is refused rather than misread by a ppm that does not know it.
/// Format 2 writes only the words of the film's sums that are not zero everywhere
/// (`ppm.sumWords`, see `state_file`); format 1 always wrote all four.
pub const STATE_FORMAT: &str = "2";
/// The state formats this ppm reads: its own and every earlier one.
pub const READABLE_STATE_FORMATS: [&str; 2] = ["1", "2"];

/// Which slice of a render a shard is: `--shard index/count` of `-n total` iterations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 0-based.
    pub index: u64,
    pub count: u64,
    /// Iterations of the whole render.
    pub total: u64,
}

impl Shard {
    /// The iterations of this slice, `first..end`: slice i of K of N is
    /// floor(N i / K)..floor(N (i + 1) / K), so the K slices tile 0..N without gaps or
    /// overlaps and differ in length by at most one.
    pub fn range(&self) -> (u64, u64) {
        let at = |i: u64| ((self.total as u128 * i as u128) / self.count as u128) as u64;
        (at(self.index), at(self.index + 1))
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{} of {}", self.index, self.count, self.total)
    }
}

/// Everything recorded about a render, written as EXR header attributes named `ppm.*`.
#[derive(Clone, Debug, PartialEq)]
pub struct Provenance {
    /// The ppm version that rendered it.
    pub version: String,
    /// The scene file as given on the command line.
    pub scene: String,
    /// [`ppm_scene::content_hash`] of the loaded scene, 16 hex digits.
    pub scene_hash: String,
    pub algorithm: String,
    pub seed: u64,
    pub width: u32,
    pub height: u32,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub light_strategy: String,
    pub direct: String,
    /// Light paths per photon-mapping iteration.
    pub photons: u32,
    /// The initial radius as the command line spells it: r_1 in scene units, or `auto` (each
    /// pixel's from its footprint); `ppm` then follows r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1).
    pub radius: String,
    pub alpha: f32,
    /// The image averages iterations first_iteration..first_iteration + iterations.
    pub first_iteration: u64,
    pub iterations: u64,
    /// Samples dropped as NaN, infinite or negative, and the (iteration, pixel) of the first.
    pub rejected: u64,
    pub first_rejected: Option<(u64, u32)>,
    /// Render time summed over every run that contributed (resumed runs, merged shards).
    pub render_seconds: f64,
    /// Worker threads of each run that contributed, comma-separated.
    pub threads: String,
    /// The slice this image renders, when rendered with `--shard`.
    pub shard: Option<Shard>,
    /// The pixels a `--cropwindow` / `--pixelbounds` render covers, `x0 x1 y0 y1 of WxH`: a
    /// part of the image, which is never resumed or merged as a whole one.
    pub crop: Option<String>,
    /// The camera as pbrt-v4 records it (`worldToCamera`, `worldToNDC`), when known: set
    /// from the scene by a render, carried over by `--resume` and `ppm merge` from files
    /// that have it. Not a `ppm.*` attribute: not compared, not in the state checksum.
    pub camera: Option<CameraMatrices>,
}

/// The setting an attribute of [`Provenance::identity`] records, if not every algorithm
/// reads it.
fn setting_named(attribute: &str) -> Option<Setting> {
    match attribute {
        "ppm.lightStrategy" => Some(Setting::LightStrategy),
        "ppm.direct" => Some(Setting::Direct),
        "ppm.photons" => Some(Setting::Photons),
        "ppm.radius" => Some(Setting::Radius),
        "ppm.alpha" => Some(Setting::Alpha),
        _ => None,
    }
}

/// Short names for the settings enums, as on the command line (an algorithm's is
/// [`Algorithm::name`]).
fn light_strategy_name(s: LightStrategy) -> &'static str {
    match s {
        LightStrategy::Mis => "mis",
        LightStrategy::LightOnly => "light",
        LightStrategy::BsdfOnly => "bsdf",
    }
}

fn direct_name(d: DirectMode) -> &'static str {
    match d {
        DirectMode::Photons => "photons",
        DirectMode::Sampled => "sampled",
    }
}

impl Provenance {
    /// The record of a render of `scene` (hash `scene_hash`) with `settings` at `width` x
    /// `height`; the iteration counts and times are filled in when the image is written.
    pub fn new(
        scene: &str,
        scene_hash: u64,
        settings: &RenderSettings,
        (width, height): (u32, u32),
        threads: usize,
    ) -> Self {
        Provenance {
            version: env!("CARGO_PKG_VERSION").to_string(),
            scene: scene.to_string(),
            scene_hash: format!("{scene_hash:016x}"),
            algorithm: settings.algorithm.name().to_string(),
            seed: settings.seed,
            width,
            height,
            max_depth: settings.max_depth,
            rr_depth: settings.rr_depth,
            light_strategy: light_strategy_name(settings.light_strategy).to_string(),
            direct: direct_name(settings.direct).to_string(),
            photons: settings.photons,
            radius: settings.radius.to_string(),
            alpha: settings.alpha,
            first_iteration: 0,
            iterations: 0,
            rejected: 0,
            first_rejected: None,
            render_seconds: 0.0,
            threads: threads.to_string(),
            shard: None,
            crop: None,
            camera: None,
        }
    }

    /// What must be equal for two images to be parts of one render: (attribute, value). The
    /// scene file's name, times, threads and iteration ranges are not in it.
    pub fn identity(&self) -> Vec<(&'static str, String)> {
        vec![
            ("ppm.version", self.version.clone()),
            ("ppm.sceneHash", self.scene_hash.clone()),
            ("ppm.algorithm", self.algorithm.clone()),
            ("ppm.seed", self.seed.to_string()),
            ("resolution", format!("{}x{}", self.width, self.height)),
            ("ppm.maxDepth", self.max_depth.to_string()),
            ("ppm.rrDepth", self.rr_depth.to_string()),
            ("ppm.lightStrategy", self.light_strategy.clone()),
            ("ppm.direct", self.direct.clone()),
            ("ppm.photons", self.photons.to_string()),
            ("ppm.radius", self.radius.to_string()),
            ("ppm.alpha", self.alpha.to_string()),
        ]
    }

    /// The first setting in which `self` differs from `other`, as
    /// "<attribute>: <self's value> vs <other's value>", or None if they are parts of one
    /// render.
    ///
    /// A setting the algorithm does not read ([`Algorithm::reads`]) is not compared: it
    /// changes no pixel, so a path-traced render continues with any `--photons`. (The
    /// algorithm itself is compared before any setting.)
    pub fn difference(&self, other: &Provenance) -> Option<String> {
        let algorithm = self.algorithm.parse::<Algorithm>().ok();
        let read = |name: &str| match (algorithm, setting_named(name)) {
            (Some(a), Some(setting)) => a.reads(setting),
            _ => true,
        };
        self.identity()
            .into_iter()
            .zip(other.identity())
            .filter(|((name, _), _)| read(name))
            .find(|((_, a), (_, b))| a != b)
            .map(|((name, a), (_, b))| match name {
                "ppm.sceneHash" => format!(
                    "scene content (hash {a} of {} vs {b} of {})",
                    self.scene, other.scene
                ),
                _ => format!("{name}: {a} vs {b}"),
            })
    }

    /// The `ppm.*` header attributes, by name, as text (`state_attributes` stores them typed).
    pub fn to_attributes(&self) -> BTreeMap<&'static str, String> {
        let mut a: BTreeMap<&'static str, String> = self
            .identity()
            .into_iter()
            .filter(|(name, _)| *name != "resolution")
            .collect();
        a.insert("ppm.state", STATE_FORMAT.to_string());
        a.insert("ppm.scene", self.scene.clone());
        a.insert("ppm.firstIteration", self.first_iteration.to_string());
        a.insert("ppm.iterations", self.iterations.to_string());
        a.insert("ppm.rejected", self.rejected.to_string());
        if let Some((i, p)) = self.first_rejected {
            a.insert("ppm.firstRejected", format!("{i}/{p}"));
        }
        // Milliseconds, in the shortest form that reads back (stored as a double).
        let seconds = (self.render_seconds * 1000.0).round() / 1000.0;
        a.insert("ppm.renderSeconds", seconds.to_string());
        a.insert("ppm.threads", self.threads.clone());
        if let Some(s) = self.shard {
            a.insert("ppm.shard", s.to_string());
        }
        if let Some(c) = &self.crop {
            a.insert("ppm.crop", c.clone());
        }
        a
    }

    /// Refuses to `action` (resume, merge) the image at `path` if it is a crop: its pixels are
    /// a part of the image, at other places than a whole image's of the same size.
    pub fn refuse_crop(&self, path: &std::path::Path, action: &str) -> Result<()> {
        if let Some(crop) = &self.crop {
            bail!(
                "cannot {action} {}: it is a crop (pixels {crop}), and only whole images can be \
                 resumed or merged",
                path.display()
            );
        }
        Ok(())
    }

    /// Reads the attributes written by [`Provenance::to_attributes`] of an image of
    /// `width` x `height`; errors name the attribute.
    pub fn from_attributes(
        attributes: &BTreeMap<String, String>,
        (width, height): (u32, u32),
    ) -> Result<Self> {
        let text = |name: &str| -> Result<String> {
            attributes.get(name).cloned().with_context(|| {
                format!(
                    "attribute {name} is missing (not an image saved by ppm with its render state)"
                )
            })
        };
        let state = text("ppm.state")?;
        if !READABLE_STATE_FORMATS.contains(&state.as_str()) {
            bail!(
                "saved state format {state} is not a supported format ({})",
                READABLE_STATE_FORMATS.join(", ")
            );
        }
        fn parse<T: std::str::FromStr>(name: &str, v: String) -> Result<T> {
            v.trim()
                .parse()
                .map_err(|_| anyhow::anyhow!("attribute {name}: '{v}' is not a valid value"))
        }
        let num = |name: &str| -> Result<u64> { parse(name, text(name)?) };
        let first_rejected = match attributes.get("ppm.firstRejected") {
            None => None,
            Some(v) => {
                let (i, p) = v.split_once('/').with_context(|| {
                    format!("attribute ppm.firstRejected: '{v}' is not iteration/pixel")
                })?;
                Some((
                    parse("ppm.firstRejected", i.to_string())?,
                    parse("ppm.firstRejected", p.to_string())?,
                ))
            }
        };
        let shard = match attributes.get("ppm.shard") {
            None => None,
            Some(v) => Some(parse_shard_record(v).with_context(|| {
                format!("attribute ppm.shard: '{v}' is not 'index/count of total'")
            })?),
        };
        Ok(Provenance {
            version: text("ppm.version")?,
            scene: text("ppm.scene")?,
            scene_hash: text("ppm.sceneHash")?,
            algorithm: text("ppm.algorithm")?,
            seed: num("ppm.seed")?,
            width,
            height,
            max_depth: parse("ppm.maxDepth", text("ppm.maxDepth")?)?,
            rr_depth: parse("ppm.rrDepth", text("ppm.rrDepth")?)?,
            light_strategy: text("ppm.lightStrategy")?,
            direct: text("ppm.direct")?,
            photons: parse("ppm.photons", text("ppm.photons")?)?,
            radius: text("ppm.radius")?,
            alpha: parse("ppm.alpha", text("ppm.alpha")?)?,
            first_iteration: num("ppm.firstIteration")?,
            iterations: num("ppm.iterations")?,
            rejected: num("ppm.rejected")?,
            first_rejected,
            render_seconds: parse("ppm.renderSeconds", text("ppm.renderSeconds")?)?,
            threads: text("ppm.threads")?,
            shard,
            crop: attributes.get("ppm.crop").cloned(),
            camera: None,
        })
    }
}

/// `index/count of total`, as [`Shard`] displays.
fn parse_shard_record(v: &str) -> Option<Shard> {
    let (slice, total) = v.split_once(" of ")?;
    let (index, count) = slice.split_once('/')?;
    Some(Shard {
        index: index.trim().parse().ok()?,
        count: count.trim().parse().ok()?,
        total: total.trim().parse().ok()?,
    })
}

/// Parses `--shard I/K`: 0 <= I < K.
pub fn parse_shard_arg(s: &str) -> Result<(u64, u64), String> {
    let bad = || format!("'{s}' is not I/K with 0 <= I < K (e.g. 0/4 ... 3/4)");
    let (i, k) = s.split_once('/').ok_or_else(bad)?;
    let i: u64 = i.trim().parse().map_err(|_| bad())?;
    let k: u64 = k.trim().parse().map_err(|_| bad())?;
    if k == 0 || i >= k {
        return Err(bad());
    }
    Ok((i, k))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::integrator::Radius;

    /// Two renders that differ in one setting are parts of one render exactly when their
    /// algorithm does not read it: every such setting is recorded and named to `difference`.
    #[test]
    fn only_settings_the_algorithm_reads_tell_renders_apart() {
        for algorithm in Algorithm::ALL {
            let a = RenderSettings {
                algorithm,
                seed: 1,
                max_depth: 8,
                rr_depth: 3,
                light_strategy: LightStrategy::Mis,
                photons: 1000,
                radius: Radius::World(0.1),
                alpha: 0.7,
                direct: DirectMode::Sampled,
            };
            for setting in Setting::ALL {
                let mut b = a.clone();
                match setting {
                    Setting::Photons => b.photons = 2000,
                    Setting::Radius => b.radius = Radius::Auto,
                    Setting::Alpha => b.alpha = 0.5,
                    Setting::Direct => b.direct = DirectMode::Photons,
                    Setting::LightStrategy => b.light_strategy = LightStrategy::BsdfOnly,
                }
                let record = |s: &RenderSettings| Provenance::new("s.yml", 7, s, (4, 4), 1);
                let difference = record(&a).difference(&record(&b));
                assert_eq!(
                    difference.is_some(),
                    algorithm.reads(setting),
                    "{algorithm:?}, {setting:?}: {difference:?}"
                );
            }
            let other = RenderSettings {
                seed: 2,
                ..a.clone()
            };
            let record = |s: &RenderSettings| Provenance::new("s.yml", 7, s, (4, 4), 1);
            assert!(record(&a).difference(&record(&other)).is_some());
        }
    }

    #[test]
    fn shards_tile_the_iterations() {
        for total in [1u64, 7, 10, 100, 1001] {
            for count in 1..=total.min(13) {
                let mut next = 0;
                for index in 0..count {
                    let (first, end) = Shard {
                        index,
                        count,
                        total,
                    }
                    .range();
                    assert_eq!(first, next, "{index}/{count} of {total}");
                    assert!(end > first, "{index}/{count} of {total} is empty");
                    next = end;
                }
                assert_eq!(next, total);
            }
        }
    }

    #[test]
    fn shard_arguments() {
        assert_eq!(parse_shard_arg("0/4"), Ok((0, 4)));
        assert_eq!(parse_shard_arg("3/4"), Ok((3, 4)));
        for bad in ["4/4", "1/0", "-1/3", "a/b", "3", ""] {
            assert!(parse_shard_arg(bad).is_err(), "{bad}");
        }
        let s = Shard {
            index: 2,
            count: 5,
            total: 40,
        };
        assert_eq!(parse_shard_record(&s.to_string()), Some(s));
    }
}
