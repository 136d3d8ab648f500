//! `shapegroup` and `instance`: a group's shapes built once, in the group's space, and
//! placed by each instance's `to_world` without copying their triangles (the meshes become
//! ppm instances, a two-level BVH; Mitsuba 3's `instance` plugin does the same with its own
//! acceleration structures). A sphere in a group is copied per instance instead (ppm's
//! spheres are analytic and placed by a similarity, `placement::place_sphere`).

use super::{add_shape, unsupported, Materials, Target};
use crate::mitsuba::props::Props;
use crate::mitsuba::tree::SceneTree;
use crate::placement::place_sphere;
use crate::LoadError;
use ppm_core::geometry::Sphere;
use ppm_core::scene::SceneBuilder;
use std::collections::HashMap;

/// A built shape group: its meshes (indices of the builder's instanced meshes) and its
/// spheres in the group's space.
#[derive(Default)]
pub struct Group {
    pub meshes: Vec<u32>,
    pub spheres: Vec<Sphere>,
}

/// The shape groups of a scene: built when an instance first names them.
#[derive(Default)]
pub struct Groups {
    built: HashMap<usize, Group>,
    declared: Vec<usize>,
}

impl Groups {
    /// A `shapegroup` at the top level (built when an instance names it).
    pub fn declared(&mut self, group: usize) {
        self.declared.push(group);
    }

    /// Mitsuba renders a group no instance names nowhere; say so.
    pub fn warn_unplaced(&self, tree: &SceneTree, warnings: &mut Vec<String>) {
        for g in &self.declared {
            if !self.built.contains_key(g) {
                let o = &tree.objects[*g];
                warnings.push(format!(
                    "{}: {} is never placed by an instance: it is not rendered",
                    o.location,
                    o.describe()
                ));
            }
        }
    }
}

/// `instance`: the shape group it names (one nested or referenced `shapegroup`) placed by
/// its `to_world`.
pub fn add_instance(
    tree: &SceneTree,
    index: usize,
    builder: &mut SceneBuilder,
    materials: &mut Materials,
    groups: &mut Groups,
    warnings: &mut Vec<String>,
) -> Result<(), LoadError> {
    let p = Props::new(tree, index);
    let to_world = p.transform("to_world")?;
    let shapes = p.objects("shape");
    let group = match shapes.as_slice() {
        [g] if tree.objects[*g].plugin == "shapegroup" => *g,
        _ => {
            return Err(p.error(format!(
                "{} needs exactly one shapegroup (nested or by <ref>)",
                p.object.describe()
            )))
        }
    };
    p.finish()?;
    if let std::collections::hash_map::Entry::Vacant(slot) = groups.built.entry(group) {
        let g = Props::new(tree, group);
        let mut built = Group::default();
        for shape in g.objects("shape") {
            match tree.objects[shape].plugin.as_str() {
                "shapegroup" | "instance" => return Err(unsupported(&tree.objects[shape])),
                _ => add_shape(
                    tree,
                    shape,
                    builder,
                    materials,
                    Target::Group(&mut built),
                    warnings,
                )?,
            }
        }
        g.finish()?;
        slot.insert(built);
    }
    let built = &groups.built[&group];
    for &mesh in &built.meshes {
        builder.add_instance(mesh, to_world);
    }
    for s in &built.spheres {
        let (center, radius) = place_sphere(s.center.as_dvec3(), s.radius as f64, to_world)
            .map_err(|e| p_error(tree, index, &e.describe("to_world")))?;
        builder.add_sphere(Sphere {
            center,
            radius,
            ..*s
        });
    }
    Ok(())
}

/// An error about object `index`, named with its place.
fn p_error(tree: &SceneTree, index: usize, why: &str) -> LoadError {
    let o = &tree.objects[index];
    o.location
        .error(format!("{} at {}: {why}", o.describe(), o.location))
}
