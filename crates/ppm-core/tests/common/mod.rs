//! Support for the BSDF tests: the chi-square distribution, Gauss-Legendre quadrature, a
//! goodness-of-fit test of a direction sampler against its claimed pdf on the sphere, and a
//! few small helpers.

// Each test file uses a different subset.
#![allow(dead_code)]

use glam::Vec3;
use ppm_core::sampling::Rng;
use std::f64::consts::PI;

/// ln Gamma(x) for x > 0: shift to x >= 10 by Gamma(x) = Gamma(x + 1) / x, then Stirling's series
/// (x - 1/2) ln x - x + ln(2 pi) / 2 + 1/(12x) - 1/(360x^3) + 1/(1260x^5) - 1/(1680x^7),
/// whose truncation error at x >= 10 is below 1e-14.
pub fn ln_gamma(mut x: f64) -> f64 {
    let mut shift = 0.0;
    while x < 10.0 {
        shift -= x.ln();
        x += 1.0;
    }
    let (x2, x3) = (x * x, x * x * x);
    shift + (x - 0.5) * x.ln() - x + 0.5 * (2.0 * PI).ln() + 1.0 / (12.0 * x) - 1.0 / (360.0 * x3)
        + 1.0 / (1260.0 * x3 * x2)
        - 1.0 / (1680.0 * x3 * x2 * x2)
}

/// The regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a).
/// For x < a + 1 the power series of P = 1 - Q converges fast:
///   P(a, x) = x^a e^-x / Gamma(a + 1) * sum_k x^k / ((a + 1)...(a + k));
/// otherwise Legendre's continued fraction for Q, evaluated by the modified Lentz method:
///   Q(a, x) = x^a e^-x / Gamma(a) * 1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - 2 (2 - a) / ...)).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    assert!(a > 0.0 && x >= 0.0, "gamma_q({a}, {x})");
    if x == 0.0 {
        return 1.0;
    }
    let prefactor = (a * x.ln() - x - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..1_000_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * prefactor
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1_000_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

/// Survival function of the chi-square distribution: P(X > x) with `dof` degrees of freedom.
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    gamma_q(0.5 * dof as f64, 0.5 * x)
}

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1], by Newton's method on
/// the Legendre polynomial P_n (three-term recurrence), started from cos(pi (i + 3/4) / (n + 1/2)).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            loop {
                // P_n(x) and P_{n-1}(x) by (k+1) P_{k+1} = (2k+1) x P_k - k P_{k-1}.
                let (mut p0, mut p1) = (1.0, x);
                for k in 1..n {
                    let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
                    p0 = p1;
                    p1 = p2;
                }
                // P_n'(x) = n (x P_n - P_{n-1}) / (x^2 - 1).
                let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    return (x, 2.0 / ((1.0 - x * x) * dp * dp));
                }
            }
        })
        .collect()
}

/// Outcome of [`chi2_directions`].
#[derive(Debug)]
pub struct Chi2Outcome {
    pub statistic: f64,
    pub dof: usize,
    pub p_value: f64,
    /// Integral of the pdf over the sphere (the rest is the probability of "no sample").
    pub pdf_mass: f64,
    /// The worst cells, (theta bin, phi bin or usize::MAX for "no sample", observed, expected).
    pub worst: Vec<(usize, usize, f64, f64)>,
    /// Mean of pdf(wi) over the samples (0 for a lost one) and its standard error...
    pub collision_observed: (f64, f64),
    /// ... which should equal the integral of pdf^2 over the sphere.
    pub collision_expected: f64,
    /// Two-sided p-value of the observed mean (normal approximation).
    pub collision_p_value: f64,
}

/// Resolution of the (theta, phi) histogram; theta = pi/2 is a bin edge, so the discontinuity
/// of one-sided pdfs at the horizon never falls inside a bin.
pub const THETA_BINS: usize = 48;
pub const PHI_BINS: usize = 2 * THETA_BINS;
/// Cells whose expected count is below this are pooled into one cell (the usual rule of five).
pub const MIN_EXPECTED: f64 = 5.0;

/// How many times a cell's quadrature may be halved in each direction (see [`cell_integrals`]).
const CELL_DEPTH: u32 = 5;

/// Integrals of `pdf` and `pdf^2` over the cell [theta0, theta1] x [phi0, phi1] of the sphere,
/// `pdf(w) sin(theta) dtheta dphi`, by 6 x 6 Gauss-Legendre points, adaptively: the cell's
/// rule is compared with the sum over its four quarters, and where they differ by more than
/// 1e-9 (absolute, a thousandth of a sample in a million) the quarters are refined in turn,
/// at most `depth` times. A lobe narrower than a cell (a microfacet lobe reflected at a
/// grazing angle is a sliver along the horizon) is then still integrated to the accuracy the
/// expected counts need.
fn cell_integrals(
    pdf: &impl Fn(Vec3) -> f64,
    rule: &[(f64, f64)],
    cell: [f64; 4],
    depth: u32,
) -> (f64, f64) {
    let whole = cell_rule(pdf, rule, cell);
    if depth == 0 {
        return whole;
    }
    let [t0, t1, p0, p1] = cell;
    let (tm, pm) = (0.5 * (t0 + t1), 0.5 * (p0 + p1));
    let quarters = [
        [t0, tm, p0, pm],
        [t0, tm, pm, p1],
        [tm, t1, p0, pm],
        [tm, t1, pm, p1],
    ];
    let parts = quarters.map(|q| cell_rule(pdf, rule, q));
    let sum = parts
        .iter()
        .fold((0.0, 0.0), |acc, p| (acc.0 + p.0, acc.1 + p.1));
    if (sum.0 - whole.0).abs() <= 1e-9 {
        return sum;
    }
    quarters
        .iter()
        .map(|&q| cell_integrals(pdf, rule, q, depth - 1))
        .fold((0.0, 0.0), |acc, p| (acc.0 + p.0, acc.1 + p.1))
}

/// Slices of a cell along the horizon (see [`horizon_cell_integrals`]).
const HORIZON_SLICES: usize = 16;

/// The integrals of [`cell_integrals`] for a cell bordering the horizon, cut into
/// [`HORIZON_SLICES`] slices in theta, each integrated adaptively. A direction at a grazing
/// angle makes features as thin as its angle to the horizon there: a rough dielectric seen at
/// 89.9 degrees refracts through microfacets up to the edge of the upper hemisphere, and its
/// pdf drops to zero 0.04 degrees below the horizon. No rule on the whole cell, nor on its
/// quarters, has a point in that band, so comparing them cannot see it; the first slice's
/// rule has (its first point is 0.008 degrees from the edge).
fn horizon_cell_integrals(
    pdf: &impl Fn(Vec3) -> f64,
    rule: &[(f64, f64)],
    cell: [f64; 4],
) -> (f64, f64) {
    let [t0, t1, p0, p1] = cell;
    let dt = (t1 - t0) / HORIZON_SLICES as f64;
    (0..HORIZON_SLICES)
        .map(|k| {
            let a = t0 + k as f64 * dt;
            cell_integrals(pdf, rule, [a, a + dt, p0, p1], CELL_DEPTH)
        })
        .fold((0.0, 0.0), |acc, p| (acc.0 + p.0, acc.1 + p.1))
}

/// The rule applied on each of `k x k` equal sub-cells of `cell`.
fn subdivided_cell_integrals(
    pdf: &impl Fn(Vec3) -> f64,
    rule: &[(f64, f64)],
    cell: [f64; 4],
    k: usize,
) -> (f64, f64) {
    let [t0, t1, p0, p1] = cell;
    let (dt, dp) = ((t1 - t0) / k as f64, (p1 - p0) / k as f64);
    let mut sum = (0.0, 0.0);
    for a in 0..k {
        for b in 0..k {
            let (t, p) = (t0 + a as f64 * dt, p0 + b as f64 * dp);
            let r = cell_rule(pdf, rule, [t, t + dt, p, p + dp]);
            sum = (sum.0 + r.0, sum.1 + r.1);
        }
    }
    sum
}

/// One application of the product Gauss-Legendre rule to a cell (no refinement).
fn cell_rule(pdf: &impl Fn(Vec3) -> f64, rule: &[(f64, f64)], cell: [f64; 4]) -> (f64, f64) {
    let [t0, t1, p0, p1] = cell;
    let (dt, dp) = (t1 - t0, p1 - p0);
    let (mut integral, mut integral_sq) = (0.0, 0.0);
    for &(xt, wt) in rule {
        let theta = t0 + 0.5 * (xt + 1.0) * dt;
        let (sin_t, cos_t) = theta.sin_cos();
        for &(xp, wp) in rule {
            let phi = p0 + 0.5 * (xp + 1.0) * dp;
            let w = Vec3::new(
                (sin_t * phi.cos()) as f32,
                (sin_t * phi.sin()) as f32,
                cos_t as f32,
            );
            let p = pdf(w);
            integral += wt * wp * p * sin_t;
            integral_sq += wt * wp * p * p * sin_t;
        }
    }
    (integral * 0.25 * dt * dp, integral_sq * 0.25 * dt * dp)
}

/// Pearson's chi-square test of a direction sampler against the density it claims.
///
/// `sample` is called `n` times (returning `None` for a lost sample); the sphere is cut into
/// a (theta, phi) grid and each cell's expected count is `n` times the integral of `pdf` over
/// it, `pdf(w) sin(theta) dtheta dphi`, by adaptive 6 x 6 Gauss-Legendre points (never on cell
/// edges; [`cell_integrals`]).
/// "No sample" is one more cell, expected `n (1 - integral of pdf)` (at least `1e-6 n`).
/// Cells expecting fewer than [`MIN_EXPECTED`] are pooled. Fails outright (Err) if the pdf integrates to more than one or
/// samples land where the pdf is zero.
///
/// Cells wider than a narrow lobe cannot see its width, so a second statistic does: the mean of
/// pdf(wi) over the samples estimates integral of q(w) pdf(w) dw for the true density q of
/// `sample`, which equals the integral of pdf^2 when q = pdf. A lobe sampled too wide (narrow)
/// lands at lower (higher) pdf values on average.
pub fn chi2_directions(
    n: usize,
    rng: &mut Rng,
    mut sample: impl FnMut(&mut Rng) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
) -> Result<Chi2Outcome, String> {
    let (nt, np) = (THETA_BINS, PHI_BINS);
    let (dt, dp) = (PI / nt as f64, 2.0 * PI / np as f64);

    let mut observed = vec![0.0f64; nt * np + 1];
    // One sampled direction per cell, to tell a sample where the pdf is zero from one in a
    // sliver of support too thin for the quadrature to see.
    let mut witness: Vec<Option<Vec3>> = vec![None; nt * np + 1];
    let mut collision = Stats::default();
    for _ in 0..n {
        let wi = sample(rng);
        collision.push(wi.map_or(0.0, &pdf));
        let cell = match wi {
            Some(w) => {
                let theta = (w.z as f64).clamp(-1.0, 1.0).acos();
                let phi = (w.y as f64).atan2(w.x as f64).rem_euclid(2.0 * PI);
                let i = ((theta / dt) as usize).min(nt - 1);
                let j = ((phi / dp) as usize).min(np - 1);
                i * np + j
            }
            None => nt * np,
        };
        observed[cell] += 1.0;
        if witness[cell].is_none() {
            witness[cell] = wi;
        }
    }

    let rule = gauss_legendre(6);
    let mut expected = vec![0.0f64; nt * np + 1];
    let (mut mass, mut collision_expected) = (0.0, 0.0);
    for i in 0..nt {
        for j in 0..np {
            let cell = [
                i as f64 * dt,
                (i + 1) as f64 * dt,
                j as f64 * dp,
                (j + 1) as f64 * dp,
            ];
            let (integral, integral_sq) = if i + 1 == nt / 2 || i == nt / 2 {
                horizon_cell_integrals(&pdf, &rule, cell)
            } else {
                cell_integrals(&pdf, &rule, cell, CELL_DEPTH)
            };
            mass += integral;
            collision_expected += integral_sq;
            expected[i * np + j] = integral * n as f64;
        }
    }
    // A cell whose quadrature found no density but which a sample with a positive pdf landed
    // in holds a sliver of the support thinner than the quadrature's points (the edge of
    // total internal reflection seen at a grazing angle): it is integrated again on a
    // 32 x 32 grid of sub-cells.
    for c in 0..nt * np {
        if expected[c] == 0.0 && witness[c].is_some_and(|w| pdf(w) > 0.0) {
            let (i, j) = (c / np, c % np);
            let cell = [
                i as f64 * dt,
                (i + 1) as f64 * dt,
                j as f64 * dp,
                (j + 1) as f64 * dp,
            ];
            let (integral, integral_sq) = subdivided_cell_integrals(&pdf, &rule, cell, 32);
            mass += integral;
            collision_expected += integral_sq;
            expected[c] = integral * n as f64;
        }
    }
    if mass > 1.0 + 1e-3 {
        return Err(format!("pdf integrates to {mass} > 1 over the sphere"));
    }
    // The integral of an f32 pdf is only known to ~1e-7, and float samplers lose a few
    // zero-measure samples (u = 0 exactly), so "no sample" expects at least 1e-6 n.
    expected[nt * np] = (1.0 - mass).max(1e-6) * n as f64;

    let cell_name = |c: usize| {
        if c == nt * np {
            (usize::MAX, usize::MAX)
        } else {
            (c / np, c % np)
        }
    };
    let mut statistic = 0.0;
    let mut cells = 0usize;
    let (mut pooled_obs, mut pooled_exp) = (0.0, 0.0);
    let mut contributions = Vec::new();
    for (c, (&o, &e)) in observed.iter().zip(&expected).enumerate() {
        if e == 0.0 && o > 0.0 {
            let (i, j) = cell_name(c);
            return Err(format!(
                "{o} samples in cell ({i}, {j}) where the pdf is zero"
            ));
        }
        if e < MIN_EXPECTED {
            pooled_obs += o;
            pooled_exp += e;
        } else {
            let term = (o - e) * (o - e) / e;
            statistic += term;
            cells += 1;
            contributions.push((term, c, o, e));
        }
    }
    if pooled_exp > 0.0 {
        statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
        cells += 1;
    } else if pooled_obs > 0.0 {
        return Err(format!(
            "{pooled_obs} samples in sparse cells expecting none"
        ));
    }
    let dof = cells.saturating_sub(1).max(1);
    contributions.sort_by(|a, b| b.0.total_cmp(&a.0));
    let worst = contributions
        .iter()
        .take(5)
        .map(|&(_, c, o, e)| {
            let (i, j) = cell_name(c);
            (i, j, o, e)
        })
        .collect();
    // z^2 of a standard normal is chi-square with one degree of freedom.
    let z = (collision.mean() - collision_expected) / collision.std_error().max(1e-300);
    Ok(Chi2Outcome {
        statistic,
        dof,
        p_value: chi2_sf(statistic, dof),
        pdf_mass: mass,
        worst,
        collision_observed: (collision.mean(), collision.std_error()),
        collision_expected,
        collision_p_value: chi2_sf(z * z, 1),
    })
}

/// Sidak-corrected significance: each of `tests` tests runs at this level so that the family
/// rejects a correct sampler with probability `alpha` overall.
pub fn sidak(alpha: f64, tests: usize) -> f64 {
    1.0 - (1.0 - alpha).powf(1.0 / tests as f64)
}

/// Running mean and variance (Welford), for Monte Carlo estimates with a standard error.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    n: f64,
    mean: f64,
    m2: f64,
}

impl Stats {
    pub fn push(&mut self, x: f64) {
        self.n += 1.0;
        let d = x - self.mean;
        self.mean += d / self.n;
        self.m2 += d * (x - self.mean);
    }
    pub fn mean(&self) -> f64 {
        self.mean
    }
    /// Standard error of the mean.
    pub fn std_error(&self) -> f64 {
        (self.m2 / (self.n - 1.0) / self.n).sqrt()
    }
}

/// Indices of refraction the glass tests use: water, crown glass, diamond.
pub const IORS: [f32; 3] = [1.33, 1.5, 2.4];

/// A direction with the given cos(theta) (possibly tiny or negative) and azimuth.
pub fn direction(cos_theta: f32, phi: f32) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// A deterministic seed per test name (FNV-1a), so tests draw independent numbers.
pub fn seed(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// |a - b| within `rel` of the larger magnitude (or of 1e-6 near zero).
pub fn close(a: f32, b: f32, rel: f32) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-6)
}

/// [`close`] per channel.
pub fn close3(a: Vec3, b: Vec3, rel: f32) -> bool {
    (0..3).all(|k| close(a[k], b[k], rel))
}
