//! Which integrator renders the image: the [`Algorithm`] type and its table, the one place
//! that names each integrator for the command line (`-a`), the scene format
//! (`render: { algorithm: ... }`), the saved renders' provenance and the benchmarks.

/// Which integrator renders the image. Each variant has one line in [`Algorithm::TABLE`]
/// and one in the integrator registration (`integrator/renderer.rs`). Saved renders record
/// the table's names and scene fingerprints the variants' spellings: never rename either.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Algorithm {
    /// Unidirectional path tracing with next-event estimation and MIS (`-a pt`).
    Path,
    /// Progressive photon mapping (`-a ppm`, the default).
    Ppm,
    /// Stochastic progressive photon mapping (`-a sppm`): per-pixel radii and statistics,
    /// the camera paths' visible points gather the photons of one batch of light paths at a
    /// time, so memory grows with the pixels only.
    Sppm,
    /// Vertex connection and merging (`-a vcm`, Georgiev et al. 2012): bidirectional path
    /// tracing and photon mapping combined by MIS; one light subpath per pixel per iteration.
    Vcm,
    /// Bidirectional path tracing (`-a bpt`): VCM's connection techniques and light tracing,
    /// no merging (Veach 1997, ch. 10; SmallVCM's `bpt`).
    Bpt,
    /// Bidirectional photon mapping (`-a bpm`): merging at every non-delta camera vertex,
    /// weighted by MIS over the merges (Georgiev et al. 2012, sec. 4; SmallVCM's `bpm`).
    Bpm,
    /// Light tracing (`-a lt`): light subpaths connected to the camera; camera rays only
    /// take the emission they see through delta lobes (SmallVCM's `lt`).
    Lt,
}

/// A render setting that some integrators read and the others ignore (the seed, the depths
/// and the resolution every integrator reads).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Setting {
    /// [`super::RenderSettings::photons`] (`--photons`).
    Photons,
    /// [`super::RenderSettings::radius`] (`--radius`).
    Radius,
    /// [`super::RenderSettings::alpha`] (`--alpha`).
    Alpha,
    /// [`super::RenderSettings::direct`] (`--direct`).
    Direct,
    /// [`super::RenderSettings::light_strategy`] (`--light-strategy`).
    LightStrategy,
}

impl Setting {
    /// Every setting that not all integrators read.
    pub const ALL: [Setting; 5] = [
        Setting::Photons,
        Setting::Radius,
        Setting::Alpha,
        Setting::Direct,
        Setting::LightStrategy,
    ];
}

/// One line of [`Algorithm::TABLE`].
#[derive(Clone, Copy, Debug)]
pub struct AlgorithmEntry {
    pub algorithm: Algorithm,
    /// The name on the command line, in scene files, in saved renders and in CSV files.
    pub name: &'static str,
    /// Other spellings accepted wherever the name is.
    pub aliases: &'static [&'static str],
    /// One line for `--help`.
    pub description: &'static str,
    /// The settings it reads besides the seed, the depths and the resolution (see
    /// [`Algorithm::reads`]).
    pub reads: &'static [Setting],
}

/// The name given matches no algorithm.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown algorithm `{0}`: expected one of {names}", names = Algorithm::NAMES.join(", "))]
pub struct UnknownAlgorithm(pub String);

impl Algorithm {
    /// The integrator of a render that names none (on the command line or in the scene).
    pub const DEFAULT: Algorithm = Algorithm::Ppm;

    /// Every integrator, one line each, in the order of the variants.
    pub const TABLE: &'static [AlgorithmEntry] = &[
        AlgorithmEntry {
            algorithm: Algorithm::Path,
            name: "pt",
            aliases: &["path"],
            description: "Path tracing with next-event estimation and MIS.",
            reads: &[Setting::LightStrategy],
        },
        AlgorithmEntry {
            algorithm: Algorithm::Ppm,
            name: "ppm",
            aliases: &[],
            description: "Progressive photon mapping.",
            reads: &[
                Setting::Photons,
                Setting::Direct,
                Setting::Radius,
                Setting::Alpha,
            ],
        },
        AlgorithmEntry {
            algorithm: Algorithm::Sppm,
            name: "sppm",
            aliases: &[],
            description: "Stochastic progressive photon mapping (per-pixel radii; photons never \
                          stored).",
            reads: &[
                Setting::Photons,
                Setting::Direct,
                Setting::Radius,
                Setting::Alpha,
            ],
        },
        AlgorithmEntry {
            algorithm: Algorithm::Vcm,
            name: "vcm",
            aliases: &[],
            description: "Vertex connection and merging: bidirectional path tracing and photon \
                          mapping by MIS.",
            reads: &[Setting::Radius, Setting::Alpha],
        },
        AlgorithmEntry {
            algorithm: Algorithm::Bpt,
            name: "bpt",
            aliases: &[],
            description: "Bidirectional path tracing (VCM without merging).",
            reads: &[],
        },
        AlgorithmEntry {
            algorithm: Algorithm::Bpm,
            name: "bpm",
            aliases: &[],
            description: "Bidirectional photon mapping (VCM's merging alone, by MIS).",
            reads: &[Setting::Radius, Setting::Alpha],
        },
        AlgorithmEntry {
            algorithm: Algorithm::Lt,
            name: "lt",
            aliases: &[],
            description: "Light tracing: light paths connected to the camera (incomplete behind \
                          mirrors and glass).",
            reads: &[],
        },
    ];

    /// Every integrator, for tests and harnesses that check each one: a new integrator
    /// added to [`Algorithm::TABLE`] gets all of their checks.
    pub const ALL: [Algorithm; Self::TABLE.len()] = {
        let mut all = [Algorithm::Path; Self::TABLE.len()];
        let mut i = 0;
        while i < all.len() {
            all[i] = Self::TABLE[i].algorithm;
            i += 1;
        }
        all
    };

    /// Every integrator's name, in table order (for "expected one of" messages).
    pub const NAMES: [&'static str; Self::TABLE.len()] = {
        let mut names = [""; Self::TABLE.len()];
        let mut i = 0;
        while i < names.len() {
            names[i] = Self::TABLE[i].name;
            i += 1;
        }
        names
    };

    /// This integrator's line of the table.
    pub fn entry(self) -> &'static AlgorithmEntry {
        &Self::TABLE[self as usize]
    }

    /// The name on the command line, in scene files and in saved renders (`pt`, `ppm`, ...).
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// True if the integrator reads `setting`; an integrator that does not renders the same
    /// image whatever its value (the test `each_integrator_reads_the_settings_it_declares`
    /// renders both ways). The path tracer traces no photons and merges nothing; VCM traces
    /// one light path per pixel and lights every vertex by its own MIS (no `photons`, no
    /// `direct`); the photon mappers take the light strategy of their eye paths as fixed.
    pub fn reads(self, setting: Setting) -> bool {
        self.entry().reads.contains(&setting)
    }
}

/// The table is indexed by the variant: line i holds the variant of discriminant i.
const _: () = {
    let mut i = 0;
    while i < Algorithm::TABLE.len() {
        assert!(Algorithm::TABLE[i].algorithm as usize == i);
        i += 1;
    }
};

impl std::str::FromStr for Algorithm {
    type Err = UnknownAlgorithm;

    /// A name or an alias of [`Algorithm::TABLE`], exactly as written there.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::TABLE
            .iter()
            .find(|e| e.name == s || e.aliases.contains(&s))
            .map(|e| e.algorithm)
            .ok_or_else(|| UnknownAlgorithm(s.to_string()))
    }
}

impl std::fmt::Display for Algorithm {
    /// The name ([`Algorithm::name`]).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_and_alias_parses_to_its_algorithm() {
        for entry in Algorithm::TABLE {
            assert_eq!(entry.algorithm.name(), entry.name);
            assert_eq!(entry.name.parse::<Algorithm>(), Ok(entry.algorithm));
            assert_eq!(entry.algorithm.to_string().parse(), Ok(entry.algorithm));
            for alias in entry.aliases {
                assert_eq!(alias.parse::<Algorithm>(), Ok(entry.algorithm), "{alias}");
            }
        }
        let e = "mlt".parse::<Algorithm>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "unknown algorithm `mlt`: expected one of pt, ppm, sppm, vcm, bpt, bpm, lt"
        );
        assert!("PPM".parse::<Algorithm>().is_err(), "names are exact");
    }

    #[test]
    fn names_and_aliases_are_unique() {
        let mut all: Vec<&str> = Algorithm::TABLE
            .iter()
            .flat_map(|e| std::iter::once(e.name).chain(e.aliases.iter().copied()))
            .collect();
        let n = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), n);
    }
}
