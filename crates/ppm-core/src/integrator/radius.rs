//! The global radius schedule of progressive photon mapping, which ppm, sppm and vcm share.

/// The smallest initial merge radius ppm, sppm, vcm and bpm accept for a scene whose bounding
/// box has diagonal `diagonal` (scene units): the larger of two bounds from single precision.
///
/// - The disc area pi r^2 must be a normal f32 (r >= sqrt(f32::MIN_POSITIVE / pi) = 6.1e-20,
///   whatever the scene): below, pi r^2 is subnormal or 0, and the density estimate's
///   1 / (pi r^2) and VCM's merge weights (which divide by pi r^2 times the light paths)
///   overflow to infinity, so every merged sample is NaN or infinite and dropped.
/// - The disc must be larger than the resolution of positions at the scene's scale: f32
///   resolves a coordinate x only to half an ulp, a relative 2^-24, so hit points across a
///   scene of extent D are known to within about 2^-24 D. A disc of radius below 2^-24 D
///   is smaller than the rounding of the points it compares; a photon falls in it only where
///   rounding puts it (its area is 2^-48 D^2 against surfaces of order D^2: one photon in
///   10^14 at best), so the merge estimate is zero: a black image or one without indirect
///   light.
///
/// The radius then shrinks as the schedule below says (by about n^((alpha - 1) / 2): a factor
/// 100 after 10^6 iterations at alpha = 2/3); the bound is on the radius a render starts with.
pub fn smallest_radius(diagonal: f32) -> f32 {
    // sqrt(MIN_POSITIVE / pi) in f64, raised by 2^-20 relative so that pi r^2 computed in f32
    // (two roundings) is still normal.
    let normal_area = ((f32::MIN_POSITIVE as f64 / std::f64::consts::PI).sqrt()
        * (1.0 + 1.0 / (1 << 20) as f64)) as f32;
    let resolution = if diagonal.is_finite() {
        diagonal * (1.0 / (1u32 << 24) as f32)
    } else {
        0.0
    };
    normal_area.max(resolution)
}

/// Knaus and Zwicker 2011 (eq. 19): after iteration i (i = 1, 2, ...) the squared radius
/// shrinks as r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), alpha in (0, 1).
///
/// The product telescopes to r_n^2 = r_1^2 Gamma(n + alpha) / (Gamma(1 + alpha) Gamma(n + 1)),
/// about r_1^2 n^(alpha - 1) / Gamma(1 + alpha): the radius shrinks slowly enough that the
/// number of photons inside it still grows (variance falls) while the bias vanishes. For
/// surfaces, alpha = 2/3 balances the two and gives the best asymptotic rate, O(n^(-2/3)) for
/// the mean squared error (Knaus and Zwicker sec. 4.3; Kaplanyan and Dachsbacher 2013).
/// The state is kept in f64: after 10^6 iterations r^2 has shrunk by about 10^4, far from
/// any underflow.
#[derive(Clone, Copy, Debug)]
pub struct RadiusSchedule {
    r2: f64,
    alpha: f64,
    /// The iteration whose radius `r2` is (1-based).
    iteration: u64,
}

impl RadiusSchedule {
    /// The schedule starting at `radius` for iteration 1.
    pub fn new(radius: f32, alpha: f32) -> Self {
        RadiusSchedule {
            r2: (radius as f64).powi(2),
            alpha: alpha as f64,
            iteration: 1,
        }
    }

    /// The schedule at the 1-based `iteration`: the radius every render of these settings
    /// uses there, bit for bit (see [`RadiusSchedule::advance_to`]).
    pub fn at_iteration(radius: f32, alpha: f32, iteration: u64) -> Self {
        let mut schedule = RadiusSchedule::new(radius, alpha);
        schedule.advance_to(iteration, &|| false);
        schedule
    }

    /// Advances to the 1-based `iteration` (no further than that; an earlier one is a no-op).
    /// The recurrence is replayed (a multiplication per iteration, about a second for 10^9)
    /// rather than evaluated by the closed form, whose Gamma functions would round
    /// differently: a shard or a resumed render starting at iteration k must use exactly the
    /// radius an uninterrupted render reached there. `stop` is asked every 2^20 steps; if it
    /// says yes, false is returned and the schedule stays where it got, so a later call goes
    /// on from there (a shard far into a huge `-n` still stops at once).
    pub fn advance_to<F: Fn() -> bool>(&mut self, iteration: u64, stop: &F) -> bool {
        const STEPS_PER_POLL: u64 = 1 << 20;
        while self.iteration < iteration {
            if stop() {
                return false;
            }
            let end = iteration.min(self.iteration.saturating_add(STEPS_PER_POLL));
            while self.iteration < end {
                self.advance();
            }
        }
        true
    }

    /// The radius of the current iteration.
    pub fn radius(&self) -> f32 {
        self.r2.sqrt() as f32
    }

    /// The squared radius of the current iteration.
    pub fn radius2(&self) -> f64 {
        self.r2
    }

    /// The current iteration (1-based).
    pub fn iteration(&self) -> u64 {
        self.iteration
    }

    /// Moves to the next iteration: r^2 *= (i + alpha) / (i + 1).
    pub fn advance(&mut self) {
        let i = self.iteration as f64;
        self.r2 *= (i + self.alpha) / (i + 1.0);
        self.iteration += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At the bound pi r^2 is a normal f32 and 1 / (pi r^2) finite; for a unit scene the
    /// precision bound (2^-24 = 6e-8) decides.
    #[test]
    fn the_smallest_radius_keeps_the_disc_area_normal() {
        let r = smallest_radius(0.0);
        let area = std::f32::consts::PI * r * r;
        assert!(
            area.is_normal() && (1.0 / area).is_finite(),
            "{r:e} {area:e}"
        );
        assert!(r > 6.0e-20 && r < 6.2e-20, "{r:e}");
        let below = r * 0.999;
        assert!(!(std::f32::consts::PI * below * below).is_normal());
        assert_eq!(smallest_radius(1.0), 1.0 / (1u32 << 24) as f32);
        assert_eq!(smallest_radius(f32::INFINITY), r);
    }

    /// A replay cut short by a stop request keeps what it reached and, continued, ends bit
    /// for bit where an uninterrupted one does.
    #[test]
    fn a_stopped_replay_goes_on_where_it_stopped() {
        let target = 3 << 20;
        let polls = std::cell::Cell::new(0);
        let stop_at_third_poll = || {
            polls.set(polls.get() + 1);
            polls.get() == 3
        };
        let mut schedule = RadiusSchedule::new(0.05, 0.7);
        assert!(!schedule.advance_to(target, &stop_at_third_poll));
        assert_eq!(
            schedule.iteration(),
            1 + (2 << 20),
            "two chunks before the stop"
        );
        assert!(schedule.advance_to(target, &|| false));
        let straight = RadiusSchedule::at_iteration(0.05, 0.7, target);
        assert_eq!(schedule.iteration(), target);
        assert_eq!(schedule.radius2().to_bits(), straight.radius2().to_bits());
        assert!(
            schedule.advance_to(5, &|| true),
            "an earlier iteration is no work"
        );
        assert_eq!(schedule.iteration(), target);
    }

    /// ln Gamma(x) for x > 0 by recurrence up to x >= 10, then Stirling's series (error < 1e-12).
    fn ln_gamma(mut x: f64) -> f64 {
        let mut shift = 0.0;
        while x < 10.0 {
            shift -= x.ln();
            x += 1.0;
        }
        let x2 = x * x;
        shift + (x - 0.5) * x.ln() - x + 0.5 * (2.0 * std::f64::consts::PI).ln() + 1.0 / (12.0 * x)
            - 1.0 / (360.0 * x * x2)
            + 1.0 / (1260.0 * x2 * x2 * x)
    }

    #[test]
    fn ln_gamma_is_right() {
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-10);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-10);
    }

    #[test]
    fn schedule_matches_closed_form() {
        for &alpha in &[0.5f32, 2.0 / 3.0, 0.7, 0.9] {
            let mut s = RadiusSchedule::new(0.03, alpha);
            let a = alpha as f64;
            let r1 = (0.03f32 as f64).powi(2);
            for n in 1..=100_000u64 {
                if n.is_power_of_two() || n == 100_000 {
                    let nf = n as f64;
                    let closed =
                        r1 * (ln_gamma(nf + a) - ln_gamma(1.0 + a) - ln_gamma(nf + 1.0)).exp();
                    let rel = (s.radius2() - closed).abs() / closed;
                    assert!(
                        rel < 1e-9,
                        "alpha {alpha} n {n}: {} vs {closed}",
                        s.radius2()
                    );
                }
                s.advance();
            }
        }
    }

    #[test]
    fn a_schedule_started_late_equals_one_advanced_there() {
        let mut s = RadiusSchedule::new(0.02, 0.7);
        for k in 1..=300u64 {
            let late = RadiusSchedule::at_iteration(0.02, 0.7, k);
            assert_eq!(late.iteration(), k);
            assert_eq!(
                late.radius2().to_bits(),
                s.radius2().to_bits(),
                "iteration {k}"
            );
            s.advance();
        }
    }

    #[test]
    fn schedule_stays_positive_and_finite_for_a_million_iterations() {
        let mut s = RadiusSchedule::new(1e-3, 0.7);
        let mut last = s.radius2();
        for _ in 0..1_000_000 {
            s.advance();
            let r2 = s.radius2();
            assert!(r2 > 0.0 && r2.is_finite() && r2 < last);
            last = r2;
        }
        // n^(alpha-1) / Gamma(1 + alpha) at n = 1e6: about 1.73e-2 for alpha = 0.7.
        let ratio = s.radius2() / 1e-6;
        assert!(
            (ratio - 1e6f64.powf(-0.3) / (ln_gamma(1.7)).exp()).abs() / ratio < 1e-3,
            "{ratio}"
        );
        assert!(s.radius() > 0.0);
    }
}
