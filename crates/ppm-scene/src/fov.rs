//! Field-of-view conventions shared by scene format v1 and the Mitsuba importer: a field of
//! view along the image's x or y axis or its diagonal, or a focal length on 35 mm film,
//! converted to the vertical field of view ppm's camera takes.

use serde::Deserialize;

/// The image axis a field of view spans (Mitsuba 3's `fov_axis`; pbrt-v4's `fov` spans the
/// shorter axis, which is `x` for a portrait image and `y` for a landscape one).
#[derive(Deserialize, Clone, Copy, Debug, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum FovAxis {
    X,
    Y,
    Diagonal,
}

/// The diagonal of 36 x 24 mm film, in mm: a focal length f gives the diagonal field of view
/// 2 atan(diagonal / (2 f)) (Mitsuba 3's `focal_length` convention).
pub const FILM_DIAGONAL_MM: f64 = 43.266_615_305_567_87;

/// The diagonal field of view, degrees, of a lens of focal length `mm` on 35 mm film.
pub fn focal_length_fov(mm: f64) -> f64 {
    2.0 * (FILM_DIAGONAL_MM / (2.0 * mm)).atan().to_degrees()
}

/// The vertical field of view, degrees, of an image of aspect ratio `aspect` (width / height)
/// whose field of view along `axis` is `fov` degrees. With t = tan(fov / 2), tan(vertical / 2)
/// is t / aspect (x), t (y), t / sqrt(1 + aspect^2) (diagonal): the image plane at distance 1
/// is 2 tan(vertical / 2) high and aspect times as wide.
pub fn vertical_fov(fov: f64, axis: FovAxis, aspect: f64) -> f64 {
    let t = (fov.to_radians() * 0.5).tan();
    let tan_vertical = match axis {
        FovAxis::X => t / aspect,
        FovAxis::Y => t,
        FovAxis::Diagonal => t / (1.0 + aspect * aspect).sqrt(),
    };
    2.0 * tan_vertical.atan().to_degrees()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_agree_on_a_square_image_and_y_is_the_identity() {
        assert!((vertical_fov(40.0, FovAxis::Y, 1.7) - 40.0).abs() < 1e-12);
        assert!((vertical_fov(40.0, FovAxis::X, 1.0) - 40.0).abs() < 1e-12);
        // The diagonal of a square is sqrt(2) times its side.
        let t = (vertical_fov(40.0, FovAxis::Diagonal, 1.0).to_radians() / 2.0).tan();
        assert!((t * 2f64.sqrt() - (20f64.to_radians()).tan()).abs() < 1e-12);
        // 50 mm on 35 mm film: 46.79 degrees diagonally, 39.6 horizontally (36 mm wide).
        assert!((focal_length_fov(50.0) - 46.793).abs() < 1e-3);
        // On a 3:2 image the diagonal field of view of 50 mm spans 36 mm horizontally.
        let x = 2.0 * (18.0f64 / 50.0).atan().to_degrees();
        let from_diagonal = {
            let v = vertical_fov(focal_length_fov(50.0), FovAxis::Diagonal, 1.5);
            2.0 * ((v.to_radians() / 2.0).tan() * 1.5).atan().to_degrees()
        };
        assert!((from_diagonal - x).abs() < 1e-9, "{from_diagonal} vs {x}");
    }
}
