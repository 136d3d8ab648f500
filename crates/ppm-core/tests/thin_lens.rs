//! The thin-lens camera end to end: the plane in focus is sharp and an edge off it blurs by
//! the circle of confusion's analytic profile; a furnace stays uniform; light tracing, bpt
//! and vcm through the lens agree with the path tracer per pixel.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{Techniques, VcmRenderer};
use ppm_core::pixel_bounds::PixelBounds;
use ppm_core::prelude::*;
use test_scenes::{
    assert_converges_to_pt, assert_uniform_image, cornell_builder, furnace, render_stats,
    BoxContents, PixelStats,
};

/// An emitting (L = 1), non-reflecting quad covering x >= 0 at depth `depth` in front of a
/// camera at the origin looking down -z, with a lens of radius `radius` focused at `focus`;
/// nothing else. The quad's edge projects onto the image's middle column boundary.
fn edge_scene(depth: f32, radius: f32, focus: f32) -> Scene {
    let camera = Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 40.0, (32, 16))
        .unwrap()
        .with_lens(radius, focus)
        .unwrap();
    let mut b = SceneBuilder::new(camera);
    let m = b.add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::ONE));
    // Normal cross(u, v) = +z, toward the camera.
    b.add_mesh(TriangleMesh::quad(
        Vec3::new(0.0, -50.0, -depth),
        Vec3::new(50.0, 0.0, 0.0),
        Vec3::new(0.0, 100.0, 0.0),
        m,
    ));
    b.build().unwrap()
}

/// P(s < t) for s the x coordinate of a point uniform in a disk of radius `r` (r > 0):
/// 1/2 + (t sqrt(r^2 - t^2) + r^2 asin(t / r)) / (pi r^2) inside, 0 or 1 outside.
fn disk_marginal_cdf(t: f64, r: f64) -> f64 {
    if r == 0.0 {
        return if t > 0.0 { 1.0 } else { 0.0 };
    }
    let t = t.clamp(-r, r);
    0.5 + (t * (r * r - t * t).sqrt() + r * r * (t / r).asin()) / (std::f64::consts::PI * r * r)
}

/// The expected pixel value of column `i` of [`edge_scene`]: the lens ray from lens point l
/// through the focus-plane point q hits the quad at depth z when q's pixel offset u from the
/// edge exceeds s = l_x (f - z) / z d_img / f; l_x is the x-marginal of the disk, so s is that
/// of a disk of radius R = coc / 2 pixels. The pixel averages P(s < u) over u in its width
/// (midpoint rule, 2000 points).
fn expected_column(i: u32, width: u32, coc: f64) -> f64 {
    let n = 2000;
    (0..n)
        .map(|k| {
            let u = i as f64 + (k as f64 + 0.5) / n as f64 - width as f64 / 2.0;
            disk_marginal_cdf(u, coc / 2.0)
        })
        .sum::<f64>()
        / n as f64
}

/// In focus every pixel is 0 or 1 exactly (the edge lies on a pixel boundary of the focus
/// plane); off focus each column matches the circle of confusion's profile (5 standard errors
/// per pixel plus 1e-3), and the blurred columns span the computed diameter.
#[test]
fn focus_plane_is_sharp_and_defocus_blurs_by_the_circle_of_confusion() {
    let (radius, focus) = (0.4, 2.0);
    for depth in [2.0f32, 1.5, 3.0] {
        let scene = edge_scene(depth, radius, focus);
        let coc = scene.camera.circle_of_confusion(depth) as f64;
        let settings = RenderSettings {
            seed: 7,
            ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
        };
        let stats = render_stats(&scene, &settings, 1500);
        let width = scene.camera.width;
        let mut blurred = 0;
        for y in 0..scene.camera.height {
            for x in 0..width {
                let i = (y * width + x) as usize;
                let expected = expected_column(x, width, coc);
                let (mean, se) = (stats.mean(i, 0), stats.var_of_mean(i, 0).sqrt());
                assert!(
                    (mean - expected).abs() <= 5.0 * se + 1e-3,
                    "depth {depth}: pixel ({x}, {y}) {mean} (se {se}), expected {expected} (coc {coc} px)"
                );
                if y == 0 && mean > 0.01 && mean < 0.99 {
                    blurred += 1;
                }
            }
        }
        eprintln!("depth {depth}: circle of confusion {coc} px, {blurred} blurred columns");
        if depth == focus {
            assert_eq!(coc, 0.0);
            assert_eq!(blurred, 0, "in focus the edge is sharp");
        } else {
            // The partial columns are those meeting the interval of width coc about the edge
            // (at most ceil(coc) + 1), less nearly saturated ones at its ends.
            assert!(coc > 2.0, "{coc}");
            assert!(blurred as f64 <= coc.ceil() + 1.0 && blurred as f64 >= coc - 2.0);
        }
    }
}

/// The camera inside a uniformly emitting furnace sees L = 1 / (1 - a) through any lens: the
/// lens changes which directions a pixel averages, never the radiance.
#[test]
fn the_furnace_stays_uniform_through_a_lens() {
    let mut scene = furnace(0.5, 8);
    scene.camera = scene.camera.with_lens(0.3, 0.6).unwrap();
    for algorithm in [Algorithm::Path, Algorithm::Vcm] {
        let settings = RenderSettings {
            radius: Radius::World(0.1),
            seed: 11,
            max_depth: 10_000,
            ..RenderSettings::for_algorithm(&scene, algorithm)
        };
        let stats = render_stats(&scene, &settings, 200);
        eprintln!("{algorithm:?}: furnace image mean {}", stats.image_mean());
        assert_uniform_image(&stats, 2.0, 5.0, "lens furnace");
    }
}

fn vcm_stats(scene: &Scene, techniques: Techniques, iterations: u32) -> PixelStats {
    let settings = RenderSettings {
        radius: Radius::World(0.05),
        seed: 21,
        ..RenderSettings::for_algorithm(scene, Algorithm::Vcm)
    };
    let bounds = PixelBounds::full(scene.camera.width, scene.camera.height);
    let mut r = Renderer::Vcm(Box::new(VcmRenderer::with_techniques(
        settings, bounds, techniques,
    )));
    let mut stats = PixelStats::new((scene.camera.width * scene.camera.height) as usize);
    for _ in 0..iterations {
        r.iterate(scene);
        stats.add(r.last_estimates());
    }
    assert_eq!(r.rejected(), 0, "{}: NaN or Inf samples", techniques.name());
    stats
}

/// Light tracing connects each light vertex to a point sampled on the lens with the thin
/// lens's importance; bpt and vcm weigh those connections by MIS with the camera's pdfs at
/// the lens point. All three agree with the path tracer per pixel in the diffuse box, seen
/// through a lens focused on the block.
#[test]
fn light_tracing_bpt_and_vcm_through_a_lens_agree_with_the_path_tracer() {
    let mut b = cornell_builder(12, BoxContents::Diffuse);
    b.camera = b.camera.with_lens(0.3, 0.6).unwrap();
    let scene = b.build().unwrap();
    let pt_settings = RenderSettings {
        seed: 1,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let pt = render_stats(&scene, &pt_settings, 3000);
    for (techniques, iterations) in [
        (Techniques::LT, 3000),
        (Techniques::BPT, 3000),
        (Techniques::VCM, 3000),
    ] {
        let other = vcm_stats(&scene, techniques, iterations);
        let bound = if techniques == Techniques::VCM {
            2.0
        } else {
            1.5
        };
        assert_converges_to_pt("lens box", techniques.name(), &pt, &other, bound);
    }
}
