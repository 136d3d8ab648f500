//! # ppm-core
//!
//! The rendering core of **ppm**, a progressive photon mapping renderer: geometry and a BVH,
//! a pinhole camera, sampling, a closed set of BSDFs, area and point lights, the photon hash
//! grid, and two integrators (a path tracer and progressive photon mapping).
//!
//! It knows no file formats: a [`Scene`] is built in code (or by the `ppm-scene` crate from
//! YAML/OBJ) and rendered into an [`film::Image`] of linear RGB.
//!
//! ```
//! use ppm_core::prelude::*;
//!
//! // A camera inside a closed, inward-facing sphere that emits 1 and reflects 80%.
//! let mut builder = SceneBuilder::new(
//!     Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 60.0, (8, 8)).unwrap(),
//! );
//! let furnace = builder.add_material(Material::new(
//!     Bsdf::diffuse(Vec3::splat(0.8)),
//!     Vec3::ONE,
//! ));
//! builder.add_sphere(Sphere::new(Vec3::ZERO, -1.0, furnace)); // negative radius: normal points in
//! let scene = builder.build().unwrap();
//!
//! let settings = RenderSettings { algorithm: Algorithm::Path, ..RenderSettings::new(&scene) };
//! let mut renderer = Renderer::new(&scene, &settings);
//! for _ in 0..4 {
//!     renderer.iterate(&scene);
//! }
//! let image = renderer.image();
//! assert_eq!(image.width, 8);
//! ```

pub mod bsdf;
pub mod camera;
pub mod error;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod material;
pub mod medium;
pub mod metrics;
pub mod photon;
pub mod pixel_bounds;
pub mod sampling;
pub mod scene;
mod simd;
pub mod texture;

pub use error::{SceneError, StateError};
pub use glam::{Vec2, Vec3};

/// The types most programs need, in one import.
pub mod prelude {
    pub use crate::bsdf::{Bsdf, TransportMode};
    pub use crate::camera::Camera;
    pub use crate::film::Image;
    pub use crate::geometry::{Sphere, TriangleMesh};
    pub use crate::integrator::{Algorithm, DirectMode, Radius, RenderSettings, Renderer};
    pub use crate::light::PointLight;
    pub use crate::material::Material;
    pub use crate::scene::{Scene, SceneBuilder};
    pub use crate::SceneError;
    pub use glam::{Vec2, Vec3};
}
