//! pbrt-v4 media: a `homogeneous` medium that does not scatter (`sigma_s` 0) is ppm's
//! Beer-Lambert absorption, sigma_a * `scale`, on the sides `MediumInterface "inside"
//! "outside"` names (inside: opposite the surface's normal, ppm's interior); a scattering,
//! emitting or other medium, an unknown name, and a camera inside a medium are errors naming
//! the directive and its line.

use glam::Vec3;
use ppm_core::scene::SceneBuilder;
use ppm_scene::pbrt::parse_pbrt;
use std::path::Path;

/// A camera, a light, `media` (before WorldBegin's shapes), then `body`.
fn scene(media: &str, body: &str) -> String {
    format!(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0 3 3]\n{media}\n{body}"
    )
}

fn load(text: &str) -> Result<SceneBuilder, String> {
    parse_pbrt(text, Path::new("media.pbrt"))
        .map(|(b, _)| b)
        .map_err(|e| e.to_string())
}

const INK: &str = "MakeNamedMedium \"ink\" \"string type\" \"homogeneous\" \
                   \"rgb sigma_a\" [1 2 3] \"rgb sigma_s\" [0 0 0] \"float scale\" 0.5";

#[test]
fn an_absorbing_medium_bounds_the_shapes_under_its_interface() {
    let b = load(&scene(
        INK,
        "AttributeBegin\n  MediumInterface \"ink\" \"\"\n  Material \"dielectric\"\n  Shape \"sphere\"\nAttributeEnd\n\
         Shape \"sphere\" \"float radius\" 0.5\n\
         AttributeBegin\n  MediumInterface \"ink\"\n  Shape \"sphere\" \"float radius\" 0.25\nAttributeEnd",
    ))
    .unwrap();
    let medium = |i: usize| b.materials[b.spheres[i].material as usize].medium;
    // sigma_a * scale inside, nothing outside.
    assert_eq!(medium(0).interior, Vec3::new(0.5, 1.0, 1.5));
    assert_eq!(medium(0).exterior, Vec3::ZERO);
    // AttributeEnd restores the interface: the second sphere bounds no medium.
    assert!(medium(1).is_clear());
    // One name is both sides.
    assert_eq!(medium(2).interior, Vec3::new(0.5, 1.0, 1.5));
    assert_eq!(medium(2).exterior, Vec3::new(0.5, 1.0, 1.5));
}

#[test]
fn what_is_not_pure_absorption_is_an_error_naming_it() {
    let inside = |m: &str| scene(m, "MediumInterface \"m\" \"\"\nShape \"sphere\"");
    for (media, want) in [
        // pbrt's default sigma_s is 1: a medium must say it does not scatter.
        (
            "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1]",
            "media.pbrt:6:1: MakeNamedMedium \"m\": it scatters",
        ),
        (
            "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\"",
            "media.pbrt:6:1: MakeNamedMedium \"m\": medium type \"uniformgrid\" is not supported yet",
        ),
        (
            "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"string preset\" \"Wholemilk\"",
            "media.pbrt:6:1: MakeNamedMedium \"m\": a preset",
        ),
        (
            "MakeNamedMedium \"m\" \"string type\" \"homogeneous\" \"rgb sigma_s\" [0 0 0] \"rgb Le\" [1 1 1]",
            "media.pbrt:6:1: MakeNamedMedium \"m\": an emitting medium",
        ),
        (
            "MakeNamedMedium \"other\" \"string type\" \"homogeneous\"",
            "media.pbrt:7:1: MediumInterface: no medium \"m\"",
        ),
    ] {
        let e = load(&inside(media)).err().expect("an error");
        assert!(e.starts_with(want), "{media}:\n  got  {e}\n  want {want}");
    }
    // The camera inside a medium (the outside in force at Camera).
    let text = format!(
        "{INK}\nMediumInterface \"\" \"ink\"\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0 3 3]\n"
    );
    let e = load(&text).err().expect("an error");
    assert!(
        e.starts_with("media.pbrt:2:1: MediumInterface: the camera is in medium \"ink\""),
        "{e}"
    );
}
