//! `ppm model.obj`: a scene is a YAML file, and an OBJ is refused in one line that shows the
//! three lines wrapping it in a scene, instead of a YAML type error quoting the OBJ.

use std::path::Path;

/// True for a path ending in `.obj` (any case).
pub fn is_obj(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// The error for an OBJ given where a scene is expected: what to write instead, with a
/// camera that frames the model ([`framing_camera`]).
pub fn refusal(path: &Path) -> String {
    let file = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string());
    let (position, look_at) = framing_camera(path);
    format!(
        "{} is a mesh, not a scene: a scene is a YAML file (docs/scene-format.md). Save these \
         three lines as scene.yml beside it (the camera frames the model from +z; its MTL \
         materials are used, and one of them needs an emission `Ke` to light it):\n\
         camera: {{ position: {}, look_at: {}, up: [0, 1, 0], fov: 40 }}\n\
         objects:\n  - {{ type: mesh, file: {file} }}",
        path.display(),
        list(position),
        list(look_at)
    )
}

/// A camera position and target that frame the OBJ's vertices (`v` lines) with a 40 degree
/// field of view: the target is the centre of their bounding box, the camera on its +z side
/// at 1.2 times the distance at which the box's bounding sphere fills the view. Without
/// readable vertices, the unit-scale default: from [0, 1, 4] toward [0, 1, 0].
pub fn framing_camera(path: &Path) -> ([f64; 3], [f64; 3]) {
    let default = ([0.0, 1.0, 4.0], [0.0, 1.0, 0.0]);
    use std::io::BufRead;
    let Ok(file) = std::fs::File::open(path) else {
        return default;
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    // Streamed: a model of gigabytes is read once, in constant memory.
    for line in std::io::BufReader::new(file).lines().map_while(Result::ok) {
        let Some(rest) = line.trim_start().strip_prefix("v ") else {
            continue;
        };
        let v: Vec<f64> = rest
            .split_whitespace()
            .take(3)
            .filter_map(|x| x.parse().ok())
            .collect();
        if v.len() == 3 && v.iter().all(|x| x.is_finite()) {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
    }
    if lo[0] > hi[0] {
        return default;
    }
    let center = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let radius = 0.5 * (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
    // A sphere of radius R fills a 40 degree view from R / sin(20 degrees); a flat or
    // one-point model still gets a camera off its plane.
    let distance = 1.2 * radius.max(1e-3 * center.iter().fold(1.0f64, |m, c| m.max(c.abs())))
        / 20f64.to_radians().sin();
    let position = [center[0], center[1], center[2] + distance];
    (position.map(round), center.map(round))
}

/// `x` to 4 significant digits, so the suggested line reads as a person would write it.
fn round(x: f64) -> f64 {
    format!("{x:.3e}").parse().unwrap_or(x)
}

/// `[x, y, z]` as YAML.
fn list(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
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
        assert!(
            yaml.starts_with("camera: { position: [0, 1, 4], look_at: [0, 1, 0]"),
            "a missing file gets the unit-scale camera: {yaml}"
        );
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

    /// A model 4000 units wide far from the origin is framed: the camera looks at its centre
    /// from outside its box, at a distance that scales with it; a model without vertices
    /// keeps the unit-scale camera.
    #[test]
    fn the_suggested_camera_frames_the_model() {
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("big.obj");
        std::fs::write(
            &obj,
            "# a quad\nv 1000 0 -500\nv 5000 0 -500\nv 5000 2000 -500\nv 1000 2000 -500\nvn 0 0 1\nf 1 2 3 4\n",
        )
        .unwrap();
        let (position, look_at) = framing_camera(&obj);
        assert_eq!(look_at, [3000.0, 1000.0, -500.0]);
        assert_eq!(&position[..2], &look_at[..2]);
        // Half the diagonal (2236) over sin 20 degrees (0.342), times 1.2.
        assert!(
            (position[2] - (-500.0 + 7846.0)).abs() < 5.0,
            "{position:?}"
        );
        let empty = dir.path().join("empty.obj");
        std::fs::write(&empty, "# nothing\n").unwrap();
        assert_eq!(framing_camera(&empty), ([0.0, 1.0, 4.0], [0.0, 1.0, 0.0]));
    }
}
