//! From a parsed scene file to a [`SceneBuilder`]: the checks that need context (which
//! fields a type takes, material names, camera geometry) and the mapping to ppm-core types.

use crate::error::LoadError;
use crate::fov::{focal_length_fov, vertical_fov, FovAxis};
use crate::materials;
use crate::obj::{self, ObjMaterials};
use crate::object_transform::{object_matrix, TransformStep};
use crate::placement::{place_mesh, place_sphere, PlacementError};
use crate::yaml::{
    CameraDesc, InstanceDesc, MaterialDesc, MaterialType, ObjectDesc, ObjectType, SceneFile,
};
use glam::{DMat4, DVec3, Vec3};
use ppm_core::bsdf::{Bsdf, Phong};
use ppm_core::camera::Camera;
use ppm_core::geometry::{Sphere, TriangleMesh};
use ppm_core::integrator::{bounded_depth, MAX_DEPTH};
use ppm_core::material::Material;
use ppm_core::scene::{RenderDefaults, SceneBuilder};
use std::collections::HashMap;
use std::path::Path;

/// A camera farther than this from the world origin (in any coordinate) has the scene made
/// camera-relative in double precision at load; f32 keeps 6e-5 units at this distance.
pub const FAR_CAMERA: f64 = 1e3;

/// Image size when the scene file gives none.
pub const DEFAULT_RESOLUTION: (u32, u32) = (512, 512);

/// Assembles the scene described by `file`, read from `path` (which locates relative files).
pub fn build(
    file: SceneFile,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<SceneBuilder, LoadError> {
    let c = &file.camera;
    let resolution = file
        .resolution
        .map(|r| (r.0, r.1))
        .unwrap_or(DEFAULT_RESOLUTION);
    // With the camera far from the world origin every point is made relative to the camera
    // here, in double precision, before it is rounded to f32: a scene 1e6 units away keeps
    // its millimetres (in f32 they would snap to 1/16 of a unit). Directions (up, a quad's
    // edges) do not move. Nearer, points are rounded as written, as ppm always did, so the
    // scene's content hash, and with it `--resume` of renders made before, is unchanged.
    let origin = if c.position.0.abs().max_element() > FAR_CAMERA {
        c.position.0
    } else {
        DVec3::ZERO
    };
    let position = c.position.relative_to(origin);
    let look_at = c.look_at.relative_to(origin);
    let camera = Camera::new(
        position,
        look_at,
        c.up.value(),
        camera_fov(c, resolution, path)?,
        resolution,
    )
    .map_err(|e| LoadError::invalid(path, "camera", e.to_string()))?;
    // A zero (default) aperture keeps the pinhole; the focus defaults to the look_at point's
    // distance along the view direction.
    let aperture = c.aperture_radius.as_ref().map_or(0.0, |r| r.0);
    let focus = c
        .focus_distance
        .as_ref()
        .map_or_else(|| (look_at - position).length(), |f| f.0);
    let camera = camera
        .with_lens(aperture, focus)
        .map_err(|e| LoadError::invalid(path, "camera.aperture_radius", e.to_string()))?;
    let mut builder = SceneBuilder::new(camera);
    builder.world_offset = origin.as_vec3();

    let materials = file.materials.map(|m| m.0).unwrap_or_default();
    let mut used = vec![false; materials.len()];
    // Names to indices once, so each object's lookup is O(1) and loading stays linear in the
    // number of objects and materials.
    let index: HashMap<&str, usize> = materials
        .iter()
        .enumerate()
        .map(|(i, (n, _))| (n.as_str(), i))
        .collect();
    for (name, desc) in &materials {
        let m = material(name, desc, path, warnings)?;
        builder.add_material(m);
    }
    let lookup = |name: &str, field: &str, used: &mut Vec<bool>| -> Result<u32, LoadError> {
        match index.get(name) {
            Some(&i) => {
                used[i] = true;
                Ok(i as u32)
            }
            None => {
                let defined: Vec<&str> = materials.iter().map(|(n, _)| n.as_str()).collect();
                let defined = if defined.is_empty() {
                    "no materials are defined".into()
                } else {
                    format!("defined: {}", defined.join(", "))
                };
                Err(LoadError::invalid(
                    path,
                    field,
                    format!("undefined material `{name}` ({defined})"),
                ))
            }
        }
    };

    for (i, o) in file.objects.unwrap_or_default().iter().enumerate() {
        let field = format!("objects[{i}]");
        check_fields(
            path,
            &field,
            object_type_name(o.kind),
            &object_fields(o),
            allowed_object_fields(o.kind),
        )?;
        let kind = object_type_name(o.kind);
        let need =
            |name: &str| LoadError::invalid(path, &field, format!("a {kind} needs `{name}`"));
        let material = match &o.material {
            Some(name) => Some(lookup(name, &format!("{field}.material"), &mut used)?),
            None => None,
        };
        // The object's transform, followed by the move to camera-relative coordinates.
        let placement = match &o.transform {
            Some(steps) => {
                Some(DMat4::from_translation(-origin) * object_matrix(steps, &field, path)?)
            }
            None => None,
        };
        let misplaced = |e: PlacementError| {
            LoadError::invalid(
                path,
                format!("{field}.transform"),
                e.describe("the transform"),
            )
        };
        match o.kind {
            ObjectType::Mesh => {
                let file = o.file.as_deref().ok_or_else(|| need("file"))?;
                let instances = match &o.instances {
                    Some(list) => {
                        Some(instance_matrices(list, &o.transform, origin, &field, path)?)
                    }
                    None => None,
                };
                let at = MeshPlacement {
                    origin,
                    placement,
                    instances,
                };
                add_mesh(&mut builder, path, &field, file, material, at, warnings)?;
            }
            ObjectType::Sphere => {
                let center = o.center.as_ref().ok_or_else(|| need("center"))?;
                let radius = o.radius.as_ref().ok_or_else(|| need("radius"))?.0;
                let (center, radius) = match placement {
                    Some(m) => place_sphere(center.0, radius as f64, m).map_err(misplaced)?,
                    None => (center.relative_to(origin), radius),
                };
                let sphere = Sphere::new(center, radius, material.ok_or_else(|| need("material"))?);
                builder.add_sphere(if o.inward == Some(true) {
                    sphere.inward()
                } else {
                    sphere
                });
            }
            ObjectType::Quad => {
                let corner = o.corner.as_ref().ok_or_else(|| need("corner"))?;
                let corner = match placement {
                    Some(_) => corner.value(),
                    None => corner.relative_to(origin),
                };
                let u = o.edge_u.as_ref().ok_or_else(|| need("edge_u"))?.value();
                let v = o.edge_v.as_ref().ok_or_else(|| need("edge_v"))?.value();
                let m = material.ok_or_else(|| need("material"))?;
                let n = u.cross(v);
                if !(n.is_finite() && n.length() > 1e-6 * u.length() * v.length()) {
                    return Err(LoadError::invalid(
                        path,
                        field,
                        "edge_u and edge_v are zero or parallel: the quad has no area",
                    ));
                }
                let mut quad = TriangleMesh::quad(corner, u, v, m);
                if let Some(m) = placement {
                    place_mesh(&mut quad, m, false).map_err(misplaced)?;
                }
                builder.add_mesh(quad);
            }
        }
    }

    for (i, l) in file.lights.unwrap_or_default().iter().enumerate() {
        builder.add_light(crate::yaml_light::light(
            l,
            &format!("lights[{i}]"),
            origin,
            path,
        )?);
    }

    let mut defaults = RenderDefaults::default();
    if let Some(r) = file.render {
        if let Some(d) = r.max_depth {
            defaults.max_depth = bounded_depth(d.0);
            if defaults.max_depth != d.0 {
                warnings.push(format!(
                    "{}: render.max_depth: {} is above the supported {MAX_DEPTH} bounces; \
                     using {MAX_DEPTH}",
                    path.display(),
                    d.0
                ));
            }
        }
        if let Some(p) = r.photons {
            defaults.photons = Some(p.0);
        }
        if let Some(radius) = r.radius {
            defaults.radius = Some(radius.0);
        }
        if let Some(a) = r.alpha {
            defaults.alpha = a.0;
        }
        if let Some(a) = r.algorithm {
            defaults.algorithm = Some(a.0);
        }
        if let Some(w) = r.pixel_bounds {
            defaults.crop = Some(
                crate::crop::window(w.0, resolution)
                    .map_err(|m| LoadError::invalid(path, "render.pixel_bounds", m))?,
            );
        }
    }
    builder.defaults = defaults;

    for ((name, _), used) in materials.iter().zip(&used) {
        if !used {
            warnings.push(format!("{}: materials.{name}: never used", path.display()));
        }
    }
    if !builder.has_light() {
        warnings.push(format!(
            "{}: the scene has no light (no emissive material on any object, no point, spot, directional or environment light): the image will be black",
            path.display()
        ));
    }
    Ok(builder)
}

/// Where a mesh file's points go: made relative to `origin` as written, or moved by
/// `placement` (the object's transform, ending with the move relative to `origin`).
struct MeshPlacement {
    origin: DVec3,
    placement: Option<DMat4>,
    /// `instances:` each placement's whole transform (ending with the move relative to
    /// `origin`); the mesh is then kept once, in its file's coordinates.
    instances: Option<Vec<DMat4>>,
}

/// The transforms of an object's `instances:` list (at `field`): each instance's steps after
/// the object's own `transform`, then the move relative to `origin` (a translation by exactly
/// zero when the camera is at the origin, so an instance without steps is the identity).
fn instance_matrices(
    list: &[InstanceDesc],
    object: &Option<Vec<TransformStep>>,
    origin: DVec3,
    field: &str,
    path: &Path,
) -> Result<Vec<DMat4>, LoadError> {
    if list.is_empty() {
        return Err(LoadError::invalid(
            path,
            format!("{field}.instances"),
            "an empty list places the mesh nowhere; leave `instances` out to place it once",
        ));
    }
    let object = match object {
        Some(steps) => object_matrix(steps, field, path)?,
        None => DMat4::IDENTITY,
    };
    let shift = DMat4::from_translation(-origin);
    list.iter()
        .enumerate()
        .map(|(k, inst)| {
            let own = match &inst.transform {
                Some(steps) => object_matrix(steps, &format!("{field}.instances[{k}]"), path)?,
                None => DMat4::IDENTITY,
            };
            let m = shift * own * object;
            let det = glam::DMat3::from_mat4(m).determinant();
            if !(det.is_finite() && det != 0.0) {
                return Err(LoadError::invalid(
                    path,
                    format!("{field}.instances[{k}].transform"),
                    PlacementError::Singular.describe("the transform"),
                ));
            }
            Ok(m)
        })
        .collect()
}

/// Loads an OBJ and adds its meshes, with `material` for everything or its MTL materials.
fn add_mesh(
    builder: &mut SceneBuilder,
    scene: &Path,
    field: &str,
    file: &str,
    material: Option<u32>,
    at: MeshPlacement,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    // With a transform (or instances) the file's points stay as written until the
    // transform (which ends with the camera-relative move) takes them to the world.
    let origin = match (&at.placement, &at.instances) {
        (None, None) => at.origin,
        _ => DVec3::ZERO,
    };
    let obj_path = scene.parent().unwrap_or(Path::new("")).join(file);
    let policy = if material.is_some() {
        ObjMaterials::Ignore
    } else {
        ObjMaterials::FromMtl
    };
    let is_ply = Path::new(file)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("ply"));
    if is_ply && material.is_none() {
        return Err(LoadError::invalid(
            scene,
            field,
            "a PLY mesh has no materials of its own: give `material`",
        ));
    }
    let loaded = if is_ply {
        crate::ply_object::load_ply_object(&obj_path, origin)
    } else {
        obj::load_obj_relative(&obj_path, policy, origin, warnings)
    };
    let data = loaded.map_err(|e| match e {
        LoadError::Io { path, what, source } => LoadError::Io {
            path,
            what: format!("{what} ({field}.file of {})", scene.display()),
            source,
        },
        e => e,
    })?;
    let offset = builder.materials.len() as u32;
    for m in data.materials {
        builder.add_material(m);
    }
    for mut mesh in data.meshes {
        for m in &mut mesh.materials {
            *m = material.unwrap_or(*m + offset);
        }
        if let Some(placements) = &at.instances {
            let k = builder.add_instanced_mesh(mesh);
            for &m in placements {
                builder.add_instance(k, m);
            }
            continue;
        }
        if let Some(m) = at.placement {
            let normals_ok = place_mesh(&mut mesh, m, false).map_err(|e| {
                LoadError::invalid(
                    scene,
                    format!("{field}.transform"),
                    e.describe("the transform"),
                )
            })?;
            if !normals_ok {
                warnings.push(format!(
                    "{}: {field}.transform: some vertex normals of {file} become zero or not finite; using the faces' normals",
                    scene.display()
                ));
            }
        }
        builder.add_mesh(mesh);
    }
    Ok(())
}

/// A ppm material from its YAML description.
fn material(
    name: &str,
    d: &MaterialDesc,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Material, LoadError> {
    let field = format!("materials.{name}");
    // Textures first: the BSDF is built with their means.
    let dir = path.parent().unwrap_or(Path::new(""));
    let textures = crate::texture_desc::textures(d, &field, path, dir)?;
    let bsdf = match materials::mitsuba_bsdf(d, &field, path)? {
        Some(bsdf) => bsdf,
        None => classic_bsdf(d, &field, path, warnings)?,
    };
    let emission = d.emission.as_ref().map_or(Vec3::ZERO, |e| e.value());
    // `absorption` and `ext_absorption` were checked against the type's fields above.
    let medium = ppm_core::medium::MediumInterface {
        interior: d.absorption.as_ref().map_or(Vec3::ZERO, |a| a.value()),
        exterior: d.ext_absorption.as_ref().map_or(Vec3::ZERO, |a| a.value()),
    };
    Material::new(bsdf, emission)
        .named(name)
        .with_medium(medium)
        .textured(textures)
        .map_err(|slot| {
            LoadError::invalid(
                path,
                field,
                format!("the material has no {} to texture", slot.name()),
            )
        })
}

/// The BSDF of one of the original material types (diffuse, mirror, glass, phong).
pub(crate) fn classic_bsdf(
    d: &MaterialDesc,
    field: &str,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<Bsdf, LoadError> {
    let type_name = materials::type_name(d.kind);
    let allowed: &[&str] = match d.kind {
        MaterialType::Diffuse => &["color", "emission"],
        MaterialType::Mirror => &["color", "emission"],
        MaterialType::Glass => &["ior", "color", "emission", "absorption"],
        MaterialType::Phong => &["diffuse", "specular", "exponent", "emission"],
        _ => unreachable!("the Mitsuba-style types are built in materials.rs"),
    };
    check_fields(
        path,
        field,
        &format!("{type_name} material"),
        &materials::present_fields(d),
        allowed,
    )?;
    let need = |what: &str| {
        LoadError::invalid(
            path,
            field,
            format!("a {type_name} material needs `{what}`"),
        )
    };
    let color = d.color.as_ref().map(|c| c.value());
    Ok(match d.kind {
        MaterialType::Diffuse => Bsdf::diffuse(color.ok_or_else(|| need("color"))?),
        MaterialType::Mirror => Bsdf::mirror(color.unwrap_or(Vec3::ONE)),
        MaterialType::Glass => Bsdf::glass(
            d.ior.as_ref().ok_or_else(|| need("ior"))?.0,
            color.unwrap_or(Vec3::ONE),
        ),
        MaterialType::Phong => {
            let kd = d.diffuse.as_ref().ok_or_else(|| need("diffuse"))?.value();
            let ks = d.specular.as_ref().ok_or_else(|| need("specular"))?.value();
            let n = d.exponent.as_ref().ok_or_else(|| need("exponent"))?.0;
            let sum = kd + ks;
            if let Some(ch) = (0..3).find(|&c| sum[c] > 1.0) {
                return Err(LoadError::invalid(
                    path,
                    field,
                    format!(
                        "diffuse + specular is {} in the {} channel; it must be <= 1 or the surface creates energy",
                        sum[ch],
                        ["red", "green", "blue"][ch]
                    ),
                ));
            }
            if n > Phong::MAX_EXPONENT {
                warnings.push(format!(
                    "{}: {field}.exponent: {n:e} is rendered as {:e}, the largest exponent ppm renders (a lobe about 1e-5 rad wide); for a perfect mirror use `type: mirror`",
                    path.display(),
                    Phong::MAX_EXPONENT
                ));
            }
            Bsdf::phong(kd, ks, n)
        }
        _ => unreachable!("the Mitsuba-style types are built in materials.rs"),
    })
}

fn object_type_name(kind: ObjectType) -> &'static str {
    match kind {
        ObjectType::Mesh => "mesh",
        ObjectType::Sphere => "sphere",
        ObjectType::Quad => "quad",
    }
}

fn object_fields(o: &ObjectDesc) -> [(&'static str, bool); 9] {
    [
        ("instances", o.instances.is_some()),
        ("material", o.material.is_some()),
        ("file", o.file.is_some()),
        ("center", o.center.is_some()),
        ("radius", o.radius.is_some()),
        ("inward", o.inward.is_some()),
        ("corner", o.corner.is_some()),
        ("edge_u", o.edge_u.is_some()),
        ("edge_v", o.edge_v.is_some()),
    ]
}

fn allowed_object_fields(kind: ObjectType) -> &'static [&'static str] {
    match kind {
        ObjectType::Mesh => &["file", "material", "instances"],
        ObjectType::Sphere => &["center", "radius", "material", "inward"],
        ObjectType::Quad => &["corner", "edge_u", "edge_v", "material"],
    }
}

/// Fails on the first present field that `what` does not take.
pub(crate) fn check_fields(
    path: &Path,
    field: &str,
    what: &str,
    present: &[(&str, bool)],
    allowed: &[&str],
) -> Result<(), LoadError> {
    match present
        .iter()
        .find(|(name, p)| *p && !allowed.contains(name))
    {
        Some((name, _)) => Err(LoadError::invalid(
            path,
            field,
            format!(
                "`{name}` does not apply to {} {what} (it takes `type`, {})",
                if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                },
                allowed.join(", ")
            ),
        )),
        None => Ok(()),
    }
}

/// The vertical field of view, degrees, of `camera:`: `fov` along `fov_axis` (default y, so a
/// bare `fov` keeps its meaning and its exact value), or `focal_length` (mm on 36 x 24 mm
/// film, the diagonal), converted for the image's aspect ratio.
fn camera_fov(c: &CameraDesc, (width, height): (u32, u32), path: &Path) -> Result<f32, LoadError> {
    let aspect = width as f64 / height as f64;
    let (fov, axis) = match (
        c.fov.as_ref().map(|f| f.0),
        c.focal_length.as_ref().map(|f| f.0),
        c.fov_axis,
    ) {
        (Some(_), Some(_), _) => {
            return Err(LoadError::invalid(
                path,
                "camera.focal_length",
                "give either `fov` or `focal_length`, not both",
            ))
        }
        (None, None, _) => {
            return Err(LoadError::invalid(
                path,
                "camera.fov",
                "missing: give `fov` (degrees) or `focal_length` (mm)",
            ))
        }
        (None, Some(_), Some(_)) => {
            return Err(LoadError::invalid(
                path,
                "camera.fov_axis",
                "applies to `fov`; a `focal_length` spans the film diagonal",
            ))
        }
        (Some(fov), None, None | Some(FovAxis::Y)) => return Ok(fov),
        (Some(fov), None, Some(axis)) => (fov as f64, axis),
        (None, Some(mm), _) => (focal_length_fov(mm as f64), FovAxis::Diagonal),
    };
    Ok(vertical_fov(fov, axis, aspect) as f32)
}
