//! The render loop shared by `ppm render` and `ppm converge`: when it stops ([`StopRule`]) and
//! what it counts ([`LoopTotals`], which the progress bar and the black-image diagnosis read).

use crate::signal::Interrupt;
use anyhow::Result;
use ppm_core::integrator::{PassTimes, Renderer};
use ppm_core::scene::Scene;
use std::time::Instant;

/// When a render stops: after `iterations`, or after the iteration that crosses `time_limit`
/// seconds of render time, whichever comes first.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StopRule {
    pub iterations: Option<u64>,
    pub time_limit: Option<f64>,
}

impl StopRule {
    /// True when a render with these totals is finished.
    pub fn done(&self, iterations: u64, seconds: f64) -> bool {
        self.iterations.is_some_and(|n| iterations >= n)
            || self.time_limit.is_some_and(|t| seconds >= t)
    }
}

/// Counts over all iterations so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoopTotals {
    pub iterations: u64,
    /// Render time: the sum of the iterations' times, without the observer's work.
    pub seconds: f64,
    pub rays: u64,
    /// Closest-hit rays of the photon pass (included in `rays`).
    pub photon_rays: u64,
    pub shadow_rays: u64,
    pub light_paths: u64,
    pub photons: u64,
    /// Render time by pass.
    pub passes: PassTimes,
    /// True if the loop stopped because of an interrupt.
    pub interrupted: bool,
}

/// Renders iterations until `stop` says so or `interrupt` is raised, calling `after` after each
/// with the renderer, the totals and whether it was the last iteration. The time `after` takes
/// (error measurement, checkpoints) is not render time.
///
/// An interrupt abandons the iteration in progress (its passes poll the flag), so a stop
/// request is seen within one parallel work item even when an iteration is very long; the
/// renderer's image stays the average of the finished iterations. `after` is then called once
/// more with `last` set, for the final measurement, if any iteration finished.
pub fn render_loop(
    scene: &Scene,
    renderer: &mut Renderer,
    stop: &StopRule,
    interrupt: &Interrupt,
    mut after: impl FnMut(&Renderer, &LoopTotals, bool) -> Result<()>,
) -> Result<LoopTotals> {
    let mut totals = LoopTotals::default();
    while !stop.done(totals.iterations, totals.seconds) && !interrupt.requested() {
        let start = Instant::now();
        let Some(stats) = renderer.iterate_until(scene, &|| interrupt.requested()) else {
            if totals.iterations > 0 {
                after(renderer, &totals, true)?;
            }
            break;
        };
        totals.seconds += start.elapsed().as_secs_f64();
        totals.iterations += 1;
        totals.rays += stats.rays;
        totals.photon_rays += stats.photon_rays;
        totals.shadow_rays += stats.shadow_rays;
        totals.light_paths += stats.light_paths;
        totals.photons += stats.photons;
        totals.passes.add(&stats.passes);
        let last = stop.done(totals.iterations, totals.seconds) || interrupt.requested();
        after(renderer, &totals, last)?;
    }
    totals.interrupted = interrupt.requested();
    Ok(totals)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stop_rule_stops_at_the_first_limit_reached() {
        let n = StopRule {
            iterations: Some(3),
            time_limit: None,
        };
        assert!(!n.done(2, 1e9) && n.done(3, 0.0));
        let t = StopRule {
            iterations: None,
            time_limit: Some(1.5),
        };
        assert!(!t.done(1_000_000, 1.49) && t.done(1, 1.5));
        let both = StopRule {
            iterations: Some(10),
            time_limit: Some(1.0),
        };
        assert!(both.done(10, 0.1) && both.done(2, 1.0) && !both.done(9, 0.9));
        assert!(
            !StopRule::default().done(u64::MAX, f64::MAX),
            "no limit: only an interrupt stops"
        );
    }
}
