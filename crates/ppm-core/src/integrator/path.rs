//! Path tracer (TODO).
use super::{IterationStats, RenderSettings};
use crate::film::Film;
use crate::scene::Scene;
/// Path tracer state.
pub struct PathTracer { settings: RenderSettings, film: Film }
impl PathTracer {
    pub fn new(scene: &Scene, settings: RenderSettings) -> Self { let c = &scene.camera; PathTracer { settings, film: Film::new(c.width, c.height) } }
    pub fn iterate(&mut self, _scene: &Scene) -> IterationStats { let _ = &self.settings; todo!() }
    pub fn film(&self) -> &Film { &self.film }
    pub fn memory_bytes(&self) -> usize { 0 }
}
