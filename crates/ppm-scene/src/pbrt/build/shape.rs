//! `Shape` to ppm geometry, one function per shape type: `trianglemesh`, `plymesh`,
//! `bilinearmesh` (two triangles per patch), `disk` (a fan), `cylinder` (a tube of quads) and
//! the analytic `sphere`.
//!
//! Orientation follows pbrt-v4 (`shapes.h`): a triangle's geometric normal is
//! cross(p1 - p0, p2 - p0) (ppm's convention too), negated when `ReverseOrientation` and a
//! mirroring transform disagree (`reverseOrientation ^ transformSwapsHandedness`); with
//! vertex normals (negated by `ReverseOrientation`, `TriangleMesh`'s constructor) it is turned
//! to the normals' side instead (`FaceForward`), done here per triangle at its centroid. The
//! side the geometric normal faces is where an area light emits and a dielectric's outside.

use super::super::params::{ParamSet, ParamType};
use super::super::parse::resolve;
use super::super::scene::ShapeEntity;
use crate::mitsuba::SEGMENTS;
use crate::ply::{self, MeshData};
use crate::LoadError;
use glam::{DMat3, DMat4, DVec3, Vec3};
use ppm_core::geometry::{Sphere, TriangleMesh};
use std::collections::HashMap;
use std::f64::consts::TAU;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// What one shape becomes; the material is set by the caller.
pub enum Geometry {
    Mesh(TriangleMesh),
    Sphere(Sphere),
}

/// PLY files already read (instances name the same file many times).
#[derive(Default)]
pub struct PlyCache(HashMap<PathBuf, Rc<MeshData>>);

/// The geometry of `shape` moved to the world by `to_world` (the world mirror times the
/// shape's transform). When `textured`, a shape the file gives no uv gets pbrt-v4's where
/// ppm can give it ([`default_triangle_uvs`], [`disk`], [`cylinder`]); untextured shapes keep
/// their vertices as they always were.
pub fn geometry(
    shape: &ShapeEntity,
    to_world: DMat4,
    main_folder: &Path,
    cache: &mut PlyCache,
    textured: bool,
    warnings: &mut Vec<String>,
) -> Result<Geometry, LoadError> {
    let e = &shape.entity;
    let p = ParamSet::new(
        format!("Shape \"{}\"", e.kind),
        e.loc.clone(),
        &e.params,
        &shape.defaults,
    );
    // A cut-out (alpha) is not supported; alpha 1 (opaque, the default) is.
    if let Some(alpha) = p.get("alpha") {
        if alpha.ty != ParamType::Float || p.float("alpha", 1.0)? != 1.0 {
            return Err(p.error_at(alpha, "alpha cut-outs are not supported yet"));
        }
    }
    p.ignore(&["emissionfilename"]);
    let mut made_uvs = Vec::new();
    let (positions, normals, indices) = match e.kind.as_str() {
        "sphere" => {
            let s = sphere(&p, to_world, shape.reverse_orientation)?;
            p.finish()?;
            return Ok(Geometry::Sphere(s));
        }
        "trianglemesh" => triangle_mesh(&p)?,
        "bilinearmesh" => bilinear_mesh(&p, warnings)?,
        "plymesh" => {
            let (parts, uvs) = ply_mesh(&p, main_folder, cache)?;
            made_uvs = uvs;
            parts
        }
        "disk" => {
            let (parts, uvs) = disk(&p, textured)?;
            made_uvs = uvs;
            parts
        }
        "cylinder" => {
            let (parts, uvs) = cylinder(&p, textured)?;
            made_uvs = uvs;
            parts
        }
        _ => return Err(p.error("shape type not supported yet (trianglemesh, plymesh, bilinearmesh, sphere, disk and cylinder are)")),
    };
    // Per-vertex uv of a trianglemesh or bilinearmesh (checked by `vertices`) or a PLY file
    // is kept as given; textures apply pbrt's conventions on top (`texture.rs`).
    let given: Vec<glam::Vec2> = match e.kind.as_str() {
        "trianglemesh" | "bilinearmesh" => p
            .point2s("uv")?
            .unwrap_or_default()
            .iter()
            .map(|uv| uv.as_vec2())
            .collect(),
        _ => made_uvs,
    };
    let ((positions, normals, indices), uvs) =
        if textured && given.is_empty() && e.kind == "trianglemesh" {
            default_triangle_uvs((positions, normals, indices))
        } else {
            ((positions, normals, indices), given)
        };
    p.finish()?;
    let mut mesh = place(
        positions,
        normals,
        indices,
        to_world,
        shape.reverse_orientation,
        &p,
    )?;
    mesh.uvs = uvs;
    Ok(Geometry::Mesh(mesh))
}

type Parts = (Vec<DVec3>, Vec<DVec3>, Vec<[u32; 3]>);

/// Vertex indices in `[0, n)`, in groups of `k`; `None` given means the vertices in order
/// when there are exactly `k` of them (pbrt-v4's rule for a single triangle or patch).
fn grouped_indices(p: &ParamSet, n: usize, k: usize) -> Result<Vec<Vec<u32>>, LoadError> {
    let indices = match p.ints("indices")? {
        Some(v) => v,
        None if n == k => (0..k as i64).collect(),
        None => return Err(p.error(format!("needs \"integer indices\" ({k} per face)"))),
    };
    if indices.len() % k != 0 {
        return Err(p.error(format!(
            "{} indices is not a multiple of {k}",
            indices.len()
        )));
    }
    if let Some(bad) = indices.iter().find(|&&i| i < 0 || i as usize >= n) {
        return Err(p.error(format!("index {bad} is outside the {n} vertices")));
    }
    Ok(indices
        .chunks_exact(k)
        .map(|c| c.iter().map(|&i| i as u32).collect())
        .collect())
}

/// `P` and the optional `N` (one per vertex); `uv` is checked here and read by `geometry`.
fn vertices(p: &ParamSet) -> Result<(Vec<DVec3>, Vec<DVec3>), LoadError> {
    let positions = p
        .triples("P", ParamType::Point3)?
        .ok_or_else(|| p.error("needs \"point3 P\""))?;
    if positions.len() > u32::MAX as usize / 2 {
        return Err(p.error("too many vertices"));
    }
    let normals = p.triples("N", ParamType::Normal3)?.unwrap_or_default();
    if !normals.is_empty() && normals.len() != positions.len() {
        return Err(p.error(format!(
            "{} normals for {} vertices",
            normals.len(),
            positions.len()
        )));
    }
    if let Some(uv) = p.point2s("uv")? {
        if uv.len() != positions.len() {
            return Err(p.error(format!("{} uv for {} vertices", uv.len(), positions.len())));
        }
    }
    if p.has("S") {
        p.get("S");
        return Err(p.error("per-vertex tangents (S) are not supported yet"));
    }
    p.ignore(&["faceIndices"]);
    Ok((positions, normals))
}

fn triangle_mesh(p: &ParamSet) -> Result<Parts, LoadError> {
    let (positions, normals) = vertices(p)?;
    let indices = grouped_indices(p, positions.len(), 3)?
        .into_iter()
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    Ok((positions, normals, indices))
}

/// `bilinearmesh`: patches of four vertices p00, p10, p01, p11 (pbrt-v4's order), each as the
/// triangles (p00, p10, p11) and (p00, p11, p01), whose normals are the patch's
/// cross(dp/du, dp/dv); exact for planar patches, a warning for curved ones.
fn bilinear_mesh(p: &ParamSet, warnings: &mut Vec<String>) -> Result<Parts, LoadError> {
    let (positions, normals) = vertices(p)?;
    let patches = grouped_indices(p, positions.len(), 4)?;
    let mut indices = Vec::with_capacity(2 * patches.len());
    let uv = p.point2s("uv")?.unwrap_or_default();
    let (mut curved, mut warped) = (0, 0);
    for q in &patches {
        let [a, b, c, d] = [q[0], q[1], q[2], q[3]];
        let v = |i: u32| positions[i as usize];
        let n = (v(b) - v(a)).cross(v(c) - v(a));
        let off = n.normalize_or_zero().dot(v(d) - v(a)).abs();
        if off > 1e-6 * (v(d) - v(a)).length().max(f64::MIN_POSITIVE) {
            curved += 1;
        }
        // pbrt interpolates uv bilinearly over the patch, the two triangles linearly: the
        // same when uv is affine in the patch, uv00 + uv11 = uv10 + uv01.
        if !uv.is_empty() {
            let t = |i: u32| uv[i as usize];
            let skew = (t(a) + t(d)) - (t(b) + t(c));
            if skew.length() > 1e-6 * (t(d) - t(a)).length().max(f64::MIN_POSITIVE) {
                warped += 1;
            }
        }
        indices.push([a, b, d]);
        indices.push([a, d, c]);
    }
    if curved > 0 {
        warnings.push(format!(
            "{}: {}: {curved} of {} bilinear patches are not planar; each is rendered as two flat triangles",
            p.loc,
            p.what,
            patches.len()
        ));
    }
    if warped > 0 {
        warnings.push(format!(
            "{}: {}: the uv of {warped} of {} bilinear patches is not affine; each triangle interpolates it linearly, pbrt bilinearly",
            p.loc,
            p.what,
            patches.len()
        ));
    }
    Ok((positions, normals, indices))
}

/// `plymesh`: see `ply.rs` (polygons as fans), with the file's uv if it has them.
/// Displacement is not supported.
fn ply_mesh(
    p: &ParamSet,
    main_folder: &Path,
    cache: &mut PlyCache,
) -> Result<(Parts, Vec<glam::Vec2>), LoadError> {
    let name = p
        .string_opt("filename")?
        .ok_or_else(|| p.error("needs \"string filename\""))?;
    if p.has("displacement") {
        p.get("displacement");
        return Err(p.error("displacement is not supported yet"));
    }
    p.ignore(&["edgelength"]);
    let path = resolve(name, &p.loc, main_folder);
    let data = match cache.0.get(&path) {
        Some(d) => d.clone(),
        None => {
            let d = Rc::new(ply::load_ply(&path)?);
            cache.0.insert(path, d.clone());
            d
        }
    };
    Ok((
        (
            data.positions.iter().map(|x| x.as_dvec3()).collect(),
            data.normals.iter().map(|x| x.as_dvec3()).collect(),
            data.indices.clone(),
        ),
        data.uvs.clone(),
    ))
}

/// `disk`: radius `radius` at z = `height`, normal +z, as a fan of [`SEGMENTS`] triangles (a
/// regular polygon keeping 99.96 % of the area); partial or annular disks are errors.
///
/// With `uv`, pbrt-v4's (`Disk`, shapes.h): u = phi / phiMax, v = (radius - r) / (radius -
/// innerradius), phi = atan2(y, x) in [0, 2 pi), so u = i / SEGMENTS on the rim's i-th vertex
/// (the first repeated at u = 1 to close the seam) and v = 1 at the centre, which each
/// triangle then has a copy of at its wedge's middle u. Interpolated linearly across a
/// triangle they equal pbrt's at the vertices; inside, u differs by at most 1 / (2
/// SEGMENTS) near the centre and v by the polygon's 0.03 % of the radius.
fn disk(p: &ParamSet, uv: bool) -> Result<(Parts, Vec<glam::Vec2>), LoadError> {
    let height = p.float("height", 0.0)?;
    let radius = p.float("radius", 1.0)?;
    if p.float("innerradius", 0.0)? != 0.0 {
        return Err(p.error("an annulus (innerradius > 0) is not supported yet"));
    }
    if p.float("phimax", 360.0)? < 360.0 {
        return Err(p.error("a partial disk (phimax < 360) is not supported yet"));
    }
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(p.error(format!("radius {radius} is not positive")));
    }
    let n = SEGMENTS as u32;
    let rim = |i: u32| {
        let a = TAU * i as f64 / SEGMENTS as f64;
        DVec3::new(radius * a.cos(), radius * a.sin(), height)
    };
    if !uv {
        let mut positions = vec![DVec3::new(0.0, 0.0, height)];
        positions.extend((0..n).map(rim));
        let indices = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
        return Ok(((positions, Vec::new(), indices), Vec::new()));
    }
    // Rim vertices 0..=n (the last at phi = 2 pi, u = 1), then one centre per triangle.
    let mut positions: Vec<DVec3> = (0..=n).map(rim).collect();
    let mut uvs: Vec<glam::Vec2> = (0..=n)
        .map(|i| glam::Vec2::new(i as f32 / n as f32, 0.0))
        .collect();
    let mut indices = Vec::with_capacity(SEGMENTS);
    for i in 0..n {
        let centre = positions.len() as u32;
        positions.push(DVec3::new(0.0, 0.0, height));
        uvs.push(glam::Vec2::new((i as f32 + 0.5) / n as f32, 1.0));
        indices.push([centre, i, i + 1]);
    }
    Ok(((positions, Vec::new(), indices), uvs))
}

/// `cylinder`: the open tube of `radius` around z from `zmin` to `zmax` (pbrt-v4's defaults
/// 1, -1, 1), [`SEGMENTS`] quads around with radial vertex normals, facing outward as pbrt's
/// cross(dp/du, dp/dv) does; a partial one (`phimax` < 360) is an error.
///
/// With `uv`, pbrt-v4's (`Cylinder`, shapes.h): u = phi / phiMax with phi = atan2(y, x) in
/// [0, 2 pi), v = (z - zmin) / (zmax - zmin) with zmin the smaller z; the column at phi = 0
/// is repeated at u = 1 to close the seam. v is exact across each quad, u exact at the
/// vertices and linear in between (pbrt's is linear in the angle, not along the chord: they
/// differ by less than 1e-5).
fn cylinder(p: &ParamSet, uv: bool) -> Result<(Parts, Vec<glam::Vec2>), LoadError> {
    let radius = p.float("radius", 1.0)?;
    let (z0, z1) = (p.float("zmin", -1.0)?, p.float("zmax", 1.0)?);
    if p.float("phimax", 360.0)? < 360.0 {
        return Err(p.error("a partial cylinder (phimax < 360) is not supported yet"));
    }
    if !(radius > 0.0 && radius.is_finite()) || z0 == z1 {
        return Err(p.error(format!(
            "radius {radius} from z {z0} to {z1}: expected a positive radius and zmin != zmax"
        )));
    }
    // Columns around: SEGMENTS, or one more (the seam's copy) with uv.
    let columns = SEGMENTS as u32 + u32::from(uv);
    let (mut positions, mut normals, mut indices) = (Vec::new(), Vec::new(), Vec::new());
    let mut uvs = Vec::new();
    for i in 0..columns {
        let a = TAU * i as f64 / SEGMENTS as f64;
        let radial = DVec3::new(a.cos(), a.sin(), 0.0);
        for (z, v) in [(z0.min(z1), 0.0), (z0.max(z1), 1.0)] {
            positions.push(radius * radial + DVec3::new(0.0, 0.0, z));
            normals.push(radial);
            if uv {
                uvs.push(glam::Vec2::new(i as f32 / SEGMENTS as f32, v));
            }
        }
    }
    let n = SEGMENTS as u32;
    for i in 0..n {
        let next = if uv { i + 1 } else { (i + 1) % n };
        let (a0, b0) = (2 * i, 2 * i + 1);
        let (a1, b1) = (2 * next, 2 * next + 1);
        // cross(a1 - a0, b1 - a0) points along the radial direction: outward.
        indices.push([a0, a1, b1]);
        indices.push([a0, b1, b0]);
    }
    Ok(((positions, normals, indices), uvs))
}

/// pbrt-v4's uv of a triangle whose mesh gives none (`Triangle`, shapes.h): (0, 0), (1, 0),
/// (1, 1) at its three vertices in the file's order, so uv = (b1 + b2, b2) for barycentrics
/// (b0, b1, b2). Vertices are unshared (three per triangle) to carry them; this runs only for
/// textured meshes, before `place` may reorder a triangle's vertices (which keep their uv).
fn default_triangle_uvs((positions, normals, indices): Parts) -> (Parts, Vec<glam::Vec2>) {
    const CORNERS: [glam::Vec2; 3] = [
        glam::Vec2::new(0.0, 0.0),
        glam::Vec2::new(1.0, 0.0),
        glam::Vec2::new(1.0, 1.0),
    ];
    let mut unshared = (
        Vec::with_capacity(3 * indices.len()),
        Vec::new(),
        Vec::with_capacity(indices.len()),
    );
    let mut uvs = Vec::with_capacity(3 * indices.len());
    for t in &indices {
        let first = unshared.0.len() as u32;
        for (k, &i) in t.iter().enumerate() {
            unshared.0.push(positions[i as usize]);
            if !normals.is_empty() {
                unshared.1.push(normals[i as usize]);
            }
            uvs.push(CORNERS[k]);
        }
        unshared.2.push([first, first + 1, first + 2]);
    }
    (unshared, uvs)
}

/// `sphere`: a full sphere of `radius` at the object's origin, moved by `m` (which must keep
/// it a sphere); facing inward under `ReverseOrientation`. Partial spheres are errors.
fn sphere(p: &ParamSet, m: DMat4, reverse: bool) -> Result<Sphere, LoadError> {
    let radius = p.float("radius", 1.0)?;
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(p.error(format!("radius {radius} is not positive")));
    }
    let zmin = p.float("zmin", -radius)?;
    let zmax = p.float("zmax", radius)?;
    let phimax = p.float("phimax", 360.0)?;
    if zmin > -radius || zmax < radius || phimax < 360.0 {
        return Err(p.error("a partial sphere (zmin, zmax or phimax) is not supported yet"));
    }
    let linear = DMat3::from_mat4(m);
    let axes = [linear.x_axis, linear.y_axis, linear.z_axis];
    let s = axes[0].length();
    let similar = s > 0.0
        && axes.iter().all(|a| (a.length() - s).abs() <= 1e-6 * s)
        && axes[0].dot(axes[1]).abs() <= 1e-6 * s * s
        && axes[1].dot(axes[2]).abs() <= 1e-6 * s * s
        && axes[0].dot(axes[2]).abs() <= 1e-6 * s * s;
    if !similar {
        return Err(p.error(
            "a transform that does not keep the sphere a sphere (non-uniform scale or shear) is not supported yet",
        ));
    }
    let c = m.transform_point3(DVec3::ZERO).as_vec3();
    let r = (radius * s) as f32;
    if !(c.is_finite() && r.is_finite() && r > 0.0) {
        return Err(p.error("its centre or radius is out of single-precision range"));
    }
    // pbrt-v4 flips a sphere's normal for reverseOrientation ^ transformSwapsHandedness, and
    // its normal from cross(dpdu, dpdv) flips with a mirroring transform: outward unless
    // ReverseOrientation.
    let sphere = Sphere::new(c, r, 0);
    Ok(if reverse { sphere.inward() } else { sphere })
}

/// The mesh in the world: points by `m`, normals by its inverse transpose (negated by
/// `ReverseOrientation`), winding as the module documentation says.
fn place(
    positions: Vec<DVec3>,
    normals: Vec<DVec3>,
    mut indices: Vec<[u32; 3]>,
    m: DMat4,
    reverse: bool,
    p: &ParamSet,
) -> Result<TriangleMesh, LoadError> {
    let linear = DMat3::from_mat4(m);
    let det = linear.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err(p.error("its transform is singular (it flattens the shape)"));
    }
    let world: Vec<Vec3> = positions
        .iter()
        .map(|x| m.transform_point3(*x).as_vec3())
        .collect();
    if world.iter().any(|x| !x.is_finite()) {
        return Err(p.error("its transform takes points out of single-precision range"));
    }
    let normal_matrix = linear.inverse().transpose();
    let sign = if reverse { -1.0 } else { 1.0 };
    let world_normals: Vec<DVec3> = normals
        .iter()
        .map(|n| sign * (normal_matrix * *n).normalize_or_zero())
        .collect();
    let usable = world_normals
        .iter()
        .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-6);
    if usable && !world_normals.is_empty() {
        for t in &mut indices {
            let [a, b, c] = t.map(|i| world[i as usize].as_dvec3());
            let ng = (b - a).cross(c - a);
            let ns: DVec3 = t.iter().map(|&i| world_normals[i as usize]).sum();
            if ng.dot(ns) < 0.0 {
                t.swap(1, 2);
            }
        }
    } else if reverse != (det < 0.0) {
        for t in &mut indices {
            t.swap(1, 2);
        }
    }
    let mut mesh = TriangleMesh::new(world, indices, 0);
    if usable {
        mesh.normals = world_normals.iter().map(|n| n.as_vec3()).collect();
    }
    Ok(mesh)
}
