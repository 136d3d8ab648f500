//! The build layer: a [`Description`] to ppm's [`SceneBuilder`], one module per entity kind
//! (`camera.rs` with the film, `material.rs`, `shape.rs`, `light.rs`); the render settings
//! (`Integrator`, `Sampler`, `PixelFilter`, `Option`) here.

mod camera;
mod light;
mod material;
mod medium;
mod shape;
mod texture;

use super::params::ParamSet;
use super::scene::{Description, MaterialEntity, MaterialRef, ShapeEntity};
use crate::LoadError;
use glam::{DMat4, Vec3};
use ppm_core::bsdf::Bsdf;
use ppm_core::integrator::MAX_DEPTH;
use ppm_core::material::Material;
use ppm_core::scene::{RenderDefaults, SceneBuilder};
use ppm_core::texture::{ColourSlot, Texture};
use shape::{Geometry, PlyCache};
use std::collections::HashMap;

/// pbrt-v4's default path depth (its default integrator is `volpath`, maxdepth 5).
const DEFAULT_MAX_DEPTH: i64 = 5;

/// Most triangles a scene may hold (an instanced mesh counts once).
pub const MAX_TRIANGLES: usize = 1 << 28;

/// Assembles the scene `desc` describes.
pub fn build(desc: &Description, warnings: &mut Vec<String>) -> Result<SceneBuilder, LoadError> {
    let path = desc.main_folder.join("scene");
    let file = desc
        .camera
        .as_ref()
        .map(|(e, _)| e.loc.file.to_path_buf())
        .or_else(|| desc.shapes.first().map(|s| s.entity.loc.file.to_path_buf()))
        .unwrap_or(path);
    let (camera, mirror, crop) = camera::camera(desc, &file, warnings)?;
    let mut builder = SceneBuilder::new(camera);
    builder.defaults = RenderDefaults {
        max_depth: max_depth(desc, warnings)?,
        crop,
        ..RenderDefaults::default()
    };
    settings_warnings(desc, warnings)?;
    if let Some(names) = &desc.camera_media {
        if !names.outside.is_empty() {
            return Err(names.loc.error(format!(
                "MediumInterface: the camera is in medium \"{}\" (the outside in force at Camera); ppm's camera sees through no medium: bound the medium with a surface instead",
                names.outside
            )));
        }
    }

    let mut materials: HashMap<MaterialKey, (u32, Textured)> = HashMap::new();
    // Each material as bounding each distinct pair of media: (material, interior and
    // exterior sigma_a bits) -> the copy's index.
    let mut bounded: HashMap<(u32, [u32; 6]), u32> = HashMap::new();
    let mut cache = PlyCache::default();
    let mut triangles = 0usize;
    // The shared mesh of each (object, shape) an `ObjectInstance` placed, by its index.
    let mut instanced: HashMap<(std::rc::Rc<str>, usize), u32> = HashMap::new();
    for s in &desc.shapes {
        // A mesh inside an object is built once in the object's space and placed by each
        // `ObjectInstance`'s CTM (a sphere is copied: it stays an analytic sphere).
        let instance = s.instance.as_ref().filter(|_| s.entity.kind != "sphere");
        if let Some(i) = instance {
            if let Some(&k) = instanced.get(&(i.object.clone(), i.shape)) {
                builder.add_instance(k, mirror * i.to_world);
                continue;
            }
        }
        let to_world = match instance {
            Some(i) => i.definition,
            None => mirror * s.ctm,
        };
        let (index, (bsdf, textures)) =
            material_of(desc, s, &mut materials, &mut builder, warnings)?;
        // A textured shape gets pbrt's uv where the file gives none (`shape.rs`).
        let textured = !textures.is_empty();
        let geometry = shape::geometry(
            s,
            to_world,
            &desc.main_folder,
            &mut cache,
            textured,
            warnings,
        )?;
        let has_uv = match &geometry {
            Geometry::Mesh(m) => !m.uvs.is_empty(),
            Geometry::Sphere(_) => false,
        };
        if textured && !has_uv {
            return Err(s.entity.loc.error(format!(
                "Shape \"{}\": its material has a texture, and this shape has no uv: ppm gives pbrt's uv to a trianglemesh (given or pbrt's default per triangle), a bilinearmesh with \"point2 uv\", a plymesh whose file has uv, a disk and a cylinder (the default uv of a bilinearmesh or of a plymesh without uv, and the uv of an analytic sphere, are not supported yet)",
                s.entity.kind
            )));
        }
        let material = match &s.area_light {
            None => index,
            Some(light) => {
                let area = match &geometry {
                    Geometry::Mesh(m) => mesh_area(m),
                    Geometry::Sphere(sp) => sp.area() as f64,
                };
                let le = light::area_radiance(light, area)?;
                let m = Material::new(bsdf, le)
                    .named(format!("area light ({})", s.entity.loc))
                    .textured(textures)
                    .map_err(|slot| {
                        s.entity
                            .loc
                            .error(format!("{} cannot be textured", slot.name()))
                    })?;
                builder.add_material(m)
            }
        };
        // The media on the shape's two sides: its material bounding them (a copy per pair).
        let material = match &s.media {
            None => material,
            Some(names) => {
                let interface = medium::interface(desc, names)?;
                if interface.is_clear() {
                    material
                } else {
                    let bits = [interface.interior, interface.exterior]
                        .map(|v| v.to_array().map(f32::to_bits));
                    let key = (
                        material,
                        [
                            bits[0][0], bits[0][1], bits[0][2], bits[1][0], bits[1][1], bits[1][2],
                        ],
                    );
                    match bounded.get(&key) {
                        Some(&k) => k,
                        None => {
                            let m = builder.materials[material as usize]
                                .clone()
                                .with_medium(interface);
                            let k = builder.add_material(m);
                            bounded.insert(key, k);
                            k
                        }
                    }
                }
            }
        };
        match geometry {
            Geometry::Sphere(mut sp) => {
                sp.material = material;
                builder.add_sphere(sp);
            }
            Geometry::Mesh(mut mesh) => {
                triangles += mesh.indices.len();
                if triangles > MAX_TRIANGLES {
                    return Err(s.entity.loc.error(format!(
                        "the scene has more than {MAX_TRIANGLES} triangles (an instanced mesh counts once)"
                    )));
                }
                mesh.materials.iter_mut().for_each(|m| *m = material);
                match instance {
                    Some(i) => {
                        let k = builder.add_instanced_mesh(mesh);
                        instanced.insert((i.object.clone(), i.shape), k);
                        builder.add_instance(k, mirror * i.to_world);
                    }
                    None => builder.add_mesh(mesh),
                }
            }
        }
    }
    for l in &desc.lights {
        light::add_light(l, mirror, &desc.main_folder, &mut builder)?;
    }
    // Materials no shape uses are still checked, as pbrt-v4 creates them all.
    for (i, m) in desc.materials.iter().enumerate() {
        if !materials.contains_key(&MaterialKey::Anonymous(i)) {
            material::bsdf(desc, m, &mut Vec::new())?;
        }
    }
    for (name, m) in &desc.named_materials {
        if !materials.contains_key(&MaterialKey::Named(name.clone())) {
            material::bsdf(desc, m, &mut Vec::new())?;
            warnings.push(format!(
                "{}: material \"{name}\" is never used",
                m.entity.loc
            ));
        }
    }
    if !builder.has_light() {
        warnings.push(format!(
            "{}: the scene has no light ppm renders: the image will be black",
            file.display()
        ));
    }
    Ok(builder)
}

/// A material's BSDF and the textures of its colours.
type Textured = (Bsdf, Vec<(ColourSlot, Texture)>);

/// A material as shapes name it.
#[derive(Clone, PartialEq, Eq, Hash)]
enum MaterialKey {
    Anonymous(usize),
    Named(String),
}

/// The shape's ppm material (without emission), built once per pbrt material, and its BSDF.
fn material_of(
    desc: &Description,
    s: &ShapeEntity,
    materials: &mut HashMap<MaterialKey, (u32, Textured)>,
    builder: &mut SceneBuilder,
    warnings: &mut Vec<String>,
) -> Result<(u32, Textured), LoadError> {
    let (key, entity): (MaterialKey, &MaterialEntity) = match &s.material {
        MaterialRef::Anonymous(i) => (MaterialKey::Anonymous(*i), &desc.materials[*i]),
        MaterialRef::Named(name, loc) => (
            MaterialKey::Named(name.clone()),
            desc.named_materials
                .get(name)
                .ok_or_else(|| loc.error(format!("NamedMaterial: no material \"{name}\"")))?,
        ),
    };
    if let Some(found) = materials.get(&key) {
        return Ok(found.clone());
    }
    let (bsdf, textures) = material::bsdf(desc, entity, warnings)?;
    let name = match &entity.name {
        Some(n) => n.clone(),
        None => format!("{} ({})", entity.entity.kind, entity.entity.loc),
    };
    let material = Material::new(bsdf, Vec3::ZERO)
        .named(name)
        .textured(textures.clone())
        .map_err(|slot| {
            entity
                .entity
                .loc
                .error(format!("{} cannot be textured", slot.name()))
        })?;
    let index = builder.add_material(material);
    materials.insert(key, (index, (bsdf, textures.clone())));
    Ok((index, (bsdf, textures)))
}

/// The area of a mesh in double precision.
fn mesh_area(m: &ppm_core::geometry::TriangleMesh) -> f64 {
    m.indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize].as_dvec3());
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

/// ppm's path depth from the `Integrator`'s `maxdepth`: pbrt-v4 counts bounces as ppm does
/// (maxdepth 1 is direct lighting, 0 the lights alone). Any pbrt integrator is accepted:
/// ppm's algorithm is what `-a` chooses.
fn max_depth(desc: &Description, warnings: &mut Vec<String>) -> Result<u32, LoadError> {
    let Some(e) = &desc.integrator else {
        return Ok(DEFAULT_MAX_DEPTH as u32);
    };
    let p = ParamSet::new(
        format!("Integrator \"{}\"", e.kind),
        e.loc.clone(),
        &e.params,
        &[],
    );
    if matches!(e.kind.as_str(), "ambientocclusion" | "aov" | "function") {
        return Err(p.error("not supported (ppm renders light transport)"));
    }
    let depth = p.int("maxdepth", DEFAULT_MAX_DEPTH)?;
    let ignored: Vec<&str> = [
        "regularize",
        "lightsampler",
        "photonsperiteration",
        "radius",
        "iterations",
        "seed",
        "bootstrapsamples",
        "chains",
        "mutationsperpixel",
        "largestepprobability",
        "sigma",
        "visualizestrategies",
        "visualizeweights",
        "samplelights",
        "samplebsdf",
    ]
    .into_iter()
    .filter(|n| p.has(n))
    .collect();
    p.ignore(&ignored);
    if !ignored.is_empty() {
        warnings.push(format!(
            "{}: {}: {} not used: ppm's algorithm and its settings come from the command line",
            e.loc,
            p.what,
            ignored.join(", ")
        ));
    }
    p.finish()?;
    if depth < 0 {
        return Err(p.error(format!("maxdepth {depth} is negative")));
    }
    if depth > MAX_DEPTH as i64 {
        warnings.push(format!(
            "{}: maxdepth {depth} is above the supported {MAX_DEPTH}; using {MAX_DEPTH}",
            e.loc
        ));
    }
    Ok(depth.min(MAX_DEPTH as i64) as u32)
}

/// `Sampler`, `PixelFilter`, `Accelerator` and `Option`: nothing of them changes ppm's image
/// but the sample count and filter, which are warned about.
fn settings_warnings(desc: &Description, warnings: &mut Vec<String>) -> Result<(), LoadError> {
    if let Some(e) = &desc.sampler {
        let p = ParamSet::new(
            format!("Sampler \"{}\"", e.kind),
            e.loc.clone(),
            &e.params,
            &[],
        );
        if p.has("pixelsamples") {
            let n = p.int("pixelsamples", 16)?;
            warnings.push(format!(
                "{}: Sampler: pixelsamples {n} is not used: ppm's -n sets the iterations, and its sampling is its own",
                e.loc
            ));
        }
        p.ignore(&[
            "seed",
            "dimensions",
            "jitter",
            "randomization",
            "xsamples",
            "ysamples",
        ]);
        p.finish()?;
    }
    if let Some(e) = &desc.filter {
        let p = ParamSet::new(
            format!("PixelFilter \"{}\"", e.kind),
            e.loc.clone(),
            &e.params,
            &[],
        );
        p.ignore(&["xradius", "yradius", "sigma", "alpha", "B", "C", "tau"]);
        p.finish()?;
        if e.kind != "box" {
            warnings.push(format!(
                "{}: PixelFilter \"{}\" is not used: ppm averages each pixel's samples (a box filter)",
                e.loc, e.kind
            ));
        }
    }
    for o in &desc.options {
        warnings.push(format!("{}: Option {} is not used", o.loc, o.decl()));
    }
    let _ = DMat4::IDENTITY;
    Ok(())
}
