//! Per-pixel statistics of stochastic progressive photon mapping, and the order-independent
//! accumulators one iteration's photons are added to.

use glam::Vec3;
use std::sync::atomic::{AtomicBool, Ordering};

/// What a pixel keeps from iteration to iteration (Hachisuka and Jensen 2009, sec. 3: the
/// statistics of progressive photon mapping, shared by all the visible points of a pixel).
///
/// The reflected radiance of the pixel after i iterations and N_e emitted light paths is
/// L_i = tau_i / (N_e pi R_i^2) (Hachisuka, Ogaki and Jensen 2008, sec. 4.2, radiance
/// evaluation); tau is a flux already weighted by the camera path's throughput and the
/// BSDF, i.e. the visible point's importance times the photons' flux.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelStatistics {
    /// R_i^2, the squared gather radius of the next iteration (world units).
    pub r2: f64,
    /// N_i, the accumulated (alpha-weighted) photon count.
    pub n: f64,
    /// tau_i, the accumulated flux, corrected to the current radius.
    pub tau: [f64; 3],
}

impl PixelStatistics {
    /// A pixel starting at radius `radius` with nothing gathered.
    pub fn new(radius: f32) -> Self {
        PixelStatistics {
            r2: (radius as f64).powi(2),
            n: 0.0,
            tau: [0.0; 3],
        }
    }

    /// Adds one iteration's gather: `m` photons inside the radius, carrying the weighted flux
    /// `phi` = sum over those photons of beta f(wo, wi_p) Phi_p.
    ///
    /// Radius reduction (Hachisuka, Ogaki and Jensen 2008, sec. 4.2): of the M new
    /// photons only a fraction alpha is kept, N_{i+1} = N_i + alpha M_i, and the disc shrinks
    /// so that the photon density stays the same:
    ///   R_{i+1}^2 = R_i^2 (N_i + alpha M_i) / (N_i + M_i).
    /// Flux correction (same section): the flux outside the smaller disc is
    /// dropped in proportion to the areas,
    ///   tau_{i+1} = (tau_i + Phi_i) R_{i+1}^2 / R_i^2.
    /// With M_i = 0 nothing changes (pbrt-v4's SPPMIntegrator does the same).
    pub fn update(&mut self, m: u64, phi: [f64; 3], alpha: f64) {
        if m == 0 {
            return;
        }
        let m = m as f64;
        let n_next = self.n + alpha * m;
        let ratio = n_next / (self.n + m);
        for (tau, phi) in self.tau.iter_mut().zip(phi) {
            *tau = (*tau + phi) * ratio;
        }
        self.n = n_next;
        self.r2 *= ratio;
    }

    /// The photon part of the pixel's radiance, tau / (N_e pi R^2), with `emitted` = N_e the
    /// light paths traced so far (all iterations).
    pub fn radiance(&self, emitted: f64) -> Vec3 {
        if emitted <= 0.0 {
            return Vec3::ZERO;
        }
        let scale = 1.0 / (emitted * std::f64::consts::PI * self.r2);
        Vec3::new(
            (self.tau[0] * scale) as f32,
            (self.tau[1] * scale) as f32,
            (self.tau[2] * scale) as f32,
        )
    }
}

/// One pixel's accumulator for the current iteration: Phi_i in three channels and M_i,
/// as unsigned fixed-point integers.
///
/// Integer addition is associative, so the sum does not depend on the order in which the
/// photons arrive: the same seed gives the same image at any thread count and however the
/// light paths are cut into batches. Float sums would not.
#[derive(Clone, Copy, Debug, Default)]
pub struct Accumulator {
    phi: [u64; 3],
    m: u64,
}

/// The fixed-point code of one iteration's splats: a flux value v is stored as
/// round(v / flux_unit * scale), with flux_unit the largest channel of the scene's emitted
/// power, the typical flux of one photon. The default scale 2^32 resolves 2^-32 of that flux
/// (the rounding error of a splat is below 1e-9 of a photon's flux) and leaves room for 2^32
/// photon fluxes in one pixel per iteration. If a sum would overflow anyway, the overflow is
/// flagged and the iteration's photon pass redone with a coarser scale.
#[derive(Debug)]
pub struct FixedPoint {
    /// Integer units per flux_unit.
    scale: f64,
    /// flux_unit / scale: the flux of one integer unit.
    unit: f64,
    overflowed: AtomicBool,
}

impl FixedPoint {
    /// The finest scale, used first in every iteration.
    pub const FINE_SCALE: f64 = 4_294_967_296.0;

    /// The code for photons of typical flux `flux_unit` at `scale` integer units per flux_unit.
    pub fn new(flux_unit: f32, scale: f64) -> Self {
        let flux_unit = if flux_unit.is_finite() && flux_unit > 0.0 {
            flux_unit as f64
        } else {
            1.0
        };
        FixedPoint {
            scale: scale / flux_unit,
            unit: flux_unit / scale,
            overflowed: AtomicBool::new(false),
        }
    }

    /// Adds one photon of weighted flux `phi` (finite, non-negative) to `acc`.
    #[inline]
    pub fn splat(&self, acc: &mut Accumulator, phi: Vec3) {
        for (slot, v) in acc.phi.iter_mut().zip(phi.to_array()) {
            let code = (v as f64 * self.scale).round();
            // Also catches a single value beyond u64 (the cast would saturate silently).
            if code >= u64::MAX as f64 {
                self.overflowed.store(true, Ordering::Relaxed);
                continue;
            }
            let code = code as u64;
            let (sum, wrapped) = slot.overflowing_add(code);
            *slot = sum;
            if wrapped {
                self.overflowed.store(true, Ordering::Relaxed);
            }
        }
        acc.m += 1;
    }

    /// True if a sum wrapped around since the accumulators were cleared.
    pub fn overflowed(&self) -> bool {
        self.overflowed.load(Ordering::Relaxed)
    }

    /// The (M, Phi) an accumulator holds, decoded, and clears it.
    pub fn take(&self, acc: &mut Accumulator) -> (u64, [f64; 3]) {
        let m = std::mem::take(&mut acc.m);
        let phi = std::mem::take(&mut acc.phi).map(|a| a as f64 * self.unit);
        (m, phi)
    }
}

/// Clears accumulators (after an overflowed pass).
pub fn clear(accumulators: &mut [Accumulator]) {
    accumulators.fill(Accumulator::default());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn update_keeps_density_and_corrects_flux() {
        // N = 10, M = 20, alpha = 0.5: N' = 20, R'^2 = R^2 20/30, tau' = (tau + phi) 2/3.
        let mut s = PixelStatistics {
            r2: 0.09,
            n: 10.0,
            tau: [3.0, 0.0, 1.0],
        };
        s.update(20, [3.0, 6.0, 0.5], 0.5);
        assert!((s.n - 20.0).abs() < 1e-12);
        assert!((s.r2 - 0.06).abs() < 1e-12);
        assert!((s.tau[0] - 4.0).abs() < 1e-12);
        assert!((s.tau[1] - 4.0).abs() < 1e-12);
        assert!((s.tau[2] - 1.0).abs() < 1e-12);
        // No photons: unchanged.
        let before = s;
        s.update(0, [0.0; 3], 0.5);
        assert_eq!(s, before);
    }

    #[test]
    fn constant_density_gives_the_density() {
        // Photons of flux 1 land uniformly with density rho per unit area per light path:
        // each iteration brings M = rho pi R^2 photons (taken exactly, as expectations). The
        // estimate tau / (i pi R^2) must then be rho at every step, whatever alpha.
        let rho = 1000.0;
        for alpha in [0.5, 2.0 / 3.0, 0.9] {
            let mut s = PixelStatistics::new(0.1);
            for i in 1..=50 {
                let m = rho * std::f64::consts::PI * s.r2;
                // Scale M to an integer count by splitting it in photons of flux m / round(m).
                let count = m.round().max(1.0);
                s.update(count as u64, [m; 3], alpha);
                let l = s.radiance(i as f64);
                let rel = (l.x as f64 - rho).abs() / rho;
                assert!(rel < 0.02, "alpha {alpha}, iteration {i}: {} vs {rho}", l.x);
            }
        }
    }

    #[test]
    fn fixed_point_round_trips_and_flags_overflow() {
        let fp = FixedPoint::new(2.0, FixedPoint::FINE_SCALE);
        let mut acc = Accumulator::default();
        fp.splat(&mut acc, Vec3::new(1.0, 0.25, 0.0));
        fp.splat(&mut acc, Vec3::new(3.0, 0.25, 1e-6));
        assert!(!fp.overflowed());
        let (m, phi) = fp.take(&mut acc);
        assert_eq!(m, 2);
        assert!((phi[0] - 4.0).abs() < 1e-9 && (phi[1] - 0.5).abs() < 1e-9);
        assert!((phi[2] - 1e-6).abs() < 1e-9);
        assert_eq!(fp.take(&mut acc), (0, [0.0; 3]));
        // 2^31 flux units per pixel are representable; beyond, the sum wraps and is flagged.
        let big = Vec3::splat(2.0 * 2f32.powi(31));
        fp.splat(&mut acc, big);
        assert!(!fp.overflowed());
        fp.splat(&mut acc, big);
        assert!(fp.overflowed());
    }
}
