//! The camera of a render as the standard OpenEXR attributes `worldToCamera` and
//! `worldToNDC` (type m44f), with pbrt-v4's conventions, so that compositing tools and pbrt's
//! own utilities can project world points into the image.
//!
//! pbrt-v4 (`ProjectiveCamera::InitMetadata`, `Image::Write` for EXR) writes
//! - `worldToCamera` = cameraFromWorld: camera space has +x toward the image's right, +y up
//!   and +z along the view direction (pbrt's left-handed camera space; in ppm's right-handed
//!   world this is the frame (right, up, forward) of [`Camera::frame`]), origin at the
//!   camera's position;
//! - `worldToNDC` = T(1/2, 1/2, 1/2) S(1/2, 1/2, 1/2) screenFromCamera cameraFromWorld, with
//!   screenFromCamera = S(1/tan(fov/2), 1/tan(fov/2), 1) Perspective(near 0.01, far 1000),
//!   where Perspective maps (x, y, z, 1) to (x, y, f (z - n) / (f - n), z) and `fov` spans
//!   the shorter image axis (pbrt's `fov` parameter). A point's NDC is the homogeneous
//!   result divided by its w (the camera-space depth z); on the shorter axis the image spans
//!   NDC [0, 1] (0 at the left or bottom), on the longer one [1/2 - a/2, 1/2 + a/2] for the
//!   aspect ratio a >= 1, as pbrt writes it.
//!
//! Both matrices are stored as pbrt stores them: m[i][j] of the matrix that multiplies column
//! vectors (p' = M p, translation in the last column), row by row (16 f32 in the order
//! m[0][0], m[0][1], ...).

use glam::{DMat4, DVec3, DVec4};
use ppm_core::camera::Camera;

/// pbrt-v4's near and far planes of the perspective projection behind `worldToNDC`.
const NEAR: f64 = 1e-2;
const FAR: f64 = 1000.0;

/// `worldToCamera` and `worldToNDC`, row-major (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraMatrices {
    pub world_to_camera: [f32; 16],
    pub world_to_ndc: [f32; 16],
}

impl CameraMatrices {
    /// The matrices of `camera` placed at `position` in the world (a loaded scene keeps its
    /// camera at the origin and the world position in `Scene::origin`).
    pub fn new(camera: &Camera, position: DVec3) -> Self {
        let (right, up, forward, tan_half_fov) = camera.frame();
        let (right, up, forward) = (right.as_dvec3(), up.as_dvec3(), forward.as_dvec3());
        // cameraFromWorld: rows are the camera axes, then the translation to the eye.
        let camera_from_world = DMat4::from_cols(
            DVec4::new(right.x, up.x, forward.x, 0.0),
            DVec4::new(right.y, up.y, forward.y, 0.0),
            DVec4::new(right.z, up.z, forward.z, 0.0),
            DVec4::new(
                -right.dot(position),
                -up.dot(position),
                -forward.dot(position),
                1.0,
            ),
        );
        // tan of half the field of view across the shorter image axis.
        let aspect = camera.width as f64 / camera.height as f64;
        let tan_vertical = tan_half_fov as f64;
        let tan_short = if aspect >= 1.0 {
            tan_vertical
        } else {
            tan_vertical * aspect
        };
        let perspective = DMat4::from_cols(
            DVec4::new(1.0, 0.0, 0.0, 0.0),
            DVec4::new(0.0, 1.0, 0.0, 0.0),
            DVec4::new(0.0, 0.0, FAR / (FAR - NEAR), 1.0),
            DVec4::new(0.0, 0.0, -FAR * NEAR / (FAR - NEAR), 0.0),
        );
        let screen_from_camera =
            DMat4::from_scale(DVec3::new(1.0 / tan_short, 1.0 / tan_short, 1.0)) * perspective;
        let ndc_from_screen =
            DMat4::from_translation(DVec3::splat(0.5)) * DMat4::from_scale(DVec3::splat(0.5));
        let ndc_from_world = ndc_from_screen * screen_from_camera * camera_from_world;
        CameraMatrices {
            world_to_camera: row_major(&camera_from_world),
            world_to_ndc: row_major(&ndc_from_world),
        }
    }
}

/// m[i][j] row by row (glam stores columns).
fn row_major(m: &DMat4) -> [f32; 16] {
    m.transpose().to_cols_array().map(|x| x as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    /// (M p) for a row-major 4x4 `m` and a point, divided by w.
    fn project(m: &[f32; 16], p: DVec3) -> DVec3 {
        let row = |i: usize| {
            m[4 * i] as f64 * p.x
                + m[4 * i + 1] as f64 * p.y
                + m[4 * i + 2] as f64 * p.z
                + m[4 * i + 3] as f64
        };
        DVec3::new(row(0), row(1), row(2)) / row(3)
    }

    /// A world point seen at a pixel lands, through worldToNDC, where pbrt's NDC puts that
    /// pixel; through worldToCamera at the right depth along +z; for wide and tall images.
    #[test]
    fn matrices_project_world_points_onto_their_pixels() {
        for (width, height) in [(64, 48), (30, 50), (40, 40)] {
            let position = Vec3::new(1.0, 2.0, 5.0);
            let camera = Camera::new(
                position,
                Vec3::new(0.2, 1.5, 0.0),
                Vec3::Y,
                40.0,
                (width, height),
            )
            .unwrap();
            let m = CameraMatrices::new(&camera, position.as_dvec3());
            let (w, h) = (width as f64, height as f64);
            let short = w.min(h);
            for (px, py) in [
                (0.5, 0.5),
                (10.0, 3.0),
                (w - 1.0, h - 2.0),
                (w / 2.0, h / 2.0),
            ] {
                let ray = camera.generate_ray(Vec2::new(px as f32, py as f32));
                let depth = 3.0;
                let p = (ray.origin + ray.dir * depth).as_dvec3();
                let c = project(&m.world_to_camera, p);
                let along = ray.dir.as_dvec3().dot(camera.forward().as_dvec3()) * depth as f64;
                assert!((c.z - along).abs() < 1e-4, "{c} {along}");
                // pbrt's screen coordinates of the pixel: the shorter axis spans [-1, 1],
                // y up; NDC = (screen + 1) / 2.
                let screen_x = (2.0 * px - w) / short;
                let screen_y = (h - 2.0 * py) / short;
                let ndc = project(&m.world_to_ndc, p);
                assert!((ndc.x - (screen_x + 1.0) / 2.0).abs() < 1e-4, "{ndc} {px}");
                assert!((ndc.y - (screen_y + 1.0) / 2.0).abs() < 1e-4, "{ndc} {py}");
                assert!(ndc.z > 0.0 && ndc.z < 1.0, "{ndc}");
            }
        }
    }
}
