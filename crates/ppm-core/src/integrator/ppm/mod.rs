//! Progressive photon mapping (TODO).
use super::{IterationStats, RenderSettings};
use crate::film::Film;
use crate::scene::Scene;
/// PPM state.
pub struct PpmRenderer { settings: RenderSettings, film: Film }
impl PpmRenderer {
    pub fn new(scene: &Scene, settings: RenderSettings) -> Self { let c = &scene.camera; PpmRenderer { settings, film: Film::new(c.width, c.height) } }
    pub fn iterate(&mut self, _scene: &Scene) -> IterationStats { let _ = &self.settings; todo!() }
    pub fn film(&self) -> &Film { &self.film }
    pub fn memory_bytes(&self) -> usize { 0 }
}
