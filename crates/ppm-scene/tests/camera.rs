//! The camera of scene format v1 and of the Mitsuba importer: field of view along each axis
//! or from a focal length, the thin lens's aperture and focus (with their defaults), the same
//! camera from YAML and from a Mitsuba `thinlens`, and errors naming the field.

mod common;

use common::write_files;
use glam::Vec2;
use ppm_core::camera::Camera;
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::parse_scene;
use std::path::Path;

/// The camera of a YAML scene whose `camera:` mapping holds `camera` (position (0, 1, 4),
/// looking at (0, 1, 0), a 40 x 20 image).
fn yaml_camera(test: &str, camera: &str) -> Result<Camera, String> {
    let yaml = format!(
        "camera: {{ position: [0, 1, 4], look_at: [0, 1, 0], up: [0, 1, 0], {camera} }}\n\
         resolution: [40, 20]\n\
         materials: {{ white: {{ type: diffuse, color: [0.5, 0.5, 0.5] }} }}\n\
         objects: [{{ type: sphere, center: [0, 1, 0], radius: 1, material: white }}]\n\
         lights: [{{ type: point, position: [0, 3, 3], intensity: [1, 1, 1] }}]\n"
    );
    let dir = write_files(test, &[("scene.yml", &yaml)]);
    parse_scene(&yaml, &dir.join("scene.yml"))
        .map(|(b, _)| b.camera)
        .map_err(|e| e.to_string())
}

/// tan(vertical fov / 2) of a camera.
fn tan_half_vertical(c: &Camera) -> f64 {
    c.frame().3 as f64
}

#[test]
fn the_field_of_view_spans_the_axis_given() {
    // A 40 x 20 image (aspect 2) and fov 60: tan(30 degrees) along the axis.
    let t = 30f64.to_radians().tan();
    for (axis, expected) in [
        ("", t),
        (", fov_axis: y", t),
        (", fov_axis: x", t / 2.0),
        (", fov_axis: diagonal", t / 5f64.sqrt()),
    ] {
        let c = yaml_camera("camera_fov_axis", &format!("fov: 60{axis}")).unwrap();
        let got = tan_half_vertical(&c);
        assert!(
            (got - expected).abs() < 1e-6,
            "`{axis}`: {got} vs {expected}"
        );
    }
    // A bare fov is the vertical one exactly, as before fov_axis existed.
    let c = yaml_camera("camera_fov_bare", "fov: 38").unwrap();
    assert_eq!(c.frame().3, (38f32.to_radians() * 0.5).tan());
    // 50 mm on 36 x 24 mm film spans the film's diagonal, 43.27 mm at 50 mm.
    let c = yaml_camera("camera_focal", "focal_length: 50").unwrap();
    let expected = 36f64.hypot(24.0) / 100.0 / 5f64.sqrt();
    assert!((tan_half_vertical(&c) - expected).abs() < 1e-6);
}

#[test]
fn the_lens_defaults_to_a_pinhole_focused_on_look_at() {
    let c = yaml_camera("camera_pinhole", "fov: 40").unwrap();
    assert!(c.is_pinhole());
    let c = yaml_camera("camera_lens_default", "fov: 40, aperture_radius: 0.05").unwrap();
    assert_eq!((c.lens_radius(), c.focus_distance()), (0.05, 4.0));
    let c = yaml_camera(
        "camera_lens",
        "fov: 40, aperture_radius: 0.1, focus_distance: 2.5",
    )
    .unwrap();
    assert_eq!((c.lens_radius(), c.focus_distance()), (0.1, 2.5));
}

#[test]
fn camera_errors_name_the_field() {
    for (camera, expected) in [
        ("fov: 40, focal_length: 35", "camera.focal_length"),
        ("focal_length: 35, fov_axis: x", "camera.fov_axis"),
        ("up: [0, 1, 0]", "camera"),
        ("fov: 40, aperture_radius: -1", "aperture_radius"),
        ("fov: 40, focus_distance: 0", "focus_distance"),
        ("fov: 40, fov_axis: z", "fov_axis"),
    ] {
        let camera = camera.replace("up: [0, 1, 0]", "");
        let e = yaml_camera("camera_errors", &camera).unwrap_err();
        assert!(e.contains(expected), "{camera}: {e}");
    }
}

/// A Mitsuba scene with a `thinlens` sensor at (0, 1, 4) looking at (0, 1, 0) whose
/// properties are `props`.
fn mitsuba_camera(props: &str) -> Result<Camera, String> {
    let xml = format!(
        r#"<scene version="3.0.0">
<sensor type="thinlens">{props}<float name="fov" value="60"/><string name="fov_axis" value="y"/>
<transform name="to_world"><lookat origin="0,1,4" target="0,1,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/></film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/><rgb name="intensity" value="5"/></emitter>
</scene>"#
    );
    parse_mitsuba(&xml, Path::new("scene.xml"), &[])
        .map(|(b, _)| b.camera)
        .map_err(|e| e.to_string())
}

#[test]
fn a_mitsuba_thinlens_is_the_yaml_lens() {
    let xml = mitsuba_camera(
        r#"<float name="aperture_radius" value="0.2"/><float name="focus_distance" value="3"/>"#,
    )
    .unwrap();
    let yaml = yaml_camera(
        "camera_thinlens",
        "fov: 60, aperture_radius: 0.2, focus_distance: 3",
    )
    .unwrap();
    for (film, u) in [
        (Vec2::new(0.5, 0.5), Vec2::new(0.1, 0.9)),
        (Vec2::new(39.0, 3.0), Vec2::new(0.7, 0.2)),
        (Vec2::new(20.0, 10.0), Vec2::new(0.5, 0.5)),
    ] {
        let (a, b) = (
            xml.generate_lens_ray(film, u),
            yaml.generate_lens_ray(film, u),
        );
        assert!(a.origin.abs_diff_eq(b.origin, 1e-6), "{a:?} {b:?}");
        assert!(a.dir.abs_diff_eq(b.dir, 1e-6), "{a:?} {b:?}");
    }
    // Mitsuba's focus default is far_clip (10^4 unless given); the radius is required.
    let c = mitsuba_camera(r#"<float name="aperture_radius" value="0.2"/>"#).unwrap();
    assert_eq!(c.focus_distance(), 1e4);
    let c = mitsuba_camera(
        r#"<float name="aperture_radius" value="0.2"/><float name="far_clip" value="50"/>"#,
    )
    .unwrap();
    assert_eq!(c.focus_distance(), 50.0);
    let e = mitsuba_camera("").unwrap_err();
    assert!(
        e.contains("aperture_radius") && e.contains("scene.xml"),
        "{e}"
    );
    let e = mitsuba_camera(r#"<float name="aperture_radius" value="-1"/>"#).unwrap_err();
    assert!(e.contains("aperture radius"), "{e}");
}

/// Mitsuba 3's `perspective` reads `focus_distance` (its projective cameras share it) and a
/// pinhole has nothing to focus: files of the field write it (mitsuba-data's Cornell box), so
/// it loads, to the same pinhole as without it.
#[test]
fn a_mitsuba_perspective_takes_and_ignores_focus_distance() {
    let camera = |props: &str| {
        let xml = format!(
            r#"<scene version="3.0.0">
<sensor type="perspective">{props}<float name="fov" value="60"/>
<transform name="to_world"><lookat origin="0,1,4" target="0,1,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/></film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/><rgb name="intensity" value="5"/></emitter>
</scene>"#
        );
        parse_mitsuba(&xml, Path::new("scene.xml"), &[])
            .map(|(b, _)| b.camera)
            .unwrap()
    };
    let with = camera(r#"<float name="focus_distance" value="1000"/>"#);
    let without = camera("");
    assert_eq!(with.lens_radius(), 0.0);
    let film = Vec2::new(3.5, 17.5);
    let (a, b) = (
        with.generate_lens_ray(film, Vec2::new(0.3, 0.6)),
        without.generate_lens_ray(film, Vec2::new(0.3, 0.6)),
    );
    assert_eq!((a.origin, a.dir), (b.origin, b.dir));
}
