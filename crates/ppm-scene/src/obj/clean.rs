//! From tobj's meshes to ppm's: degenerate triangles dropped, vertex normals made unit
//! length or repaired, so that no NaN reaches the renderer.

use super::safe_normalize;
use glam::{Vec2, Vec3};
use ppm_core::geometry::TriangleMesh;
use std::path::Path;

/// Counts of what [`clean`] repaired, reported once per file.
#[derive(Default)]
pub(super) struct CleanStats {
    pub degenerate: usize,
    pub bad_normals: usize,
    pub flipped: usize,
}

/// "1 thing", "2 things".
fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

impl CleanStats {
    pub fn warn(&self, path: &Path, warnings: &mut Vec<String>) {
        let file = path.display();
        if self.degenerate > 0 {
            warnings.push(format!(
                "{file}: skipped {} (repeated vertices, zero area or non-finite positions)",
                count(self.degenerate, "degenerate triangle")
            ));
        }
        if self.bad_normals > 0 {
            warnings.push(format!(
                "{file}: replaced {} (NaN, infinite or zero) by the area-weighted normal of the adjacent triangles",
                count(self.bad_normals, "unusable vertex normal")
            ));
        }
        if self.flipped > 0 {
            warnings.push(format!(
                "{file}: {} vertex normals facing away from their counter-clockwise winding; the winding decides which side emits and which side is inside glass",
                match self.flipped {
                    1 => "1 triangle has".to_string(),
                    n => format!("{n} triangles have"),
                }
            ));
        }
    }
}

/// A tobj mesh as a [`TriangleMesh`] without degenerate triangles and with unit vertex
/// normals; `None` if no triangle is left.
pub(super) fn clean(
    mesh: &tobj::Mesh,
    name: &str,
    material: u32,
    path: &Path,
    stats: &mut CleanStats,
    warnings: &mut Vec<String>,
) -> Option<TriangleMesh> {
    let positions: Vec<Vec3> = mesh
        .positions
        .chunks_exact(3)
        .map(Vec3::from_slice)
        .collect();
    let mut normals: Vec<Vec3> = mesh.normals.chunks_exact(3).map(Vec3::from_slice).collect();
    if !normals.is_empty() && normals.len() != positions.len() {
        warnings.push(format!(
            "{}: object `{name}`: some faces have vertex normals and some do not; its vertex normals are ignored",
            path.display()
        ));
        normals.clear();
    }

    let mut indices = Vec::with_capacity(mesh.indices.len() / 3);
    // Area-weighted sum of the geometric normals around each vertex (to repair bad normals).
    let mut around = vec![
        Vec3::ZERO;
        if normals.is_empty() {
            0
        } else {
            positions.len()
        }
    ];
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]];
        let (Some(&p0), Some(&p1), Some(&p2)) = (
            positions.get(a as usize),
            positions.get(b as usize),
            positions.get(c as usize),
        ) else {
            stats.degenerate += 1;
            continue;
        };
        let (e1, e2) = (p1 - p0, p2 - p0);
        let n = e1.cross(e2); // |n| = 2 * area
                              // Zero area, or so thin (sine of the angle below 1e-6) that f32 cannot orient it.
        let ok = a != b
            && b != c
            && a != c
            && (p0.is_finite() && p1.is_finite() && p2.is_finite())
            && n.is_finite()
            && n.length() > 1e-6 * e1.length() * e2.length();
        if !ok {
            stats.degenerate += 1;
            continue;
        }
        for &v in &[a, b, c] {
            if let Some(s) = around.get_mut(v as usize) {
                *s += n;
            }
        }
        indices.push([a, b, c]);
    }
    if indices.is_empty() {
        return None;
    }

    for (ns, sum) in normals.iter_mut().zip(&around) {
        let unit = safe_normalize(*ns);
        *ns = match unit {
            Some(u) => u,
            None => {
                stats.bad_normals += 1;
                safe_normalize(*sum).unwrap_or(Vec3::Y)
            }
        };
    }
    if !normals.is_empty() {
        for &[a, b, c] in &indices {
            let [p0, p1, p2] = [a, b, c].map(|i| positions[i as usize]);
            let ng = (p1 - p0).cross(p2 - p0);
            let sum = normals[a as usize] + normals[b as usize] + normals[c as usize];
            if sum.dot(ng) < 0.0 {
                stats.flipped += 1;
            }
        }
    }

    // OBJ's v runs up the image, Mitsuba's (and ppm's) down from its top row: v -> 1 - v,
    // as Mitsuba 3's OBJ loader does. Coordinates on some vertices only are dropped.
    let mut uvs: Vec<Vec2> = mesh
        .texcoords
        .chunks_exact(2)
        .map(|t| Vec2::new(t[0], 1.0 - t[1]))
        .collect();
    if !uvs.is_empty() && uvs.len() != positions.len() {
        warnings.push(format!(
            "{}: object `{name}`: some faces have texture coordinates and some do not; its texture coordinates are ignored",
            path.display()
        ));
        uvs.clear();
    }
    let materials = vec![material; indices.len()];
    Some(TriangleMesh {
        positions,
        normals,
        uvs,
        indices,
        materials,
    })
}
