//! SmallVCM's other algorithms as integrators of their own: `bpt`, `bpm` and `lt` are VCM's
//! render state with a fixed technique set ([`Techniques`]), so the front end names, shards,
//! resumes and estimates them as it does `vcm`. The estimators and their MIS weights are VCM's
//! (see `techniques.rs` and docs/vcm.md); nothing here changes what an iteration computes.

use super::{Techniques, VcmRenderer};
use crate::film::Film;
use crate::integrator::{
    Features, Integrator, IterationStats, MemoryEstimate, RenderSettings, RenderStart, Stop,
};
use crate::scene::Scene;
use glam::Vec3;
use std::marker::PhantomData;
use std::ops::Range;

/// A technique set fixed at compile time, one per registered subset.
pub trait TechniqueSet: Send + Sync + 'static {
    /// The set an iteration runs.
    const TECHNIQUES: Techniques;
}

/// Bidirectional path tracing ([`Techniques::BPT`]).
pub struct Bpt;
/// Bidirectional photon mapping ([`Techniques::BPM`]).
pub struct Bpm;
/// Light tracing ([`Techniques::LT`]).
pub struct Lt;

impl TechniqueSet for Bpt {
    const TECHNIQUES: Techniques = Techniques::BPT;
}
impl TechniqueSet for Bpm {
    const TECHNIQUES: Techniques = Techniques::BPM;
}
impl TechniqueSet for Lt {
    const TECHNIQUES: Techniques = Techniques::LT;
}

/// VCM's render state restricted to the technique set `S`.
pub struct VcmSubset<S: TechniqueSet> {
    vcm: VcmRenderer,
    set: PhantomData<S>,
}

/// The render state of `-a bpt`.
pub type BptRenderer = VcmSubset<Bpt>;
/// The render state of `-a bpm`.
pub type BpmRenderer = VcmSubset<Bpm>;
/// The render state of `-a lt`.
pub type LtRenderer = VcmSubset<Lt>;

impl<S: TechniqueSet> Integrator for VcmSubset<S> {
    /// VCM's: no AOVs, shards and resumes (an iteration depends on (seed, i) alone).
    fn features() -> Features {
        VcmRenderer::features()
    }

    fn memory_estimate(width: u32, height: u32, settings: &RenderSettings) -> MemoryEstimate {
        VcmRenderer::memory_estimate_with_techniques(width, height, settings, S::TECHNIQUES)
    }

    /// VCM's words with a merge radius; without merging, no radius to state.
    fn settings_words(settings: &RenderSettings, image: Range<u64>) -> String {
        if S::TECHNIQUES.merging() {
            VcmRenderer::settings_words(settings, image)
        } else {
            format!(
                "seed {}, one light path per pixel per iteration",
                settings.seed
            )
        }
    }

    fn start(start: RenderStart) -> Self {
        VcmSubset {
            vcm: VcmRenderer::start_with(start, S::TECHNIQUES),
            set: PhantomData,
        }
    }

    fn iterate_until(&mut self, scene: &Scene, stop: Stop) -> Option<IterationStats> {
        self.vcm.iterate_until(scene, stop)
    }

    fn film(&self) -> &Film {
        self.vcm.film()
    }

    fn last_estimates(&self) -> &[Vec3] {
        self.vcm.last_estimates()
    }

    fn memory_bytes(&self) -> usize {
        self.vcm.memory_bytes()
    }
}
