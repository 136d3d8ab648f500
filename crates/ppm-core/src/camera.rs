//! The pinhole camera of scene format v1.
//!
//! Conventions: right-handed world; looking down -z with +y up, world +x is on the right of the
//! image; pixel (0, 0) is the top-left pixel; `fov` is the vertical field of view in degrees.

use crate::geometry::Ray;
use crate::SceneError;
use glam::{Vec2, Vec3};

/// Largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 1 << 14;

/// A pinhole camera and the image resolution it renders to.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub position: Vec3,
    /// Unit vectors: right, up (both in the image plane) and forward (view direction).
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// tan(fov / 2): half-height of the image plane at distance 1.
    tan_half_fov: f32,
    pub width: u32,
    pub height: u32,
}

impl Camera {
    /// A camera at `position` looking at `look_at`. Fails when the view direction is zero or
    /// parallel to `up`, when `fov` is not in (0, 180) degrees, or the resolution is unusable.
    pub fn new(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        fov_degrees: f32,
        (width, height): (u32, u32),
    ) -> Result<Self, SceneError> {
        if !(position.is_finite() && look_at.is_finite() && up.is_finite()) {
            return Err(SceneError::DegenerateCamera(
                "position, look_at and up must be finite".into(),
            ));
        }
        let forward = (look_at - position).normalize_or_zero();
        if forward == Vec3::ZERO {
            return Err(SceneError::DegenerateCamera(
                "look_at equals position".into(),
            ));
        }
        let right = forward.cross(up);
        if right.length() < 1e-6 * up.length().max(f32::MIN_POSITIVE) || up == Vec3::ZERO {
            return Err(SceneError::DegenerateCamera(
                "up is zero or parallel to the view direction".into(),
            ));
        }
        if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
            return Err(SceneError::DegenerateCamera(format!(
                "fov {fov_degrees} is not in (0, 180) degrees"
            )));
        }
        let mut camera = Camera {
            position,
            right: right.normalize(),
            up: Vec3::ZERO,
            forward,
            tan_half_fov: (fov_degrees.to_radians() * 0.5).tan(),
            width: 1,
            height: 1,
        };
        camera.up = camera.right.cross(forward);
        camera.set_resolution(width, height)?;
        Ok(camera)
    }

    /// Changes the image size (the vertical field of view is kept).
    pub fn set_resolution(&mut self, width: u32, height: u32) -> Result<(), SceneError> {
        if width == 0 || height == 0 || width > MAX_RESOLUTION || height > MAX_RESOLUTION {
            return Err(SceneError::Resolution {
                width,
                height,
                max: MAX_RESOLUTION,
            });
        }
        self.width = width;
        self.height = height;
        Ok(())
    }

    /// The same camera moved to `position` (orientation and field of view kept).
    pub fn with_position(mut self, position: Vec3) -> Self {
        self.position = position;
        self
    }

    /// The angle (radians, small-angle) one pixel subtends at the image centre:
    /// 2 tan(fov / 2) / height. A pixel's footprint at distance d is about d times this.
    pub fn pixel_angle(&self) -> f32 {
        2.0 * self.tan_half_fov / self.height as f32
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// The primary ray through image position `film` in pixels: (0, 0) is the top-left corner
    /// of the image, (width, height) the bottom-right; pixel (x, y) covers [x, x+1) x [y, y+1).
    #[inline]
    pub fn generate_ray(&self, film: Vec2) -> Ray {
        let aspect = self.width as f32 / self.height as f32;
        let ndc_x = 2.0 * film.x / self.width as f32 - 1.0; // -1 left, +1 right
        let ndc_y = 1.0 - 2.0 * film.y / self.height as f32; // +1 top, -1 bottom
        let dir = self.forward
            + self.right * (ndc_x * self.tan_half_fov * aspect)
            + self.up * (ndc_y * self.tan_half_fov);
        Ray::new(self.position, dir.normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera::new(
            Vec3::new(0.0, 1.0, 3.9),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            38.0,
            (512, 412),
        )
        .unwrap()
    }

    #[test]
    fn center_ray_looks_at_target_and_x_is_right_y_is_up() {
        let c = cam();
        let center = c.generate_ray(Vec2::new(256.0, 206.0));
        assert!((center.dir - Vec3::NEG_Z).length() < 1e-6);
        let right = c.generate_ray(Vec2::new(500.0, 206.0));
        assert!(right.dir.x > 0.0);
        let top_left = c.generate_ray(Vec2::new(0.0, 0.0));
        assert!(top_left.dir.x < 0.0 && top_left.dir.y > 0.0);
    }

    #[test]
    fn vertical_fov_is_respected() {
        let c = cam();
        let top = c.generate_ray(Vec2::new(256.0, 0.0));
        let angle = top.dir.angle_between(Vec3::NEG_Z).to_degrees();
        assert!((angle - 19.0).abs() < 1e-3, "{angle}");
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        let p = Vec3::ZERO;
        assert!(Camera::new(p, Vec3::Y, Vec3::Y, 40.0, (4, 4)).is_err());
        assert!(Camera::new(p, p, Vec3::Y, 40.0, (4, 4)).is_err());
        assert!(Camera::new(p, Vec3::Z, Vec3::Y, 0.0, (4, 4)).is_err());
        assert!(Camera::new(p, Vec3::Z, Vec3::Y, 180.0, (4, 4)).is_err());
        assert!(Camera::new(p, Vec3::Z, Vec3::Y, f32::NAN, (4, 4)).is_err());
        assert!(Camera::new(p, Vec3::Z, Vec3::Y, 40.0, (0, 4)).is_err());
        assert!(Camera::new(p, Vec3::Z, Vec3::Y, 40.0, (100_000, 4)).is_err());
    }
}
