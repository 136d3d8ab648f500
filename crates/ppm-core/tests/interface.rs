//! Every registered integrator answers the interface the front end asks consistently: what
//! its `Features` promise is what its render state does, and its name parses back to it. A new
//! integrator added to `Algorithm::TABLE` gets these checks without a line here.

use ppm_test_support::test_scenes;

use ppm_core::integrator::{Aov, Snapshot};
use ppm_core::prelude::*;
use test_scenes::{cornell, BoxContents};

fn settings(scene: &Scene, algorithm: Algorithm) -> RenderSettings {
    RenderSettings {
        seed: 3,
        photons: 2000,
        max_depth: 6,
        ..RenderSettings::for_algorithm(scene, algorithm)
    }
}

#[test]
fn every_algorithm_is_named_and_parsed_by_its_table_line() {
    assert_eq!(Algorithm::ALL.len(), Algorithm::TABLE.len());
    for (algorithm, entry) in Algorithm::ALL.into_iter().zip(Algorithm::TABLE) {
        assert_eq!(entry.algorithm, algorithm);
        assert_eq!(algorithm.name().parse::<Algorithm>(), Ok(algorithm));
        for alias in entry.aliases {
            assert_eq!(alias.parse::<Algorithm>(), Ok(algorithm), "{alias}");
        }
        assert!(!entry.description.is_empty());
    }
    // The names saved renders and scene files hold stay what they were; new ones follow.
    assert_eq!(
        Algorithm::NAMES,
        ["pt", "ppm", "sppm", "vcm", "bpt", "bpm", "lt"]
    );
}

/// An integrator writes exactly the AOVs it declares, once an iteration is done; its snapshot
/// carries the per-pixel channels it declares; its counts follow the iterations.
#[test]
fn each_integrator_does_what_its_features_say() {
    let scene = cornell(12, BoxContents::Diffuse);
    for algorithm in Algorithm::ALL {
        let features = algorithm.features();
        let settings = settings(&scene, algorithm);
        let mut renderer = Renderer::new(&scene, &settings);
        assert_eq!(renderer.iterations(), 0);
        for _ in 0..2 {
            renderer.iterate(&scene);
        }
        assert_eq!(renderer.iterations(), 2, "{algorithm}");
        assert_eq!(renderer.first_iteration(), 0);
        for aov in [Aov::Radius, Aov::Photons] {
            let image = renderer.aov_image(aov, &scene);
            assert_eq!(
                image.is_some(),
                features.aovs.contains(&aov),
                "{algorithm} {aov:?}"
            );
            if let Some(image) = image {
                assert_eq!((image.width, image.height), (12, 12));
                assert!(image
                    .pixels
                    .iter()
                    .all(|p| p.is_finite() && p.min_element() >= 0.0));
                assert!(image.mean().max_element() > 0.0, "{algorithm} {aov:?}");
            }
        }
        assert_eq!(
            features.aovs.is_empty(),
            !features.aov_refusal.is_empty(),
            "{algorithm}: an integrator without AOVs says why"
        );
        let snapshot = renderer.snapshot();
        assert_eq!(
            snapshot.pixels.len(),
            features.snapshot_channels,
            "{algorithm}"
        );
        let words = algorithm.settings_words(&settings, 0..2);
        assert!(words.starts_with("seed 3, "), "{algorithm}: {words}");
        assert!(
            Renderer::memory_estimate(&scene, &settings).total() > 0,
            "{algorithm}"
        );
    }
}

/// An integrator that shards starts at a later iteration; one that does not refuses to.
/// Every one resumes from its own snapshot to the image of one uninterrupted render.
#[test]
fn sharding_and_resuming_are_as_declared() {
    let scene = cornell(8, BoxContents::Diffuse);
    for algorithm in Algorithm::ALL {
        let settings = settings(&scene, algorithm);
        let shard = Renderer::from_snapshot(&scene, &settings, Snapshot::starting_at(8, 8, 3));
        match algorithm.features().shard_refusal {
            None => assert_eq!(shard.unwrap().first_iteration(), 3, "{algorithm}"),
            Some(_) => assert!(shard.is_err(), "{algorithm} cannot start at iteration 3"),
        }
        let mut straight = Renderer::new(&scene, &settings);
        let mut first = Renderer::new(&scene, &settings);
        for _ in 0..2 {
            straight.iterate(&scene);
        }
        first.iterate(&scene);
        let mut resumed = Renderer::from_snapshot(&scene, &settings, first.snapshot()).unwrap();
        resumed.iterate(&scene);
        assert_eq!(
            resumed.image().pixels,
            straight.image().pixels,
            "{algorithm}"
        );
    }
}
