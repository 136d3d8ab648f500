//! `ppm model.obj`: a scene is a YAML file, and an OBJ is refused in one line that shows the
//! three lines wrapping it in a scene, instead of a YAML type error quoting the OBJ.

use std::path::Path;

/// True for a path ending in `.obj` (any case).
pub fn is_obj(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// The error for an OBJ given where a scene is expected: what to write instead.
pub fn refusal(path: &Path) -> String {
    let file = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    format!(
        "{} is a mesh, not a scene: a scene is a YAML file (docs/scene-format.md). Save these \
         three lines as scene.yml beside it (place the camera to frame the model; its MTL \
         materials are used, and one of them needs an emission `Ke` to light it):\n\
         camera: {{ position: [0, 1, 4], look_at: [0, 1, 0], up: [0, 1, 0], fov: 40 }}\n\
         objects:\n  - {{ type: mesh, file: {file} }}",
        path.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_refusal_is_a_loadable_scene() {
        assert!(is_obj(Path::new("a/Model.OBJ")) && !is_obj(Path::new("a.yml")));
        let msg = refusal(Path::new("models/bunny.obj"));
        let yaml: String = msg.lines().skip(1).collect::<Vec<_>>().join("\n");
        assert_eq!(yaml.lines().count(), 3, "{msg}");
        // The three lines parse as a scene (the mesh itself is missing here).
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("bunny.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        )
        .unwrap();
        let scene = dir.path().join("scene.yml");
        std::fs::write(&scene, &yaml).unwrap();
        ppm_scene::load_scene(&scene).unwrap_or_else(|e| panic!("{e}\n{yaml}"));
    }
}
