//! The recursive MIS weights against the power heuristic over each technique set's
//! techniques, computed by brute force.

use super::*;
use crate::sampling::Rng;

/// One full path x_0 (on an area light) .. x_k (the pinhole) of non-delta vertices, by
/// the numbers every technique's pdf is made of.
struct Path {
    k: usize,
    /// d[j]: the distance from x_j to x_{j+1}.
    d: Vec<f32>,
    /// |cos| at x_j towards x_{j-1} (`toward_light`) and towards x_{j+1} (`toward_camera`).
    toward_light: Vec<f32>,
    toward_camera: Vec<f32>,
    /// At x_j (0 < j < k): the solid-angle pdf of sampling towards x_{j+1} having arrived
    /// from x_{j-1} (`forward`), and of the opposite (`reverse`).
    forward: Vec<f32>,
    reverse: Vec<f32>,
    /// p_light p_A of x_0, the light's emission pdf towards x_1, the camera's per-pixel
    /// solid-angle pdf towards x_{k-1}.
    light_area: f32,
    emission_dir: f32,
    camera: f32,
    /// delta[m]: x_m (0 < m < k) has a delta lobe (a mirror): its forward and reverse pdfs
    /// are the same discrete probability, and no technique ends there.
    delta: Vec<bool>,
    /// The light is a sun (directional, at infinity): x_0 is a direction that next-event
    /// estimation picks with probability 1, the light subpath reaches x_1 with area
    /// density `light_area` (the disk's p_pos) |cos_1|, with no distance, and the camera
    /// subpath cannot find it.
    sun: bool,
}

impl Path {
    fn random(k: usize, rng: &mut Rng) -> Path {
        let mut value = |lo: f32, hi: f32| lo + (hi - lo) * rng.uniform();
        let mut list = |lo, hi| (0..=k).map(|_| value(lo, hi)).collect::<Vec<f32>>();
        let (d, toward_light, toward_camera) = (list(0.3, 3.0), list(0.1, 1.0), list(0.1, 1.0));
        let (mut forward, reverse) = (list(0.05, 2.0), list(0.05, 2.0));
        // Half of the paths of 3 or more edges get one mirror vertex; a sixth of all paths
        // are mirrors from end to end (a light seen in a chain of mirrors).
        let mut delta = vec![false; k + 1];
        let (one, chain) = (value(0.0, 1.0), value(0.0, 1.0));
        if k >= 3 && one < 0.5 {
            delta[1 + (value(0.0, 1.0) * (k - 1) as f32) as usize] = true;
        } else if chain < 1.0 / 6.0 {
            delta[1..k].fill(true);
        }
        for m in 1..k {
            if delta[m] {
                forward[m] = reverse[m];
            }
        }
        Path {
            k,
            d,
            toward_light,
            toward_camera,
            forward,
            reverse,
            light_area: value(0.2, 2.0),
            emission_dir: value(0.05, 0.4),
            camera: value(0.5, 4.0),
            delta,
            sun: false,
        }
    }

    /// True if x_j has a delta lobe.
    fn is_delta(&self, j: usize) -> bool {
        self.delta[j]
    }

    /// True if every vertex between the light and the camera has a delta lobe.
    fn all_delta(&self) -> bool {
        (1..self.k).all(|j| self.delta[j])
    }

    /// Whether technique `t` (in the order of [`Path::technique_pdfs`]) belongs to the
    /// set `techniques`: without connections, emission only on a path of mirrors.
    fn in_set(&self, t: usize, techniques: Techniques) -> bool {
        let k = self.k;
        match t {
            0 => techniques.connection() || self.all_delta(),
            t if t < k => techniques.connection(),
            t if t == k => techniques.light_tracing(),
            _ => techniques.merging(),
        }
    }

    /// Area pdf of x_j sampled by the light subpath (from x_{j-1}), j < k.
    fn p_light(&self, j: usize) -> f64 {
        let step = match j {
            0 if self.sun => return 1.0,
            0 => return self.light_area as f64,
            1 if self.sun => return (self.light_area * self.toward_light[1]) as f64,
            1 => self.emission_dir,
            _ => self.forward[j - 1],
        };
        (step * self.toward_light[j] / (self.d[j - 1] * self.d[j - 1])) as f64
    }

    /// Area pdf of x_j sampled by the camera subpath (from x_{j+1}), j < k.
    fn p_camera(&self, j: usize) -> f64 {
        let step = if j == self.k - 1 {
            self.camera
        } else {
            self.reverse[j + 1]
        };
        (step * self.toward_camera[j] / (self.d[j] * self.d[j])) as f64
    }

    /// The pdf of every technique that makes this path, by definition (TR sec. 3-4):
    /// a connection of the light subpath x_0..x_{s-1} and the camera subpath
    /// x_s..x_k is the product of their vertices' area pdfs (s = 0: the camera subpath
    /// finds the light; s = k: light tracing, one for each of the N light subpaths), and
    /// merging at x_i is the connection with the light subpath x_0..x_{i-1}, times the
    /// light subpath's density at x_i over the disc (pi r^2 p), times N. In order:
    /// s = 0..=k, then merges at x_1..x_{k-1}; `None` for a technique that would end a
    /// subpath at the delta vertex.
    fn technique_pdfs(&self, radius: f32, n: f32) -> Vec<Option<f64>> {
        let k = self.k;
        let light = |s: usize| (0..s).map(|j| self.p_light(j)).product::<f64>();
        let camera = |s: usize| (s..k).map(|j| self.p_camera(j)).product::<f64>();
        let open = |s: usize| {
            if s == 0 {
                !self.sun
            } else {
                !(self.is_delta(s - 1) || self.is_delta(s))
            }
        };
        let mut pdfs: Vec<Option<f64>> = (0..k)
            .map(|s| open(s).then(|| light(s) * camera(s)))
            .collect();
        pdfs.push((!self.is_delta(k - 1)).then(|| n as f64 * light(k)));
        let disc = std::f64::consts::PI * (radius as f64).powi(2) * n as f64;
        pdfs.extend((1..k).map(|i| (!self.is_delta(i)).then(|| disc * light(i + 1) * camera(i))));
        pdfs
    }

    /// The weights the estimators give each technique of `technique_pdfs`, from the
    /// subpaths' recursive quantities with the constants `c` of a technique set; `None`
    /// for a technique that ends a subpath at a delta vertex or that the set's kernels do
    /// not run (all but the emission, which the camera subpath always finds).
    #[allow(clippy::needless_range_loop)] // j indexes the path's arrays and the states
    fn weights(&self, c: &MisConstants) -> Vec<Option<f32>> {
        let k = self.k;
        // The light subpath's quantities on arriving at x_j (index j, 1..k-1).
        let mut light = vec![SubpathMis::default(); k];
        let mut state = if self.sun {
            SubpathMis::light_start_at_infinity(self.light_area, 1.0, true, c)
        } else {
            SubpathMis::light_start(
                self.light_area,
                self.emission_dir,
                self.toward_camera[0],
                false,
                c,
            )
        };
        for j in 1..k {
            if j > 1 {
                let (fwd, rev) = (self.forward[j - 1], self.reverse[j - 1]);
                let delta = self.is_delta(j - 1);
                state.scatter(delta, self.toward_camera[j - 1], fwd, rev, c);
            }
            let d = self.d[j - 1];
            let d2 = if self.sun && j == 1 { 1.0 } else { d * d };
            assert!(state.arrive(d2, self.toward_light[j]));
            light[j] = state;
        }
        // The camera subpath's on arriving at x_j (index j, 0..k-1).
        let mut camera = vec![SubpathMis::default(); k];
        let mut state = SubpathMis::camera_start(self.camera, c);
        for j in (0..k).rev() {
            if j < k - 1 {
                let (fwd, rev) = (self.reverse[j + 1], self.forward[j + 1]);
                let delta = self.is_delta(j + 1);
                state.scatter(delta, self.toward_light[j + 1], fwd, rev, c);
            }
            let d = self.d[j];
            assert!(state.arrive(d * d, self.toward_camera[j]));
            camera[j] = state;
        }
        let mut weights = Vec::new();
        // s = 0: the camera subpath finds the light at x_0.
        weights.push((!self.sun).then(|| {
            emission_weight(
                &camera[0],
                self.light_area,
                self.emission_dir,
                self.all_delta(),
                c,
            )
        }));
        // s = 1: next-event estimation at x_1 (a sun: its direction with pdf 1, and
        // `Light::pdf_emission_at`'s p_pos |cos| for the light subpath reaching x_1).
        let d0 = self.d[0];
        let (direct_pdf, emission_area) = if self.sun {
            (1.0, self.light_area * self.toward_light[1])
        } else {
            (
                self.light_area * d0 * d0 / self.toward_camera[0],
                self.emission_dir * self.toward_light[1] / (d0 * d0),
            )
        };
        weights.push((!self.is_delta(1)).then(|| {
            direct_weight(
                &camera[1],
                direct_pdf,
                self.sun,
                self.reverse[1],
                emission_area,
                self.forward[1],
                c,
            )
        }));
        // 2 <= s < k: connection of x_{s-1} and x_s.
        for s in 2..k {
            let d2 = self.d[s - 1] * self.d[s - 1];
            let open = !(self.is_delta(s - 1) || self.is_delta(s));
            weights.push(open.then(|| {
                connection_weight(
                    &light[s - 1],
                    &camera[s],
                    self.reverse[s] * self.toward_camera[s - 1] / d2,
                    self.forward[s - 1] * self.toward_light[s] / d2,
                    self.reverse[s - 1],
                    self.forward[s],
                    c,
                )
            }));
        }
        // s = k: light tracing from x_{k-1}.
        let d2 = self.d[k - 1] * self.d[k - 1];
        weights.push((!self.is_delta(k - 1)).then(|| {
            light_tracing_weight(
                &light[k - 1],
                self.camera * self.toward_camera[k - 1] / d2,
                self.reverse[k - 1],
                c,
            )
        }));
        // Merging at x_i.
        for i in 1..k {
            weights.push(
                (!self.is_delta(i)).then(|| {
                    merge_weight(&light[i], &camera[i], self.reverse[i], self.forward[i], c)
                }),
            );
        }
        for (t, w) in weights.iter_mut().enumerate().skip(1) {
            if !self.in_set(t, c.techniques) {
                *w = None;
            }
        }
        weights
    }
}

/// The recursive weights (dVCM, dVC, dVM and the five estimators' formulas) equal the
/// power heuristic over every technique's pdf written out as a product of the path's
/// area pdfs, technique by technique, on random paths of 2 to 7 edges (half of those of
/// 3 or more with a mirror vertex, a sixth of all mirrors from end to end), so they sum
/// to one: the estimator is unbiased whatever the radius and the number of light paths.
/// The same holds for each technique set (`bpt`, `bpm`, `lt`) over exactly its own
/// techniques, with the constants it zeroes; only light tracing alone leaves paths
/// without a technique (a surface seen in a mirror), and it gives them no weight.
#[test]
fn recursive_weights_equal_the_power_heuristic_over_all_techniques() {
    let mut rng = Rng::new(5, 0, 0);
    // Per set, techniques of each kind (emission, next-event, connection, light tracing,
    // merging) that carried a weight between 5% and 95% somewhere: the test compares real
    // mixtures. The kinds a set mixes: all for vcm, its connections for bpt, merges for
    // bpm, none for lt (one technique per path).
    let mixes: [&[usize]; 4] = [&[0, 1, 2, 3, 4], &[0, 1, 2, 3], &[4], &[]];
    let mut mixed = [[0usize; 5]; 4];
    let (mut deltas, mut chains, mut uncovered) = (0, 0, 0);
    for case in 0..1200 {
        let k = 2 + case % 6;
        let path = Path::random(k, &mut rng);
        let (radius, n) = ([0.01, 0.05, 0.3][case % 3], [100.0, 4096.0][case % 2]);
        deltas += path.delta.contains(&true) as usize;
        chains += path.all_delta() as usize;
        let all_pdfs = path.technique_pdfs(radius, n);
        for (set, techniques) in Techniques::ALL.into_iter().enumerate() {
            let c = MisConstants::new(techniques, radius, n as u32);
            let pdfs: Vec<Option<f64>> = (0..all_pdfs.len())
                .map(|t| all_pdfs[t].filter(|_| path.in_set(t, techniques)))
                .collect();
            let total: f64 = pdfs.iter().flatten().map(|p| p * p).sum();
            let weights = path.weights(&c);
            assert_eq!(weights.len(), pdfs.len());
            let name = techniques.name();
            for (t, (&w, &p)) in weights.iter().zip(&pdfs).enumerate() {
                let (w, expected) = match (w, p) {
                    (Some(w), Some(p)) => (w, p * p / total),
                    (None, None) => continue,
                    // The emission of a path the set samples otherwise: weight 0.
                    (Some(w), None) if t == 0 && all_pdfs[0].is_some() => (w, 0.0),
                    _ => panic!("{name}, case {case}: technique {t} is available to one side only"),
                };
                let kind = match t {
                    0 => 0,
                    1 => 1,
                    t if t < k => 2,
                    t if t == k => 3,
                    _ => 4,
                };
                mixed[set][kind] += (0.05..0.95).contains(&expected) as usize;
                assert!(
                    (w as f64 - expected).abs() <= 1e-4 * expected.max(1e-3),
                    "{name}, case {case}, k = {k}, technique {t}: {w} against {expected}"
                );
            }
            let sum: f64 = weights.iter().flatten().map(|&w| w as f64).sum();
            if total == 0.0 {
                assert_eq!(
                    techniques,
                    Techniques::LT,
                    "case {case}: {name} misses a path"
                );
                assert_eq!(
                    sum, 0.0,
                    "lt, case {case}: a path without a technique counted"
                );
                uncovered += 1;
                continue;
            }
            assert!(
                (sum - 1.0).abs() < 1e-4,
                "{name}, case {case}: the weights sum to {sum}"
            );
        }
    }
    for (set, kinds) in mixes.iter().enumerate() {
        let name = Techniques::ALL[set].name();
        assert!(
            kinds.iter().all(|&kind| mixed[set][kind] >= 20),
            "{name}: too few mixed weights: {:?}",
            mixed[set]
        );
    }
    assert!(deltas > 300, "too few paths with a delta vertex: {deltas}");
    assert!(chains > 100, "too few paths of mirrors only: {chains}");
    assert!(
        uncovered > 50,
        "too few paths light tracing misses: {uncovered}"
    );
}

/// For a sun (a directional light at infinity) the recursive weights equal the power
/// heuristic over every technique too (no emission technique: no camera subpath finds
/// it), on random paths of 2 to 7 edges without mirrors, for every technique set but
/// light tracing alone: the first light vertex's density p_pos |cos_1| without distance,
/// dVCM = mis(1/p_pos) at the start and next-event's p_pos |cos| agree.
#[test]
fn recursive_weights_for_a_sun_equal_the_power_heuristic() {
    let mut rng = Rng::new(9, 0, 0);
    for case in 0..600 {
        let k = 2 + case % 6;
        let mut path = Path::random(k, &mut rng);
        path.sun = true;
        path.delta.fill(false);
        let (radius, n) = ([0.01, 0.05, 0.3][case % 3], [100.0, 4096.0][case % 2]);
        let all_pdfs = path.technique_pdfs(radius, n);
        for techniques in [Techniques::VCM, Techniques::BPT, Techniques::BPM] {
            let c = MisConstants::new(techniques, radius, n as u32);
            let pdfs: Vec<Option<f64>> = (0..all_pdfs.len())
                .map(|t| all_pdfs[t].filter(|_| path.in_set(t, techniques)))
                .collect();
            let total: f64 = pdfs.iter().flatten().map(|p| p * p).sum();
            let weights = path.weights(&c);
            let name = techniques.name();
            for (t, (&w, &p)) in weights.iter().zip(&pdfs).enumerate() {
                match (w, p) {
                    (Some(w), Some(p)) => {
                        let expected = p * p / total;
                        assert!(
                            (w as f64 - expected).abs() <= 1e-4 * expected.max(1e-3),
                            "{name}, case {case}, k = {k}, technique {t}: {w} vs {expected}"
                        );
                    }
                    (None, None) => {}
                    _ => panic!("{name}, case {case}: technique {t} on one side only"),
                }
            }
            let sum: f64 = weights.iter().flatten().map(|&w| w as f64).sum();
            assert!((sum - 1.0).abs() < 1e-4, "{name}, case {case}: sum {sum}");
        }
    }
}
