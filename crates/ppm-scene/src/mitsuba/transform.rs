//! The operations of a `<transform>` element, in double precision. Each operation is
//! applied after the ones before it: the running matrix M becomes `op * M`, as in Mitsuba
//! (so `<scale>` then `<translate>` scales first).

use glam::{DMat3, DMat4, DVec3};

/// Translation by `t`.
pub fn translate(t: DVec3) -> DMat4 {
    DMat4::from_translation(t)
}

/// Scaling by `s` along the axes.
pub fn scale(s: DVec3) -> DMat4 {
    DMat4::from_scale(s)
}

/// Rotation by `degrees` around `axis` (not necessarily unit, not zero), counter-clockwise
/// seen from the tip of the axis (right-handed): Rodrigues' formula
/// R = cos a I + sin a [k]x + (1 - cos a) k k^T with k the unit axis.
pub fn rotate(axis: DVec3, degrees: f64) -> Option<DMat4> {
    let k = axis.try_normalize()?;
    Some(DMat4::from_axis_angle(k, degrees.to_radians()))
}

/// The camera-to-world matrix of a camera at `origin` looking at `target`: its columns are
/// `left = normalize(up x dir)`, `up' = dir x left`, `dir = normalize(target - origin)` and
/// `origin`, so the camera looks down its +z with +y up and +x to the image's left
/// (Mitsuba's convention). A zero `up` is replaced by any vector perpendicular to `dir`.
/// `None` when the frame degenerates (target = origin, up parallel to the view).
pub fn look_at(origin: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (target - origin).try_normalize()?;
    let up = if up == DVec3::ZERO {
        dir.any_orthonormal_vector()
    } else {
        up
    };
    let left = up.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    let m = DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    );
    m.is_finite().then_some(m)
}

/// A matrix written row by row: 16 values (4x4) or 9 (the linear 3x3 part, no translation).
pub fn matrix(values: &[f64]) -> Option<DMat4> {
    match values.len() {
        16 => Some(DMat4::from_cols_array(&values.try_into().ok()?).transpose()),
        9 => {
            let m = DMat3::from_cols_array(&values.try_into().ok()?).transpose();
            Some(DMat4::from_mat3(m))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DMat4, b: DMat4) -> bool {
        a.abs_diff_eq(b, 1e-12)
    }

    #[test]
    fn rotation_about_z_by_90_degrees_takes_x_to_y() {
        let r = rotate(DVec3::new(0.0, 0.0, 2.0), 90.0).unwrap();
        #[rustfmt::skip]
        let expected = matrix(&[
            0.0, -1.0, 0.0, 0.0,
            1.0,  0.0, 0.0, 0.0,
            0.0,  0.0, 1.0, 0.0,
            0.0,  0.0, 0.0, 1.0,
        ]).unwrap();
        assert!(close(r, expected), "{r}");
        assert!(rotate(DVec3::ZERO, 10.0).is_none());
    }

    #[test]
    fn look_at_puts_the_view_on_z_and_left_on_x() {
        let m = look_at(
            DVec3::new(0.0, 1.0, 4.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::Y,
        )
        .unwrap();
        // dir = -z, left = up x dir = y x -z = -x, up' = dir x left = -z x -x = y.
        #[rustfmt::skip]
        let expected = matrix(&[
            -1.0, 0.0,  0.0, 0.0,
             0.0, 1.0,  0.0, 1.0,
             0.0, 0.0, -1.0, 4.0,
             0.0, 0.0,  0.0, 1.0,
        ]).unwrap();
        assert!(close(m, expected), "{m}");
        assert!(look_at(DVec3::ONE, DVec3::ONE, DVec3::Y).is_none());
        assert!(look_at(DVec3::ZERO, DVec3::Y, DVec3::Y).is_none());
        assert!(look_at(DVec3::ZERO, DVec3::Z, DVec3::ZERO).is_some());
    }

    #[test]
    fn matrices_are_read_row_by_row() {
        let m = matrix(&[
            1., 2., 3., 4., 5., 6., 7., 8., 9., 10., 11., 12., 0., 0., 0., 1.,
        ])
        .unwrap();
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(4.0, 8.0, 12.0));
        assert_eq!(m.col(0).truncate(), DVec3::new(1.0, 5.0, 9.0));
        let m3 = matrix(&[1., 2., 3., 4., 5., 6., 7., 8., 9.]).unwrap();
        assert_eq!(m3.transform_point3(DVec3::X), DVec3::new(1.0, 4.0, 7.0));
        assert!(matrix(&[1.0; 12]).is_none());
    }
}
