//! Image error metrics, shared by the tests and the command-line tools.
//!
//! Every metric compares an image `a` against a reference `b`, channel by channel, and is
//! accumulated in f64. The relative MSE divides by the reference's square plus a small
//! constant, so that dark pixels (where noise is most visible) count as much as bright ones
//! and black pixels do not divide by zero:
//!
//! ```text
//! relMSE = 1/(3N) sum_{pixels, channels} (a - b)^2 / (b^2 + 0.01)
//! RMSE   = sqrt( 1/(3N) sum_{pixels, channels} (a - b)^2 )
//! ```
//!
//! The trimmed relMSE drops the largest 0.1% of the per-pixel-channel terms before averaging:
//! a handful of fireflies can dominate the plain relMSE of an otherwise converged image.

use crate::film::Image;
use glam::Vec3;

/// The constant added to b^2 in the relMSE denominator.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Fraction of the largest relMSE terms that [`trimmed_rel_mse`] drops.
pub const TRIM_FRACTION: f64 = 0.001;

/// Two images that cannot be compared because their sizes differ.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("image sizes differ: {a_width}x{a_height} against reference {b_width}x{b_height}")]
pub struct SizeMismatch {
    pub a_width: u32,
    pub a_height: u32,
    pub b_width: u32,
    pub b_height: u32,
}

/// The errors of an image against a reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorMetrics {
    /// Relative mean squared error (see the module docs).
    pub rel_mse: f64,
    /// Root mean squared error.
    pub rmse: f64,
    /// Relative MSE without the largest [`TRIM_FRACTION`] of its terms.
    pub rel_mse_trimmed: f64,
}

fn check_sizes(a: &Image, b: &Image) -> Result<(), SizeMismatch> {
    if a.width == b.width && a.height == b.height && a.pixels.len() == b.pixels.len() {
        Ok(())
    } else {
        Err(SizeMismatch {
            a_width: a.width,
            a_height: a.height,
            b_width: b.width,
            b_height: b.height,
        })
    }
}

/// The per-pixel-channel terms (a - b)^2 and (a - b)^2 / (b^2 + eps), in pixel order.
fn terms<'a>(a: &'a Image, b: &'a Image) -> impl Iterator<Item = (f64, f64)> + 'a {
    a.pixels.iter().zip(&b.pixels).flat_map(|(pa, pb)| {
        let (pa, pb): ([f32; 3], [f32; 3]) = ((*pa).into(), (*pb).into());
        (0..3).map(move |c| {
            let (x, r) = (pa[c] as f64, pb[c] as f64);
            let sq = (x - r) * (x - r);
            (sq, sq / (r * r + REL_MSE_EPSILON))
        })
    })
}

/// Mean over pixels and channels of (a - b)^2 / (b^2 + 0.01), with `b` the reference.
pub fn rel_mse(a: &Image, b: &Image) -> Result<f64, SizeMismatch> {
    check_sizes(a, b)?;
    let n = (3 * a.pixels.len()).max(1) as f64;
    Ok(terms(a, b).map(|(_, rel)| rel).sum::<f64>() / n)
}

/// Square root of the mean over pixels and channels of (a - b)^2.
pub fn rmse(a: &Image, b: &Image) -> Result<f64, SizeMismatch> {
    check_sizes(a, b)?;
    let n = (3 * a.pixels.len()).max(1) as f64;
    Ok((terms(a, b).map(|(sq, _)| sq).sum::<f64>() / n).sqrt())
}

/// The relMSE after dropping the `floor(fraction * 3N)` largest terms (none for small images).
pub fn trimmed_rel_mse(a: &Image, b: &Image, fraction: f64) -> Result<f64, SizeMismatch> {
    check_sizes(a, b)?;
    let mut rel: Vec<f64> = terms(a, b).map(|(_, rel)| rel).collect();
    Ok(trimmed_mean(&mut rel, fraction))
}

/// Mean of `values` without its `floor(fraction * len)` largest entries (reorders `values`).
fn trimmed_mean(values: &mut [f64], fraction: f64) -> f64 {
    let drop =
        ((values.len() as f64 * fraction.clamp(0.0, 1.0)).floor() as usize).min(values.len());
    let keep = values.len() - drop;
    if keep == 0 {
        return 0.0;
    }
    if drop > 0 {
        // Partition so that the `keep` smallest terms come first (NaN sorts as largest).
        values.select_nth_unstable_by(keep - 1, |x, y| x.total_cmp(y));
    }
    values[..keep].iter().sum::<f64>() / keep as f64
}

/// All three metrics at once (one pass for the sums, one selection for the trimmed mean).
pub fn error_metrics(a: &Image, b: &Image) -> Result<ErrorMetrics, SizeMismatch> {
    check_sizes(a, b)?;
    let n = (3 * a.pixels.len()).max(1) as f64;
    let (mut sum_sq, mut sum_rel) = (0.0, 0.0);
    let mut rel: Vec<f64> = Vec::with_capacity(3 * a.pixels.len());
    for (sq, r) in terms(a, b) {
        sum_sq += sq;
        sum_rel += r;
        rel.push(r);
    }
    Ok(ErrorMetrics {
        rel_mse: sum_rel / n,
        rmse: (sum_sq / n).sqrt(),
        rel_mse_trimmed: trimmed_mean(&mut rel, TRIM_FRACTION),
    })
}

/// Mean RGB of an image (summed in f64).
pub fn mean_rgb(image: &Image) -> Vec3 {
    image.mean()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, pixels: &[[f32; 3]]) -> Image {
        Image {
            width,
            height,
            pixels: pixels.iter().map(|p| Vec3::from(*p)).collect(),
        }
    }

    /// A 2x1 image against a 2x1 reference, every term worked out by hand:
    ///
    /// pixel 0: a = (1, 0, 0.5), b = (1, 0.1, 0)  -> (a-b)^2 = (0, 0.01, 0.25)
    ///          rel = (0 / 1.01, 0.01 / 0.02, 0.25 / 0.01) = (0, 0.5, 25)
    /// pixel 1: a = (2, 1, 1),   b = (1, 1, 3)    -> (a-b)^2 = (1, 0, 4)
    ///          rel = (1 / 1.01, 0, 4 / 9.01)
    ///
    /// relMSE = (0.5 + 25 + 1/1.01 + 4/9.01) / 6, RMSE = sqrt(5.26 / 6).
    #[test]
    fn hand_computed_example() {
        let a = image(2, 1, &[[1.0, 0.0, 0.5], [2.0, 1.0, 1.0]]);
        let b = image(2, 1, &[[1.0, 0.1, 0.0], [1.0, 1.0, 3.0]]);
        // 0.1 is not exact in f32: use the stored value in the expected (a-b)^2.
        let b01 = 0.1f32 as f64;
        let expected_rel = (b01 * b01 / (b01 * b01 + 0.01) + 25.0 + 1.0 / 1.01 + 4.0 / 9.01) / 6.0;
        let expected_rmse = ((b01 * b01 + 0.25 + 1.0 + 4.0) / 6.0).sqrt();
        assert!((rel_mse(&a, &b).unwrap() - expected_rel).abs() < 1e-12);
        assert!((rmse(&a, &b).unwrap() - expected_rmse).abs() < 1e-12);
        assert!((expected_rel - 4.4890).abs() < 1e-4, "{expected_rel}"); // the numbers by hand
        assert!((expected_rmse - 0.9363).abs() < 1e-4, "{expected_rmse}");
        let all = error_metrics(&a, &b).unwrap();
        assert_eq!(all.rel_mse, rel_mse(&a, &b).unwrap());
        assert_eq!(all.rmse, rmse(&a, &b).unwrap());
        // 6 terms: 0.1% of them is less than one, nothing is trimmed.
        assert_eq!(all.rel_mse_trimmed, all.rel_mse);
    }

    #[test]
    fn reference_is_the_second_argument() {
        let a = image(1, 1, &[[0.0; 3]]);
        let b = image(1, 1, &[[1.0; 3]]);
        assert!((rel_mse(&a, &b).unwrap() - 1.0 / 1.01).abs() < 1e-12);
        assert!((rel_mse(&b, &a).unwrap() - 100.0).abs() < 1e-9);
    }

    #[test]
    fn identical_images_have_zero_error() {
        let a = image(
            2,
            2,
            &[[0.3, 0.2, 0.1], [5.0, 0.0, 1.0], [0.0; 3], [1e-3, 1e3, 7.0]],
        );
        let m = error_metrics(&a, &a).unwrap();
        assert_eq!((m.rel_mse, m.rmse, m.rel_mse_trimmed), (0.0, 0.0, 0.0));
    }

    #[test]
    fn trimming_drops_the_largest_terms() {
        // 2000 pixels = 6000 terms: the 6 largest are dropped. Five pixels carry a firefly of
        // relMSE term 100 in one channel; the one term 1e6 and the five 100s are all dropped.
        let b = Image::new(2000, 1);
        let mut a = Image::new(2000, 1);
        for x in 0..5 {
            a.pixels[x].x = 1.0; // (1 - 0)^2 / 0.01 = 100
        }
        a.pixels[1999].y = 100.0; // 1e4 / 0.01 = 1e6
        for p in &mut a.pixels[100..1100] {
            p.z = 0.1; // the stored f32 0.1, squared over 0.01: about 1
        }
        let z = (0.1f32 as f64).powi(2) / 0.01;
        let m = error_metrics(&a, &b).unwrap();
        assert!((m.rel_mse - (500.0 + 1e6 + 1000.0 * z) / 6000.0).abs() < 1e-9);
        assert!(
            (m.rel_mse_trimmed - 1000.0 * z / 5994.0).abs() < 1e-12,
            "{}",
            m.rel_mse_trimmed
        );
        assert_eq!(
            trimmed_rel_mse(&a, &b, TRIM_FRACTION).unwrap(),
            m.rel_mse_trimmed
        );
        assert_eq!(trimmed_rel_mse(&a, &b, 0.0).unwrap(), m.rel_mse);
    }

    #[test]
    fn size_mismatch_is_an_error() {
        let e = rel_mse(&Image::new(2, 3), &Image::new(3, 2)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "image sizes differ: 2x3 against reference 3x2"
        );
        assert!(error_metrics(&Image::new(1, 1), &Image::new(1, 2)).is_err());
    }

    #[test]
    fn mean_rgb_averages_each_channel() {
        let a = image(2, 1, &[[1.0, 2.0, 0.0], [3.0, 0.0, 1.0]]);
        assert_eq!(mean_rgb(&a), Vec3::new(2.0, 1.0, 0.5));
    }
}
