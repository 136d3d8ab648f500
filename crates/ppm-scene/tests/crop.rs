//! Crop windows in scene files: scene format v1's `render.pixel_bounds`, a Mitsuba film's
//! `crop_offset_x`/`_y` and `crop_width`/`crop_height`, pbrt-v4's `Film` `pixelbounds` and
//! `cropwindow`. Each loads to the same pixels of the image (the renders of a window are
//! checked against Mitsuba's in `mitsuba_renders.rs`); a window that leaves the image is an
//! error naming the field and the image's size; `ppm convert` writes the window.

mod common;

use ppm_core::pixel_bounds::PixelBounds;
use ppm_scene::convert::convert_scene;
use ppm_scene::mitsuba::parse_mitsuba;
use ppm_scene::pbrt::parse_pbrt;
use ppm_scene::{content_hash, load_scene_builder, parse_scene};
use std::path::Path;

/// (x0, x1, y0, y1, full width) of a window.
fn edges(b: PixelBounds) -> (u32, u32, u32, u32, u32) {
    (b.x0, b.x1, b.y0, b.y1, b.full_width)
}

/// A 40 x 20 Mitsuba scene whose film has the properties `film`.
fn mitsuba(film: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="20"/>{film}</film></sensor>
<emitter type="point"><point name="position" x="0" y="3" z="3"/><rgb name="intensity" value="5"/></emitter>
</scene>"#
    )
}

/// A 40 x 20 pbrt-v4 scene whose `Film` has the parameters `film`.
fn pbrt(film: &str) -> String {
    format!(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nFilm \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20 {film}\nWorldBegin\nLightSource \"point\" \"point3 from\" [0 3 3]\n"
    )
}

/// A 40 x 20 YAML scene whose `render:` holds `render`.
fn yaml(render: &str) -> String {
    format!(
        "camera: {{ position: [0, 0, 5], look_at: [0, 0, 0], up: [0, 1, 0], fov: 40 }}\nresolution: [40, 20]\nlights:\n  - {{ type: point, position: [0, 3, 3], intensity: [5, 5, 5] }}\nrender:\n  {render}\n"
    )
}

#[test]
fn the_three_formats_give_the_same_window() {
    let m = mitsuba(
        r#"<integer name="crop_offset_x" value="8"/><integer name="crop_offset_y" value="3"/>
           <integer name="crop_width" value="12"/><integer name="crop_height" value="15"/>"#,
    );
    let (b, w) = parse_mitsuba(&m, Path::new("s.xml"), &[]).unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(edges(b.defaults.crop.unwrap()), (8, 20, 3, 18, 40));

    let (b, w) = parse_pbrt(
        &pbrt("\"integer pixelbounds\" [8 20 3 18]"),
        Path::new("s.pbrt"),
    )
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(edges(b.defaults.crop.unwrap()), (8, 20, 3, 18, 40));
    // Fractions round up to pixels: ceil(0.2 * 40) = 8, ceil(0.5 * 40) = 20,
    // ceil(0.11 * 20) = 3, ceil(0.9 * 20) = 18.
    let (b, _) = parse_pbrt(
        &pbrt("\"float cropwindow\" [0.2 0.5 0.11 0.9]"),
        Path::new("s.pbrt"),
    )
    .unwrap();
    assert_eq!(edges(b.defaults.crop.unwrap()), (8, 20, 3, 18, 40));

    let (b, w) = parse_scene(&yaml("pixel_bounds: [8, 20, 3, 18]"), Path::new("s.yml")).unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(edges(b.defaults.crop.unwrap()), (8, 20, 3, 18, 40));
}

#[test]
fn mitsubas_defaults_are_the_offset_zero_and_the_films_size() {
    // Only an offset: the crop keeps the film's width, which then no longer fits (Mitsuba
    // throws too).
    let e = parse_mitsuba(
        &mitsuba(r#"<integer name="crop_offset_x" value="4"/>"#),
        Path::new("s.xml"),
        &[],
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("film") && e.contains("40 x 20") && e.contains("offset 4, 0"),
        "{e}"
    );
    // Only a height: the offset is 0, the width the film's.
    let (b, _) = parse_mitsuba(
        &mitsuba(r#"<integer name="crop_height" value="5"/>"#),
        Path::new("s.xml"),
        &[],
    )
    .unwrap();
    assert_eq!(edges(b.defaults.crop.unwrap()), (0, 40, 0, 5, 40));
    // No crop property: the whole image, and no fingerprint change.
    let (b, _) = parse_mitsuba(&mitsuba(""), Path::new("s.xml"), &[]).unwrap();
    assert_eq!(b.defaults.crop, None);
}

#[test]
fn windows_outside_the_image_are_errors_naming_the_field() {
    for film in [
        r#"<integer name="crop_width" value="41"/>"#,
        r#"<integer name="crop_width" value="0"/>"#,
        r#"<integer name="crop_offset_y" value="-1"/><integer name="crop_height" value="2"/>"#,
    ] {
        let e = parse_mitsuba(&mitsuba(film), Path::new("s.xml"), &[])
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains("s.xml") && e.contains("film"), "{film}: {e}");
    }
    for (film, field) in [
        ("\"integer pixelbounds\" [0 41 0 20]", "pixelbounds"),
        ("\"integer pixelbounds\" [5 5 0 20]", "pixelbounds"),
        ("\"integer pixelbounds\" [0 1 0]", "pixelbounds"),
        ("\"float cropwindow\" [0 1.5 0 1]", "cropwindow"),
        ("\"float cropwindow\" [0.999 1 0 1]", "cropwindow"),
    ] {
        let e = parse_pbrt(&pbrt(film), Path::new("s.pbrt"))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("s.pbrt:4") && e.contains("Film") && e.contains(field),
            "{film}: {e}"
        );
    }
    for window in [
        "[0, 41, 0, 20]",
        "[3, 3, 0, 1]",
        "[0, 1, 0]",
        "[-1, 1, 0, 1]",
    ] {
        let e = parse_scene(
            &yaml(&format!("pixel_bounds: {window}")),
            Path::new("s.yml"),
        )
        .err()
        .unwrap()
        .to_string();
        assert!(e.contains("pixel_bounds"), "{window}: {e}");
    }
}

/// pbrt-v4 takes the `cropwindow` when both are given, with a warning.
#[test]
fn pbrts_cropwindow_wins_over_pixelbounds() {
    let (b, w) = parse_pbrt(
        &pbrt("\"integer pixelbounds\" [0 4 0 4] \"float cropwindow\" [0.5 1 0.5 1]"),
        Path::new("s.pbrt"),
    )
    .unwrap();
    assert_eq!(edges(b.defaults.crop.unwrap()), (20, 40, 10, 20, 40));
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("pixelbounds is not used"), "{}", w[0]);
}

/// `ppm convert` of a cropped Mitsuba film writes `render.pixel_bounds`, and the written
/// scene has the import's fingerprint (which counts the window).
#[test]
fn convert_writes_the_window() {
    let m = mitsuba(
        r#"<integer name="crop_offset_x" value="8"/><integer name="crop_offset_y" value="3"/>
           <integer name="crop_width" value="12"/><integer name="crop_height" value="15"/>"#,
    );
    let dir = common::write_files("crop_convert", &[("s.xml", &m)]);
    let out = dir.join("s.yml");
    convert_scene(&dir.join("s.xml"), &out, &[]).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("pixel_bounds: [8, 20, 3, 18]"), "{text}");
    let (direct, _) = load_scene_builder(&dir.join("s.xml")).unwrap();
    let (back, _) = load_scene_builder(&out).unwrap();
    assert_eq!(content_hash(&back), content_hash(&direct));
    let (uncropped, _) = parse_mitsuba(&mitsuba(""), Path::new("s.xml"), &[]).unwrap();
    assert_ne!(content_hash(&uncropped), content_hash(&direct));
}
