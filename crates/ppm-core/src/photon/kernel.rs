//! The density-estimation kernel of the photon gather.

use std::f32::consts::PI;

/// The 2D Epanechnikov kernel over a disc of radius `r`, from squared distances:
///
/// ```text
/// k(d², r²) = 2 / (π r²) · (1 − d² / r²)   if d² ≤ r²,   else 0.
/// ```
///
/// It is normalised over the disc: ∫₀ʳ k(s², r²) 2πs ds = (4 / r²)(r²/2 − r²/4) = 1, so
/// photons of flux Φ_p give the irradiance estimate `E(x) ≈ Σ_p Φ_p k(d_p², r²)` and the
/// radiance estimate `L(x, wo) ≈ Σ_p f(wo, wi_p) Φ_p k(d_p², r²)`. Compared with the constant
/// kernel 1/(π r²) it weights distant photons less, which reduces the blur at edges.
#[inline]
pub fn epanechnikov(d2: f32, r2: f32) -> f32 {
    if d2 <= r2 {
        2.0 / (PI * r2) * (1.0 - d2 / r2)
    } else {
        0.0
    }
}

/// [`epanechnikov`] with the divisions done once per gather radius, for the gather loop:
/// `weight(d²) = norm − norm / r² · d²` with `norm = 2 / (π r²)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kernel {
    r2: f32,
    norm: f32,
    slope: f32,
}

impl Kernel {
    /// The kernel for gather radius `radius` (> 0).
    #[inline]
    pub fn new(radius: f32) -> Self {
        let r2 = radius * radius;
        let norm = 2.0 / (PI * r2);
        Kernel {
            r2,
            norm,
            slope: norm / r2,
        }
    }

    /// The squared gather radius.
    #[inline]
    pub fn r2(&self) -> f32 {
        self.r2
    }

    /// `(norm, slope)` with `weight(d²) = max(norm - slope d², 0)` inside the disc.
    #[inline]
    pub(crate) fn coefficients(&self) -> (f32, f32) {
        (self.norm, self.slope)
    }

    /// The weight of a photon at squared distance `d2`; zero outside the disc.
    #[inline]
    pub fn weight(&self, d2: f32) -> f32 {
        if d2 <= self.r2 {
            (self.norm - self.slope * d2).max(0.0)
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_to_one_over_the_disc() {
        // Midpoint rule in the radial coordinate: ∫₀ʳ k(s²) 2πs ds.
        for r in [0.01f32, 0.5, 3.0] {
            let n = 100_000;
            let ds = r as f64 / n as f64;
            let integral: f64 = (0..n)
                .map(|i| {
                    let s = (i as f64 + 0.5) * ds;
                    epanechnikov((s * s) as f32, r * r) as f64 * 2.0 * std::f64::consts::PI * s * ds
                })
                .sum();
            assert!((integral - 1.0).abs() < 1e-4, "r = {r}: {integral}");
        }
    }

    #[test]
    fn precomputed_kernel_matches_formula() {
        for r in [0.02f32, 1.0, 7.5] {
            let kernel = Kernel::new(r);
            assert_eq!(kernel.r2(), r * r);
            for i in 0..=110 {
                let d2 = r * r * i as f32 / 100.0;
                let (a, b) = (kernel.weight(d2), epanechnikov(d2, r * r));
                assert!(
                    (a - b).abs() <= 1e-5 * epanechnikov(0.0, r * r),
                    "{r} {d2}: {a} {b}"
                );
                assert!(a >= 0.0);
            }
            assert_eq!(kernel.weight(r * r * 1.0001), 0.0);
            assert!((kernel.weight(0.0) - 2.0 / (PI * r * r)).abs() < 1e-6 / (r * r));
        }
    }
}
