//! The thin lens: depth of field for the camera (pbrt-v4's `lensradius` / `focaldistance`,
//! Mitsuba 3's `thinlens` sensor with `aperture_radius` / `focus_distance`).
//!
//! The lens is a disk of radius r centred on the camera position, perpendicular to the view
//! direction. A camera ray starts at a point uniform on the disk (area density 1 / (pi r^2))
//! and passes through the point of the plane in focus (at distance `focus_distance` along the
//! view direction) that the pinhole ray through the same film position would hit (pbrt-v4
//! book, sec. 5.2.3). Points on the focus plane are therefore sharp; a point at depth z images
//! to a disk (the circle of confusion) of diameter 2 r |z - f| / z on the focus plane,
//! i.e. 2 r |z - f| / z * d_img / f pixels, with d_img [`Camera::image_plane_distance`].
//!
//! Importance (radiance vs importance transport: the camera emits importance W_e, the
//! measurement of pixel j is the integral of W_e L cos theta over the lens area and the solid
//! angle). A film point uniform in the image and a lens point uniform on the disk give the
//! ray (x_lens, w) the density p_A(x_lens) p(w | x_lens) = 1 / (pi r^2) * 1 / (A cos^3 theta):
//! from x_lens the film position maps linearly to the focus plane (a pixel there is (f / d_img)
//! times as wide), and the plane's area at distance f / cos theta subtends
//! dw = cos theta dA / (f / cos theta)^2, so the direction density is the pinhole's,
//! 1 / (A cos^3 theta), with theta the angle between w and the view direction and A the
//! image's area at distance 1 ([`Camera::image_area`]). The measurement's W_e cos theta equals
//! that density, hence
//!     W_e(x_lens, w) = 1 / (A_lens A cos^4 theta),  A_lens = pi r^2,
//! in the lens's area measure (pbrt-v4 book, sec. 16.1.1, `PerspectiveCamera::We`; Veach 1997,
//! sec. 10.2). The per-pixel solid-angle pdf VCM's MIS needs (SmallVCM's `cameraPdfW`) is the
//! pinhole's [`Camera::pixel_direction_pdf`] at that theta, and the lens point's own density
//! 1 / A_lens is the same for the camera subpath and for light tracing's lens sample, so it
//! cancels from every MIS ratio and the lens changes only where the camera vertex is.

use super::Camera;
use crate::geometry::Ray;
use crate::sampling::{concentric_disc, Rng};
use crate::SceneError;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

impl Camera {
    /// The same camera with a thin lens of aperture radius `radius`, focused at distance
    /// `focus_distance` along the view direction. A radius of 0 is the pinhole (the image is
    /// the pinhole's bit for bit). Fails when the radius is negative or not finite, or the
    /// focus distance is not positive and finite.
    pub fn with_lens(mut self, radius: f32, focus_distance: f32) -> Result<Self, SceneError> {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(SceneError::DegenerateCamera(format!(
                "aperture radius {radius} is not a finite number >= 0"
            )));
        }
        if !(focus_distance.is_finite() && focus_distance > 0.0) {
            return Err(SceneError::DegenerateCamera(format!(
                "focus distance {focus_distance} is not a finite number > 0"
            )));
        }
        self.lens_radius = radius;
        self.focus_distance = focus_distance;
        Ok(self)
    }

    /// The aperture radius (0 for a pinhole).
    #[inline]
    pub fn lens_radius(&self) -> f32 {
        self.lens_radius
    }

    /// The distance along the view direction to the plane in focus (unused by a pinhole).
    #[inline]
    pub fn focus_distance(&self) -> f32 {
        self.focus_distance
    }

    /// True without a lens: camera rays start at `position`.
    #[inline]
    pub fn is_pinhole(&self) -> bool {
        self.lens_radius == 0.0
    }

    /// The area of the aperture disk, pi r^2.
    #[inline]
    pub fn lens_area(&self) -> f32 {
        PI * self.lens_radius * self.lens_radius
    }

    /// The point of the lens for the unit-square sample `u`: the concentric map of `u` onto
    /// the disk, uniform in area (density 1 / [`Camera::lens_area`]).
    #[inline]
    pub fn lens_point(&self, u: Vec2) -> Vec3 {
        let d = concentric_disc(u) * self.lens_radius;
        self.position + self.right * d.x + self.up * d.y
    }

    /// The camera ray through film position `film` (pixels, as [`Camera::generate_ray`])
    /// leaving the lens at the point for `u_lens`: it passes through the focus-plane point
    /// of the pinhole ray through `film`.
    #[inline]
    pub fn generate_lens_ray(&self, film: Vec2, u_lens: Vec2) -> Ray {
        let aspect = self.width as f32 / self.height as f32;
        let ndc_x = 2.0 * film.x / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * film.y / self.height as f32;
        // The pinhole direction with unit component along `forward`: scaled by the focus
        // distance it reaches the focus plane.
        let d = self.forward
            + self.right * (ndc_x * self.tan_half_fov * aspect)
            + self.up * (ndc_y * self.tan_half_fov);
        let focus = self.position + d * self.focus_distance;
        let origin = self.lens_point(u_lens);
        Ray::new(origin, (focus - origin).normalize())
    }

    /// The camera ray through film position `film` of a pixel path whose random stream is
    /// `rng`: the pinhole's ray ([`Camera::generate_ray`], drawing nothing from `rng`, so a
    /// pinhole's streams and images are unchanged), or with a lens the ray from the lens point
    /// for the stream's next two numbers.
    #[inline(always)]
    pub fn sample_ray(&self, film: Vec2, rng: &mut Rng) -> Ray {
        if self.is_pinhole() {
            self.generate_ray(film)
        } else {
            self.generate_lens_ray(film, rng.uniform2())
        }
    }

    /// The image position (pixels) of the camera ray from the lens point `lens` through the
    /// world point `p`, or `None` when `p` is not in front of the lens or the ray leaves the
    /// image. The ray from `lens` toward `p` meets the focus plane at
    /// lens + (p - lens) f / ((p - lens) . forward), whose pinhole projection is the position
    /// ([`Camera::raster_position`]); with `lens` at the camera position it is the pinhole's.
    #[inline]
    pub fn lens_raster_position(&self, lens: Vec3, p: Vec3) -> Option<Vec2> {
        let v = p - lens;
        let z = v.dot(self.forward);
        if z.is_nan() || z <= 0.0 {
            return None;
        }
        self.raster_position(lens + v * (self.focus_distance / z))
    }

    /// The thin lens's importance W_e = 1 / (A_lens A cos^4 theta) (module docs) for the ray
    /// leaving the lens point `lens` in unit direction `dir`, 0 when it leaves the image.
    /// Per unit lens area and solid angle, normalised over the whole image.
    #[inline]
    pub fn lens_importance(&self, lens: Vec3, dir: Vec3) -> f32 {
        let cos = dir.dot(self.forward);
        if cos <= 0.0 || self.lens_raster_position(lens, lens + dir).is_none() {
            return 0.0;
        }
        let cos2 = cos * cos;
        1.0 / (self.lens_area() * self.image_area() * cos2 * cos2)
    }

    /// The diameter, in pixels, of the circle of confusion of a point on the view axis at
    /// depth `z`: the lens's rays through it spread over a disk of diameter
    /// 2 r |z - f| / z on the focus plane (similar triangles with apex at the point), and
    /// a focus-plane length l spans l d_img / f pixels.
    pub fn circle_of_confusion(&self, z: f32) -> f32 {
        let f = self.focus_distance;
        2.0 * self.lens_radius * (z - f).abs() / z * self.image_plane_distance() / f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{uniform_sphere, Rng};

    fn lens_camera() -> Camera {
        Camera::new(
            Vec3::new(0.5, 1.0, 3.9),
            Vec3::new(0.0, 1.2, 0.0),
            Vec3::Y,
            38.0,
            (64, 48),
        )
        .unwrap()
        .with_lens(0.2, 3.0)
        .unwrap()
    }

    /// A zero radius draws nothing from the stream and gives the pinhole's ray bit for bit.
    #[test]
    fn zero_radius_is_the_pinhole() {
        let c = lens_camera().with_lens(0.0, 3.0).unwrap();
        let mut rng = Rng::new(1, 2, 3);
        let mut copy = rng.clone();
        for _ in 0..100 {
            let film = copy.uniform2() * Vec2::new(64.0, 48.0);
            rng.uniform2();
            let (a, b) = (c.sample_ray(film, &mut rng), c.generate_ray(film));
            assert_eq!((a.origin, a.dir), (b.origin, b.dir));
        }
        assert_eq!(rng.uniform(), copy.uniform());
    }

    /// Every lens ray through a film position meets the focus plane at one point, and
    /// projecting any point of the ray back through its lens point gives that film position.
    #[test]
    fn lens_rays_converge_on_the_focus_plane_and_project_back() {
        let c = lens_camera();
        let mut rng = Rng::new(5, 0, 0);
        for _ in 0..500 {
            let film = rng.uniform2() * Vec2::new(64.0, 48.0);
            let pinhole = c.generate_ray(film);
            let focus = pinhole.at(c.focus_distance() / pinhole.dir.dot(c.forward()));
            let ray = c.generate_lens_ray(film, rng.uniform2());
            assert!((ray.origin - c.position).length() <= 0.2 + 1e-6);
            assert!((ray.origin - c.position).dot(c.forward()).abs() < 1e-6);
            let t = (focus - ray.origin).dot(ray.dir);
            assert!((ray.at(t) - focus).length() < 1e-4, "{film}");
            let depth = 0.3 + 8.0 * rng.uniform();
            let back = c.lens_raster_position(ray.origin, ray.at(depth)).unwrap();
            assert!((back - film).length() < 2e-2, "{film} -> {back}");
        }
    }

    /// W_e cos theta integrates to 1 over the lens area and the sphere of directions (lens
    /// points uniform, directions uniform; 4 standard errors).
    #[test]
    fn lens_importance_integrates_to_one() {
        let c = lens_camera();
        let mut rng = Rng::new(9, 0, 0);
        let n = 400_000;
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let lens = c.lens_point(rng.uniform2());
            let dir = uniform_sphere(rng.uniform2());
            let pdf = 1.0 / (4.0 * std::f64::consts::PI * c.lens_area() as f64);
            let w = (c.lens_importance(lens, dir) * dir.dot(c.forward()).max(0.0)) as f64 / pdf;
            sum += w;
            sum2 += w * w;
        }
        let mean = sum / n as f64;
        let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        assert!((mean - 1.0).abs() < 4.0 * se, "{mean} (se {se})");
    }

    #[test]
    fn bad_lenses_are_rejected() {
        let c = lens_camera();
        assert!(c.with_lens(-0.1, 1.0).is_err());
        assert!(c.with_lens(f32::NAN, 1.0).is_err());
        assert!(c.with_lens(0.1, 0.0).is_err());
        assert!(c.with_lens(0.1, f32::INFINITY).is_err());
    }
}
