//! Small scenes built in code and per-pixel statistics, shared by the integrator tests.

use ppm_core::prelude::*;

/// The camera inside a closed, inward-facing diffuse sphere of albedo `albedo` emitting 1.
/// Every pixel sees L = 1 / (1 - albedo).
pub fn furnace(albedo: f32, resolution: u32) -> Scene {
    let camera = Camera::new(
        Vec3::ZERO,
        Vec3::NEG_Z,
        Vec3::Y,
        60.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let m = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(albedo)), Vec3::ONE));
    b.add_sphere(Sphere::new(Vec3::ZERO, 1.0, m).inward());
    b.build().unwrap()
}

/// What goes in the small Cornell box.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum BoxContents {
    /// A diffuse block.
    Diffuse,
    /// A diffuse block and a glass sphere.
    Glass,
    /// A phong floor and a phong sphere.
    Glossy,
}

/// A closed Cornell-like box [-1,1] x [0,2] x [-1,1] (front wall included, behind the camera
/// side it is closed too) with an area light under the ceiling. Closed so that the power
/// conservation test can count every photon.
pub fn cornell(resolution: u32, contents: BoxContents) -> Scene {
    cornell_builder(resolution, contents).build().unwrap()
}

/// The parts of [`cornell`], for tests that add to it.
pub fn cornell_builder(resolution: u32, contents: BoxContents) -> SceneBuilder {
    let camera = Camera::new(
        Vec3::new(0.0, 1.0, 0.95),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        70.0,
        (resolution, resolution),
    )
    .unwrap();
    let mut b = SceneBuilder::new(camera);
    let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.73)), Vec3::ZERO));
    let red = b.add_material(Material::new(
        Bsdf::diffuse(Vec3::new(0.63, 0.06, 0.05)),
        Vec3::ZERO,
    ));
    let green = b.add_material(Material::new(
        Bsdf::diffuse(Vec3::new(0.14, 0.45, 0.09)),
        Vec3::ZERO,
    ));
    let lamp = b.add_material(Material::new(
        Bsdf::diffuse(Vec3::splat(0.78)),
        Vec3::new(17.0, 12.0, 4.0),
    ));
    let floor_material = if contents == BoxContents::Glossy {
        b.add_material(Material::new(
            Bsdf::phong(Vec3::splat(0.3), Vec3::splat(0.5), 30.0),
            Vec3::ZERO,
        ))
    } else {
        white
    };
    let q = |c: [f32; 3], u: [f32; 3], v: [f32; 3], m: u32| {
        TriangleMesh::quad(Vec3::from(c), Vec3::from(u), Vec3::from(v), m)
    };
    // Inward-facing walls: normal = cross(edge_u, edge_v) points into the box.
    b.add_mesh(q(
        [-1.0, 0.0, -1.0],
        [0.0, 0.0, 2.0],
        [2.0, 0.0, 0.0],
        floor_material,
    )); // floor, +y
    b.add_mesh(q(
        [-1.0, 2.0, -1.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, 2.0],
        white,
    )); // ceiling, -y
    b.add_mesh(q(
        [-1.0, 0.0, -1.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
        white,
    )); // back, +z
    b.add_mesh(q([-1.0, 0.0, 1.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0], white)); // front, -z
    b.add_mesh(q([-1.0, 0.0, -1.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0], red)); // left, +x
    b.add_mesh(q([1.0, 0.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0], green)); // right, -x
    b.add_mesh(q(
        [-0.25, 1.98, -0.25],
        [0.5, 0.0, 0.0],
        [0.0, 0.0, 0.5],
        lamp,
    )); // light, -y
    match contents {
        BoxContents::Diffuse => add_block(&mut b, Vec3::new(-0.35, 0.0, -0.3), 0.5, 0.8, white),
        BoxContents::Glass => {
            add_block(&mut b, Vec3::new(-0.35, 0.0, -0.3), 0.5, 0.8, white);
            let glass = b.add_material(Material::new(Bsdf::glass(1.5, Vec3::ONE), Vec3::ZERO));
            b.add_sphere(Sphere::new(Vec3::new(0.45, 0.35, 0.1), 0.35, glass));
        }
        BoxContents::Glossy => {
            let glossy = b.add_material(Material::new(
                Bsdf::phong(Vec3::splat(0.1), Vec3::splat(0.8), 200.0),
                Vec3::ZERO,
            ));
            b.add_sphere(Sphere::new(Vec3::new(0.4, 0.4, -0.2), 0.4, glossy));
        }
    }
    b
}

/// The diffuse [`cornell`] box lit only by a spot light under the ceiling (its lamp quad
/// emits nothing), aimed down and to the left so that its cone and falloff fall on the
/// floor, the block and the red wall.
pub fn spot_box(resolution: u32) -> SceneBuilder {
    let mut b = cornell_builder(resolution, BoxContents::Diffuse);
    for m in &mut b.materials {
        m.emission = Vec3::ZERO;
    }
    let spot = ppm_core::light::Light::spot(
        Vec3::new(0.2, 1.9, 0.1),
        Vec3::new(-0.4, -1.0, -0.2),
        Vec3::new(3.0, 2.5, 2.0),
        35f32.to_radians(),
        20f32.to_radians(),
    )
    .unwrap();
    b.add_light(spot);
    b
}

/// An axis-aligned box with its bottom centre at `base`, outward normals.
pub fn add_block(b: &mut SceneBuilder, base: Vec3, size: f32, height: f32, m: u32) {
    let lo = base - Vec3::new(size / 2.0, 0.0, size / 2.0);
    let (x, y, z) = (Vec3::X * size, Vec3::Y * height, Vec3::Z * size);
    let faces = [
        (lo + y, z, x), // top, +y
        (lo, x, z),     // bottom, -y
        (lo, y, x),     // back, -z
        (lo + z, x, y), // front, +z
        (lo, z, y),     // left, -x
        (lo + x, y, z), // right, +x
    ];
    for (c, u, v) in faces {
        b.add_mesh(TriangleMesh::quad(c, u, v, m));
    }
}

/// Per-pixel running mean and variance of iteration estimates (f64).
pub struct PixelStats {
    pub n: u64,
    /// Sum and sum of squares of the per-iteration image means (pixels of one iteration are
    /// correlated in photon mapping, iterations are independent).
    image_sum: f64,
    image_sum2: f64,
    sum: Vec<[f64; 3]>,
    sum2: Vec<[f64; 3]>,
}

impl PixelStats {
    pub fn new(pixels: usize) -> Self {
        PixelStats {
            n: 0,
            image_sum: 0.0,
            image_sum2: 0.0,
            sum: vec![[0.0; 3]; pixels],
            sum2: vec![[0.0; 3]; pixels],
        }
    }

    pub fn add(&mut self, estimates: &[Vec3]) {
        let m = estimates
            .iter()
            .map(|e| (e.x + e.y + e.z) as f64)
            .sum::<f64>()
            / (3 * estimates.len()) as f64;
        self.image_sum += m;
        self.image_sum2 += m * m;
        for (i, e) in estimates.iter().enumerate() {
            for c in 0..3 {
                let v = e[c] as f64;
                self.sum[i][c] += v;
                self.sum2[i][c] += v * v;
            }
        }
        self.n += 1;
    }

    /// Mean of channel `c` of pixel `i`.
    pub fn mean(&self, i: usize, c: usize) -> f64 {
        self.sum[i][c] / self.n as f64
    }

    /// Estimated variance of the mean of channel `c` of pixel `i`.
    pub fn var_of_mean(&self, i: usize, c: usize) -> f64 {
        let n = self.n as f64;
        let m = self.sum[i][c] / n;
        let m2 = self.sum2[i][c] / n;
        ((m2 - m * m) * n / (n - 1.0)).max(0.0) / n
    }

    pub fn pixels(&self) -> usize {
        self.sum.len()
    }

    /// Standard error of [`PixelStats::image_mean`], from the spread of the iteration means.
    pub fn image_mean_se(&self) -> f64 {
        let n = self.n as f64;
        let m = self.image_sum / n;
        ((self.image_sum2 / n - m * m).max(0.0) / (n - 1.0)).sqrt()
    }

    /// Mean over all pixels and channels.
    pub fn image_mean(&self) -> f64 {
        let total: f64 = self.sum.iter().map(|s| s[0] + s[1] + s[2]).sum();
        total / (3.0 * self.n as f64 * self.sum.len() as f64)
    }
}

/// Renders `iterations` iterations and collects per-pixel statistics of the iteration estimates.
pub fn render_stats(scene: &Scene, settings: &RenderSettings, iterations: u32) -> PixelStats {
    let mut r = Renderer::new(scene, settings);
    let mut stats = PixelStats::new((scene.camera.width * scene.camera.height) as usize);
    for _ in 0..iterations {
        r.iterate(scene);
        stats.add(r.last_estimates());
    }
    assert_eq!(r.rejected(), 0, "NaN or Inf samples");
    stats
}

/// The image of `iterations` iterations rendered on a pool of `threads` threads, for the
/// thread-count determinism tests.
pub fn render_on_threads(
    scene: &Scene,
    settings: &RenderSettings,
    iterations: u32,
    threads: usize,
) -> Image {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut r = Renderer::new(scene, settings);
        for _ in 0..iterations {
            r.iterate(scene);
        }
        r.image()
    })
}

/// `seeds` independent SPPM renders of `iterations` iterations each; their final images are
/// the samples of the per-pixel statistics (SPPM's iterations share per-pixel state, so
/// unlike `ppm` they are not independent samples: whole renders are).
pub fn sppm_stats(
    scene: &Scene,
    settings: &RenderSettings,
    seeds: u64,
    iterations: u32,
) -> PixelStats {
    let mut stats = PixelStats::new((scene.camera.width * scene.camera.height) as usize);
    for seed in 0..seeds {
        let settings = RenderSettings {
            seed: settings.seed + seed,
            ..settings.clone()
        };
        let mut r = Renderer::new(scene, &settings);
        for _ in 0..iterations {
            r.iterate(scene);
        }
        assert_eq!(r.rejected(), 0, "NaN or Inf samples");
        stats.add(&r.image().pixels);
    }
    stats
}

/// Two-sample z statistics per pixel and channel between independent estimates a and b:
/// z = (mean_a - mean_b) / sqrt(var_a + var_b). Returns all z values (pixels with zero
/// variance on both sides and equal means are skipped).
pub fn z_scores(a: &PixelStats, b: &PixelStats) -> Vec<f64> {
    let mut z = Vec::new();
    for i in 0..a.pixels() {
        for c in 0..3 {
            let v = a.var_of_mean(i, c) + b.var_of_mean(i, c);
            let d = a.mean(i, c) - b.mean(i, c);
            if v > 0.0 {
                z.push(d / v.sqrt());
            } else {
                assert!(
                    d.abs() < 1e-9,
                    "pixel {i}: zero variance but means differ by {d}"
                );
            }
        }
    }
    z
}

/// Asserts that `other`, a consistent estimator (`label`), renders scene `name` as the path
/// tracer does: image means within 4 standard errors of their difference and within 1%; at
/// most 1% of pixel channels beyond 4 sigma (z from [`z_scores`]); mean z^2 below
/// `mean_z2_bound` (1 for unbiased estimators; a consistent one keeps a bias near concave
/// corners and sharp caustics, which the caller's bound allows for).
pub fn assert_converges_to_pt(
    name: &str,
    label: &str,
    pt: &PixelStats,
    other: &PixelStats,
    mean_z2_bound: f64,
) {
    assert_agrees_with_pt(name, label, pt, other, Some(0.01), mean_z2_bound);
}

/// [`assert_converges_to_pt`] with the bound on the image means' relative difference given
/// (`None`: only the 4 standard errors of their difference).
pub fn assert_agrees_with_pt(
    name: &str,
    label: &str,
    pt: &PixelStats,
    other: &PixelStats,
    relative_bound: Option<f64>,
    mean_z2_bound: f64,
) {
    let (a, b) = (pt.image_mean(), other.image_mean());
    let se = (pt.image_mean_se().powi(2) + other.image_mean_se().powi(2)).sqrt();
    eprintln!(
        "{name}: pt {a} (se {}) {label} {b} (se {}), relative difference {:+.2e}",
        pt.image_mean_se(),
        other.image_mean_se(),
        (b - a) / a
    );
    assert!(
        (a - b).abs() < 4.0 * se,
        "{name}: image means pt {a} {label} {b}, se of difference {se}"
    );
    if let Some(bound) = relative_bound {
        assert!(
            (a - b).abs() / a < bound,
            "{name}: image means pt {a} {label} {b}"
        );
    }
    let z = z_scores(pt, other);
    let beyond = z.iter().filter(|z| z.abs() > 4.0).count();
    let mean_z2 = z.iter().map(|z| z * z).sum::<f64>() / z.len() as f64;
    eprintln!(
        "{name}: {beyond} of {} beyond 4 sigma, mean z^2 {mean_z2}",
        z.len()
    );
    assert!(
        beyond * 100 <= z.len(),
        "{name}: {beyond} of {} pixel channels differ beyond 4 sigma",
        z.len()
    );
    assert!(mean_z2 < mean_z2_bound, "{name}: mean z^2 = {mean_z2}");
}

/// Asserts that every pixel's mean is `expected` within `k` standard errors, and that the
/// mean over the image is within `k` standard errors of the image mean (pixels independent).
pub fn assert_uniform_image(stats: &PixelStats, expected: f64, k: f64, what: &str) {
    let n = stats.pixels();
    let mut sum_var = 0.0;
    for i in 0..n {
        for c in 0..3 {
            let se = stats.var_of_mean(i, c).sqrt();
            let d = stats.mean(i, c) - expected;
            assert!(
                d.abs() <= k * se + 1e-9,
                "{what}: pixel {i} channel {c}: {} vs {expected} (se {se})",
                stats.mean(i, c)
            );
            sum_var += stats.var_of_mean(i, c);
        }
    }
    let se_image = (sum_var).sqrt() / (3 * n) as f64;
    let d = stats.image_mean() - expected;
    assert!(
        d.abs() <= k * se_image,
        "{what}: image mean {} vs {expected} (se {se_image})",
        stats.image_mean()
    );
}
