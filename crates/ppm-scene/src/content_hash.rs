//! A fingerprint of a loaded scene, recorded in every rendered image so that `--resume` and
//! `ppm merge` can refuse to join renders of different scenes.

use ppm_core::scene::SceneBuilder;
use std::fmt::Write;

/// FNV-1a (64-bit) over the exact textual form of every value the renderer will see: camera,
/// materials, triangle meshes (every vertex, normal and index, so OBJ files are included),
/// spheres, point lights and render defaults. Floats print in Rust's shortest round-trip form,
/// so two scenes hash alike exactly when they hold the same values; comments, whitespace and
/// file names do not count. The textual form follows the ppm version, so hashes are compared
/// between images of the same version (which `--resume` and `merge` also require).
///
/// FNV-1a is not collision resistant against a forger; it guards against honest mistakes
/// (a part of another scene), which is what it is used for.
pub fn content_hash(builder: &SceneBuilder) -> u64 {
    let mut hasher = Fnv1a(0xcbf2_9ce4_8422_2325);
    // Writing to the hasher cannot fail.
    let _ = write!(
        hasher,
        "{:?}{:?}{:?}{:?}{:?}{:?}",
        builder.camera,
        builder.materials,
        builder.meshes,
        builder.spheres,
        builder.point_lights,
        builder.defaults
    );
    hasher.0
}

/// The FNV-1a state, fed by `write!` without building the text.
struct Fnv1a(u64);

impl Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for byte in s.bytes() {
            self.0 ^= byte as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_reference_values() {
        // Published test vectors of FNV-1a 64.
        let hash = |s: &str| {
            let mut h = Fnv1a(0xcbf2_9ce4_8422_2325);
            h.write_str(s).unwrap();
            h.0
        };
        assert_eq!(hash(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(hash("a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(hash("foobar"), 0x8594_4171_f739_67e8);
    }
}
