//! From a parsed scene file to a [`SceneBuilder`]: the checks that need context (which
//! fields a type takes, material names, camera geometry) and the mapping to ppm-core types.

use crate::error::LoadError;
use crate::materials;
use crate::obj::{self, ObjMaterials};
use crate::yaml::{
    LightDesc, LightType, MaterialDesc, MaterialType, ObjectDesc, ObjectType, SceneFile,
};
use glam::{DVec3, Vec3};
use ppm_core::bsdf::{Bsdf, Phong};
use ppm_core::camera::Camera;
use ppm_core::geometry::{Sphere, TriangleMesh};
use ppm_core::integrator::{bounded_depth, MAX_DEPTH};
use ppm_core::light::{Light, PointLight};
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
    let camera = Camera::new(
        c.position.relative_to(origin),
        c.look_at.relative_to(origin),
        c.up.value(),
        c.fov.0,
        resolution,
    )
    .map_err(|e| LoadError::invalid(path, "camera", e.to_string()))?;
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
        match o.kind {
            ObjectType::Mesh => {
                let file = o.file.as_deref().ok_or_else(|| need("file"))?;
                add_mesh(&mut builder, path, &field, file, material, origin, warnings)?;
            }
            ObjectType::Sphere => {
                let center = o.center.as_ref().ok_or_else(|| need("center"))?;
                let center = center.relative_to(origin);
                let radius = o.radius.as_ref().ok_or_else(|| need("radius"))?.0;
                let sphere = Sphere::new(center, radius, material.ok_or_else(|| need("material"))?);
                builder.add_sphere(if o.inward == Some(true) {
                    sphere.inward()
                } else {
                    sphere
                });
            }
            ObjectType::Quad => {
                let corner = o.corner.as_ref().ok_or_else(|| need("corner"))?;
                let corner = corner.relative_to(origin);
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
                builder.add_mesh(TriangleMesh::quad(corner, u, v, m));
            }
        }
    }

    for (i, l) in file.lights.unwrap_or_default().iter().enumerate() {
        builder.add_light(light(l, &format!("lights[{i}]"), origin, path)?);
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
            // `auto` (None) is also the default.
            defaults.radius = radius.0;
        }
        if let Some(a) = r.alpha {
            defaults.alpha = a.0;
        }
        if let Some(a) = r.algorithm {
            defaults.algorithm = Some(a.0);
        }
    }
    builder.defaults = defaults;

    for ((name, _), used) in materials.iter().zip(&used) {
        if !used {
            warnings.push(format!("{}: materials.{name}: never used", path.display()));
        }
    }
    let emits = |m: u32| builder.materials[m as usize].is_emissive();
    let has_light = !builder.lights.is_empty()
        || builder.spheres.iter().any(|s| emits(s.material))
        || builder
            .meshes
            .iter()
            .any(|mesh| mesh.materials.iter().any(|&m| emits(m)));
    if !has_light {
        warnings.push(format!(
            "{}: the scene has no light (no emissive material on any object, no point, spot, directional or environment light): the image will be black",
            path.display()
        ));
    }
    Ok(builder)
}

/// A light of the `lights:` list (at `field`), its points made relative to `origin`.
fn light(l: &LightDesc, field: &str, origin: DVec3, path: &Path) -> Result<Light, LoadError> {
    let kind = light_type_name(l.kind);
    let present = [
        ("position", l.position.is_some()),
        ("intensity", l.intensity.is_some()),
        ("irradiance", l.irradiance.is_some()),
        ("direction", l.direction.is_some()),
        ("look_at", l.look_at.is_some()),
        ("cone_angle", l.cone_angle.is_some()),
        ("falloff_start", l.falloff_start.is_some()),
        ("color", l.color.is_some()),
        ("file", l.file.is_some()),
        ("scale", l.scale.is_some()),
        ("rotate", l.rotate.is_some()),
    ];
    let allowed: &[&str] = match l.kind {
        LightType::Point => &["position", "intensity"],
        LightType::Spot => &[
            "position",
            "intensity",
            "direction",
            "look_at",
            "cone_angle",
            "falloff_start",
        ],
        LightType::Directional => &["direction", "irradiance"],
        LightType::Environment => &["color", "file", "scale", "rotate"],
    };
    check_fields(path, field, kind, &present, allowed)?;
    let invalid = |name: &str, why: String| LoadError::invalid(path, format!("{field}{name}"), why);
    // The required fields, each named when missing.
    let position = || {
        l.position
            .as_ref()
            .map(|p| p.relative_to(origin))
            .ok_or_else(|| invalid("", format!("a {kind} needs `position`")))
    };
    let intensity = || {
        l.intensity
            .as_ref()
            .map(|i| i.value())
            .ok_or_else(|| invalid("", format!("a {kind} needs `intensity`")))
    };
    match l.kind {
        LightType::Environment => crate::environment::light(l, field, path),
        LightType::Point => Ok(Light::Point(PointLight {
            position: position()?,
            intensity: intensity()?,
        })),
        LightType::Directional => {
            let direction = l
                .direction
                .as_ref()
                .ok_or_else(|| {
                    invalid(
                        "",
                        "a directional light needs `direction` (the way its light travels)".into(),
                    )
                })?
                .value();
            let irradiance = l
                .irradiance
                .as_ref()
                .ok_or_else(|| invalid("", "a directional light needs `irradiance`".into()))?
                .value();
            Light::directional(direction, irradiance).ok_or_else(|| {
                invalid(".direction", "a zero direction has no way to travel".into())
            })
        }
        LightType::Spot => {
            let (position, intensity) = (position()?, intensity()?);
            let direction = match (&l.direction, &l.look_at) {
                (Some(d), None) => d.value(),
                (None, Some(target)) => target.relative_to(origin) - position,
                (Some(_), Some(_)) => {
                    return Err(invalid(
                        "",
                        "a spot light takes `direction` or `look_at`, not both".into(),
                    ))
                }
                (None, None) => {
                    return Err(invalid(
                        "",
                        "a spot light needs `direction` or `look_at`".into(),
                    ))
                }
            };
            let axis = if l.direction.is_some() {
                ".direction"
            } else {
                ".look_at"
            };
            if !(direction.is_finite() && direction.length() > 0.0) {
                return Err(invalid(
                    axis,
                    "the axis has no direction (a zero direction, or look_at at position)".into(),
                ));
            }
            let cone = l
                .cone_angle
                .as_ref()
                .ok_or_else(|| invalid("", "a spot light needs `cone_angle`".into()))?
                .0;
            if cone > 180.0 {
                return Err(invalid(
                    ".cone_angle",
                    format!("{cone} degrees is more than 180 (the whole sphere)"),
                ));
            }
            // No falloff start: full intensity up to the cone's edge.
            let start = l.falloff_start.as_ref().map_or(cone, |s| s.0);
            if start > cone {
                return Err(invalid(
                    ".falloff_start",
                    format!("{start} degrees is beyond cone_angle ({cone} degrees)"),
                ));
            }
            Light::spot(
                position,
                direction,
                intensity,
                cone.to_radians(),
                start.to_radians(),
            )
            .ok_or_else(|| invalid("", "not a valid spot light".into()))
        }
    }
}

fn light_type_name(kind: LightType) -> &'static str {
    match kind {
        LightType::Point => "point light",
        LightType::Spot => "spot light",
        LightType::Directional => "directional light",
        LightType::Environment => "environment light",
    }
}

/// Loads an OBJ and adds its meshes, with `material` for everything or its MTL materials.
fn add_mesh(
    builder: &mut SceneBuilder,
    scene: &Path,
    field: &str,
    file: &str,
    material: Option<u32>,
    origin: DVec3,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let obj_path = scene.parent().unwrap_or(Path::new("")).join(file);
    let policy = if material.is_some() {
        ObjMaterials::Ignore
    } else {
        ObjMaterials::FromMtl
    };
    let data =
        obj::load_obj_relative(&obj_path, policy, origin, warnings).map_err(|e| match e {
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
    let bsdf = match materials::mitsuba_bsdf(d, &field, path)? {
        Some(bsdf) => bsdf,
        None => classic_bsdf(d, &field, path, warnings)?,
    };
    let emission = d.emission.as_ref().map_or(Vec3::ZERO, |e| e.value());
    Ok(Material::new(bsdf, emission).named(name))
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
        MaterialType::Glass => &["ior", "color", "emission"],
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

fn object_fields(o: &ObjectDesc) -> [(&'static str, bool); 8] {
    [
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
        ObjectType::Mesh => &["file", "material"],
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
