//! `ppm compare A B`: the error of image A against the reference B.

use crate::args::CompareArgs;
use crate::output::{check_finite, read_image};
use anyhow::{Context, Result};
use ppm_core::film::Image;
use ppm_core::metrics::{error_metrics, mean_rgb, ErrorMetrics};
use std::fmt::Write;
use std::path::Path;

/// Reads both images and compares them; the report names the files.
pub fn compare_files(a: &Path, b: &Path) -> Result<(ErrorMetrics, String)> {
    let image_a = read_image(a)?;
    let image_b = read_image(b)?;
    check_finite(&image_a, a, "the image")?;
    check_finite(&image_b, b, "the reference")?;
    let metrics = error_metrics(&image_a, &image_b)
        .with_context(|| format!("cannot compare {} with {}", a.display(), b.display()))?;
    Ok((metrics, report(a, &image_a, b, &image_b, &metrics)))
}

/// The printed report: one line per image, then the metrics.
fn report(a: &Path, image_a: &Image, b: &Path, image_b: &Image, m: &ErrorMetrics) -> String {
    let mut s = String::new();
    for (tag, path, image) in [("A", a, image_a), ("B", b, image_b)] {
        let mean = mean_rgb(image);
        let _ = writeln!(
            s,
            "{tag} {}: {}x{}, mean RGB ({:.6}, {:.6}, {:.6})",
            path.display(),
            image.width,
            image.height,
            mean.x,
            mean.y,
            mean.z
        );
    }
    let _ = writeln!(s, "relMSE (B is the reference): {:.6e}", m.rel_mse);
    let _ = writeln!(s, "RMSE:                        {:.6e}", m.rmse);
    let _ = write!(s, "relMSE, worst 0.1% trimmed:  {:.6e}", m.rel_mse_trimmed);
    s
}

/// Runs the subcommand: prints the report to stdout.
pub fn run(args: &CompareArgs) -> Result<()> {
    let (_, report) = compare_files(&args.a, &args.b)?;
    crate::console::print_stdout(&format!("{report}\n"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::write_exr;
    use glam::Vec3;

    #[test]
    fn compares_two_small_exrs() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a.exr"), dir.path().join("b.exr"));
        // a = (1, 0, 0.5), (2, 1, 1); b = (1, 0.5, 0), (1, 1, 3): worked out term by term,
        // rel = (0, 0.25/0.26, 0.25/0.01, 1/1.01, 0, 4/9.01), sq = (0, 0.25, 0.25, 1, 0, 4).
        let px = |v: [[f32; 3]; 2]| Image {
            width: 2,
            height: 1,
            pixels: v.map(Vec3::from).to_vec(),
        };
        write_exr(&a, &px([[1.0, 0.0, 0.5], [2.0, 1.0, 1.0]])).unwrap();
        write_exr(&b, &px([[1.0, 0.5, 0.0], [1.0, 1.0, 3.0]])).unwrap();
        let (m, report) = compare_files(&a, &b).unwrap();
        let rel = (0.25 / 0.26 + 25.0 + 1.0 / 1.01 + 4.0 / 9.01) / 6.0;
        assert!((m.rel_mse - rel).abs() < 1e-12, "{}", m.rel_mse);
        assert!((m.rmse - (5.5f64 / 6.0).sqrt()).abs() < 1e-12);
        assert_eq!(m.rel_mse_trimmed, m.rel_mse, "6 terms: nothing to trim");
        assert!(
            report.contains("a.exr: 2x1, mean RGB (1.500000, 0.500000, 0.750000)"),
            "{report}"
        );
        assert!(
            report.contains("b.exr: 2x1, mean RGB (1.000000, 0.750000, 1.500000)"),
            "{report}"
        );
        assert!(report.contains(&format!("{:.6e}", rel)), "{report}");
    }

    #[test]
    fn size_mismatch_and_unreadable_files_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("small.exr"), dir.path().join("large.exr"));
        write_exr(&a, &Image::new(2, 2)).unwrap();
        write_exr(&b, &Image::new(3, 2)).unwrap();
        let err = format!("{:#}", compare_files(&a, &b).unwrap_err());
        assert!(
            err.contains("small.exr") && err.contains("large.exr") && err.contains("2x2"),
            "{err}"
        );
        let err = format!(
            "{:#}",
            compare_files(&a, &dir.path().join("absent.exr")).unwrap_err()
        );
        assert!(err.contains("absent.exr"), "{err}");
    }
}
