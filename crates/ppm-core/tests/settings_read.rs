//! Which settings each integrator reads: [`Algorithm::reads`] is what the command line warns
//! by (a flag with no effect) and what resuming compares, so it is checked against the
//! integrators themselves. Each setting is changed on its own: an integrator that reads it
//! must render a different image, one that does not must render the same image bit for bit.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{LightStrategy, Setting};
use ppm_core::prelude::*;
use test_scenes::{cornell, BoxContents};

fn render(scene: &Scene, settings: &RenderSettings) -> Image {
    let mut renderer = Renderer::new(scene, settings);
    // Three iterations: alpha first changes the radius of the second.
    for _ in 0..3 {
        renderer.iterate(scene);
    }
    renderer.image()
}

/// `settings` with `setting` set to a value other than its own.
fn changed(settings: &RenderSettings, setting: Setting) -> RenderSettings {
    let mut s = settings.clone();
    match setting {
        Setting::Photons => s.photons += s.photons / 2,
        Setting::Radius => {
            s.radius = match s.radius {
                Radius::Auto | Radius::Photons => Radius::World(0.08),
                Radius::World(r) => Radius::World(r * 1.5),
            }
        }
        Setting::Alpha => s.alpha = if s.alpha == 0.5 { 0.9 } else { 0.5 },
        Setting::Direct => {
            s.direct = match s.direct {
                DirectMode::Photons => DirectMode::Sampled,
                DirectMode::Sampled => DirectMode::Photons,
            }
        }
        Setting::LightStrategy => {
            s.light_strategy = match s.light_strategy {
                LightStrategy::Mis => LightStrategy::LightOnly,
                _ => LightStrategy::Mis,
            }
        }
    }
    s
}

#[test]
fn each_integrator_reads_the_settings_it_declares() {
    // Glass: caustics and a specular chain, so every setting has light to act on.
    let scene = cornell(16, BoxContents::Glass);
    for algorithm in Algorithm::ALL {
        let settings = RenderSettings {
            algorithm,
            seed: 5,
            photons: 2000,
            ..RenderSettings::new(&scene)
        };
        let base = render(&scene, &settings);
        assert!(
            base.mean().max_element() > 0.0,
            "{algorithm:?}: black image"
        );
        for setting in Setting::ALL {
            let other = render(&scene, &changed(&settings, setting));
            let same = (0..base.height)
                .all(|y| (0..base.width).all(|x| base.get(x, y) == other.get(x, y)));
            assert_eq!(
                same,
                !algorithm.reads(setting),
                "{algorithm:?} with another {setting:?}: {} image, but reads() says {}",
                if same { "the same" } else { "a different" },
                algorithm.reads(setting)
            );
        }
    }
}
