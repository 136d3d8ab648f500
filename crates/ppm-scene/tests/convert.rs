//! `ppm convert` (`ppm_scene::convert`): a scene written back as scene format v1 loads to
//! the same scene content fingerprint as the scene it was converted from, for every Mitsuba
//! and pbrt-v4 scene of the test data and the shipped YAML scenes, and for small scenes
//! built here that use what the importers produce (rough conductors and dielectrics,
//! plastics, twosided, textures, absorbing media, thin lens, point, spot, directional and
//! environment lights); converting a converted file gives the same text; a feature ppm
//! cannot render is still an error naming it.

mod common;

use ppm_scene::convert::convert_scene;
use ppm_scene::{content_hash, load_scene_builder, LoadError};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// Every file under `dir` with one of `extensions`.
fn files(dir: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files(&p, extensions, out);
        } else if p
            .extension()
            .is_some_and(|e| extensions.contains(&e.to_str().unwrap()))
        {
            out.push(p);
        }
    }
}

/// Converts `scene` into `out_dir/converted.yml`, loads that, and checks the fingerprints
/// agree; returns the written text. A scene with instances is written as their copies, with
/// one note saying so: it must then equal the imported scene with its instances copied.
fn round_trip(scene: &Path, out_dir: &Path) -> String {
    let (mut direct, _) =
        load_scene_builder(scene).unwrap_or_else(|e| panic!("{}: {e}", scene.display()));
    let out = out_dir.join("converted.yml");
    let conversion =
        convert_scene(scene, &out, &[]).unwrap_or_else(|e| panic!("{}: {e}", scene.display()));
    let expected_notes = if direct.instances.is_empty() {
        0
    } else {
        direct.flatten_instances().unwrap();
        direct.instanced_meshes.clear();
        assert!(
            conversion
                .notes
                .iter()
                .any(|n| n.contains("written as copies")),
            "{}: {:?}",
            scene.display(),
            conversion.notes
        );
        1
    };
    assert!(
        conversion.notes.len() == expected_notes,
        "{}: {:?}",
        scene.display(),
        conversion.notes
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let (back, _) =
        load_scene_builder(&out).unwrap_or_else(|e| panic!("{}: {e}\n{text}", scene.display()));
    assert_eq!(
        content_hash(&back),
        content_hash(&direct),
        "{}: the converted scene differs:\n{text}",
        scene.display()
    );
    text
}

/// Every Mitsuba and pbrt scene of the test data, and the shipped YAML scenes.
#[test]
fn converted_test_scenes_keep_their_fingerprint() {
    let mut scenes = Vec::new();
    files(&data(), &["xml", "pbrt", "yml"], &mut scenes);
    files(&common::scenes_dir(), &["yml"], &mut scenes);
    let mut converted = 0;
    for (i, scene) in scenes.iter().enumerate() {
        let dir = common::scratch(&format!("convert_data_{i}"));
        // Fragments (a lamp or a stage another scene includes) are not scenes on their own:
        // converting one fails as loading it does.
        if let Err(e) = load_scene_builder(scene) {
            let c = convert_scene(scene, &dir.join("converted.yml"), &[]).err();
            assert_eq!(c.map(|c| c.to_string()), Some(e.to_string()));
            continue;
        }
        round_trip(scene, &dir);
        converted += 1;
    }
    assert!(converted >= 10, "{converted} of {scenes:?}");
}

/// Writes `text` as `name` in a scratch folder (with a tiny PNG texture beside it) and
/// round-trips it.
fn round_trip_text(test: &str, name: &str, text: &str) -> String {
    let dir = common::write_files(test, &[(name, text)]);
    std::fs::copy(data().join("textures/grid.png"), dir.join("grid.png")).unwrap();
    std::fs::copy(data().join("mitsuba/envmap/sky.exr"), dir.join("sky.exr")).unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    round_trip(&dir.join(name), &out)
}

const MITSUBA: &str = r#"<scene version="3.0.0">
    <default name="spp" value="4"/>
    <integrator type="path"><integer name="max_depth" value="7"/></integrator>
    <sensor type="thinlens">
        <float name="aperture_radius" value="0.05"/>
        <float name="focus_distance" value="3.1"/>
        <float name="fov" value="35"/>
        <string name="fov_axis" value="x"/>
        <transform name="to_world"><lookat origin="0.3, 1, 3.9" target="0, 0.9, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/></film>
    </sensor>
    <bsdf type="roughconductor" id="gold">
        <string name="material" value="Au"/>
        <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/>
    </bsdf>
    <bsdf type="roughdielectric" id="frosted">
        <string name="distribution" value="beckmann"/>
        <float name="alpha" value="0.2"/>
        <float name="int_ior" value="1.33"/>
    </bsdf>
    <bsdf type="dielectric" id="tinted"/>
    <bsdf type="twosided" id="shell"><bsdf type="roughplastic">
        <rgb name="diffuse_reflectance" value="0.2, 0.5, 0.3"/><float name="alpha" value="0.15"/>
    </bsdf></bsdf>
    <bsdf type="diffuse" id="floor">
        <texture type="bitmap" name="reflectance">
            <string name="filename" value="grid.png"/>
            <string name="filter_type" value="nearest"/>
            <transform name="to_uv"><rotate z="1" angle="30"/><scale x="2" y="3"/></transform>
        </texture>
    </bsdf>
    <bsdf type="plastic" id="checks">
        <texture type="checkerboard" name="diffuse_reflectance">
            <rgb name="color0" value="0.1, 0.2, 0.3"/><rgb name="color1" value="0.6, 0.5, 0.4"/>
        </texture>
    </bsdf>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <ref id="floor"/>
    </shape>
    <shape type="sphere"><point name="center" x="-0.8" y="0.5" z="0"/><float name="radius" value="0.5"/><ref id="gold"/></shape>
    <shape type="sphere"><point name="center" x="0.8" y="0.5" z="0"/><float name="radius" value="0.4"/><ref id="frosted"/></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.2"/><translate x="0" y="1.5" z="-0.5"/></transform><ref id="tinted"/>
        <medium type="homogeneous" name="interior">
            <rgb name="albedo" value="0, 0, 0"/><rgb name="sigma_t" value="0.5, 0.25, 0.125"/><float name="scale" value="2"/>
        </medium></shape>
    <shape type="cylinder"><float name="radius" value="0.1"/><transform name="to_world"><translate x="1" y="0" z="-1"/></transform><ref id="shell"/></shape>
    <shape type="disk"><transform name="to_world"><translate x="-1" y="0.01" z="-1"/><rotate x="1" angle="-90"/></transform><ref id="checks"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.3"/><rotate x="1" angle="90"/><translate y="2.5"/></transform>
        <emitter type="area"><rgb name="radiance" value="10, 9, 8"/></emitter>
    </shape>
    <emitter type="spot">
        <transform name="to_world"><lookat origin="2, 3, 2" target="0, 0, 0"/></transform>
        <rgb name="intensity" value="20, 20, 20"/>
        <float name="cutoff_angle" value="25"/><float name="beam_width" value="17"/>
    </emitter>
    <emitter type="point"><point name="position" x="-1" y="2" z="1"/><rgb name="intensity" value="3, 3, 3"/></emitter>
    <emitter type="directional"><vector name="direction" x="0.3" y="-1" z="0.2"/><rgb name="irradiance" value="0.5, 0.5, 0.5"/></emitter>
    <emitter type="envmap">
        <string name="filename" value="sky.exr"/><float name="scale" value="0.7"/>
        <transform name="to_world"><rotate y="1" angle="70"/><rotate x="1" angle="10"/></transform>
    </emitter>
</scene>"#;

/// A Mitsuba scene with most of what the importer maps.
#[test]
fn a_mitsuba_scene_with_every_kind_of_part_converts_exactly() {
    let text = round_trip_text("convert_mitsuba", "scene.xml", MITSUBA);
    // Names come from the XML ids; the lens and the roughness are written as such.
    for expected in [
        "\"gold\":",
        "type: roughconductor",
        "alpha_u: 0.05",
        "distribution: beckmann",
        "aperture_radius: 0.05",
        "type: spot",
        "to_world:",
        "to_uv:",
        "texture: checkerboard",
        "absorption: [1.0, 0.5, 0.25]",
        "type: twosided",
    ] {
        assert!(text.contains(expected), "no `{expected}` in\n{text}");
    }
}

const PBRT: &str = r#"Film "rgb" "integer xresolution" 40 "integer yresolution" 30
Scale -1 1 1
LookAt 0 1 4  0 0.8 0  0 1 0
Camera "perspective" "float fov" 38 "float lensradius" 0.04 "float focaldistance" 3.5
Sampler "halton" "integer pixelsamples" 8
Integrator "volpath" "integer maxdepth" 5
WorldBegin
LightSource "spot" "point3 from" [1 3 1] "point3 to" [0 0 0] "float coneangle" 30 "float conedeltaangle" 5 "rgb I" [9 9 9]
LightSource "distant" "point3 from" [0 1 0] "point3 to" [0.2 0 0.1] "rgb L" [0.4 0.4 0.4]
Texture "grid" "spectrum" "imagemap" "string filename" "grid.png" "float uscale" 4 "float vscale" 2
Texture "checks" "spectrum" "checkerboard" "rgb tex1" [0.1 0.1 0.1] "rgb tex2" [0.7 0.7 0.7]
MakeNamedMaterial "floor" "string type" "diffuse" "texture reflectance" "grid"
MakeNamedMaterial "metal" "string type" "conductor" "spectrum eta" "metal-Cu-eta" "spectrum k" "metal-Cu-k" "float roughness" 0.2
MakeNamedMaterial "glass" "string type" "dielectric" "float eta" 1.5
MakeNamedMaterial "board" "string type" "diffuse" "texture reflectance" "checks"
NamedMaterial "floor"
Shape "trianglemesh" "point3 P" [-2 0 -2  2 0 -2  -2 0 2  2 0 2] "point2 uv" [0 0 1 0 0 1 1 1] "integer indices" [0 2 1  1 2 3]
NamedMaterial "metal"
Shape "sphere" "float radius" 0.5
NamedMaterial "glass"
AttributeBegin
  Translate 1 0.5 0
  Shape "sphere" "float radius" 0.4
AttributeEnd
NamedMaterial "board"
Shape "trianglemesh" "point3 P" [-2 0 -1.9  2 0 -1.9  0 2 -1.9] "point2 uv" [0 0 1 0 0.5 1] "integer indices" [0 1 2]
AttributeBegin
  Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
  AreaLightSource "diffuse" "rgb L" [8 8 8]
  Translate 0 2.5 0
  Rotate 90 1 0 0
  Shape "disk" "float radius" 0.3
AttributeEnd
"#;

/// A pbrt-v4 scene with most of what the importer maps.
#[test]
fn a_pbrt_scene_with_every_kind_of_part_converts_exactly() {
    let text = round_trip_text("convert_pbrt", "scene.pbrt", PBRT);
    for expected in [
        "\"metal\":",
        "\"glass\":",
        "type: spot",
        "type: directional",
    ] {
        assert!(text.contains(expected), "no `{expected}` in\n{text}");
    }
}

/// Converting a converted file again writes the same text (and the same files).
#[test]
fn converting_a_converted_scene_gives_the_same_text() {
    let first = round_trip_text("convert_idempotent", "scene.xml", MITSUBA);
    let dir = common::scratch("convert_idempotent_again");
    let converted = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ppm-scene-tests/convert_idempotent/out/converted.yml");
    let second = round_trip(&converted, &dir);
    assert_eq!(first, second);
    let mesh = |root: &Path| std::fs::read(root.join("converted_files/mesh0.ply")).unwrap();
    assert_eq!(mesh(converted.parent().unwrap()), mesh(&dir));
}

/// An unsupported feature in the input is still an error naming it, and nothing is written.
#[test]
fn an_unsupported_feature_is_still_an_error() {
    let dir = common::write_files(
        "convert_unsupported",
        &[(
            "scene.xml",
            r#"<scene version="3.0.0"><sensor type="perspective"/><bsdf type="hair" id="h"/><shape type="sphere"><ref id="h"/></shape></scene>"#,
        )],
    );
    let out = dir.join("out.yml");
    let e: LoadError = convert_scene(&dir.join("scene.xml"), &out, &[])
        .err()
        .unwrap();
    assert!(e.to_string().contains("hair"), "{e}");
    assert!(!out.exists());
}
