//! The camera of scene format v1: a pinhole, or a thin lens ([`lens`]).
//!
//! Conventions: right-handed world; looking down -z with +y up, world +x is on the right of the
//! image; pixel (0, 0) is the top-left pixel; `fov` is the vertical field of view in degrees.

mod lens;

use crate::geometry::Ray;
use crate::SceneError;
use glam::{Vec2, Vec3};

/// Largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 1 << 14;

/// A pinhole or thin-lens camera and the image resolution it renders to. A new camera is a
/// pinhole; [`Camera::with_lens`] gives it a lens.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub position: Vec3,
    /// Unit vectors: right, up (both in the image plane) and forward (view direction).
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// tan(fov / 2): half-height of the image plane at distance 1.
    tan_half_fov: f32,
    /// Radius of the thin lens's aperture disk (0: a pinhole).
    lens_radius: f32,
    /// Distance along `forward` from the lens to the plane in focus.
    focus_distance: f32,
    pub width: u32,
    pub height: u32,
    /// The arguments of [`Camera::new`] that the frame was computed from (see
    /// [`Camera::placement`]); not used in rendering.
    placement: (Vec3, Vec3, f32),
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
            lens_radius: 0.0,
            focus_distance: 1.0,
            width: 1,
            height: 1,
            placement: (look_at, up, fov_degrees),
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
        self.placement.0 += position - self.position;
        self.position = position;
        self
    }

    /// The `look_at`, `up` and vertical `fov_degrees` this camera was made from by
    /// [`Camera::new`]: with `position`, [`Camera::new`] of them gives this camera's frame bit
    /// for bit, which the frame alone cannot (normalising again rounds differently). Scene
    /// writers (`ppm convert`) use them.
    pub fn placement(&self) -> (Vec3, Vec3, f32) {
        self.placement
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

    /// The unit vectors right, up and forward, and tan(fov / 2), as the camera holds them
    /// (the scene fingerprint records these values).
    pub fn frame(&self) -> (Vec3, Vec3, Vec3, f32) {
        (self.right, self.up, self.forward, self.tan_half_fov)
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

    /// Distance from the pinhole to the image plane, in pixels: the plane on which one pixel
    /// is a unit square, `height / (2 tan(fov / 2))`.
    #[inline]
    pub fn image_plane_distance(&self) -> f32 {
        0.5 * self.height as f32 / self.tan_half_fov
    }

    /// The image position (pixels, as [`Camera::generate_ray`] takes it) whose primary ray
    /// passes through the world point `p`; `None` when `p` is behind the camera, on its plane,
    /// or projects outside [0, width) x [0, height). The inverse of [`Camera::generate_ray`]:
    /// with d = `p - position`, the ray's direction is proportional to
    /// `forward + right x tan * aspect + up y tan`, so x and y are d's components along
    /// `right` and `up` divided by its component along `forward`.
    #[inline]
    pub fn raster_position(&self, p: Vec3) -> Option<Vec2> {
        let d = p - self.position;
        let z = d.dot(self.forward);
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        let aspect = self.width as f32 / self.height as f32;
        let ndc_x = d.dot(self.right) / (z * self.tan_half_fov * aspect);
        let ndc_y = d.dot(self.up) / (z * self.tan_half_fov);
        let film = Vec2::new(
            (ndc_x + 1.0) * 0.5 * self.width as f32,
            (1.0 - ndc_y) * 0.5 * self.height as f32,
        );
        let inside = film.x >= 0.0
            && film.y >= 0.0
            && film.x < self.width as f32
            && film.y < self.height as f32;
        inside.then_some(film)
    }

    /// Area of the image on the plane at distance 1 from the pinhole:
    /// A = (2 tan(fov / 2) aspect) (2 tan(fov / 2)).
    #[inline]
    pub fn image_area(&self) -> f32 {
        let aspect = self.width as f32 / self.height as f32;
        4.0 * self.tan_half_fov * self.tan_half_fov * aspect
    }

    /// The pinhole's importance W_e toward the unit direction `dir`, normalised over the whole
    /// image: W_e = 1 / (A cos^4 theta) inside the image, 0 outside, with theta the angle to
    /// the view direction and A [`Camera::image_area`] (Veach 1997, sec. 10.2 (the pinhole's
    /// importance is the image-plane density); pbrt-v3, `PerspectiveCamera::We`). Derivation:
    /// a point uniform on the image plane at distance 1 has area density 1/A; the plane's area
    /// element at angle theta subtends dw = cos^3 theta dA, so the ray direction has the
    /// solid-angle density [`Camera::direction_pdf`] = 1 / (A cos^3 theta), and
    /// W_e cos theta equals it (the measurement integrates W_e L cos theta dw), hence
    /// the integral of W_e cos theta over the sphere is 1.
    #[inline]
    pub fn importance(&self, dir: Vec3) -> f32 {
        let cos = dir.dot(self.forward);
        if self.raster_position(self.position + dir).is_none() || cos <= 0.0 {
            return 0.0;
        }
        let cos2 = cos * cos;
        1.0 / (self.image_area() * cos2 * cos2)
    }

    /// The solid-angle density of the direction of a primary ray through a point uniform
    /// over the whole image: 1 / (A cos^3 theta) inside the image (see [`Camera::importance`]),
    /// 0 outside.
    #[inline]
    pub fn direction_pdf(&self, dir: Vec3) -> f32 {
        let cos = dir.dot(self.forward);
        if self.raster_position(self.position + dir).is_none() || cos <= 0.0 {
            return 0.0;
        }
        1.0 / (self.image_area() * cos * cos * cos)
    }

    /// The same density per pixel, for estimators whose pixels are unit squares of the image
    /// (each pixel's estimate is the mean over its area, as [`Camera::generate_ray`] jitters):
    /// a point uniform in one pixel gives the direction `dir` (through that pixel) the density
    /// N_pixels / (A cos^3 theta) = d^2 / cos^3 theta, with d
    /// [`Camera::image_plane_distance`] in pixels. Not checked against the image bounds.
    /// This is SmallVCM's `imageToSolidAngleFactor` (Georgiev et al. 2012, tech. report,
    /// sec. 5.1 (camera subpath start)).
    #[inline]
    pub fn pixel_direction_pdf(&self, cos_theta: f32) -> f32 {
        let d = self.image_plane_distance();
        d * d / (cos_theta * cos_theta * cos_theta)
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

    /// Projection inverts ray generation: a point along the ray through an image position
    /// projects back to that position, and points behind or beside the image do not project.
    #[test]
    fn raster_position_inverts_generate_ray() {
        let c = cam();
        let mut rng = crate::sampling::Rng::new(1, 2, 3);
        for _ in 0..1000 {
            let film = rng.uniform2() * Vec2::new(512.0, 412.0);
            let ray = c.generate_ray(film);
            let t = 0.1 + 10.0 * rng.uniform();
            let back = c.raster_position(ray.at(t)).expect("in the image");
            assert!((back - film).length() < 2e-2, "{film} -> {back}");
        }
        assert!(c.raster_position(c.position - c.forward()).is_none());
        assert!(c.raster_position(c.position).is_none());
        let outside = c.generate_ray(Vec2::new(-3.0, 10.0)).at(2.0);
        assert!(c.raster_position(outside).is_none());
    }

    /// The importance integrates to 1 against cos theta over the sphere, and the direction
    /// pdf to 1 (Monte Carlo with uniform directions; 4 standard errors). The per-pixel pdf is
    /// the image pdf times the pixel count.
    #[test]
    fn importance_and_direction_pdf_integrate_to_one() {
        for (fov, res) in [(38.0, (512, 412)), (90.0, (64, 32)), (20.0, (10, 40))] {
            let c = Camera::new(Vec3::ZERO, Vec3::new(0.3, -0.2, -1.0), Vec3::Y, fov, res).unwrap();
            let mut rng = crate::sampling::Rng::new(7, 0, 0);
            let n = 400_000;
            let (mut s_w, mut s_w2, mut s_p, mut s_p2) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for _ in 0..n {
                let dir = crate::sampling::uniform_sphere(rng.uniform2());
                let pdf = 1.0 / (4.0 * std::f64::consts::PI);
                let w = (c.importance(dir) * dir.dot(c.forward()).max(0.0)) as f64 / pdf;
                let p = c.direction_pdf(dir) as f64 / pdf;
                s_w += w;
                s_w2 += w * w;
                s_p += p;
                s_p2 += p * p;
                if p > 0.0 {
                    let cos = dir.dot(c.forward());
                    let pixels = (res.0 * res.1) as f32;
                    let per_pixel = c.pixel_direction_pdf(cos) / pixels;
                    assert!((per_pixel / c.direction_pdf(dir) - 1.0).abs() < 1e-4);
                }
            }
            let nf = n as f64;
            for (sum, sum2, what) in [(s_w, s_w2, "W_e cos"), (s_p, s_p2, "pdf")] {
                let mean = sum / nf;
                let se = ((sum2 / nf - mean * mean) / nf).sqrt();
                assert!(
                    (mean - 1.0).abs() < 4.0 * se,
                    "fov {fov}: {what} integrates to {mean} (se {se})"
                );
            }
        }
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
