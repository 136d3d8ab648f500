//! The pbrt-v4 build layer: the Cornell box written in pbrt-v4's format builds the same
//! scene as the Mitsuba XML one (camera rays, triangles, materials, lights) and renders to
//! the same mean; pbrt's left-handed camera renders unmirrored; materials, lights, shapes
//! and the camera map as `docs/pbrt.md` says.

mod common;

use glam::{Vec2, Vec3};
use ppm_core::integrator::{Algorithm, RenderSettings, Renderer};
use ppm_core::scene::{Scene, SceneBuilder};
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::{load_scene_builder, load_scene_builder_with_defines};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The path-traced image of `builder` at `iterations` samples per pixel.
fn render(builder: SceneBuilder, iterations: u32) -> ppm_core::film::Image {
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        seed: 7,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..iterations {
        assert_eq!(r.iterate(&scene).rejected, 0);
    }
    r.image()
}

/// The mean of a path-traced image of `builder` at `iterations` samples per pixel.
fn render_mean(builder: SceneBuilder, iterations: u32) -> Vec3 {
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        seed: 7,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..iterations {
        assert_eq!(r.iterate(&scene).rejected, 0);
    }
    r.image().mean()
}

/// What the camera sees through the film point `film`: the hit distance, the BSDF and the
/// emission of the surface.
fn seen(scene: &Scene, film: Vec2) -> Option<(f32, String, Vec3)> {
    let ray = scene.camera.generate_ray(film);
    let hit = scene.intersect(&ray)?;
    let m = scene.material(&hit);
    Some((hit.t, format!("{:?}", m.bsdf), m.emission))
}

fn cboxes(res: u32) -> (SceneBuilder, SceneBuilder) {
    let defines = [("res".to_string(), res.to_string())];
    let (xml, _) = load_scene_builder_with_defines(&data("mitsuba/cbox.xml"), &defines).unwrap();
    let (mut pbrt, warnings) = load_scene_builder(&data("pbrt/cbox.pbrt")).unwrap();
    // The film's file name and the sampler's count are not used, and said so.
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(
        warnings[0].contains("filename \"cbox.exr\" is not used"),
        "{warnings:?}"
    );
    assert!(
        warnings[1].contains("pixelsamples 64 is not used"),
        "{warnings:?}"
    );
    pbrt.camera.set_resolution(res, res).unwrap();
    (xml, pbrt)
}

#[test]
fn the_pbrt_cornell_box_is_the_mitsuba_one() {
    let (xml, pbrt) = cboxes(32);
    assert_eq!(xml.defaults.max_depth, pbrt.defaults.max_depth);
    for film in [
        Vec2::new(0.5, 0.5),
        Vec2::new(31.0, 3.0),
        Vec2::new(16.0, 30.0),
    ] {
        let (a, b) = (
            xml.camera.generate_ray(film),
            pbrt.camera.generate_ray(film),
        );
        assert!(a.origin.abs_diff_eq(b.origin, 1e-6), "{a:?} {b:?}");
        assert!(a.dir.abs_diff_eq(b.dir, 1e-6), "{a:?} {b:?}");
    }
    // The same triangles (corners in order, so the same facing) with the same materials.
    // The pbrt scene places its walls by ObjectInstance: flattened here to compare.
    let flattened = |b: &SceneBuilder| {
        let mut meshes = b.meshes.clone();
        for p in &b.instances {
            let mut mesh = b.instanced_meshes[p.mesh as usize].clone();
            ppm_scene::placement::place_mesh(&mut mesh, p.to_world, false).unwrap();
            meshes.push(mesh);
        }
        meshes
    };
    assert_eq!(pbrt.instanced_meshes.len(), 1);
    assert_eq!(pbrt.instances.len(), 3);
    let triangles = |b: &SceneBuilder| {
        let mut t: Vec<([i64; 9], String, [i64; 3])> = flattened(b)
            .iter()
            .flat_map(|m| {
                m.indices.iter().zip(&m.materials).map(|(t, &mat)| {
                    let p = t.map(|i| m.positions[i as usize]);
                    // Rotate the corners so the smallest comes first (same winding).
                    let k = (0..3)
                        .min_by(|&a, &b| p[a].to_array().partial_cmp(&p[b].to_array()).unwrap())
                        .unwrap();
                    let q = [p[k], p[(k + 1) % 3], p[(k + 2) % 3]];
                    let key = q.map(|v| v.to_array()).concat();
                    let material = &b.materials[mat as usize];
                    let e = material.emission;
                    (
                        std::array::from_fn(|i| (key[i] * 1e5).round() as i64),
                        format!("{:?}", material.bsdf),
                        [e.x, e.y, e.z].map(|v| (v * 1e5).round() as i64),
                    )
                })
            })
            .collect();
        t.sort();
        t
    };
    let (a, b) = (triangles(&xml), triangles(&pbrt));
    assert_eq!(a.len(), 32);
    assert_eq!(a, b);
    assert!(xml.lights.is_empty() && pbrt.lights.is_empty() && pbrt.spheres.is_empty());

    // The same scene renders to the same image (to rounding: ppm's streams are keyed by
    // pixel, so it is bit for bit when the parts come in the same order).
    let (a, b) = (render(xml, 16), render(pbrt, 16));
    let rmse = (a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).length_squared())
        .sum::<f32>()
        / a.pixels.len() as f32)
        .sqrt();
    assert!(rmse < 1e-6, "RMSE {rmse}");
    let b = render_mean(cboxes(32).1, 64);
    // Mitsuba 3.9.1's mean of cbox.xml (see mitsuba_build.rs).
    let mitsuba = Vec3::new(0.30339, 0.19986, 0.05836);
    let rel = ((b - mitsuba) / mitsuba).abs();
    assert!(rel.max_element() < 0.02, "ppm {b} mitsuba {mitsuba}");
}

/// The same Cornell box in the three dialects: Mitsuba 0.6 (`cbox_v06.xml`: toWorld,
/// maxDepth, fovAxis, faceNormals), Mitsuba 3 (`cbox.xml`) and pbrt-v4 (`cbox.pbrt`). The two
/// Mitsuba files render to the same image bit for bit (their fingerprints differ only in
/// the names of anonymous materials, which carry the file and line), and the 0.6 file
/// renders the pbrt file's image (to rounding: pbrt's walls are instances).
#[test]
fn the_cornell_box_in_mitsuba_0_6_mitsuba_3_and_pbrt_v4_is_one_image() {
    let defines = [("res".to_string(), "24".to_string())];
    let (v06, warnings) =
        load_scene_builder_with_defines(&data("mitsuba/cbox_v06.xml"), &defines).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let (xml, pbrt) = cboxes(24);
    assert!(
        (v06.meshes.iter().zip(&xml.meshes)).all(|(a, b)| a.positions == b.positions
            && a.indices == b.indices
            && a.normals == b.normals)
    );
    let (a, b, c) = (render(v06, 8), render(xml, 8), render(pbrt, 8));
    assert!(
        a.pixels == b.pixels,
        "the 0.6 and 3 files render differently"
    );
    let rmse = ((a.pixels.iter().zip(&c.pixels))
        .map(|(p, q)| (*p - *q).length_squared())
        .sum::<f32>()
        / a.pixels.len() as f32)
        .sqrt();
    assert!(rmse < 1e-6, "RMSE {rmse} against the pbrt file");
}

#[test]
fn the_pbrt_cornell_box_shows_what_mitsuba_shows_pixel_for_pixel() {
    // pbrt's walls are instances: their triangles are the XML's to the last bits, not bit for
    // bit, so a pixel whose ray meets two walls where they join may see either one. Such a
    // pixel must hit on the box's edge (two coordinates at the box's faces); any other
    // pixel sees the same surface.
    let (xml, pbrt) = cboxes(24);
    let (xml, pbrt) = (xml.build().unwrap(), pbrt.build().unwrap());
    let on_edge = |film: Vec2, t: f32| {
        // The scenes are built relative to the camera at (0, 1, 3.9).
        let ray = xml.camera.generate_ray(film);
        let p = ray.origin + ray.dir * t + Vec3::new(0.0, 1.0, 3.9);
        let faces = [
            (p.x + 1.0).abs().min((p.x - 1.0).abs()),
            p.y.abs().min((p.y - 2.0).abs()),
            (p.z + 1.0).abs(),
        ];
        faces.iter().filter(|&&d| d < 1e-4).count() >= 2
    };
    let (mut hits, mut edges) = (0, 0);
    for y in 0..24 {
        for x in 0..24 {
            let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let (a, b) = (seen(&xml, film), seen(&pbrt, film));
            match (&a, &b) {
                (Some(a), Some(b)) => {
                    assert!((a.0 - b.0).abs() < 1e-4 * a.0, "{x} {y}: {a:?} {b:?}");
                    if (&a.1, a.2) != (&b.1, b.2) {
                        assert!(on_edge(film, a.0), "{x} {y}: {a:?} {b:?}");
                        edges += 1;
                    }
                    hits += 1;
                }
                _ => assert_eq!(a.is_none(), b.is_none(), "{x} {y}"),
            }
        }
    }
    // The box's four receding edges run along the image's diagonals (the view is
    // symmetric), through at most 12 pixel centres each.
    assert!(edges <= 48, "{edges} pixels see different walls");
    assert!(hits > 400, "{hits}");
}

#[test]
fn without_the_mirroring_scale_pbrt_shows_the_mirror_image() {
    // pbrt's LookAt makes the image's right up x dir: the box seen from the front with the
    // red wall on the right. ppm keeps its camera and mirrors the world, so pixel (x, y) of
    // this scene shows what pixel (w - 1 - x, y) of Mitsuba's shows.
    let text = std::fs::read_to_string(data("pbrt/cbox.pbrt")).unwrap();
    let unmirrored = text.replacen("Scale -1 1 1\n", "", 1);
    assert_ne!(text, unmirrored);
    let (mut pbrt, _) = parse_pbrt(&unmirrored, &data("pbrt/cbox.pbrt")).unwrap();
    pbrt.camera.set_resolution(24, 24).unwrap();
    let (xml, _) = cboxes(24);
    let (xml, pbrt) = (xml.build().unwrap(), pbrt.build().unwrap());
    let mut differs = 0;
    for y in 0..24 {
        for x in 0..24 {
            // Off the image's diagonals, where a ray meets two walls at their common edge
            // and rounding chooses.
            let film = Vec2::new(x as f32 + 0.3, y as f32 + 0.6);
            let mirrored = Vec2::new(24.0 - film.x, film.y);
            let (a, b) = (seen(&xml, mirrored), seen(&pbrt, film));
            match (&a, &b) {
                (Some(a), Some(b)) => {
                    assert!((a.0 - b.0).abs() < 1e-4 * a.0, "{x} {y}: {a:?} {b:?}");
                    assert_eq!((&a.1, a.2), (&b.1, b.2), "{x} {y}");
                }
                _ => assert_eq!(a.is_none(), b.is_none(), "{x} {y}"),
            }
            differs += (seen(&xml, film).map(|s| s.1) != b.map(|s| s.1)) as usize;
        }
    }
    // The image is not symmetric: the walls' colours swap sides.
    assert!(differs > 100, "{differs}");
    // The mirrored world keeps every side right (the lamp shines down): the mirror image has
    // the mean of Mitsuba's image.
    let (mut pbrt, _) = parse_pbrt(&unmirrored, &data("pbrt/cbox.pbrt")).unwrap();
    pbrt.camera.set_resolution(32, 32).unwrap();
    let mean = render_mean(pbrt, 64);
    let mitsuba = Vec3::new(0.30339, 0.19986, 0.05836);
    let rel = ((mean - mitsuba) / mitsuba).abs();
    assert!(rel.max_element() < 0.02, "ppm {mean} mitsuba {mitsuba}");
}

/// The mean colours of the left and right halves of the image (columns 0..w/2, w/2..w).
fn halves(builder: SceneBuilder, iterations: u32) -> [Vec3; 2] {
    let scene = builder.build().unwrap();
    let settings = RenderSettings {
        seed: 3,
        ..RenderSettings::for_algorithm(&scene, Algorithm::Path)
    };
    let mut r = Renderer::new(&scene, &settings);
    for _ in 0..iterations {
        r.iterate(&scene);
    }
    let image = r.image();
    let (w, h) = (image.width, image.height);
    let mut sums = [Vec3::ZERO; 2];
    for y in 0..h {
        for x in 0..w {
            sums[(x >= w / 2) as usize] += image.get(x, y);
        }
    }
    sums.map(|s| s / (w * h / 2) as f32)
}

#[test]
fn the_pbrt_cornell_box_renders_unmirrored_against_mitsubas_image() {
    // Mitsuba 3.9.1's render of cbox.xml at 16 x 16, 4096 spp: the mean of each half
    // (scripts/mitsuba/cbox_halves.py). The red wall is on the left.
    let csv = std::fs::read_to_string(data("pbrt/cbox_mitsuba_halves.csv")).unwrap();
    let mitsuba: Vec<Vec3> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f32> = l.split(',').skip(1).map(|x| x.parse().unwrap()).collect();
            Vec3::new(v[0], v[1], v[2])
        })
        .collect();
    assert!(mitsuba[0].x > 1.2 * mitsuba[1].x && mitsuba[1].y > 1.1 * mitsuba[0].y);
    let (_, mut pbrt) = cboxes(16);
    pbrt.camera.set_resolution(16, 16).unwrap();
    let ppm = halves(pbrt, 512);
    for (half, (a, b)) in ppm.iter().zip(&mitsuba).enumerate() {
        let rel = ((*a - *b) / *b).abs();
        assert!(rel.max_element() < 0.03, "half {half}: ppm {a} mitsuba {b}");
    }
}
