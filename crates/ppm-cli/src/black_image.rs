//! Why an image came out black: checked after a render whose mean is (nearly) zero, so that a
//! lamp facing the wrong way is not a silent black picture.
//!
//! An area light emits only on the side its geometric normal points to: for a quad that is
//! `cross(edge_u, edge_v)`, for an OBJ face `cross(v1 - v0, v2 - v0)` (counter-clockwise
//! winding seen from the lit side). A light none of whose triangles has any other geometry in
//! front of its plane lights nothing.

use crate::render_loop::LoopTotals;
use ppm_core::film::Image;
use ppm_core::integrator::{DirectMode, Radius, RenderSettings, Setting};
use ppm_core::scene::{Scene, SceneBuilder};
use ppm_core::{Vec2, Vec3};
use std::path::Path;

/// An image whose mean (of its brightest channel) is below this is "nearly black".
pub const NEARLY_BLACK: f32 = 1e-4;
/// At most this many triangles of one light are checked (the check is only a diagnosis).
const MAX_CHECKED_TRIANGLES: usize = 4096;

/// An emissive material all of whose (checked) triangles face away from all other geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct FacingAway {
    /// The material's name (`materials.NAME` in the scene file, or an MTL material).
    pub material: String,
    pub triangles: usize,
    /// The emission direction of its first triangle (unit length).
    pub direction: Vec3,
}

/// The emissive materials whose triangles all have every other triangle vertex and sphere of
/// the scene behind (or in) their plane, so that they light nothing.
pub fn lights_facing_away(builder: &SceneBuilder) -> Vec<FacingAway> {
    let emits = |m: u32| {
        builder
            .materials
            .get(m as usize)
            .is_some_and(|m| m.is_emissive())
    };
    // Every point of other geometry that a light could shine on: vertices of non-emissive
    // triangles; spheres are tested by their centre and radius.
    let points: Vec<Vec3> = builder
        .meshes
        .iter()
        .flat_map(|mesh| {
            mesh.indices
                .iter()
                .zip(&mesh.materials)
                .filter(|(_, m)| !emits(**m))
                .flat_map(|(tri, _)| tri.iter().map(|&i| mesh.positions[i as usize]))
        })
        .collect();
    let (lo, hi) = points.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let eps = 1e-5 * (hi - lo).length().max(1e-3);

    let mut found: Vec<(u32, FacingAway, bool)> = Vec::new(); // (material, report, all away)
    for mesh in &builder.meshes {
        for (tri, &m) in mesh.indices.iter().zip(&mesh.materials) {
            if !emits(m) {
                continue;
            }
            let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
            let n = (b - a).cross(c - a).normalize_or_zero();
            if n == Vec3::ZERO {
                continue;
            }
            let entry = match found.iter_mut().position(|(fm, _, _)| *fm == m) {
                Some(i) => &mut found[i],
                None => {
                    found.push((
                        m,
                        FacingAway {
                            material: builder.materials[m as usize].name.clone(),
                            triangles: 0,
                            direction: n,
                        },
                        true,
                    ));
                    found.last_mut().unwrap()
                }
            };
            if !entry.2 || entry.1.triangles >= MAX_CHECKED_TRIANGLES {
                continue;
            }
            entry.1.triangles += 1;
            let in_front = points.iter().any(|p| (*p - a).dot(n) > eps)
                || builder
                    .spheres
                    .iter()
                    .any(|s| (s.center - a).dot(n) + s.radius.abs() > eps);
            if in_front {
                entry.2 = false;
            }
        }
    }
    found
        .into_iter()
        .filter(|(_, _, away)| *away)
        .map(|(_, f, _)| f)
        .collect()
}

/// True if no primary ray through the centre of any pixel hits anything (on a grid of at most
/// 512 x 512 positions for larger images: a quarter of a million rays, only for a black image).
fn camera_sees_nothing(scene: &Scene) -> bool {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let (nx, ny) = (w.min(512), h.min(512));
    !(0..ny).any(|j| {
        (0..nx).any(|i| {
            let film = Vec2::new(
                (i as f32 + 0.5) * w as f32 / nx as f32,
                (j as f32 + 0.5) * h as f32 / ny as f32,
            );
            scene.intersect(&scene.camera.generate_ray(film)).is_some()
        })
    })
}

/// What the render saw, for [`explain`].
pub struct RenderFacts<'a> {
    pub scene_path: &'a Path,
    pub scene: &'a Scene,
    /// The scene's parts (for light names), if the file could be read again.
    pub builder: Option<&'a SceneBuilder>,
    pub photon_mapping: bool,
    /// Light paths traced and photons stored over the whole render (photon mapping).
    pub light_paths: u64,
    pub photons: u64,
    /// The depth bound, and whether direct light was sampled (photons then start at their
    /// second bounce).
    pub max_depth: u32,
    pub direct_sampled: bool,
    /// The initial merge radius in scene units, where the algorithm reads one and it was
    /// given as a number (not `auto`), and whether `--radius` gave it (else `render.radius`).
    pub radius: Option<(f32, bool)>,
}

/// The total area of the scene's surfaces (triangles and spheres), in f64.
fn surface_area(scene: &Scene) -> f64 {
    let g = &scene.geometry;
    let triangles = g.triangle_count();
    let triangle_area: f64 = (0..triangles)
        .map(|i| g.triangle(i as u32).0.area() as f64)
        .sum();
    let sphere_area: f64 = (0..g.sphere_count())
        .map(|i| g.sphere((triangles + i) as u32).area() as f64)
        .sum();
    triangle_area + sphere_area
}

/// The photons one merge disc of radius `r` expects over a render that stored `photons`, were
/// they spread evenly over the scene's surfaces (area `area`): photons pi r^2 / area. Below 1
/// the radius, not the light, is why the gather points found nothing.
fn photons_per_disc(photons: u64, r: f32, area: f64) -> f64 {
    photons as f64 * std::f64::consts::PI * (r as f64).powi(2) / area.max(f64::MIN_POSITIVE)
}

/// Reasons why `image` is black or nearly so, one line each; empty when it is not black.
pub fn explain(image: &Image, facts: &RenderFacts<'_>) -> Vec<String> {
    let mean = image.mean().max_element();
    // A NaN mean is not black: it is reported elsewhere (rejected samples).
    if mean.is_nan() || mean >= NEARLY_BLACK {
        return Vec::new();
    }
    let file = facts.scene_path.display();
    let mut lines = vec![if mean == 0.0 {
        "the image is black (every pixel is 0)".to_string()
    } else {
        format!("the image is nearly black (mean {mean:.3e})")
    }];
    if facts.scene.lights.is_empty() {
        // The loader has already said why (no `emission`, no point light); one line here.
        lines[0].push_str(", as the scene has no light");
        return lines;
    }
    if let Some(builder) = facts.builder {
        for f in lights_facing_away(builder) {
            let d = f.direction;
            lines.push(format!(
                "light `{}` in {file} ({} triangle{}) emits away from all other geometry: \
                 its emission direction cross(edge_u, edge_v) is ({:.3}, {:.3}, {:.3}); \
                 swap edge_u and edge_v (a quad) or the vertex order (an OBJ face) to turn it",
                f.material,
                f.triangles,
                if f.triangles == 1 { "" } else { "s" },
                d.x,
                d.y,
                d.z
            ));
        }
    }
    if mean > 0.0 {
        // Some light arrives: the scene is dim (a weak or distant light, a small lit object),
        // not broken, and none of the causes below (each of which leaves every pixel 0) holds.
        let lit = image
            .pixels
            .iter()
            .filter(|p| p.max_element() > 0.0)
            .count();
        lines.push(format!(
            "{lit} of {} pixels received light: the scene is dimly lit or what is lit is small \
             in the image; if it should be brighter, raise the lights' emission or move the \
             camera closer",
            image.pixels.len()
        ));
        return lines;
    }
    let geometry = &facts.scene.geometry;
    if geometry.triangle_count() + geometry.sphere_count() + geometry.instance_count() == 0 {
        lines.push(format!(
            "{file} has no geometry (`objects:` is empty, or its meshes have no triangle of \
             nonzero area): nothing can be lit or seen"
        ));
        return lines;
    }
    if camera_sees_nothing(facts.scene) {
        lines.push("no camera ray hits any geometry: the camera looks away from the scene".into());
    }
    if let Some(line) = starved_radius(facts) {
        lines.push(line);
        return lines;
    }
    if facts.photon_mapping {
        if facts.photons == 0 && facts.direct_sampled && facts.max_depth < 2 {
            lines.push(format!(
                "no photon was stored: with direct light sampled, photons are stored from \
                 their second bounce, which --max-depth {} leaves out; only what the camera \
                 sees lit directly is in the image",
                facts.max_depth
            ));
        } else if facts.photons == 0 {
            lines.push(format!(
                "none of the {} light paths stored a photon: no light reached a diffuse surface",
                facts.light_paths
            ));
        } else {
            lines.push(format!(
                "{} photons were stored, but the camera's gather points found almost none: \
                 the lit surfaces are out of view, or the radius is too small",
                facts.photons
            ));
        }
    } else {
        lines.push("no camera path reached a light".into());
    }
    lines
}

/// The merge radius as the cause of a black image, if photons were stored but a disc of the
/// initial radius expected fewer than one over the whole render: then the gather points found
/// none because the radius is too small, not for want of light.
fn starved_radius(facts: &RenderFacts<'_>) -> Option<String> {
    let (r, flag) = facts.radius?;
    if facts.photons == 0 {
        return None;
    }
    let area = surface_area(facts.scene);
    let expected = photons_per_disc(facts.photons, r, area);
    if expected >= 1.0 {
        return None;
    }
    // The radius at which a disc expects one photon over the render.
    let one = (area / (std::f64::consts::PI * facts.photons as f64)).sqrt();
    Some(format!(
        "the merge radius {r:e} ({}) is too small for the scene: spread over its surface \
         (area {area:.4}), the render's {} photons put {expected:.1e} in a disc of that radius, so \
         the camera's points merged none (the lights are not at fault); a disc expects one \
         photon at a radius of {one:.2e}: raise the radius, or use `auto`",
        if flag { "--radius" } else { "render.radius" },
        facts.photons
    ))
}

/// Prints why `image` is black as warnings, if it is. The scene file is read again for the
/// lights' names (only then: a black image is rare and reading is cheap next to rendering).
pub fn warn_if_black(
    image: &Image,
    scene_path: &Path,
    scene: &Scene,
    settings: &RenderSettings,
    radius_flag: bool,
    totals: &LoopTotals,
) {
    let mean = image.mean().max_element();
    if mean.is_nan() || mean >= NEARLY_BLACK {
        return;
    }
    let builder = ppm_scene::load_scene_builder(scene_path).ok().map(|b| b.0);
    let facts = RenderFacts {
        scene_path,
        scene,
        builder: builder.as_ref(),
        photon_mapping: settings.algorithm.features().photon_map,
        light_paths: totals.light_paths,
        photons: totals.photons,
        max_depth: settings.max_depth,
        direct_sampled: settings.direct == DirectMode::Sampled,
        radius: match settings.radius {
            Radius::World(r) if settings.algorithm.reads(Setting::Radius) => Some((r, radius_flag)),
            _ => None,
        },
    };
    for line in explain(image, &facts) {
        status!("warning: {line}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::prelude::*;

    /// A floor quad, and a lamp quad above it facing down (`flipped`: up).
    fn floor_and_lamp(flipped: bool) -> SceneBuilder {
        let camera =
            Camera::new(Vec3::new(0.0, 1.0, 3.0), Vec3::ZERO, Vec3::Y, 40.0, (8, 8)).unwrap();
        let mut b = SceneBuilder::new(camera);
        let white = b.add_material(Material::new(Bsdf::diffuse(Vec3::splat(0.7)), Vec3::ZERO));
        let lamp = b
            .add_material(Material::new(Bsdf::diffuse(Vec3::ZERO), Vec3::splat(5.0)).named("lamp"));
        b.add_mesh(TriangleMesh::quad(
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(2.0, 0.0, 0.0),
            white,
        ));
        let (u, v) = (Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.5));
        let (u, v) = if flipped { (v, u) } else { (u, v) };
        b.add_mesh(TriangleMesh::quad(Vec3::new(-0.25, 1.5, -0.25), u, v, lamp));
        b
    }

    #[test]
    fn a_flipped_lamp_is_named() {
        assert_eq!(lights_facing_away(&floor_and_lamp(false)), []);
        let away = lights_facing_away(&floor_and_lamp(true));
        assert_eq!(away.len(), 1);
        assert_eq!((away[0].material.as_str(), away[0].triangles), ("lamp", 2));
        assert!((away[0].direction - Vec3::Y).length() < 1e-6);
        // A sphere above the flipped lamp is lit by it.
        let mut b = floor_and_lamp(true);
        b.add_sphere(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 0.5, 0));
        assert_eq!(lights_facing_away(&b), []);
    }

    /// A dim image with some light in it is called dim, not broken: none of the causes that
    /// leave every pixel 0 is claimed (the counters of a render that stored no photon with
    /// direct light sampled, say, do not mean no light arrived).
    #[test]
    fn a_dim_image_is_not_explained_as_a_black_one() {
        let builder = floor_and_lamp(false);
        let scene = floor_and_lamp(false).build().unwrap();
        let facts = RenderFacts {
            scene_path: Path::new("dim.yml"),
            scene: &scene,
            builder: Some(&builder),
            photon_mapping: true,
            light_paths: 1000,
            photons: 0,
            max_depth: 32,
            direct_sampled: true,
            radius: None,
        };
        let mut image = Image {
            width: 8,
            height: 8,
            pixels: vec![Vec3::ZERO; 64],
        };
        let black = explain(&image, &facts);
        assert!(
            black.iter().any(|l| l.contains("stored a photon")),
            "{black:?}"
        );
        // At depth 1 no photon can be stored with direct light sampled: not "no light".
        let shallow = explain(
            &image,
            &RenderFacts {
                max_depth: 1,
                ..facts
            },
        );
        assert!(
            shallow
                .iter()
                .any(|l| l.contains("--max-depth 1 leaves out"))
                && !shallow.iter().any(|l| l.contains("no light reached")),
            "{shallow:?}"
        );
        // Without any light: one line, the loader having named the cause in detail.
        let dark = SceneBuilder::new(builder.camera).build();
        if let Ok(dark) = dark {
            let facts = RenderFacts {
                scene: &dark,
                ..facts
            };
            assert_eq!(
                explain(&image, &facts),
                ["the image is black (every pixel is 0), as the scene has no light"]
            );
        }
        image.pixels[9] = Vec3::splat(1e-3);
        image.pixels[10] = Vec3::splat(1e-3);
        let dim = explain(&image, &facts);
        assert_eq!(dim.len(), 2, "{dim:?}");
        assert!(
            dim[0].contains("nearly black") && dim[1].starts_with("2 of 64 pixels"),
            "{dim:?}"
        );
    }
}
