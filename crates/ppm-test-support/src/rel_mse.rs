//! A render's relative mean squared error against a reference image, and the value noise
//! alone gives it, so that a test can tell a per-pixel difference from noise.
//!
//! relMSE = mean over pixels i and channels c of (p_ic - r_ic)^2 / (r_ic^2 + epsilon), with
//! p the render (a mean over independent seeds) and r the reference (Mitsuba's, a mean over
//! its own seeds). When both are unbiased estimates of the same image L and independent,
//! E[(p - r)^2] = Var p + Var r (the cross term vanishes), so the noise-only value is the
//! mean of (Var p + Var r) / (r^2 + epsilon), each variance estimated from its seeds' spread.
//! A bias b in a pixel adds b^2 / (r^2 + epsilon) to the observed value and nothing to the
//! noise-only one: their ratio is near 1 for a correct renderer and above it for a
//! difference confined to part of the image (a wrong texture, a missing highlight) that the
//! image mean can hide.

use glam::Vec3;
use ppm_core::film::Image;

/// The epsilon of the relative MSE's denominator (as in the denoising literature: it keeps
/// black pixels from dominating).
pub const REL_MSE_EPSILON: f32 = 0.01;

/// The relative MSE of a render against a reference and the value noise alone gives it.
#[derive(Clone, Copy, Debug)]
pub struct RelMse {
    /// Mean of (p - r)^2 / (r^2 + epsilon).
    pub observed: f64,
    /// Mean of (Var p + Var r) / (r^2 + epsilon).
    pub noise: f64,
}

impl RelMse {
    /// observed / noise: near 1 when the two images differ by noise only.
    pub fn ratio(&self) -> f64 {
        self.observed / self.noise
    }
}

/// Per pixel, the mean of `images` (independent renders) and the variance of that mean
/// (their sample variance over their count).
pub fn mean_and_variance(images: &[Image]) -> (Vec<Vec3>, Vec<Vec3>) {
    let n = images.len() as f32;
    assert!(images.len() > 1, "a variance needs two renders");
    (0..images[0].pixels.len())
        .map(|i| {
            let mean = images.iter().map(|im| im.pixels[i]).sum::<Vec3>() / n;
            let var = images
                .iter()
                .map(|im| (im.pixels[i] - mean) * (im.pixels[i] - mean))
                .sum::<Vec3>()
                / (n - 1.0)
                / n;
            (mean, var)
        })
        .unzip()
}

/// The relative MSE of the render (`mean`, per-pixel variance `var`) against the reference
/// (`reference`, variance `reference_var`), all of the same size.
pub fn rel_mse(mean: &[Vec3], var: &[Vec3], reference: &[Vec3], reference_var: &[Vec3]) -> RelMse {
    assert!(
        mean.len() == reference.len()
            && var.len() == mean.len()
            && reference_var.len() == mean.len(),
        "images of different sizes"
    );
    let (mut observed, mut noise) = (0.0f64, 0.0f64);
    for i in 0..mean.len() {
        for c in 0..3 {
            let (p, r) = (mean[i][c] as f64, reference[i][c] as f64);
            let denominator = r * r + REL_MSE_EPSILON as f64;
            observed += (p - r) * (p - r) / denominator;
            noise += (var[i][c] + reference_var[i][c]) as f64 / denominator;
        }
    }
    let samples = 3.0 * mean.len() as f64;
    RelMse {
        observed: observed / samples,
        noise: noise / samples,
    }
}
