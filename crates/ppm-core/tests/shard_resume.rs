//! Renders cut into slices of iterations and joined (shards and merge), or stopped and
//! continued (resume), must give the image of one uninterrupted render bit for bit, at any
//! thread count, for every integrator.

use ppm_test_support::test_scenes;

use ppm_core::film::Film;
use ppm_core::integrator::{PixelChannel, Radius, Snapshot};
use ppm_core::prelude::*;
use ppm_core::StateError;
use test_scenes::{cornell, BoxContents};

const ALGORITHMS: [Algorithm; 3] = [Algorithm::Path, Algorithm::Ppm, Algorithm::Vcm];

fn settings(scene: &Scene, algorithm: Algorithm) -> RenderSettings {
    RenderSettings {
        algorithm,
        seed: 11,
        photons: 3000,
        max_depth: 8,
        ..RenderSettings::new(scene)
    }
}

/// Renders iterations `first..end` from an empty slice on `threads` threads.
fn render_slice(
    scene: &Scene,
    settings: &RenderSettings,
    first: u64,
    end: u64,
    threads: usize,
) -> Snapshot {
    let (w, h) = (scene.camera.width, scene.camera.height);
    continue_render(
        scene,
        settings,
        Snapshot::starting_at(w, h, first),
        end - first,
        threads,
    )
}

/// Continues `snapshot` for `iterations` more on `threads` threads.
fn continue_render(
    scene: &Scene,
    settings: &RenderSettings,
    snapshot: Snapshot,
    iterations: u64,
    threads: usize,
) -> Snapshot {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut renderer = Renderer::from_snapshot(scene, settings, snapshot).unwrap();
        for _ in 0..iterations {
            renderer.iterate(scene);
        }
        renderer.snapshot()
    })
}

/// The image's pixels as bits, so that a difference in the last bit fails.
fn bits(film: &Film) -> Vec<[u32; 3]> {
    film.image()
        .pixels
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn shards_merged_equal_the_single_render_at_1_and_2_threads() {
    // The glass sphere gives caustic photons: the photon pass matters to the image.
    let scene = cornell(20, BoxContents::Glass);
    for algorithm in ALGORITHMS {
        let settings = settings(&scene, algorithm);
        let single = render_slice(&scene, &settings, 0, 7, 1);
        assert_eq!(single.film.iterations(), 7);
        for (shard_threads, slices) in
            [(1, [(0, 3), (3, 5), (5, 7)]), (2, [(0, 2), (2, 6), (6, 7)])]
        {
            let parts: Vec<Snapshot> = slices
                .iter()
                .map(|&(a, b)| render_slice(&scene, &settings, a, b, shard_threads))
                .collect();
            let mut merged = parts[0].clone();
            for p in &parts[1..] {
                merged.append(p).unwrap();
            }
            assert_eq!(
                bits(&merged.film),
                bits(&single.film),
                "{algorithm:?}, shards on {shard_threads} threads: {slices:?}"
            );
            assert_eq!(
                merged, single,
                "{algorithm:?}: the whole state, not just the image"
            );
        }
    }
}

#[test]
fn resumed_render_equals_the_uninterrupted_one_at_1_and_2_threads() {
    let scene = cornell(20, BoxContents::Glass);
    for algorithm in ALGORITHMS {
        let settings = settings(&scene, algorithm);
        let uninterrupted = render_slice(&scene, &settings, 0, 6, 2);
        for (threads_before, threads_after) in [(1, 2), (2, 1)] {
            let stopped = render_slice(&scene, &settings, 0, 4, threads_before);
            let resumed = continue_render(&scene, &settings, stopped, 2, threads_after);
            assert_eq!(
                bits(&resumed.film),
                bits(&uninterrupted.film),
                "{algorithm:?}: 4 iterations on {threads_before} threads, 2 more on {threads_after}"
            );
            assert_eq!(resumed, uninterrupted);
        }
    }
}

/// A slice started late uses the radius the uninterrupted render had reached there: the
/// image of a slice alone equals the difference of two uninterrupted films, which holds only
/// if photons, eye paths and radius of iteration i depend on i alone.
#[test]
fn a_late_slice_alone_is_the_tail_of_the_uninterrupted_render() {
    let scene = cornell(16, BoxContents::Diffuse);
    let settings = settings(&scene, Algorithm::Ppm);
    let head = render_slice(&scene, &settings, 0, 5, 1);
    let tail = render_slice(&scene, &settings, 5, 8, 1);
    let whole = render_slice(&scene, &settings, 0, 8, 1);
    let mut joined = head.clone();
    joined.append(&tail).unwrap();
    assert_eq!(joined, whole);
    // Joining in the wrong order is refused, naming both ranges.
    let mut wrong = tail.clone();
    let err = wrong.append(&head).unwrap_err().to_string();
    assert!(err.contains("0..5") && err.contains("5..8"), "{err}");
}

#[test]
fn snapshots_that_do_not_fit_are_refused() {
    let scene = cornell(8, BoxContents::Diffuse);
    for algorithm in ALGORITHMS {
        let settings = settings(&scene, algorithm);
        let wrong_size = Snapshot::starting_at(9, 8, 0);
        assert!(matches!(
            Renderer::from_snapshot(&scene, &settings, wrong_size),
            Err(StateError::Size { .. })
        ));
        let mut foreign = Snapshot::starting_at(8, 8, 0);
        foreign.pixels.push(PixelChannel {
            name: "radius2".into(),
            values: vec![0; 64],
        });
        let err = Renderer::from_snapshot(&scene, &settings, foreign.clone())
            .err()
            .expect("a per-pixel channel pt and ppm do not have is refused")
            .to_string();
        assert!(err.contains("radius2"), "{err}");
        // Per-pixel state cannot be merged.
        let mut a = Snapshot::starting_at(8, 8, 0);
        assert!(matches!(
            a.append(&foreign),
            Err(StateError::Unsupported(_))
        ));
    }
}

/// SPPM carries per-pixel statistics (R², N, tau) from one iteration to the next: a saved
/// state resumes to the uninterrupted render's image bit for bit at any thread count, and
/// both the auto and a world radius survive the round trip.
#[test]
fn sppm_resumes_bit_for_bit_from_its_statistics_at_1_and_2_threads() {
    let scene = cornell(20, BoxContents::Glass);
    for radius in [Radius::Auto, Radius::World(0.05)] {
        let settings = RenderSettings {
            radius,
            ..settings(&scene, Algorithm::Sppm)
        };
        let run = |snapshot: Snapshot, iterations: u64, threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut renderer = Renderer::from_snapshot(&scene, &settings, snapshot).unwrap();
                for _ in 0..iterations {
                    renderer.iterate(&scene);
                }
                let image: Vec<[u32; 3]> = renderer
                    .image()
                    .pixels
                    .iter()
                    .map(|p| p.to_array().map(f32::to_bits))
                    .collect();
                (image, renderer.snapshot())
            })
        };
        let fresh = || Snapshot::starting_at(20, 20, 0);
        let (whole_image, whole_state) = run(fresh(), 6, 2);
        assert!(whole_state.pixels.len() == 10, "sppm saves its statistics");
        for (before, after) in [(1, 2), (2, 1)] {
            let (_, stopped) = run(fresh(), 4, before);
            let (image, state) = run(stopped, 2, after);
            assert!(
                image == whole_image,
                "{radius:?}: 4 iterations on {before} threads, 2 more on {after}"
            );
            assert_eq!(state, whole_state);
        }
    }
}

/// SPPM's iteration k depends on every iteration before it: no shard starts later than 0,
/// and its states are never merged.
#[test]
fn sppm_refuses_shards_and_merges() {
    let scene = cornell(8, BoxContents::Diffuse);
    let settings = settings(&scene, Algorithm::Sppm);
    let late = Snapshot::starting_at(8, 8, 3);
    let err = Renderer::from_snapshot(&scene, &settings, late)
        .err()
        .expect("a late sppm slice is refused")
        .to_string();
    assert!(err.contains("shard"), "{err}");
    let mut renderer = Renderer::new(&scene, &settings);
    renderer.iterate(&scene);
    let mut first = renderer.snapshot();
    renderer.iterate(&scene);
    let second = renderer.snapshot();
    assert!(matches!(
        first.append(&second),
        Err(StateError::Unsupported(_))
    ));
}
