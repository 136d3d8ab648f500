//! Crop windows: a render of a window of the image gives exactly the full render's pixels in
//! that window, for every integrator (random streams are keyed by the full image's pixel index).

use ppm_test_support::test_scenes;

use ppm_core::pixel_bounds::PixelBounds;
use ppm_core::prelude::*;
use test_scenes::{cornell, BoxContents};

fn render(scene: &Scene, settings: &RenderSettings, bounds: PixelBounds) -> Image {
    let mut renderer = Renderer::with_bounds(settings, bounds);
    for _ in 0..3 {
        renderer.iterate(scene);
    }
    renderer.image()
}

#[test]
fn crop_window_pixels_equal_the_full_renders() {
    let scene = cornell(24, BoxContents::Glass);
    let (w, h) = (scene.camera.width, scene.camera.height);
    // Odd sizes and offsets, and a window wider than the path tracer's tile rows are long.
    let crop = PixelBounds {
        x0: 5,
        x1: 18,
        y0: 3,
        y1: 14,
        full_width: w,
    };
    for algorithm in Algorithm::ALL {
        let settings = RenderSettings {
            algorithm,
            seed: 11,
            photons: 2000,
            ..RenderSettings::new(&scene)
        };
        let full = render(&scene, &settings, PixelBounds::full(w, h));
        let part = render(&scene, &settings, crop);
        assert_eq!((part.width, part.height), (13, 11));
        assert!(part.mean().max_element() > 0.0, "{algorithm:?}: black crop");
        for y in 0..part.height {
            for x in 0..part.width {
                assert_eq!(
                    part.get(x, y),
                    full.get(x + crop.x0, y + crop.y0),
                    "{algorithm:?}: pixel ({x}, {y}) of the crop"
                );
            }
        }
    }
}
