//! The build layer: from a [`SceneTree`] to ppm's [`SceneBuilder`], one function per plugin
//! (`sensor.rs`, `bsdf.rs`, `shape.rs`, emitters here). Each reads its properties through
//! [`Props`], so a property nobody reads is an error; a plugin ppm cannot render yet is an
//! error naming it and its place ([`unsupported`]), never dropped.

mod bsdf;
mod environment;
mod sensor;
pub mod shape;

use super::props::Props;
use super::spectrum::Role;
use super::tree::{Object, SceneTree};
use crate::LoadError;
use glam::{DVec3, Vec3};
use ppm_core::bsdf::Bsdf;
use ppm_core::light::PointLight;
use ppm_core::material::Material;
use ppm_core::scene::{RenderDefaults, SceneBuilder};
use shape::Geometry;
use std::collections::{HashMap, HashSet};

/// "bsdf `roughconductor` at scene.xml:12 is not supported yet".
pub fn unsupported(object: &Object) -> LoadError {
    object.location.error(format!(
        "{} `{}` at {} is not supported yet",
        object.class, object.plugin, object.location
    ))
}

/// Assembles the scene `tree` describes.
pub fn build(tree: &SceneTree, warnings: &mut Vec<String>) -> Result<SceneBuilder, LoadError> {
    let root = Props::new(tree, tree.root);
    let sensors = root.objects("sensor");
    let &sensor = sensors
        .first()
        .ok_or_else(|| root.error("the scene has no <sensor>: ppm needs a camera"))?;
    if sensors.len() > 1 {
        warnings.push(format!(
            "{}: the scene has {} sensors; ppm renders the first",
            tree.objects[sensors[1]].location,
            sensors.len()
        ));
    }
    let camera = sensor::camera(tree, sensor, warnings)?;
    let mut builder = SceneBuilder::new(camera);
    let mut defaults = RenderDefaults::default();
    if let Some(&integrator) = root.objects("integrator").first() {
        defaults.max_depth = sensor::max_depth(tree, integrator, warnings)?;
    }
    builder.defaults = defaults;

    // BSDFs defined at the top level are built when a shape uses them.
    let defined = root.objects("bsdf");
    root.objects("texture");
    let mut materials = Materials::default();
    for shape in root.objects("shape") {
        add_shape(tree, shape, &mut builder, &mut materials, warnings)?;
    }
    for emitter in root.objects("emitter") {
        add_emitter(tree, emitter, &mut builder, warnings)?;
    }
    for class in ["medium", "phase", "volume", "film", "sampler", "rfilter"] {
        if let Some(&o) = root.objects(class).first() {
            return Err(unsupported(&tree.objects[o]));
        }
    }
    root.finish()?;
    for b in defined {
        if !materials.used.contains(&b) {
            warnings.push(format!(
                "{}: {} is never used",
                tree.objects[b].location,
                tree.objects[b].describe()
            ));
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
            "{}: the scene has no light ppm renders (no area emitter on a shape, no point emitter): the image will be black",
            tree.root().location.file.display()
        ));
    }
    Ok(builder)
}

/// ppm materials made so far: one per BSDF object without emission (shared by its shapes),
/// one per emitting shape, and the default for shapes without a BSDF.
#[derive(Default)]
struct Materials {
    bsdfs: HashMap<usize, u32>,
    /// BSDF objects some shape uses.
    used: HashSet<usize>,
    default: Option<u32>,
}

/// Mitsuba's BSDF for a shape that names none: diffuse, reflectance 0.5.
const DEFAULT_REFLECTANCE: f32 = 0.5;

fn add_shape(
    tree: &SceneTree,
    index: usize,
    builder: &mut SceneBuilder,
    materials: &mut Materials,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let p = Props::new(tree, index);
    let bsdfs = p.objects("bsdf");
    if bsdfs.len() > 1 {
        return Err(p.error(format!(
            "{} has {} BSDFs, expected one",
            p.object.describe(),
            bsdfs.len()
        )));
    }
    let emitters = p.objects("emitter");
    let emission = match emitters.as_slice() {
        [] => None,
        [e] => Some(area_radiance(tree, *e)?),
        _ => return Err(p.error(format!("{} has more than one emitter", p.object.describe()))),
    };
    for class in ["medium", "texture", "sensor"] {
        if let Some(&o) = p.objects(class).first() {
            return Err(unsupported(&tree.objects[o]));
        }
    }
    let geometry = shape::geometry(&p, warnings)?;
    p.finish()?;
    materials.used.extend(bsdfs.first());
    let material = match (bsdfs.first(), emission) {
        (Some(&b), None) => match materials.bsdfs.get(&b) {
            Some(&m) => m,
            None => {
                let m = builder.add_material(
                    Material::new(bsdf::bsdf(tree, b)?, Vec3::ZERO).named(name(tree, b)),
                );
                materials.bsdfs.insert(b, m);
                m
            }
        },
        (Some(&b), Some(le)) => {
            let name = format!(
                "{} (emitting, {})",
                name(tree, b),
                tree.objects[index].location
            );
            builder.add_material(Material::new(bsdf::bsdf(tree, b)?, le).named(name))
        }
        (None, None) => *materials.default.get_or_insert_with(|| {
            builder.add_material(
                Material::new(Bsdf::diffuse(Vec3::splat(DEFAULT_REFLECTANCE)), Vec3::ZERO)
                    .named("default diffuse"),
            )
        }),
        (None, Some(le)) => builder.add_material(
            Material::new(Bsdf::diffuse(Vec3::splat(DEFAULT_REFLECTANCE)), le)
                .named(format!("emitter ({})", tree.objects[index].location)),
        ),
    };
    match geometry {
        Geometry::Sphere(mut s) => {
            s.material = material;
            builder.add_sphere(s);
        }
        Geometry::Meshes(meshes) => {
            for mut mesh in meshes {
                mesh.materials.iter_mut().for_each(|m| *m = material);
                builder.add_mesh(mesh);
            }
        }
    }
    Ok(())
}

/// A material's name: the BSDF's id, or its plugin and place.
fn name(tree: &SceneTree, bsdf: usize) -> String {
    let o = &tree.objects[bsdf];
    o.id.clone()
        .unwrap_or_else(|| format!("{} ({})", o.plugin, o.location))
}

/// A non-negative, finite colour of an emitter.
fn emission(p: &Props, name: &str, default: Option<DVec3>) -> Result<Vec3, LoadError> {
    let c = match (p.colour_opt(name, Role::Emission)?, default) {
        (Some(c), _) | (None, Some(c)) => c,
        (None, None) => {
            return Err(p.error(format!("emitter `{}` needs `{name}`", p.object.plugin)))
        }
    };
    let c = c.as_vec3();
    if !(c.is_finite() && c.min_element() >= 0.0) {
        return Err(p.error(format!(
            "emitter `{}`: `{name}` {c} is negative or out of single-precision range",
            p.object.plugin
        )));
    }
    Ok(c)
}

/// `<emitter type="area">` on a shape: its `radiance`, emitted on the side the shape's
/// normal faces (ppm's area lights are one-sided like Mitsuba's).
fn area_radiance(tree: &SceneTree, index: usize) -> Result<Vec3, LoadError> {
    let p = Props::new(tree, index);
    if p.object.plugin != "area" {
        return Err(unsupported(p.object));
    }
    let le = emission(&p, "radiance", None)?;
    p.finish()?;
    Ok(le)
}

/// A top-level emitter: `point` (`intensity` in W/sr, default 1; at `position`, or the
/// origin moved by `to_world`), `constant` and `envmap` (`environment.rs`). Area emitters
/// belong to shapes.
fn add_emitter(
    tree: &SceneTree,
    index: usize,
    builder: &mut SceneBuilder,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let p = Props::new(tree, index);
    match p.object.plugin.as_str() {
        "point" => {
            let intensity = emission(&p, "intensity", Some(DVec3::ONE))?;
            let m = p.transform("to_world")?;
            let position = match p.point_opt("position")? {
                Some(x) => x,
                None => m.transform_point3(DVec3::ZERO),
            };
            p.finish()?;
            builder.add_point_light(PointLight {
                position: position.as_vec3(),
                intensity,
            });
            Ok(())
        }
        "area" => Err(p.error("emitter `area` must be nested in a <shape>")),
        "constant" | "envmap" => environment::add(tree, index, builder, warnings),
        _ => Err(unsupported(p.object)),
    }
}
