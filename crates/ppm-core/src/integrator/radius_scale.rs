//! The bias-variance scale of the `photons` radius: one factor m by which every pixel's
//! k-nearest-photon distance d_k is multiplied, chosen from the pilot photons so that the
//! estimated error of the whole render, bias² plus variance, is least. This module is the
//! error model and the choice of m; the pilot's measurements that feed it are in
//! [`super::radius_moments`].
//!
//! A fixed photon count k fixes the relative variance of each pixel's first estimate (about
//! 1/k), not its bias, which depends on how fast the light changes across the disc. Where the
//! light is smooth everywhere the best radius is larger than d_k, near a caustic it is d_k or
//! smaller. Adaptive progressive photon mapping (Kaplanyan and Dachsbacher 2013) balances the
//! two per pixel from a kernel estimate of the Laplacian of the photon density; per pixel that
//! estimate rests on a few dozen photons and is noisier than the bias it measures, so here it
//! is pooled over a sample of pixels into one factor, and the per-pixel shape stays d_k's.
//!
//! **Bias.** For a density f on a surface and a 2D kernel K_r of radius r, the kernel
//! estimate's mean is E[Ê(r)] = f + (μ₂(r)/2) Δf + O(r⁴), μ₂ the kernel's second moment per
//! axis (Silverman 1986, ch. 4, for multivariate kernels). For the Epanechnikov kernel of the gather
//! ([`crate::photon::epanechnikov`]) μ₂(r) = r²/6, so the bias is b(r) = Δf r²/12, and two
//! radii give it without Δf: E[Ê(2r) − Ê(r)] = Δf (4r² − r²)/12 = 3 b(r), so
//!
//!   b̂(r) = (Ê(2r) − Ê(r)) / 3 = Σ_j Φ_j (K_2r(d_j) − K_r(d_j)) / 3.
//!
//! That holds where the light is smooth at the scale 2r. Across an edge (a shadow's, a
//! caustic's, a corner where two walls meet) the pixels within r of it have a bias of the
//! order of the jump, so the image's mean squared bias grows as r, not r⁴. So the pooled
//! squared bias B(r) is measured at two radii, d_k and 2 d_k, and its order p follows from
//! their ratio, B(m d_k) = B(d_k) m^p with p = log₂(B(2 d_k) / B(d_k)), within [1, 4].
//!
//! **Variance.** The photons are (nearly) a Poisson process, so a sum Σ_j Φ_j g(x_j) has
//! variance E[Σ_j Φ_j² g(x_j)²] (Campbell's theorem), estimated by the sum itself:
//! v̂(r) = Σ_j Φ_j² K_r(d_j)², and var(b̂) by Σ_j Φ_j² (K_2r − K_r)²/9, so that b̂² − var(b̂)
//! is an unbiased estimate of b². The variance at d_k is measured on the disc of 2 d_k (four
//! times the photons) and carried back by its order, v(d_k) = 4 v(2 d_k).
//!
//! **Weights.** Each pixel's terms are in radiance (a kernel sum of flux times the eye path's
//! throughput and the diffuse albedo / π, over the light paths) and divided by L², L the
//! pixel's radiance: the eye-only light (below) plus the photons' estimate with the kernel of
//! 2 d_k. The sums are then the image's relative error, and L rests on enough photons not to
//! bias the ratios.
//!
//! **The eye pass's own noise.** What the render adds to the photons (emission, sampled
//! direct light, glossy chains to lights) has a variance C per iteration that does not depend
//! on the radius, but it falls only with more iterations, and a larger disc makes each
//! iteration longer. It is measured in the pilot from [`super::radius_moments::EYE_SAMPLES`] eye-only estimates per
//! pixel of the sample.
//!
//! **The render.** Iteration i gathers with radius m d_k s_i, s_i² the schedule's factor
//! (r²ᵢ₊₁ = r²ᵢ (i + α)/(i + 1), Knaus and Zwicker 2011), and the image averages N iterations,
//! so with M light paths per iteration (the pilot has [`PILOT_LIGHT_PATHS`]), pooled,
//!
//!   bias² = c_b² B(d_k) m^p,  c_b = (1/N) Σ_i s_i^(p/2),
//!   variance = c_v V (PILOT / M) / m² + C / N,  c_v = (1/N²) Σ_i 1/s_i²,
//!
//! with V = Σ v(d_k)/L² and C = Σ c/L². At equal time N depends on m: an iteration costs its
//! rays plus [`VISIT_COST`] per photon visit of its gathers, which grow as m², so
//! N_m = N (1 + g) / (1 + g m²), g the gathers' share at m = 1 ([`gather_share`]). As
//! functions of N the three terms go as N^((α−1)p/2), N^(−α) and N^(−1) (r_i² ∝ i^(α−1); Knaus
//! and Zwicker 2011 balance the first two for p = 4). m is the scale of least error among [`SCALE_STEPS`] scales,
//! log-spaced in [[`MIN_SCALE`], [`MAX_SCALE`]], the constants evaluated on the schedule over
//! N nominal iterations ([`nominal_iterations`]): a render of [`NOMINAL_RAYS`] whose iteration
//! costs the pilot's estimate, its light paths' rays, its eye paths' (those of the eye-only
//! estimates) and its photon visits. Without the eye term and the cost, and at p = 4, the
//! minimum is m⁶ = V (PILOT / M) / (κ B(d_k)), κ = 2 c_b²/c_v (7.3 at α = 2/3 over 64
//! iterations, 5.3 over 8 and 8.1 over 4096: both terms go as N^(−2/3) there, so m hardly
//! depends on N); at p = 1 it is m³ = 2 c_v V (PILOT / M) / (c_b² B(d_k)), and m falls as
//! N^(−1/6), which is why N follows an iteration's cost, not a constant count.
//! Where no bias is measured (light uniform within the pilot's resolution) the best radius is
//! unbounded and m is the largest.

use super::radius::RadiusSchedule;
use super::{Algorithm, PILOT_LIGHT_PATHS};

/// The smallest scale: a disc of a quarter of the pilot's k photons.
pub const MIN_SCALE: f32 = 0.5;

/// The largest scale: a disc of 16 times the pilot's k photons, taken where the pilot sees
/// no bias at all. A guard, as [`super::CAP`] is.
pub const MAX_SCALE: f32 = 4.0;

/// The length of the render the scale is chosen for, in rays (an iteration's rays plus
/// [`VISIT_COST`] per photon visit): about 20 s on two cores at 10 M rays/s. A length in
/// rays, not in iterations, so that the same scene gets the radius of the same render time
/// at any resolution: an iteration at 128 px costs a fraction of one at 1024 px, and a render
/// of the same time has that many more iterations, over which a fixed bias weighs more
/// against the falling variance. Not the run's own length (`-n`, `--time-limit`): a
/// progressive render's radii must not depend on when it is stopped, so that a resumed
/// render equals an uninterrupted one.
pub const NOMINAL_RAYS: f64 = 2.0e8;

/// The most iterations [`nominal_iterations`] gives (a render whose iteration is a few rays).
pub const MAX_NOMINAL_ITERATIONS: u32 = 1 << 16;

/// The cost of one photon visit of a gather in rays (the rays of the light and eye passes,
/// shadow rays included), so that the radius is chosen for equal time, not equal iterations:
/// a larger disc visits more photons. Measured from the iterations per second of `ppm` at
/// scales 1 and 3 on the Cornell box at 512 pixels (docs/radius.md): there the gathers are
/// 14 % of an iteration at m = 1. A property of the code, not of the scene.
pub const VISIT_COST: f64 = 0.0145;

/// The range the measured order p of the squared bias is kept within: an edge's (1) and
/// smooth light's (4).
pub const BIAS_ORDERS: (f64, f64) = (1.0, 4.0);

/// One pixel's terms of the pooled sums, each divided by the pixel's L² (its radiance: the
/// eye-only mean plus the photons' estimate with the kernel of 2 d_k), per iteration of the
/// pilot's light paths.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelMoments {
    /// b(d_k)², unbiased (may be negative).
    pub bias2: f64,
    /// b(2 d_k)², unbiased (may be negative).
    pub bias2_double: f64,
    /// v(d_k).
    pub variance: f64,
    /// The eye-only estimate's variance, which does not depend on the radius.
    pub eye: f64,
}

/// The iterations of a render of [`NOMINAL_RAYS`] whose iterations take `rays` rays with
/// gathers of `share` ([`gather_share`]) at m = 1: N = NOMINAL_RAYS / (rays (1 + g)), within
/// [1, [`MAX_NOMINAL_ITERATIONS`]].
pub fn nominal_iterations(rays: f64, share: f64) -> u32 {
    let cost = rays * (1.0 + share.max(0.0));
    if !(cost > 0.0 && cost.is_finite()) {
        return MAX_NOMINAL_ITERATIONS;
    }
    (NOMINAL_RAYS / cost)
        .round()
        .clamp(1.0, MAX_NOMINAL_ITERATIONS as f64) as u32
}

/// The schedule's constants (c_b, c_v) of the module's formulas for a squared bias of order
/// `p` and radius reduction `alpha`, over `iterations` (at least 1).
pub fn schedule_constants(alpha: f32, p: f64, iterations: u32) -> (f64, f64) {
    let iterations = iterations.max(1);
    let mut schedule = RadiusSchedule::new(1.0, alpha);
    let (mut c_b, mut c_v) = (0.0f64, 0.0f64);
    for _ in 0..iterations {
        let s2 = schedule.radius2();
        c_b += s2.powf(p / 4.0);
        c_v += 1.0 / s2;
        schedule.advance();
    }
    let n = iterations as f64;
    (c_b / n, c_v / (n * n))
}

/// The share of an iteration's time spent gathering at m = 1: `VISIT_COST` photon visits
/// per ray, so that an iteration of `rays` rays and `visits` photon visits (at m = 1) costs
/// rays + VISIT_COST visits, and the gathers' part grows as m² (a disc of m² times the area).
pub fn gather_share(rays: f64, visits: f64) -> f64 {
    if rays > 0.0 {
        (VISIT_COST * visits / rays).max(0.0)
    } else {
        0.0
    }
}

/// The estimated error of the render at scale `m` relative units (see the module's
/// formulas), at equal time: the iterations are N_m = N (1 + g) / (1 + g m²), g the gathers'
/// share of an iteration at m = 1, and the two terms go as N^((α−1)p/2) and N^(−α).
fn error_at(m: f64, terms: &ErrorTerms) -> f64 {
    let fewer = (1.0 + terms.share) / (1.0 + terms.share * m * m);
    let bias2 =
        terms.bias * m.powf(terms.order) * fewer.powf((terms.alpha - 1.0) * terms.order / 2.0);
    let variance = terms.variance / (m * m) * fewer.powf(-terms.alpha);
    bias2 + variance + terms.eye / fewer
}

/// The pooled terms of the error at the nominal iteration count N.
struct ErrorTerms {
    /// c_b² B(d_k).
    bias: f64,
    /// c_v V (PILOT / M).
    variance: f64,
    /// The eye-only variance over N: C / N.
    eye: f64,
    /// p.
    order: f64,
    alpha: f64,
    /// g of [`gather_share`].
    share: f64,
}

/// Scales tried between [`MIN_SCALE`] and [`MAX_SCALE`], evenly in log m.
const SCALE_STEPS: u32 = 256;

/// The order p and the scale m of the module's rule from the pixels' `moments` (summed in
/// order, so the same moments give the same m at any thread count), for a render of `paths`
/// light paths per iteration with radius reduction `alpha`, whose gathers take `share`
/// ([`gather_share`]) of an iteration at m = 1, over `iterations` at m = 1
/// ([`nominal_iterations`]). m is the least error among [`SCALE_STEPS`] scales, log-spaced;
/// [`MAX_SCALE`] if neither pooled bias is positive.
pub fn bias_variance_scale(
    moments: &[PixelMoments],
    alpha: f32,
    paths: u32,
    share: f64,
    iterations: u32,
) -> (f64, f32) {
    let (b1, b2, v, eye) = moments
        .iter()
        .fold((0.0f64, 0.0f64, 0.0f64, 0.0f64), |(b1, b2, v, e), m| {
            (b1 + m.bias2, b2 + m.bias2_double, v + m.variance, e + m.eye)
        });
    let (lowest, highest) = BIAS_ORDERS;
    // The order from the two radii; if only the larger radius shows a bias, smooth light's,
    // carried down to d_k.
    let (p, b1) = if b1 > 0.0 && b2 > 0.0 {
        ((b2 / b1).log2().clamp(lowest, highest), b1)
    } else if b2 > 0.0 {
        (highest, b2 / 2f64.powf(highest))
    } else {
        return (highest, MAX_SCALE);
    };
    let per_iteration = PILOT_LIGHT_PATHS as f64 / paths.max(1) as f64;
    let (c_b, c_v) = schedule_constants(alpha, p, iterations);
    let terms = ErrorTerms {
        bias: c_b * c_b * b1,
        variance: c_v * v * per_iteration,
        eye: eye / iterations.max(1) as f64,
        order: p,
        alpha: alpha as f64,
        share: share.max(0.0),
    };
    if !(terms.bias.is_finite() && terms.variance.is_finite() && terms.share.is_finite()) {
        return (p, MAX_SCALE);
    }
    let (lo, hi) = ((MIN_SCALE as f64).ln(), (MAX_SCALE as f64).ln());
    let best = (0..=SCALE_STEPS)
        .map(|i| (lo + (hi - lo) * i as f64 / SCALE_STEPS as f64).exp())
        .map(|m| (m, error_at(m, &terms)))
        .fold((MAX_SCALE as f64, f64::INFINITY), |best, (m, e)| {
            if e < best.1 {
                (m, e)
            } else {
                best
            }
        });
    (p, best.0 as f32)
}

/// Whether `algorithm`'s radius takes the bias-variance scale: ppm's, whose estimate is what
/// the pilot measures (a density estimate at the first vertex with a diffuse part, with the
/// gather costs of [`VISIT_COST`]). sppm's is the same estimate, but its gathers cost far more
/// per photon visit (each photon looks up the visible points near it, and a larger radius
/// finds more): measured, the scale cost it 1.3-1.7 times the error at equal time, with 55-70 %
/// of the iterations (docs/performance.md), so it keeps m = 1. vcm and bpm merge at every
/// non-delta camera vertex, glossy ones too, which the pilot does not see; vcm also weighs its
/// merges by MIS against its connections, so a larger merge radius does not cut its variance
/// as 1/r² while the merges' share, and so their blur, grows with it. Their merge radius stays
/// the median of d_k (m = 1). The others do not merge.
pub(super) fn scales(algorithm: Algorithm) -> bool {
    match algorithm {
        Algorithm::Ppm => true,
        Algorithm::Sppm
        | Algorithm::Vcm
        | Algorithm::Bpm
        | Algorithm::Path
        | Algorithm::Bpt
        | Algorithm::Lt => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The iterations the scale's tests are evaluated over.
    const N: u32 = 64;

    /// m^(p+2) = 2 c_v V (PILOT / M) / (p c_b² B): at p = 4, 2 c_b²/c_v is about 7.3 over the
    /// nominal iterations; a render with 64 times the pilot's light paths per iteration takes
    /// half the scale; an edge's order (B doubling with the radius) takes p = 1; no pooled
    /// bias gives the largest scale, a bias far above the variance the smallest.
    #[test]
    fn the_scale_balances_bias_and_variance() {
        let alpha = 2.0 / 3.0;
        let (c_b, c_v) = schedule_constants(alpha, 4.0, N);
        let kappa = 2.0 * c_b * c_b / c_v;
        assert!((7.0..7.6).contains(&kappa), "kappa {kappa}");
        let smooth = [PixelMoments {
            bias2: 1e-4,
            bias2_double: 16e-4,
            variance: 2e-2,
            eye: 0.0,
        }];
        // The search's scales are a step of ln 8 / 256 apart in log m.
        let step = ((MAX_SCALE / MIN_SCALE) as f64).ln() / SCALE_STEPS as f64;
        let near = |m: f32, want: f64| (m as f64 / want).ln().abs() <= 0.5 * step + 1e-6;
        let (p, m) = bias_variance_scale(&smooth, alpha, PILOT_LIGHT_PATHS, 0.0, N);
        assert!((p - 4.0).abs() < 1e-9, "order {p}");
        let want = (2e-2 / (kappa * 1e-4)).powf(1.0 / 6.0);
        assert!(near(m, want), "m {m}, closed form {want}");
        let (_, more) = bias_variance_scale(&smooth, alpha, PILOT_LIGHT_PATHS * 64, 0.0, N);
        assert!(near(more, 0.5 * want), "{more} vs {want} / 2");
        let edge = [PixelMoments {
            bias2: 1e-4,
            bias2_double: 2e-4,
            variance: 2e-2,
            eye: 0.0,
        }];
        let (p, m_edge) = bias_variance_scale(&edge, alpha, PILOT_LIGHT_PATHS, 0.0, N);
        let (c_b, c_v) = schedule_constants(alpha, 1.0, N);
        let want = (2.0 * c_v * 2e-2 / (c_b * c_b * 1e-4)).powf(1.0 / 3.0);
        assert!((p - 1.0).abs() < 1e-9, "order {p}");
        assert!(near(m_edge, want), "{m_edge} vs {want}");
        let flat = [PixelMoments {
            bias2: -1e-6,
            bias2_double: -1e-6,
            variance: 2e-2,
            eye: 0.0,
        }];
        assert_eq!(bias_variance_scale(&flat, alpha, 1000, 0.0, N).1, MAX_SCALE);
        let steep = [PixelMoments {
            bias2: 1.0,
            bias2_double: 16.0,
            variance: 1e-6,
            eye: 0.0,
        }];
        assert_eq!(
            bias_variance_scale(&steep, alpha, 1000, 0.0, N).1,
            MIN_SCALE
        );
    }

    /// At equal time a larger disc costs iterations: with the gathers a tenth of an
    /// iteration the scale falls, and falls further when the eye pass's own noise, which
    /// only more iterations reduce, is large; without a gather cost that noise does not move
    /// the scale (it does not depend on the radius).
    #[test]
    fn the_scale_pays_for_its_time() {
        let alpha = 2.0 / 3.0;
        let moments = |eye| {
            [PixelMoments {
                bias2: 1e-4,
                bias2_double: 16e-4,
                variance: 2e-2,
                eye,
            }]
        };
        let at =
            |eye, share| bias_variance_scale(&moments(eye), alpha, PILOT_LIGHT_PATHS, share, N).1;
        let free = at(0.0, 0.0);
        assert_eq!(at(1.0, 0.0), free);
        let costly = at(0.0, 0.1);
        let noisy = at(1.0, 0.1);
        assert!(costly < free && noisy < costly, "{free} {costly} {noisy}");
    }

    /// The nominal iterations are [`NOMINAL_RAYS`] over an iteration's cost, its rays times
    /// 1 + g, within [1, MAX]; over more iterations an edge's bias (p = 1), which falls as
    /// N^(-(1 - alpha)/2) while the variance falls as N^(-alpha), takes a smaller scale, by
    /// the closed form m³ = 2 c_v V / (c_b² B) at each N; smooth light's (p = 4, both terms
    /// falling alike at alpha = 2/3) keeps its scale within a few percent.
    #[test]
    fn the_scale_is_chosen_for_a_render_of_nominal_length() {
        assert_eq!(nominal_iterations(1e6, 0.25), 160);
        assert_eq!(nominal_iterations(1e6, -1.0), 200);
        assert_eq!(nominal_iterations(1e12, 0.0), 1);
        assert_eq!(nominal_iterations(10.0, 0.0), MAX_NOMINAL_ITERATIONS);
        assert_eq!(nominal_iterations(0.0, 0.0), MAX_NOMINAL_ITERATIONS);
        assert_eq!(nominal_iterations(f64::NAN, 0.0), MAX_NOMINAL_ITERATIONS);
        let alpha = 2.0 / 3.0;
        let step = ((MAX_SCALE / MIN_SCALE) as f64).ln() / SCALE_STEPS as f64;
        let near = |m: f32, want: f64| (m as f64 / want).ln().abs() <= 0.5 * step + 1e-6;
        let edge = [PixelMoments {
            bias2: 1e-4,
            bias2_double: 2e-4,
            variance: 2e-2,
            eye: 0.0,
        }];
        let mut previous = f32::INFINITY;
        for n in [16, 64, 512] {
            let (_, m) = bias_variance_scale(&edge, alpha, PILOT_LIGHT_PATHS, 0.0, n);
            let (c_b, c_v) = schedule_constants(alpha, 1.0, n);
            let want = (2.0 * c_v * 2e-2 / (c_b * c_b * 1e-4)).powf(1.0 / 3.0);
            assert!(near(m, want), "{n} iterations: m {m}, closed form {want}");
            assert!(m < previous, "{n} iterations: m {m} not below {previous}");
            previous = m;
        }
        let smooth = [PixelMoments {
            bias2: 1e-4,
            bias2_double: 16e-4,
            variance: 2e-2,
            eye: 0.0,
        }];
        let at = |n| bias_variance_scale(&smooth, alpha, PILOT_LIGHT_PATHS, 0.0, n).1;
        let (short, long) = (at(64), at(512));
        assert!((long / short - 1.0).abs() < 0.05, "{short} vs {long}");
    }
}
