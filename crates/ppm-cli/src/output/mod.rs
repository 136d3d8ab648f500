//! Image files: output naming, the writability check, atomic writes, PNG and EXR writers and
//! readers.
//!
//! Every render writes two files with one stem: an 8-bit sRGB PNG for looking at and a linear
//! f32 EXR for measuring. Files are written to a temporary name in the target folder and
//! renamed over the target, so an interrupted or failed write never leaves a truncated file
//! where a good one was.

use anyhow::{bail, Context, Result};
use glam::Vec3;
use ppm_core::film::Image;
use std::fs::{self, File, OpenOptions};
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The two files of one rendered image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutputPaths {
    pub png: PathBuf,
    pub exr: PathBuf,
}

/// Image formats ppm does not write: `-o out.jpg` is refused rather than read as a name.
const OTHER_IMAGE_EXTENSIONS: &[&str] = &[
    "jpg", "jpeg", "tif", "tiff", "hdr", "bmp", "gif", "webp", "tga", "pfm", "ppm", "pgm",
];

/// The PNG and EXR paths for `-o output` (or its absence) when rendering `scene`.
///
/// `out.png`, `out.exr` and `out` all give `out.png` + `out.exr`; an existing folder (or a path
/// ending in `/`) receives `<scene stem>.png/.exr`; without `-o` those go to the current folder.
/// Only `.png` and `.exr` (any case) are taken as extensions and replaced; another image
/// format's extension (`.jpg`, `.hdr`...) is refused; any other suffix is part of the name:
/// `shot.0001` gives `shot.0001.png` + `shot.0001.exr`.
pub fn output_paths(output: Option<&Path>, scene: &Path) -> Result<OutputPaths> {
    let stem = scene
        .file_stem()
        .with_context(|| format!("scene path {} has no file name", scene.display()))?;
    let base = match output {
        None => PathBuf::from(stem),
        Some(o) if o.is_dir() || o.as_os_str().to_string_lossy().ends_with(['/', '\\']) => {
            o.join(stem)
        }
        Some(o) => match o
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
        {
            None => o.to_path_buf(),
            Some(e) if e == "png" || e == "exr" => o.with_extension(""),
            Some(e) if OTHER_IMAGE_EXTENSIONS.contains(&e.as_str()) => bail!(
                "output {}: unsupported extension .{e}; use .png, .exr or none \
                 (a PNG and an EXR are always both written)",
                o.display()
            ),
            // `shot.0001`, `render.v2`: a dot in a name is not always an extension.
            Some(_) => o.to_path_buf(),
        },
    };
    Ok(OutputPaths {
        png: with_added_extension(&base, "png"),
        exr: with_added_extension(&base, "exr"),
    })
}

impl OutputPaths {
    /// The EXR of an extra image `name` next to the render: `out.exr` gives `out.<name>.exr`.
    pub fn aov(&self, name: &str) -> PathBuf {
        with_added_extension(&self.exr.with_extension(""), &format!("{name}.exr"))
    }
}

/// `base` + `.ext`, keeping any dots already in the file name.
fn with_added_extension(base: &Path, ext: &str) -> PathBuf {
    let mut s = base.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// The folder a file path lives in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A fresh name for a temporary file next to `path` (hidden, unique within this process):
/// `.<file name>.<tag>-<pid>-<counter>`. [`crate::stale`] recognises exactly this pattern.
pub(crate) fn temp_sibling(path: &Path, tag: &str) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    parent_dir(path).join(format!(".{name}.{tag}-{}-{n}", std::process::id()))
}

/// Fails unless a file can be created at `path`: its folder must exist and accept a new file
/// (tried by creating and deleting a temporary one), and `path` must not be a folder.
/// Called before rendering so that a long render never ends in an unwritable path.
pub fn check_writable(path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    if !dir.is_dir() {
        bail!(
            "cannot write {}: folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    if path.is_dir() {
        bail!("cannot write {}: it is a folder", path.display());
    }
    let probe = temp_sibling(path, "write-test");
    OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .with_context(|| {
            format!(
                "cannot write {}: folder {} is not writable",
                path.display(),
                dir.display()
            )
        })?;
    let _ = fs::remove_file(&probe);
    Ok(())
}

/// A file written in full (and synced) under a temporary name next to its target, waiting to
/// be renamed over it by [`PendingFile::commit`]. Dropped uncommitted, it removes itself.
pub struct PendingFile {
    temp: PathBuf,
    path: PathBuf,
    committed: bool,
}

impl PendingFile {
    /// Writes `path`'s future content to a temporary file: `write` fills it, then it is
    /// synced. On any error the temporary file is removed; `path` is never touched.
    pub fn write(
        path: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
    ) -> Result<PendingFile> {
        let pending = PendingFile {
            temp: temp_sibling(path, "tmp"),
            path: path.to_path_buf(),
            committed: false,
        };
        (|| -> Result<()> {
            let file = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&pending.temp)?;
            let mut writer = BufWriter::new(file);
            write(&mut writer)?;
            let file = writer.into_inner().map_err(|e| e.into_error())?;
            file.sync_all()?;
            Ok(())
        })()
        .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(pending)
    }

    /// Renames the temporary file over the target (atomic within a file system).
    pub fn commit(mut self) -> Result<()> {
        fs::rename(&self.temp, &self.path)
            .with_context(|| format!("cannot write {}", self.path.display()))?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// Writes a file atomically: `write` fills a temporary file in the same folder, which is then
/// synced and renamed over `path`. On any error the temporary file is removed and `path` keeps
/// its old content.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    PendingFile::write(path, write)?.commit()
}

/// The sRGB opto-electronic transfer function (IEC 61966-2-1): linear [0, 1] to encoded [0, 1].
pub fn srgb_oetf(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`srgb_oetf`]: encoded [0, 1] to linear.
pub fn srgb_eotf(encoded: f32) -> f32 {
    if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value as an 8-bit sRGB code: clamped to [0, 1] (NaN to 0), encoded, rounded.
pub fn encode_srgb8(linear: f32) -> u8 {
    let v = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    (srgb_oetf(v) * 255.0 + 0.5) as u8
}

/// An image as interleaved 8-bit sRGB.
pub fn to_srgb8(image: &Image) -> Vec<u8> {
    image
        .pixels
        .iter()
        .flat_map(|p| p.to_array().map(encode_srgb8))
        .collect()
}

/// Writes interleaved 8-bit RGB as a PNG, atomically.
pub fn write_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    pending_png_rgb8(path, width, height, rgb)?.commit()
}

fn pending_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<PendingFile> {
    use image::ImageEncoder;
    PendingFile::write(path, |w| {
        image::codecs::png::PngEncoder::new(w).write_image(
            rgb,
            width,
            height,
            image::ExtendedColorType::Rgb8,
        )?;
        Ok(())
    })
}

/// Writes an image as an sRGB 8-bit PNG, atomically (renders write PNG and EXR as a pair with
/// [`write_outputs`]).
#[cfg(test)]
pub fn write_png(path: &Path, image: &Image) -> Result<()> {
    pending_png(path, image)?.commit()
}

/// A PNG of `image` written to a temporary file, to be committed (see [`commit_pair`]).
pub fn pending_png(path: &Path, image: &Image) -> Result<PendingFile> {
    pending_png_rgb8(path, image.width, image.height, &to_srgb8(image))
}

/// Writes an image as a linear RGB f32 OpenEXR file, atomically, without a render state (an
/// AOV; renders write theirs with `state_file`).
pub fn write_exr(path: &Path, image: &Image) -> Result<()> {
    pending_exr(path, image)?.commit()
}

fn pending_exr(path: &Path, image: &Image) -> Result<PendingFile> {
    use exr::prelude::{Image as ExrImage, SpecificChannels, WritableImage};
    let channels = SpecificChannels::rgb(|exr::math::Vec2(x, y)| {
        let p = image.get(x as u32, y as u32);
        (p.x, p.y, p.z)
    });
    let exr_image =
        ExrImage::from_channels((image.width as usize, image.height as usize), channels);
    PendingFile::write(path, |w| {
        exr_image
            .write()
            .to_buffered(w)
            .map_err(|e| anyhow::anyhow!("{e}"))
    })
}

/// Commits a PNG and an EXR written in full to temporary files ([`PendingFile`]) as a pair:
/// both were written before either is renamed over its target, so a full disk or any other
/// write error leaves the previous PNG and EXR both as they were (never a new PNG beside an
/// old EXR). The error says which files were replaced. The two files are encoded and written
/// at the same time, on two threads (the EXR's render state makes it the longer of the two).
pub fn commit_pair(
    paths: &OutputPaths,
    png: impl FnOnce() -> Result<PendingFile> + Send,
    exr: impl FnOnce() -> Result<PendingFile> + Send,
) -> Result<()> {
    let kept = || {
        format!(
            "neither {} nor {} was replaced",
            paths.png.display(),
            paths.exr.display()
        )
    };
    let (png, exr) = std::thread::scope(|scope| {
        let exr = scope.spawn(exr);
        let png = png();
        let exr = exr
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (png, exr)
    });
    let png = png.with_context(kept)?;
    let exr = exr.with_context(kept)?;
    png.commit().with_context(kept)?;
    exr.commit().with_context(|| {
        format!(
            "{} was replaced but {} was not: the two files are from different renders",
            paths.png.display(),
            paths.exr.display()
        )
    })
}

/// Reads an image as linear RGB: an OpenEXR file (its R, G, B channels), a Radiance .hdr file
/// (what other renderers, SmallVCM among them, write) or, as a convenience, a PNG (decoded
/// from sRGB).
pub fn read_image(path: &Path) -> Result<Image> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("exr") => read_exr(path),
        Some("hdr") => read_hdr(path),
        Some("png") => read_png(path),
        _ => bail!(
            "cannot read {}: expected an .exr, .hdr or .png file",
            path.display()
        ),
    }
    .with_context(|| format!("cannot read image {}", path.display()))
}

fn read_exr(path: &Path) -> Result<Image> {
    let exr_image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| Image::new(size.width() as u32, size.height() as u32),
        |image: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            let i = pos.y() * image.width as usize + pos.x();
            image.pixels[i] = Vec3::new(r, g, b);
        },
    )
    // exr's errors repeat their io::Error as their source: keep the message only.
    .map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok(exr_image.layer_data.channel_data.pixels)
}

fn read_hdr(path: &Path) -> Result<Image> {
    // Radiance RGBE decodes to linear floats; no transfer curve to undo.
    read_rgb(path, image::ImageFormat::Hdr, |c| c)
}

fn read_png(path: &Path) -> Result<Image> {
    // to_rgb32f maps the codes to [0, 1] (of 255 or 65535) without touching the transfer curve.
    read_rgb(path, image::ImageFormat::Png, srgb_eotf)
}

/// Decodes `path` as `format` to RGB floats and maps each channel by `to_linear`.
fn read_rgb(path: &Path, format: image::ImageFormat, to_linear: fn(f32) -> f32) -> Result<Image> {
    let reader = BufReader::new(File::open(path)?);
    let rgb = image::ImageReader::with_format(reader, format)
        .decode()?
        .to_rgb32f();
    Ok(Image {
        width: rgb.width(),
        height: rgb.height(),
        pixels: rgb
            .pixels()
            .map(|p| Vec3::from(p.0.map(to_linear)))
            .collect(),
    })
}

/// Creates (truncating) a plain file for a log that grows during the render.
pub fn create_log(path: &Path) -> Result<BufWriter<File>> {
    let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    Ok(BufWriter::new(file))
}

/// Writes one line to a log and flushes it, so a log is useful even if the run stops early.
pub fn log_line(log: &mut BufWriter<File>, path: &Path, line: &str) -> Result<()> {
    writeln!(log, "{line}")
        .and_then(|_| log.flush())
        .with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> PathBuf {
        PathBuf::from(s)
    }

    #[test]
    fn output_naming_rules() {
        let scene = Path::new("scenes/cornell_box_water.yml");
        let both = |png: &str, exr: &str| OutputPaths {
            png: p(png),
            exr: p(exr),
        };
        assert_eq!(
            output_paths(None, scene).unwrap(),
            both("cornell_box_water.png", "cornell_box_water.exr")
        );
        for o in ["out.png", "out.exr", "out", "out.PNG"] {
            assert_eq!(
                output_paths(Some(Path::new(o)), scene).unwrap(),
                both("out.png", "out.exr"),
                "{o}"
            );
        }
        assert_eq!(
            output_paths(Some(Path::new("renders/a.b.exr")), scene).unwrap(),
            both("renders/a.b.png", "renders/a.b.exr")
        );
        assert_eq!(
            output_paths(Some(Path::new("renders/")), scene).unwrap(),
            both(
                "renders/cornell_box_water.png",
                "renders/cornell_box_water.exr"
            )
        );
        let dir = tempfile::tempdir().unwrap();
        let got = output_paths(Some(dir.path()), scene).unwrap();
        assert_eq!(got.png, dir.path().join("cornell_box_water.png"));
        let err = output_paths(Some(Path::new("out.jpg")), scene)
            .unwrap_err()
            .to_string();
        assert!(err.contains("out.jpg") && err.contains(".jpg"), "{err}");
    }

    #[test]
    fn srgb_encoding_values() {
        assert_eq!(encode_srgb8(0.0), 0);
        // The linear segment ends at 0.0031308 -> 0.040450 -> 10.31 of 255.
        assert!((srgb_oetf(0.003_130_8) - 0.040_45).abs() < 1e-6);
        assert_eq!(encode_srgb8(0.003_130_8), 10);
        // 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357 -> 187.52 of 255.
        assert!((srgb_oetf(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(encode_srgb8(0.5), 188);
        assert_eq!(encode_srgb8(1.0), 255);
        assert_eq!(encode_srgb8(7.5), 255);
        assert_eq!(encode_srgb8(-1.0), 0);
        assert_eq!(encode_srgb8(f32::NAN), 0);
        assert_eq!(encode_srgb8(f32::INFINITY), 255);
        // The two pieces meet: the curve is continuous at the break point.
        let below = srgb_oetf(0.003_130_8 - 1e-7);
        let above = srgb_oetf(0.003_130_8 + 1e-7);
        assert!((above - below).abs() < 1e-5);
        for code in 0..=255u8 {
            let linear = srgb_eotf(code as f32 / 255.0);
            assert_eq!(
                encode_srgb8(linear),
                code,
                "sRGB code {code} does not round-trip"
            );
        }
    }

    fn test_image() -> Image {
        let mut image = Image::new(5, 3);
        for (i, px) in image.pixels.iter_mut().enumerate() {
            // Values an 8-bit format could not hold: tiny, huge, irrational-looking.
            *px = Vec3::new(
                i as f32 * 0.173_2,
                1e-6 * i as f32,
                1000.0 / (i as f32 + 1.0),
            );
        }
        image
    }

    #[test]
    fn exr_round_trip_is_exact() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let image = test_image();
        write_exr(&path, &image).unwrap();
        let back = read_image(&path).unwrap();
        assert_eq!(back, image);
    }

    #[test]
    fn png_round_trip_is_within_one_code() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let mut image = Image::new(4, 2);
        let values = [0.0, 0.001, 0.02, 0.18, 0.5, 0.9, 1.0, 3.0];
        for (px, v) in image.pixels.iter_mut().zip(values) {
            *px = Vec3::new(v, v * 0.5, 1.0 - v.min(1.0));
        }
        write_png(&path, &image).unwrap();
        let back = read_image(&path).unwrap();
        assert_eq!((back.width, back.height), (4, 2));
        for (a, b) in back.pixels.iter().zip(&image.pixels) {
            for (x, y) in a.to_array().into_iter().zip(b.to_array()) {
                assert_eq!(encode_srgb8(x), encode_srgb8(y));
            }
        }
    }

    /// A Radiance file (written by the image crate's encoder) reads back top row first, in
    /// R, G, B order, within RGBE's precision (8 mantissa bits under the largest channel).
    #[test]
    fn hdr_reads_in_order_within_rgbe_precision() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("other_renderer.hdr");
        let (width, height) = (3, 2);
        let pixels: Vec<Vec3> = (0..width * height)
            .map(|i| Vec3::new(1.0 + i as f32, 0.5 * i as f32, 0.03 * (5 - i) as f32))
            .collect();
        let rgb: Vec<image::Rgb<f32>> = pixels.iter().map(|p| image::Rgb(p.to_array())).collect();
        let file = BufWriter::new(File::create(&path).unwrap());
        image::codecs::hdr::HdrEncoder::new(file)
            .encode(&rgb, width, height)
            .unwrap();
        let back = read_image(&path).unwrap();
        assert_eq!((back.width, back.height), (width as u32, height as u32));
        for (i, (a, b)) in back.pixels.iter().zip(&pixels).enumerate() {
            let tolerance = b.max_element() / 128.0;
            assert!(
                (*a - *b).abs().max_element() <= tolerance,
                "pixel {i}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_temp_files() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.exr");
        write_exr(&path, &test_image()).unwrap();
        write_png(&dir.path().join("out.png"), &test_image()).unwrap();
        // A failing writer must keep the old file and remove its temporary file.
        let before = fs::read(&path).unwrap();
        let err = write_atomic(&path, |w| {
            w.write_all(b"partial")?;
            bail!("disk full")
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("out.exr"), "{err:#}");
        assert_eq!(fs::read(&path).unwrap(), before);
        let mut names: Vec<String> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["out.exr", "out.png"]);
    }

    #[test]
    fn writability_check_names_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        check_writable(&dir.path().join("fine.png")).unwrap();
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            0,
            "the probe file must be deleted"
        );

        let missing = dir.path().join("no_such_folder").join("x.png");
        let err = check_writable(&missing).unwrap_err().to_string();
        assert!(
            err.contains("no_such_folder") && err.contains("does not exist"),
            "{err}"
        );

        // A regular file used as a folder: not writable even for root.
        let file = dir.path().join("plain_file");
        fs::write(&file, b"x").unwrap();
        let err = check_writable(&file.join("x.png")).unwrap_err().to_string();
        assert!(err.contains("plain_file"), "{err}");

        let err = check_writable(dir.path()).unwrap_err().to_string();
        assert!(err.contains("is a folder"), "{err}");
    }

    #[cfg(unix)]
    #[test]
    fn writability_check_fails_on_a_read_only_folder() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let ro = dir.path().join("read_only");
        fs::create_dir(&ro).unwrap();
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
        // Root ignores permissions; the check can only be asked to fail where writing fails.
        let writing_fails = File::create(ro.join("probe")).is_err();
        let result = check_writable(&ro.join("x.png"));
        fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
        if writing_fails {
            let err = result.unwrap_err().to_string();
            assert!(
                err.contains("read_only") && err.contains("not writable"),
                "{err}"
            );
        } else {
            result.unwrap();
        }
    }

    #[test]
    fn unreadable_images_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.exr");
        assert!(format!("{:#}", read_image(&missing).unwrap_err()).contains("missing.exr"));
        let garbage = dir.path().join("garbage.exr");
        fs::write(&garbage, b"not an exr").unwrap();
        assert!(format!("{:#}", read_image(&garbage).unwrap_err()).contains("garbage.exr"));
        let err = format!("{:#}", read_image(Path::new("x.tiff")).unwrap_err());
        assert!(err.contains("x.tiff") && err.contains(".exr"), "{err}");
        let garbage = dir.path().join("garbage.hdr");
        fs::write(&garbage, b"#?RADIANCE\nnot a header").unwrap();
        assert!(format!("{:#}", read_image(&garbage).unwrap_err()).contains("garbage.hdr"));
    }
}
