//! The plainest scene checked three ways: a grey diffuse floor lit by a square area light
//! (`tests/data/mitsuba/renders/floor_lamp.xml`, read through the Mitsuba importer), whose
//! image has a closed form, against ppm's path tracer pixel by pixel and against Mitsuba 3's
//! image mean (references.csv, `scripts/mitsuba/importer_references.py`).
//!
//! The floor is y = 0, 8 x 8, albedo rho = 0.5; the light is the 2 x 2 square x in [-2, 0],
//! z in [-0.5, 1.5] at height h = 4, facing down, of radiance Le = 6. Nothing else reflects
//! light back (the light's back is the floor's sky), so the image is direct light alone:
//! L(p) = rho / pi * E(p), with E the irradiance of a parallel rectangle (below).

use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_scene::load_scene_builder;
use std::f64::consts::PI;
use std::path::Path;

const RHO: f64 = 0.5;
const LE: f64 = 6.0;
const H: f64 = 4.0;
const LAMP_X: [f64; 2] = [-2.0, 0.0];
const LAMP_Z: [f64; 2] = [-0.5, 1.5];
const SIZE: usize = 32;

/// Irradiance at the origin from the parallel rectangle [0, a] x [0, b] at height H, signed
/// (odd in a and in b) so that rectangles add up from their corners: the differential form
/// factor to a rectangle over one of its corners (Howell's catalogue, configuration B-3),
/// F = 1/(2 pi) [A / sqrt(1 + A^2) atan(B / sqrt(1 + A^2)) + (A <-> B)], A = a/h, B = b/h,
/// and E = pi Le F.
fn corner_irradiance(a: f64, b: f64) -> f64 {
    let (a, b) = (a / H, b / H);
    let term = |a: f64, b: f64| a / (1.0 + a * a).sqrt() * (b / (1.0 + a * a).sqrt()).atan();
    0.5 * LE * (term(a, b) + term(b, a))
}

/// Irradiance at the floor point (x, z) from the lamp.
fn irradiance(x: f64, z: f64) -> f64 {
    let f = |i: usize, j: usize| corner_irradiance(LAMP_X[i] - x, LAMP_Z[j] - z);
    f(1, 1) - f(0, 1) - f(1, 0) + f(0, 0)
}

/// Irradiance by brute force: the midpoint rule over the lamp, E = Le int cos cos / r^2 dA
/// = Le int h^2 / r^4 dA for a parallel emitter.
fn irradiance_by_quadrature(x: f64, z: f64, n: usize) -> f64 {
    let (w, d) = (LAMP_X[1] - LAMP_X[0], LAMP_Z[1] - LAMP_Z[0]);
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let lx = LAMP_X[0] + (i as f64 + 0.5) / n as f64 * w;
            let lz = LAMP_Z[0] + (j as f64 + 0.5) / n as f64 * d;
            let r2 = (lx - x).powi(2) + (lz - z).powi(2) + H * H;
            sum += H * H / (r2 * r2);
        }
    }
    LE * sum * w * d / (n * n) as f64
}

/// The exact image, pixel by pixel (averaged over `s` x `s` points of each pixel, as the box
/// filter does), and per pixel whether all those points see the floor. The camera is the
/// stage's: at (0, 3, 5) looking at (0, 0.6, 0), 45 degrees across x, 32 x 32.
fn exact_image(s: usize) -> (Vec<f64>, Vec<bool>) {
    let origin = [0.0, 3.0, 5.0];
    let forward = normalize(sub([0.0, 0.6, 0.0], origin));
    let right = normalize(cross(forward, [0.0, 1.0, 0.0]));
    let up = cross(right, forward);
    let tan = (45f64.to_radians() / 2.0).tan();
    let mut image = vec![0.0; SIZE * SIZE];
    let mut inside = vec![true; SIZE * SIZE];
    for py in 0..SIZE {
        for px in 0..SIZE {
            let mut sum = 0.0;
            for a in 0..s {
                for b in 0..s {
                    let u = (px as f64 + (a as f64 + 0.5) / s as f64) / SIZE as f64;
                    let v = (py as f64 + (b as f64 + 0.5) / s as f64) / SIZE as f64;
                    let (sx, sy) = ((2.0 * u - 1.0) * tan, (1.0 - 2.0 * v) * tan);
                    let d: Vec<f64> = (0..3)
                        .map(|k| forward[k] + sx * right[k] + sy * up[k])
                        .collect();
                    let t = -origin[1] / d[1];
                    let (x, z) = (origin[0] + t * d[0], origin[2] + t * d[2]);
                    if t > 0.0 && x.abs() < 4.0 && z.abs() < 4.0 {
                        sum += RHO / PI * irradiance(x, z);
                    } else {
                        inside[py * SIZE + px] = false;
                    }
                }
            }
            image[py * SIZE + px] = sum / (s * s) as f64;
        }
    }
    (image, inside)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

#[test]
fn the_closed_form_equals_the_quadrature() {
    for (x, z) in [(0.0, 0.0), (-1.0, 0.5), (2.5, -3.0), (-3.9, 3.9)] {
        let (exact, brute) = (irradiance(x, z), irradiance_by_quadrature(x, z, 400));
        assert!(
            (exact - brute).abs() < 1e-5 * exact,
            "({x}, {z}): {exact} vs {brute}"
        );
    }
}

#[test]
fn the_path_tracer_matches_the_closed_form_pixel_by_pixel() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba/renders");
    let (builder, warnings) = load_scene_builder(&data.join("floor_lamp.xml")).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        seed: 5,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut renderer = Renderer::new(&scene, &settings);
    let n = 256;
    let mut sum = vec![0.0f64; SIZE * SIZE];
    let mut sum2 = vec![0.0f64; SIZE * SIZE];
    for _ in 0..n {
        assert_eq!(renderer.iterate(&scene).rejected, 0);
        for (i, v) in renderer.last_estimates().iter().enumerate() {
            let y = (v.x as f64 + v.y as f64 + v.z as f64) / 3.0;
            sum[i] += y;
            sum2[i] += y * y;
        }
    }
    let (exact, inside) = exact_image(8);
    // Pixels wholly on the floor: each one's mean over n independent one-sample estimates
    // against the exact value, in standard errors. Their squares sum to a chi-square with
    // one degree of freedom per pixel, whose mean is 1 and spread sqrt(2 / pixels).
    let mut chi2 = 0.0;
    let mut pixels = 0;
    for i in (0..SIZE * SIZE).filter(|&i| inside[i]) {
        let mean = sum[i] / n as f64;
        let var = (sum2[i] / n as f64 - mean * mean) * n as f64 / (n - 1) as f64;
        let z = (mean - exact[i]) / (var / n as f64).sqrt();
        chi2 += z * z;
        pixels += 1;
    }
    let reduced = chi2 / pixels as f64;
    eprintln!("floor and lamp: chi2 / pixels = {reduced} over {pixels} pixels");
    assert!(pixels > 500, "{pixels} pixels on the floor");
    // A factor in the light's radiance, the floor's albedo or the camera's field of view of
    // 1 % moves each pixel by about one standard error here: chi2 / pixels near 2.
    assert!(
        (reduced - 1.0).abs() < 5.0 * (2.0 / pixels as f64).sqrt(),
        "chi2 / pixels = {reduced}"
    );
}

#[test]
fn mitsuba_matches_the_closed_form() {
    let csv = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba/renders/references.csv"),
    )
    .unwrap();
    let row: Vec<f64> = csv
        .lines()
        .find_map(|l| l.strip_prefix("floor_lamp,"))
        .expect("floor_lamp in references.csv")
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let (mitsuba, se) = (row[2], row[5]);
    // Pixels at the floor's edges are averaged over 32 x 32 points: the coverage error is
    // below 1e-4 of the mean.
    let (exact, _) = exact_image(32);
    let mean = exact.iter().sum::<f64>() / exact.len() as f64;
    eprintln!("floor and lamp: exact {mean}, Mitsuba 3 {mitsuba} +- {se}");
    assert!(
        (mitsuba - mean).abs() < 4.0 * se + 1e-4 * mean,
        "exact {mean}, Mitsuba 3 {mitsuba} +- {se}"
    );
}
