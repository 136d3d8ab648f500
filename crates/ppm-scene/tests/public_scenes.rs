//! Public scenes of the field, as their authors wrote them, against Mitsuba 3 itself: each
//! folder of `tests/data/public/` holds files fetched from a public repository (its
//! `SOURCE.md` names the repository, commit, licence and what was changed: at most the film
//! size made a `$width`/`$height` parameter). Each scene is loaded through ppm's Mitsuba
//! importer with the small size its defines give, path traced with 4 seeds, and compared with
//! the render Mitsuba 3.9.1 (`scalar_rgb`) makes of the same file, committed in
//! `tests/data/public/references/` by `scripts/mitsuba/public_refs.py`. The pbrt-v4 files of
//! `bitterli-pbrt/` are loaded through ppm's pbrt importer as published, with the film size
//! replaced as `--width`/`--height` do; Mitsuba cannot read them, so their references are
//! Mitsuba's renders of a translation of each file by `scripts/mitsuba/pbrt_public_refs.py`.
//! Every scene is checked the same way:
//!
//! - the image mean, per channel, within 1 % of Mitsuba's, or within 4 combined standard
//!   errors (sqrt(se_ppm^2 + se_mitsuba^2)) where that is larger: both renders are noisy, and
//!   4 sigma keeps a correct renderer's failure rate below 1e-4 per channel;
//! - the relative mean squared error of the image against Mitsuba's, mean over pixels and
//!   channels of (p - m)^2 / (m^2 + 0.01), at most 1.5 times the value noise alone gives,
//!   mean of (var_p + var_m) / (m^2 + 0.01), where var_p is the variance of ppm's pixel
//!   (from its seeds) and var_m that of Mitsuba's (from the script's seeds, `<scene>_var.exr`).
//!   A difference confined to a part of the image (a wrong texture, a missing highlight)
//!   shows here even when the mean hides it.
//!
//! Mitsuba's references use the box pixel filter, ppm's only one (it warns when a file asks for
//! another), so the per-pixel comparison measures everything but the filter.

use glam::Vec3;
use ppm_core::film::Image;
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_scene::load_scene_builder_with_defines;
use ppm_scene::radiance_map::read_rgb;
use ppm_test_support::rel_mse::{mean_and_variance, rel_mse};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/public")
}

/// Mitsuba's image mean and its standard error for `scene`, from references.csv (the Mitsuba
/// files') or pbrt_references.csv (the pbrt-v4 files', by `scripts/mitsuba/pbrt_public_refs.py`).
fn reference_mean(scene: &str) -> (Vec3, Vec3) {
    let mut rows = Vec::new();
    for file in ["references.csv", "pbrt_references.csv"] {
        let csv = std::fs::read_to_string(data().join("references").join(file)).unwrap();
        rows.extend(
            csv.lines()
                .skip(1)
                .map(|l| l.split(',').map(str::to_string).collect::<Vec<String>>()),
        );
    }
    let row = rows
        .iter()
        .find(|r| r[0] == scene)
        .unwrap_or_else(|| panic!("no reference for {scene}"));
    let v: Vec<f32> = row[3..9].iter().map(|x| x.parse().unwrap()).collect();
    (Vec3::new(v[0], v[1], v[2]), Vec3::new(v[3], v[4], v[5]))
}

/// An EXR of the references folder as (width, height, pixels).
fn reference_image(name: &str) -> (usize, usize, Vec<Vec3>) {
    let image = read_rgb(&data().join("references").join(name)).unwrap();
    (image.width, image.height, image.texels)
}

/// The warnings files of the field give: ppm's pixel filter is the box, its sample count is
/// `-n`, its camera does not clip, and it resamples Mitsuba's bilinear envmaps.
const GAUSSIAN: &str = "rfilter `gaussian` is not used";
const SAMPLE_COUNT: &str = "sample_count";
const CLIP: &str = "near_clip and far_clip are not used";
const ENVMAP: &str = "emitter `envmap`: Mitsuba interpolates";

/// The warnings the pbrt-v4 files give: their output file name, sample count and pixel filter.
const PBRT_FILENAME: &str = "Film: filename";
const PBRT_SAMPLES: &str = "Sampler: pixelsamples";
const PBRT_TRIANGLE: &str = "PixelFilter \"triangle\" is not used";

/// One public scene: its file under `tests/data/public/`, the defines that make it small (a
/// Mitsuba file's) or the film size that replaces the file's (a pbrt file's, as `--width` and
/// `--height` do), and the warnings ppm must give (substrings, in order).
struct Public {
    name: &'static str,
    file: &'static str,
    defines: &'static [(&'static str, &'static str)],
    resolution: Option<(u32, u32)>,
    warnings: &'static [&'static str],
}

/// ppm's renders of `scene` with `seeds` seeds of `iterations` path-traced samples per pixel.
fn render(scene: &Public, seeds: u64, iterations: u32) -> Vec<Image> {
    let defines: Vec<(String, String)> = scene
        .defines
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let (builder, warnings) = load_scene_builder_with_defines(&data().join(scene.file), &defines)
        .unwrap_or_else(|e| panic!("{}: {e}", scene.name));
    assert_eq!(
        warnings.len(),
        scene.warnings.len(),
        "{}: {warnings:#?}",
        scene.name
    );
    for (w, expected) in warnings.iter().zip(scene.warnings) {
        assert!(
            w.contains(expected),
            "{}: {w} (expected {expected})",
            scene.name
        );
    }
    let mut builder = builder;
    if let Some((width, height)) = scene.resolution {
        builder.camera.set_resolution(width, height).unwrap();
    }
    let built = builder.build().unwrap();
    (0..seeds)
        .map(|seed| {
            let settings = RenderSettings {
                seed: 1000 + seed,
                ..RenderSettings::for_algorithm(&built, Algorithm::Path)
            };
            let mut r = Renderer::new(&built, &settings);
            for _ in 0..iterations {
                assert_eq!(r.iterate(&built).rejected, 0);
            }
            r.image()
        })
        .collect()
}

/// Renders `scene` and checks its image mean and relative MSE against Mitsuba's; returns the
/// relative difference of the mean and the relative MSE over its noise-only expectation.
fn check(scene: &Public, iterations: u32) -> (Vec3, f32) {
    let seeds = 4;
    let images = render(scene, seeds, iterations);
    let (width, height, reference) = reference_image(&format!("{}.exr", scene.name));
    let (_, _, reference_var) = reference_image(&format!("{}_var.exr", scene.name));
    assert_eq!(
        (width as u32, height as u32),
        (images[0].width, images[0].height),
        "{}: the reference's size",
        scene.name
    );
    let (ppm, ppm_var) = mean_and_variance(&images);

    // The image mean: 1 %, or 4 combined standard errors.
    let means: Vec<Vec3> = images.iter().map(Image::mean).collect();
    let mean = means.iter().sum::<Vec3>() / seeds as f32;
    let se = (means
        .iter()
        .map(|m| (*m - mean) * (*m - mean))
        .sum::<Vec3>()
        / (seeds as f32 - 1.0)
        / seeds as f32)
        .powf(0.5);
    let (m, se_m) = reference_mean(scene.name);
    let bound = (0.01 * m).max(4.0 * (se * se + se_m * se_m).powf(0.5));
    let diff = mean - m;
    let relative = diff / m;

    // The relative MSE against what noise alone gives.
    let e = rel_mse(&ppm, &ppm_var, &reference, &reference_var);
    let ratio = e.ratio() as f32;
    eprintln!(
        "{}: ppm {mean} ± {se}, Mitsuba {m} ± {se_m}, relative {relative}; relMSE {:.3e}, noise alone {:.3e}, ratio {ratio:.3}",
        scene.name, e.observed, e.noise
    );
    assert!(
        diff.abs().cmple(bound).all(),
        "{}: image mean {mean} ± {se} against Mitsuba's {m} ± {se_m}: off by {diff} > {bound}",
        scene.name
    );
    assert!(
        ratio <= 1.5,
        "{}: relative MSE {:.3e} is {ratio:.2} times what noise gives ({:.3e})",
        scene.name,
        e.observed,
        e.noise
    );
    (relative, ratio)
}

#[test]
fn cbox_spectral_matches_mitsuba() {
    check(
        &Public {
            name: "cbox",
            file: "mitsuba-cbox/cbox.xml",
            resolution: None,
            defines: &[("res", "64")],
            warnings: &[GAUSSIAN, SAMPLE_COUNT, CLIP],
        },
        32,
    );
}

#[test]
fn matpreview_matches_mitsuba() {
    check(
        &Public {
            name: "matpreview",
            file: "mitsuba-matpreview/matpreview.xml",
            resolution: None,
            defines: &[("width", "64"), ("height", "48")],
            warnings: &[GAUSSIAN, SAMPLE_COUNT, ENVMAP],
        },
        32,
    );
}

#[test]
fn veach_mis_matches_mitsuba() {
    check(
        &Public {
            name: "veach-mis",
            file: "veach-mis/veach_mis.xml",
            resolution: None,
            defines: &[("width", "72"), ("height", "48")],
            warnings: &[GAUSSIAN, SAMPLE_COUNT],
        },
        256,
    );
}

#[test]
fn copper_matpreview_through_path_matches_mitsuba() {
    check(
        &Public {
            name: "copper",
            file: "mitsuba-docs/docs/scenes/bsdf_roughconductor_copper.xml",
            resolution: None,
            defines: &[("width", "64"), ("height", "48")],
            warnings: &[GAUSSIAN, SAMPLE_COUNT, ENVMAP],
        },
        32,
    );
}

#[test]
fn twosided_cbox_matches_mitsuba() {
    check(
        &Public {
            name: "twosided-cbox",
            file: "mitsuba-docs/docs/scenes/bsdf_twosided_cbox.xml",
            resolution: None,
            defines: &[("width", "64"), ("height", "64")],
            warnings: &[GAUSSIAN, SAMPLE_COUNT, CLIP],
        },
        32,
    );
}
#[test]
fn cbox_rgb_from_includes_matches_mitsuba() {
    check(
        &Public {
            name: "cbox-rgb",
            file: "mitsuba-cbox/cbox-rgb.xml",
            resolution: None,
            defines: &[("res", "64")],
            warnings: &[SAMPLE_COUNT, CLIP],
        },
        32,
    );
}

/// Benedikt Bitterli's Cornell box as converted to pbrt-v4 (`bitterli-pbrt/SOURCE.md`): the
/// file as published, at 32 x 32 (the file asks 1024 x 1024), against Mitsuba's render of
/// `scripts/mitsuba/pbrt_public_refs.py`'s translation of it.
#[test]
fn bitterli_cornell_box_in_pbrt_v4_matches_mitsuba() {
    check(
        &Public {
            name: "bitterli-cornell-box",
            file: "bitterli-pbrt/cornell-box/scene-v4.pbrt",
            defines: &[],
            resolution: Some((32, 32)),
            warnings: &[PBRT_FILENAME, PBRT_SAMPLES, PBRT_TRIANGLE],
        },
        64,
    );
}

/// Bitterli's Veach MIS scene in pbrt-v4: rough conductors (roughness 0.01 to 0.25, not
/// remapped, rgb eta and k), three spherical lights (radii 1, 0.5 and 0.05), maxdepth 3; at
/// 48 x 27 (the file asks 1280 x 720). Its smallest light makes it the noisiest scene here:
/// 1024 samples per pixel bring the mean's standard error to about 1.3 %.
#[test]
fn bitterli_veach_mis_in_pbrt_v4_matches_mitsuba() {
    check(
        &Public {
            name: "bitterli-veach-mis",
            file: "bitterli-pbrt/veach-mis/scene-v4.pbrt",
            defines: &[],
            resolution: Some((48, 27)),
            warnings: &[PBRT_FILENAME, PBRT_SAMPLES, PBRT_TRIANGLE],
        },
        1024,
    );
}
