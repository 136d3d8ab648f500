//! What every render starts from, made in one place for all integrators: the settings as
//! rendered ([`RenderSettings::normalised`]), the pixels, and the film (empty, or the saved
//! film a resumed render or a shard continues).

use super::{RenderSettings, Snapshot};
use crate::film::Film;
use crate::pixel_bounds::PixelBounds;
use crate::scene::Scene;
use crate::StateError;

/// The start of a render, handed to [`super::Integrator::start`].
pub struct RenderStart {
    /// Normalised: `max_depth` at most [`super::MAX_DEPTH`].
    pub settings: RenderSettings,
    /// The pixels rendered (the whole image unless cropped).
    pub bounds: PixelBounds,
    /// `bounds`' size; its next iteration is the render's first.
    pub film: Film,
}

impl RenderStart {
    /// A fresh render of the pixels in `bounds`.
    pub fn fresh(settings: &RenderSettings, bounds: PixelBounds) -> Self {
        RenderStart {
            settings: settings.normalised(),
            bounds,
            film: Film::new(bounds.width(), bounds.height()),
        }
    }

    /// A render of the whole image continuing from `snapshot`, for an integrator that carries
    /// nothing but its film between iterations (a snapshot with per-pixel state, or of
    /// another size, is refused).
    pub fn resumed(
        scene: &Scene,
        settings: &RenderSettings,
        snapshot: Snapshot,
    ) -> Result<Self, StateError> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        Ok(RenderStart {
            settings: settings.normalised(),
            bounds: PixelBounds::full(w, h),
            film: snapshot.into_film(w, h)?,
        })
    }
}
