//! The scenes shipped in `scenes/`: they load cleanly, the box fills the view, the walls and
//! the light face the right way, and the generated meshes are what their generator writes.

mod common;

use common::scenes_dir;
use glam::{Vec2, Vec3};
use ppm_core::bsdf::Bsdf;
use ppm_core::integrator::Radius;
use ppm_scene::obj::{load_obj, ObjMaterials};
use ppm_scene::{load_scene, load_scene_builder};
use ppm_test_support::meshes as make_meshes;
use std::collections::HashMap;
use std::path::PathBuf;

fn scene_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yml" || e == "yaml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_scene_loads_without_warnings() {
    let files = scene_files();
    assert!(files.len() >= 4, "{files:?}");
    for path in files {
        let (builder, warnings) = load_scene_builder(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(warnings.is_empty(), "{}: {warnings:#?}", path.display());
        assert!(!builder.meshes.is_empty(), "{}", path.display());
        assert!(
            builder.materials.iter().any(|m| m.is_emissive()),
            "{}: no light",
            path.display()
        );
        for mesh in &builder.meshes {
            assert!(mesh.positions.iter().all(|p| p.is_finite()));
            assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4));
            assert_eq!(mesh.indices.len(), mesh.materials.len());
        }
    }
}

#[test]
fn cornell_scenes_have_the_specified_setup() {
    let expect = [
        ("cornell_box.yml", (512, 512)),
        ("cornell_box_specular.yml", (512, 412)),
        ("cornell_box_water.yml", (512, 412)),
        ("cornell_box_glossy.yml", (512, 512)),
    ];
    for (name, (w, h)) in expect {
        let (b, _) = load_scene_builder(&scenes_dir().join(name)).unwrap();
        assert_eq!((b.camera.width, b.camera.height), (w, h), "{name}");
        assert_eq!(b.camera.position, Vec3::new(0.0, 1.0, 3.9), "{name}");
        assert!((b.camera.forward() - Vec3::NEG_Z).length() < 1e-6, "{name}");
        let d = b.defaults;
        assert!(
            d.max_depth >= 8
                && d.photons.is_some_and(|p| p >= 100_000)
                && d.alpha > 0.5
                && d.alpha < 1.0,
            "{name}"
        );
        assert!(
            matches!(d.radius, Some(Radius::World(r)) if (0.01..=0.05).contains(&r)),
            "{name}"
        );
        // The light: emission [17, 12, 4] on albedo 0.78.
        let light = b.materials.iter().find(|m| m.is_emissive()).unwrap();
        assert_eq!(light.emission, Vec3::new(17.0, 12.0, 4.0));
        let kinds = |f: fn(&Bsdf) -> bool| b.materials.iter().filter(|m| f(&m.bsdf)).count();
        match name {
            "cornell_box_specular.yml" => {
                assert_eq!(kinds(|b| matches!(b, Bsdf::Mirror(_))), 1);
                assert!(b
                    .materials
                    .iter()
                    .any(|m| matches!(m.bsdf, Bsdf::Glass(g) if g.ior == 1.5)));
                assert_eq!(b.spheres.len(), 2);
            }
            "cornell_box_water.yml" => {
                assert!(b
                    .materials
                    .iter()
                    .any(|m| matches!(m.bsdf, Bsdf::Glass(g) if g.ior == 1.33)));
            }
            "cornell_box_glossy.yml" => {
                let exponents: Vec<f32> = b
                    .materials
                    .iter()
                    .filter_map(|m| match m.bsdf {
                        Bsdf::Phong(p) => Some(p.exponent),
                        _ => None,
                    })
                    .collect();
                assert!(exponents.len() >= 3, "{exponents:?}");
            }
            _ => assert_eq!(kinds(|b| matches!(b, Bsdf::Diffuse(_))), 4),
        }
    }
}

/// The image corners look through the open front of the box (z = 1, x in [-1, 1],
/// y in [0, 2]): no background at the image border.
#[test]
fn the_box_fills_the_view() {
    for path in scene_files() {
        let (b, _) = load_scene_builder(&path).unwrap();
        let c = &b.camera;
        let (w, h) = (c.width as f32, c.height as f32);
        for film in [
            Vec2::ZERO,
            Vec2::new(w, 0.0),
            Vec2::new(0.0, h),
            Vec2::new(w, h),
        ] {
            let ray = c.generate_ray(film);
            let t = (1.0 - ray.origin.z) / ray.dir.z;
            let p = ray.origin + t * ray.dir;
            assert!(
                p.x.abs() <= 1.0 && (0.0..=2.0).contains(&p.y),
                "{}: corner {film} sees {p}",
                path.display()
            );
        }
        // The box is not tiny in the view either: the corners see at least 80% of the front.
        let p = {
            let ray = c.generate_ray(Vec2::ZERO);
            ray.origin + (1.0 - ray.origin.z) / ray.dir.z * ray.dir
        };
        assert!(p.x < -0.8 && p.y > 1.75, "{}: {p}", path.display());
    }
}

/// Every triangle lies in the box, and those on a wall face into it; the light faces down.
#[test]
fn geometry_is_inside_the_box_and_walls_face_in() {
    let inside = |p: Vec3| {
        p.x.abs() <= 1.0 + 1e-6 && p.z.abs() <= 1.0 + 1e-6 && (-1e-6..=2.0 + 1e-6).contains(&p.y)
    };
    for path in scene_files() {
        let (b, _) = load_scene_builder(&path).unwrap();
        let mut walls = 0;
        for mesh in &b.meshes {
            for (t, &m) in mesh.indices.iter().zip(&mesh.materials) {
                let [p0, p1, p2] = t.map(|i| mesh.positions[i as usize]);
                assert!(
                    inside(p0) && inside(p1) && inside(p2),
                    "{}: {p0} {p1} {p2}",
                    path.display()
                );
                let ng = (p1 - p0).cross(p2 - p0).normalize();
                let on_wall = [p0, p1, p2].iter().all(|p| p.x.abs() == 1.0)
                    || [p0, p1, p2].iter().all(|p| p.y == 0.0 || p.y == 2.0)
                    || [p0, p1, p2].iter().all(|p| p.z == -1.0);
                if on_wall {
                    walls += 1;
                    let to_center = Vec3::new(0.0, 1.0, 0.0) - p0;
                    assert!(
                        ng.dot(to_center) > 0.0,
                        "{}: wall triangle faces out",
                        path.display()
                    );
                }
                if b.materials[m as usize].is_emissive() {
                    assert!(
                        (ng - Vec3::NEG_Y).length() < 1e-6,
                        "{}: light faces {ng}",
                        path.display()
                    );
                }
            }
        }
        assert_eq!(walls, 10, "{}: 5 walls of 2 triangles", path.display());
        for s in &b.spheres {
            let r = Vec3::splat(s.radius);
            assert!(
                inside(s.center - r) && inside(s.center + r),
                "{}",
                path.display()
            );
        }
    }
}

/// The water is a closed, consistently oriented surface (every edge shared by exactly two
/// triangles, in opposite directions), enclosing a positive volume of about a quarter of the
/// box, a small gap away from the walls and floor.
#[test]
fn water_is_closed_faces_out_and_keeps_off_the_walls() {
    let path = scenes_dir().join("water.obj");
    let mut warnings = Vec::new();
    let data = load_obj(&path, ObjMaterials::Ignore, &mut warnings).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut edges: HashMap<([u32; 3], [u32; 3]), i32> = HashMap::new();
    let mut volume = 0.0f64;
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    for mesh in &data.meshes {
        assert_eq!(
            mesh.normals.len(),
            mesh.positions.len(),
            "vertex normals everywhere"
        );
        for t in &mesh.indices {
            let p = t.map(|i| mesh.positions[i as usize]);
            for k in 0..3 {
                let (a, b) = (key(p[k]), key(p[(k + 1) % 3]));
                *edges.entry((a, b)).or_default() += 1;
                lo = lo.min(p[k]);
                hi = hi.max(p[k]);
            }
            // Divergence theorem: V = sum p0 . (p1 x p2) / 6 over outward-wound triangles.
            volume += p[0].as_dvec3().dot(p[1].as_dvec3().cross(p[2].as_dvec3())) / 6.0;
            // Shading normals agree with the winding.
            let ng = (p[1] - p[0]).cross(p[2] - p[0]);
            for &i in t {
                assert!(mesh.normals[i as usize].dot(ng) > 0.0);
            }
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "edge used {n} times in one direction");
        assert_eq!(
            edges.get(&(b, a)),
            Some(&1),
            "open or inconsistently wound edge"
        );
    }
    assert!(
        lo.x > -1.0 + 1e-3 && hi.x < 1.0 - 1e-3 && lo.z > -1.0 + 1e-3 && hi.z < 1.0 - 1e-3,
        "{lo} {hi}"
    );
    assert!(lo.y >= 1e-3 && lo.y <= 5e-3, "{lo}");
    assert!(hi.y > 0.45 && hi.y < 0.56, "{hi}");
    let full = 4.0 * 2.0;
    assert!(
        (volume / full - 0.25).abs() < 0.01,
        "volume fraction {}",
        volume / full
    );
}

#[test]
fn committed_meshes_are_what_the_generator_writes() {
    let read = |name: &str| std::fs::read_to_string(scenes_dir().join(name)).unwrap();
    assert_eq!(read("water.obj"), make_meshes::water());
    let (short, tall) = make_meshes::blocks();
    assert_eq!(read("short_block.obj"), short);
    assert_eq!(read("tall_block.obj"), tall);
}

/// Needs `Geometry::new` (ppm-core): the full build, BVH and lights.
#[test]
fn every_scene_builds() {
    for path in scene_files() {
        let loaded = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let scene = loaded.scene;
        // The light quad is two emissive triangles.
        assert_eq!(scene.lights.len(), 2, "{}", path.display());
        assert!(scene.total_power().min_element() > 0.0);
        let d = scene.diagonal();
        assert!(
            (d - 12f32.sqrt()).abs() < 1e-3,
            "{}: diagonal {d}",
            path.display()
        );
    }
}

/// `scenes/compare/smallvcm_mirror_ceiling.yml` holds SmallVCM's numbers (scene 1 of its
/// scene.hxx): the box's extents, the light's power pi A Le from a 0.5 x 0.5 underside facing
/// down, the camera's resolution and forward direction; and it loads without warnings.
#[test]
fn smallvcm_scene_matches_its_source() {
    let path = scenes_dir().join("compare/smallvcm_mirror_ceiling.yml");
    let (builder, warnings) = load_scene_builder(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(warnings.is_empty(), "{warnings:#?}");
    let camera = &builder.camera;
    assert_eq!((camera.width, camera.height), (512, 512));
    let forward = Vec3::new(0.00688625, 0.998505, -0.0542161).normalize();
    let centre = camera.generate_ray(Vec2::new(256.0, 256.0)).dir;
    assert!((centre - forward).length() < 1e-5, "{centre}");

    let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}")).scene;
    // The scene is stored relative to the camera: world = stored + origin.
    let (lo, hi) = scene.geometry.bounds();
    let (lo, hi) = (lo + scene.origin, hi + scene.origin);
    let (box_lo, box_hi) = (
        Vec3::new(-1.27029, -1.25549, -1.28002),
        Vec3::new(1.28975, 1.30455, 1.28002),
    );
    assert!((lo - box_lo).abs().max_element() < 1e-5, "{lo}");
    assert!((hi - box_hi).abs().max_element() < 1e-5, "{hi}");
    assert_eq!(
        scene.lights.len(),
        2,
        "the underside is two emissive triangles"
    );
    let power = std::f32::consts::PI * 0.25 * 25.033_3;
    assert!(
        (scene.total_power() - Vec3::splat(power))
            .abs()
            .max_element()
            < 1e-3 * power
    );
    // The world origin, below the light, in the scene's stored coordinates.
    let below = -scene.origin;
    for light in &scene.lights {
        let s = light.sample_direct(below, Vec2::splat(0.5)).unwrap();
        assert!(s.n.z < -0.999 && s.li.min_element() > 25.0, "{s:?}");
    }
}

/// A mesh with 20,000 copies of one face (and a second, distinct face): the scene keeps two
/// triangles, and the load warns naming the scene file and the count.
#[test]
fn duplicate_triangles_are_dropped_with_a_warning() {
    let mut obj = String::from("v 0 0 -1\nv 1 0 -1\nv 0 1 -1\nv 1 1 -1\n");
    for _ in 0..20_000 {
        obj.push_str("f 1 2 3\n");
    }
    obj.push_str("f 2 4 3\n");
    let scene = "camera: { position: [0, 0, 3], look_at: [0, 0, 0], up: [0, 1, 0], fov: 40 }\n\
                 materials: { lamp: { type: diffuse, color: [0.5, 0.5, 0.5], emission: [1, 1, 1] } }\n\
                 objects:\n  - { type: mesh, file: copies.obj, material: lamp }\n";
    let dir = common::write_files(
        "duplicate_triangles",
        &[("copies.obj", obj.as_str()), ("scene.yml", scene)],
    );
    let loaded = load_scene(&dir.join("scene.yml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.scene.geometry.triangle_count(), 2);
    assert_eq!(loaded.scene.geometry.duplicate_triangles(), 19_999);
    // One emissive triangle per kept triangle: the copies do not multiply the light.
    assert_eq!(loaded.scene.lights.len(), 2);
    let warning = loaded
        .warnings
        .iter()
        .find(|w| w.contains("dropped 19999 triangles"))
        .unwrap_or_else(|| panic!("{:?}", loaded.warnings));
    assert!(warning.contains("scene.yml"), "{warning}");
}
