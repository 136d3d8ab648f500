//! The build layer: from a [`SceneTree`] to ppm's [`SceneBuilder`], one function per plugin
//! (`sensor.rs`, `bsdf/`, `shape.rs`, `emitter.rs`). Each reads its properties through
//! [`Props`], so a property nobody reads is an error; a plugin ppm cannot render yet is an
//! error naming it and its place ([`unsupported`]), never dropped.

mod bsdf;
mod emitter;
mod environment;
mod instance;
mod medium;
mod sensor;
pub mod shape;
mod texture;

use super::props::Props;
use super::tree::{Object, SceneTree, Value};
use crate::LoadError;
use glam::Vec3;
use ppm_core::bsdf::Bsdf;
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
    let (camera, crop) = sensor::camera(tree, sensor, warnings)?;
    let mut builder = SceneBuilder::new(camera);
    let mut defaults = RenderDefaults {
        crop,
        ..RenderDefaults::default()
    };
    if let Some(&integrator) = root.objects("integrator").first() {
        defaults.max_depth = sensor::max_depth(tree, integrator, warnings)?;
    }
    builder.defaults = defaults;

    // BSDFs defined at the top level are built when a shape uses them.
    let defined = root.objects("bsdf");
    root.objects("texture");
    let mut materials = Materials::default();
    let mut groups = instance::Groups::default();
    for shape in root.objects("shape") {
        match tree.objects[shape].plugin.as_str() {
            // A shape group renders only where an `instance` places it.
            "shapegroup" => groups.declared(shape),
            "instance" => instance::add_instance(
                tree,
                shape,
                &mut builder,
                &mut materials,
                &mut groups,
                warnings,
            )?,
            _ => add_shape(
                tree,
                shape,
                &mut builder,
                &mut materials,
                Target::Scene,
                warnings,
            )?,
        }
    }
    groups.warn_unplaced(tree, warnings);
    // An area emitter defined at the top level with an id and given to shapes by `<ref>`
    // (mitsuba-data's `cbox-rgb.xml`) is theirs: it lights them, not the scene.
    let in_shapes: HashSet<usize> = tree
        .objects
        .iter()
        .filter(|o| o.class == "shape")
        .flat_map(|o| o.properties.iter())
        .filter_map(|p| match p.value {
            Value::Object(i) => Some(i),
            _ => None,
        })
        .collect();
    for emitter in root.objects("emitter") {
        if tree.objects[emitter].plugin == "area" && in_shapes.contains(&emitter) {
            continue;
        }
        emitter::add_emitter(tree, emitter, &mut builder, warnings)?;
    }
    // Media defined at the top level are rendered where a shape names them its interior
    // or exterior (`medium.rs`); any other is not supported.
    if let Some(o) = medium::unplaced(tree, &root.objects("medium"), &root.objects("shape")) {
        return Err(unsupported(&tree.objects[o]));
    }
    for class in ["phase", "volume", "film", "sampler", "rfilter"] {
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
    if !builder.has_light() {
        warnings.push(format!(
            "{}: the scene has no light ppm renders (no area emitter on a shape, no point, spot or directional emitter): the image will be black",
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

/// Mitsuba's BSDF for a shape that names none and does not emit: diffuse, reflectance 0.5.
const DEFAULT_REFLECTANCE: f32 = 0.5;

/// Where a shape's geometry goes: into the scene, or (a shape inside a `shapegroup`) into
/// the group's instanced meshes and object-space spheres.
enum Target<'a> {
    Scene,
    Group(&'a mut instance::Group),
}

fn add_shape(
    tree: &SceneTree,
    index: usize,
    builder: &mut SceneBuilder,
    materials: &mut Materials,
    target: Target<'_>,
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
        [e] => Some(emitter::area_radiance(tree, *e)?),
        _ => return Err(p.error(format!("{} has more than one emitter", p.object.describe()))),
    };
    let media = medium::shape_media(&p)?;
    for class in ["texture", "sensor"] {
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
                let m =
                    builder.add_material(material(tree, b, warnings, Vec3::ZERO, name(tree, b))?);
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
            builder.add_material(material(tree, b, warnings, le, name)?)
        }
        (None, None) => *materials.default.get_or_insert_with(|| {
            builder.add_material(
                Material::new(Bsdf::diffuse(Vec3::splat(DEFAULT_REFLECTANCE)), Vec3::ZERO)
                    .named("default diffuse"),
            )
        }),
        // Mitsuba 3 gives an emitting shape without a BSDF a black diffuse one: it emits
        // and reflects nothing.
        (None, Some(le)) => builder.add_material(
            Material::new(Bsdf::diffuse(Vec3::ZERO), le)
                .named(format!("emitter ({})", tree.objects[index].location)),
        ),
    };
    // A shape bounding absorbing media gets a material of its own: its BSDF's with them.
    let material = if media.is_clear() {
        material
    } else {
        let m = builder.materials[material as usize].clone();
        let name = format!("{} (with media, {})", m.name, tree.objects[index].location);
        builder.add_material(m.named(name).with_medium(media))
    };
    match (geometry, target) {
        (Geometry::Sphere(mut s), target) => {
            s.material = material;
            match target {
                Target::Scene => builder.add_sphere(s),
                Target::Group(g) => g.spheres.push(s),
            }
        }
        (Geometry::Meshes(meshes), target) => {
            let mut group = match target {
                Target::Group(g) => Some(g),
                Target::Scene => None,
            };
            for mut mesh in meshes {
                mesh.materials.iter_mut().for_each(|m| *m = material);
                match group.as_mut() {
                    Some(g) => g.meshes.push(builder.add_instanced_mesh(mesh)),
                    None => builder.add_mesh(mesh),
                }
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

/// The material of BSDF object `b` emitting `le`, with the textures its colours read.
fn material(
    tree: &SceneTree,
    b: usize,
    warnings: &mut Vec<String>,
    le: Vec3,
    name: String,
) -> Result<Material, LoadError> {
    let (bsdf, textures) = texture::textured_bsdf(tree, b, warnings)?;
    Material::new(bsdf, le)
        .named(name)
        .textured(textures)
        .map_err(|slot| {
            tree.objects[b].location.error(format!(
                "{}: ppm cannot texture its {}",
                tree.objects[b].describe(),
                slot.name()
            ))
        })
}
