//! Shape plugins to ppm geometry, one function per plugin: meshes from files (`obj`, `ply`,
//! `serialized`), tessellated primitives (`rectangle`, `cube`, `disk`, `cylinder`) and the
//! analytic `sphere`. Every mesh goes through [`place`]: `to_world`, normals by the inverse
//! transpose, and the winding reversed by a mirroring transform or `flip_normals` so that the
//! side a light emits to and a glass's outside stay where Mitsuba has them.

use super::unsupported;
use crate::mitsuba::props::Props;
use crate::obj::{self, ObjMaterials};
use crate::placement::{place_mesh, place_sphere, PlacementError};
use crate::{ply, serialized, LoadError};
use glam::{DMat4, DVec3, Vec3};
use ppm_core::geometry::{Sphere, TriangleMesh};
use std::f64::consts::TAU;
use std::path::PathBuf;

/// Segments of a tessellated `disk` and around a `cylinder`: a regular 128-gon keeps
/// sin(2 pi / 128) 128 / (2 pi) = 99.96 % of the circle's area (and of a disk light's power).
pub const SEGMENTS: usize = 128;

/// What one shape becomes. Meshes get their material afterwards.
pub enum Geometry {
    Meshes(Vec<TriangleMesh>),
    Sphere(Sphere),
}

/// The geometry of shape `index`; `p` are its properties (the caller reads `bsdf` and
/// `emitter` children).
pub fn geometry(p: &Props, warnings: &mut Vec<String>) -> Result<Geometry, LoadError> {
    let to_world = p.transform("to_world")?;
    let flip = p.boolean("flip_normals", false)?;
    let meshes = match p.object.plugin.as_str() {
        "sphere" => return sphere(p, to_world, flip),
        "rectangle" => vec![rectangle()],
        "cube" => vec![cube()],
        "disk" => vec![disk()],
        "cylinder" => vec![cylinder(p)?],
        "obj" => obj_meshes(p, warnings)?,
        "ply" => vec![ply_mesh(p)?],
        "serialized" => vec![serialized_mesh(p)?],
        _ => return Err(unsupported(p.object)),
    };
    let from_file = matches!(p.object.plugin.as_str(), "obj" | "ply" | "serialized");
    let face_normals = from_file && p.boolean("face_normals", false)?;
    p.ignore(&["flip_tex_coords"]);
    let meshes = meshes
        .into_iter()
        .map(|m| {
            let mut mesh = place(m, to_world, flip, face_normals, p, warnings)?;
            // Mitsuba smooths a mesh file that stores no normals unless told `face_normals`.
            if from_file && !face_normals && mesh.normals.is_empty() {
                mesh.normals = vertex_normals(&mesh);
            }
            Ok(mesh)
        })
        .collect::<Result<_, LoadError>>()?;
    Ok(Geometry::Meshes(meshes))
}

/// A mesh file named by `filename`, relative to a `<path>` directory or to the XML file that
/// names it ([`SceneTree::resolve`](super::super::tree::SceneTree::resolve)).
fn file(p: &Props) -> Result<PathBuf, LoadError> {
    let name = p
        .string_opt("filename")?
        .ok_or_else(|| p.error(format!("{} needs a string `filename`", p.object.describe())))?;
    Ok(p.tree.resolve(&p.location().file, name))
}

/// Moves `mesh` to the world by `m`: points by `m`, shading normals by its inverse transpose
/// (dropped with `face_normals`), negated with `flip`; the triangles' winding (which fixes
/// the geometric normal, `cross(v1 - v0, v2 - v0)`) reversed when exactly one of a mirroring
/// `m` (det < 0) and `flip` holds.
fn place(
    mut mesh: TriangleMesh,
    m: DMat4,
    flip: bool,
    face_normals: bool,
    p: &Props,
    warnings: &mut Vec<String>,
) -> Result<TriangleMesh, LoadError> {
    let normals_ok = place_mesh(&mut mesh, m, flip).map_err(|e| {
        p.error(format!(
            "{}: {}",
            p.object.describe(),
            e.describe("to_world")
        ))
    })?;
    if face_normals {
        mesh.normals.clear();
    } else if !normals_ok {
        warnings.push(format!(
            "{}: {}: some vertex normals are zero or not finite; using the faces' normals",
            p.location(),
            p.object.describe()
        ));
    }
    Ok(mesh)
}

/// Smooth vertex normals, as Mitsuba computes them for a mesh that has none: each
/// triangle's unit normal added to its three corners weighted by the corner's interior angle
/// (Thürmer and Wüthrich 1998, "Computing vertex normals from polygonal facets", JGT 3(1)),
/// then normalised. Empty (flat shading) if a vertex of a triangle gets no usable normal.
pub fn vertex_normals(mesh: &TriangleMesh) -> Vec<Vec3> {
    let mut sum = vec![DVec3::ZERO; mesh.positions.len()];
    for t in &mesh.indices {
        let p = t.map(|i| mesh.positions[i as usize].as_dvec3());
        let Some(n) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
            continue;
        };
        for k in 0..3 {
            let e1 = (p[(k + 1) % 3] - p[k]).normalize_or_zero();
            let e2 = (p[(k + 2) % 3] - p[k]).normalize_or_zero();
            sum[t[k] as usize] += n * e1.dot(e2).clamp(-1.0, 1.0).acos();
        }
    }
    let mut used = vec![false; mesh.positions.len()];
    mesh.indices
        .iter()
        .flatten()
        .for_each(|&i| used[i as usize] = true);
    // A vertex no triangle uses is never shaded: any unit vector does.
    let normals: Option<Vec<Vec3>> = sum
        .iter()
        .zip(&used)
        .map(|(n, &used)| match used {
            true => n.try_normalize().map(|n| n.as_vec3()),
            false => Some(Vec3::Z),
        })
        .collect();
    normals.unwrap_or_default()
}

/// `sphere`: `center` (default origin) and `radius` (default 1) moved by `to_world`, which
/// must keep it a sphere (rotation, uniform scale, translation); ppm's analytic sphere, facing
/// inward with `flip_normals`.
fn sphere(p: &Props, m: DMat4, flip: bool) -> Result<Geometry, LoadError> {
    let center = p.point_opt("center")?.unwrap_or(DVec3::ZERO);
    let radius = p.float("radius", 1.0)?;
    if radius <= 0.0 {
        return Err(p.error(format!("sphere: radius {radius} is not positive")));
    }
    let (c, r) = place_sphere(center, radius, m).map_err(|e| match e {
        PlacementError::NotSimilar => p.error(
            "sphere: a to_world that does not keep it a sphere (non-uniform scale or shear) is not supported yet",
        ),
        PlacementError::OutOfRange => {
            p.error("sphere: its centre or radius is out of single-precision range")
        }
        e => p.error(format!("sphere: {}", e.describe("to_world"))),
    })?;
    let sphere = Sphere::new(c, r, 0);
    Ok(Geometry::Sphere(if flip {
        sphere.inward()
    } else {
        sphere
    }))
}

/// `rectangle`: [-1, 1]^2 in the plane z = 0, normal +z.
fn rectangle() -> TriangleMesh {
    TriangleMesh::quad(
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
        0,
    )
}

/// `cube`: [-1, 1]^3, normals outward, 12 triangles.
fn cube() -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    // For each axis and side, a corner and two edges whose cross product points outward.
    for axis in 0..3 {
        let (u, v) = (
            Vec3::AXES[(axis + 1) % 3] * 2.0,
            Vec3::AXES[(axis + 2) % 3] * 2.0,
        );
        for side in [-1.0f32, 1.0] {
            let normal = Vec3::AXES[axis] * side;
            let (u, v) = if side > 0.0 { (u, v) } else { (v, u) };
            let corner = normal - 0.5 * u - 0.5 * v;
            let quad = TriangleMesh::quad(corner, u, v, 0);
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(quad.positions);
            mesh.indices
                .extend(quad.indices.iter().map(|t| t.map(|i| i + base)));
        }
    }
    mesh.materials = vec![0; mesh.indices.len()];
    mesh
}

/// `disk`: the unit disk in the plane z = 0, normal +z, as a fan of [`SEGMENTS`] triangles.
fn disk() -> TriangleMesh {
    let mut positions = vec![Vec3::ZERO];
    for i in 0..SEGMENTS {
        let a = TAU * i as f64 / SEGMENTS as f64;
        positions.push(Vec3::new(a.cos() as f32, a.sin() as f32, 0.0));
    }
    let indices = (0..SEGMENTS as u32)
        .map(|i| [0, 1 + i, 1 + (i + 1) % SEGMENTS as u32])
        .collect();
    TriangleMesh::new(positions, indices, 0)
}

/// `cylinder`: the open tube of `radius` (default 1) from `p0` (default origin) to `p1`
/// (default +z), [`SEGMENTS`] quads around with radial vertex normals, normals outward.
fn cylinder(p: &Props) -> Result<TriangleMesh, LoadError> {
    let p0 = p.point_opt("p0")?.unwrap_or(DVec3::ZERO);
    let p1 = p.point_opt("p1")?.unwrap_or(DVec3::Z);
    let radius = p.float("radius", 1.0)?;
    let axis = (p1 - p0)
        .try_normalize()
        .ok_or_else(|| p.error("cylinder: p0 equals p1"))?;
    if radius <= 0.0 {
        return Err(p.error(format!("cylinder: radius {radius} is not positive")));
    }
    // A right-handed frame (t, b, axis): t x b = axis.
    let t = axis.any_orthonormal_vector();
    let b = axis.cross(t);
    let mut mesh = TriangleMesh::default();
    for i in 0..SEGMENTS {
        let a = TAU * i as f64 / SEGMENTS as f64;
        let radial = a.cos() * t + a.sin() * b;
        for end in [p0, p1] {
            mesh.positions.push((end + radius * radial).as_vec3());
            mesh.normals.push(radial.as_vec3());
        }
    }
    let n = SEGMENTS as u32;
    for i in 0..n {
        let (a0, b0) = (2 * i, 2 * i + 1);
        let (a1, b1) = (2 * ((i + 1) % n), 2 * ((i + 1) % n) + 1);
        // cross(a1 - a0, b1 - a0) points along the radial direction: outward.
        mesh.indices.push([a0, a1, b1]);
        mesh.indices.push([a0, b1, b0]);
    }
    mesh.materials = vec![0; mesh.indices.len()];
    Ok(mesh)
}

/// `obj`: every object of the file, its MTL materials ignored (the shape's BSDF applies).
fn obj_meshes(p: &Props, warnings: &mut Vec<String>) -> Result<Vec<TriangleMesh>, LoadError> {
    let path = file(p)?;
    Ok(obj::load_obj(&path, ObjMaterials::Ignore, warnings)?.meshes)
}

/// `ply`: see `ply.rs`.
fn ply_mesh(p: &Props) -> Result<TriangleMesh, LoadError> {
    let path = file(p)?;
    Ok(ply::load_ply(&path)?.into_triangle_mesh(0))
}

/// `serialized`: mesh `shape_index` (default 0) of the file; see `serialized.rs`.
fn serialized_mesh(p: &Props) -> Result<TriangleMesh, LoadError> {
    let path = file(p)?;
    let index = p.integer("shape_index", 0)?;
    let index = u32::try_from(index)
        .map_err(|_| p.error(format!("serialized: shape_index {index} is negative")))?;
    Ok(serialized::load_serialized(&path, index)?.into_triangle_mesh(0))
}
