//! Property names of Mitsuba 0.5/0.6 (scene `version` below 2) and their Mitsuba 2/3
//! spelling. Mitsuba 3 upgrades an old file by one rule applied to every property name,
//! camelCase to snake_case (`toWorld` -> `to_world`, `intIOR` -> `int_ior`); this module
//! applies the same rule, so an old file and its new spelling parse to the same tree.
//! [`UPGRADED_NAMES`] lists the names that matter to ppm, as documentation and for the tests.

/// Old names and what they become (each is what [`camel_to_snake`] gives).
pub const UPGRADED_NAMES: &[(&str, &str)] = &[
    ("toWorld", "to_world"),
    ("intIOR", "int_ior"),
    ("extIOR", "ext_ior"),
    ("specularReflectance", "specular_reflectance"),
    ("specularTransmittance", "specular_transmittance"),
    ("diffuseReflectance", "diffuse_reflectance"),
    ("fovAxis", "fov_axis"),
    ("nearClip", "near_clip"),
    ("farClip", "far_clip"),
    ("focalLength", "focal_length"),
    ("maxDepth", "max_depth"),
    ("rrDepth", "rr_depth"),
    ("hideEmitters", "hide_emitters"),
    ("sampleCount", "sample_count"),
    ("shapeIndex", "shape_index"),
    ("flipNormals", "flip_normals"),
    ("faceNormals", "face_normals"),
    ("cropOffsetX", "crop_offset_x"),
    ("cropOffsetY", "crop_offset_y"),
    ("cropWidth", "crop_width"),
    ("cropHeight", "crop_height"),
];

/// Mitsuba 3's upgrade of an old property name: an upper-case letter that follows a
/// lower-case one starts a new word, `_` and the letter in lower case; the upper-case
/// letters right after it join that word (`intIOR` -> `int_ior`). Other names are unchanged.
pub fn camel_to_snake(name: &str) -> String {
    let chars: Vec<char> = name.chars().collect();
    let mut out = String::with_capacity(name.len() + 4);
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if i > 0 && chars[i - 1].is_ascii_lowercase() && c.is_ascii_uppercase() {
            out.push('_');
            out.push(c.to_ascii_lowercase());
            while i + 1 < chars.len() && chars[i + 1].is_ascii_uppercase() {
                i += 1;
                out.push(chars[i].to_ascii_lowercase());
            }
        } else {
            out.push(c);
        }
        i += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_what_the_rule_gives() {
        for (old, new) in UPGRADED_NAMES {
            assert_eq!(camel_to_snake(old), *new, "{old}");
            assert_eq!(camel_to_snake(new), *new, "{new} must be left alone");
        }
        assert_eq!(camel_to_snake("HDRFilm"), "HDRFilm");
        assert_eq!(camel_to_snake("aBcD"), "a_bc_d");
    }
}
