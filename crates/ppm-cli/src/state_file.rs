//! The EXR a render writes, with what it takes to continue or join it: the image (R, G, B,
//! f32), the exact film sums as extra u32 channels, any per-pixel state of the integrator, and
//! the provenance attributes. `--resume`, `--shard` and `ppm merge` read it back.
//!
//! Channels: `R`, `G`, `B` (the image, linear f32, what every viewer shows);
//! `ppm.sum.R.0` .. `ppm.sum.B.<k-1>`: each channel's fixed-point sum (u128, 48 fractional
//! bits, see `ppm_core::film`) as u32 words, `.0` the least significant; `ppm.pixel.<name>`:
//! an integrator's per-pixel state ([`ppm_core::integrator::PixelChannel`]). The iteration
//! range and counts are the `ppm.*` attributes ([`Provenance`]).
//!
//! k, the attribute `ppm.sumWords`, is the number of words the largest sum needs (1 to 4):
//! the higher words are zero in every pixel and are not written (state format 2). A sum
//! reaches its third word only past 2^16 (radiance times iterations), so a render of this
//! renderer's scenes usually writes two. Format 1 files (before `ppm.sumWords`) hold all four
//! words, and are read as they are.
//!
//! The `ppm.*` attributes are stored with their EXR types (`state_attributes`), and the
//! camera as pbrt-v4's `worldToCamera` and `worldToNDC` (`camera_matrices`). The file is
//! ZIP-compressed (16 lines a block, lossless: every channel reads back bit for bit); the
//! low words of the sums and the f32 image are noise in their low bits, so it saves less
//! than on a picture (docs/performance.md has the sizes and times). Files written before
//! (uncompressed or RLE, every attribute a string) read as they are.

use crate::camera_matrices::CameraMatrices;
use crate::output::{self, PendingFile};
use crate::provenance::Provenance;
use crate::state_attributes;
use crate::state_check::{self, HashCheck};
use anyhow::{bail, Context, Result};
use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image as ExrImage, Layer,
    LayerAttributes, Text, WritableImage,
};
use ppm_core::film::{Film, FilmParts, Image};
use ppm_core::integrator::{PixelChannel, Snapshot};
use std::collections::BTreeMap;
use std::path::Path;

const RGB: [&str; 3] = ["R", "G", "B"];
const SUM_PREFIX: &str = "ppm.sum.";
/// The attribute giving how many u32 words of each sum are written (state format 2).
const SUM_WORDS: &str = "ppm.sumWords";
const PIXEL_PREFIX: &str = "ppm.pixel.";

/// How the state EXR is encoded: ZIP, 16 scan lines a block (OpenEXR's ZIP_COMPRESSION),
/// lossless.
const COMPRESSED: Encoding = Encoding::SMALL_LOSSLESS;

/// A render's saved state, as read back.
pub struct SavedRender {
    pub provenance: Provenance,
    pub snapshot: Snapshot,
}

/// Writes `image` with the state `snapshot` and `provenance` (whose iteration counts are
/// taken from the snapshot) to a temporary file beside `path`, to be committed as a pair with
/// the PNG ([`output::commit_pair`]). `image` is passed apart from the film: for most
/// integrators it is the film's average, for SPPM the film holds only the direct light.
pub fn pending(
    path: &Path,
    image: &Image,
    snapshot: &Snapshot,
    provenance: &Provenance,
) -> Result<PendingFile> {
    let film = &snapshot.film;
    let mut provenance = provenance.clone();
    provenance.first_iteration = film.first_iteration();
    provenance.iterations = film.iterations();
    provenance.rejected = film.rejected();
    provenance.first_rejected = film.first_rejected();

    let sums = film.sums();
    let words = sum_words(sums);
    let mut channels = Vec::with_capacity(3 + 3 * words + snapshot.pixels.len());
    for (c, name) in RGB.iter().enumerate() {
        let values = image.pixels.iter().map(|p| p[c]).collect();
        channels.push(AnyChannel::new(*name, FlatSamples::F32(values)));
        for word in 0..words {
            let values = sums.iter().map(|s| (s[c] >> (32 * word)) as u32).collect();
            channels.push(AnyChannel::new(
                format!("{SUM_PREFIX}{name}.{word}").as_str(),
                FlatSamples::U32(values),
            ));
        }
    }
    for p in &snapshot.pixels {
        channels.push(AnyChannel::new(
            format!("{PIXEL_PREFIX}{}", p.name).as_str(),
            FlatSamples::U32(p.values.clone()),
        ));
    }
    let named: Vec<(String, &AnyChannel<FlatSamples>)> =
        channels.iter().map(|c| (c.name.to_string(), c)).collect();
    let mut attributes = LayerAttributes {
        software_name: Some(Text::from(
            format!("ppm {}", env!("CARGO_PKG_VERSION")).as_str(),
        )),
        ..LayerAttributes::default()
    };
    let mut text = provenance.to_attributes();
    text.insert(SUM_WORDS, words.to_string());
    let typed: BTreeMap<&str, AttributeValue> = text
        .iter()
        .map(|(k, v)| (*k, state_attributes::to_exr(k, v)))
        .collect();
    let hash = state_check::state_hash(
        (image.width, image.height),
        typed.iter().map(|(k, v)| (*k, v)),
        named
            .iter()
            .map(|(name, c)| (name.as_str(), &c.sample_data)),
    );
    for (name, value) in typed {
        attributes.other.insert(Text::from(name), value);
    }
    attributes.other.insert(
        Text::from(state_check::STATE_HASH),
        AttributeValue::Text(Text::from(state_check::format_hash(hash).as_str())),
    );
    // Standard OpenEXR attributes: the exr crate writes them under their names
    // (`worldToCamera`, `worldToNDC`) from its own fields, and refuses them as custom ones.
    if let Some(camera) = &provenance.camera {
        attributes.world_to_camera = Some(camera.world_to_camera);
        attributes.world_to_normalized_device = Some(camera.world_to_ndc);
    }
    let layer = Layer::new(
        (image.width as usize, image.height as usize),
        attributes,
        COMPRESSED,
        AnyChannels::sort(channels.into()),
    );
    let exr_image = ExrImage::from_layer(layer);
    PendingFile::write(path, |w| {
        exr_image
            .write()
            .to_buffered(w)
            .map_err(|e| anyhow::anyhow!("{e}"))
    })
}

/// How many u32 words (1 to 4) hold every sum of `sums`: the words above are zero in every
/// pixel and channel.
fn sum_words(sums: &[[u128; 3]]) -> usize {
    let all = sums.iter().flatten().fold(0u128, |a, s| a | s);
    let bits = (u128::BITS - all.leading_zeros()) as usize;
    bits.div_ceil(32).max(1)
}

/// Writes the PNG and the EXR (with state) of a render as a pair: neither replaces its
/// target unless both were written in full.
pub fn write_image_and_state(
    paths: &output::OutputPaths,
    image: &Image,
    snapshot: &Snapshot,
    provenance: &Provenance,
) -> Result<()> {
    output::commit_pair(
        paths,
        || output::pending_png(&paths.png, image),
        || pending(&paths.exr, image, snapshot, provenance),
    )
}

/// Reads a render's saved state from an EXR written by [`write`]; errors name the file and
/// what is missing or wrong.
pub fn read(path: &Path) -> Result<SavedRender> {
    let exr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if !exr {
        bail!(
            "{} is not an EXR: only the EXR a render writes holds its state (the PNG beside it \
             does not)",
            path.display()
        );
    }
    read_inner(path).with_context(|| format!("cannot read the render state of {}", path.display()))
}

fn read_inner(path: &Path) -> Result<SavedRender> {
    use exr::prelude::{ReadChannels, ReadLayers};
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let layer = &image.layer_data;
    let (width, height) = (layer.size.width() as u32, layer.size.height() as u32);
    // Every attribute as text (typed ones as the text they were written from), and the
    // `ppm.*` ones as stored, for the checksum.
    let other = &layer.attributes.other;
    let attributes: BTreeMap<String, String> = other
        .iter()
        .filter_map(|(k, v)| Some((k.to_string(), state_attributes::to_text(v)?)))
        .collect();
    let stored: Vec<(String, &AttributeValue)> =
        other.iter().map(|(k, v)| (k.to_string(), v)).collect();
    let mut provenance = Provenance::from_attributes(&attributes, (width, height))?;
    if let (Some(world_to_camera), Some(world_to_ndc)) = (
        layer.attributes.world_to_camera,
        layer.attributes.world_to_normalized_device,
    ) {
        provenance.camera = Some(CameraMatrices {
            world_to_camera,
            world_to_ndc,
        });
    }
    let named: Vec<(String, &FlatSamples)> = layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), &c.sample_data))
        .collect();
    let hash = state_check::state_hash(
        (width, height),
        stored.iter().map(|(k, v)| (k.as_str(), *v)),
        named
            .iter()
            .map(|(name, samples)| (name.as_str(), *samples)),
    );
    if state_check::verify_hash(
        attributes.get(state_check::STATE_HASH).map(|s| s.as_str()),
        hash,
    )? == HashCheck::Absent
    {
        status!(
            "warning: {} has no checksum ({}: written by an older ppm); its contents cannot be \
             verified",
            path.display(),
            state_check::STATE_HASH
        );
    }
    state_check::check_header(&state_check::Header {
        width,
        height,
        first_iteration: provenance.first_iteration,
        iterations: provenance.iterations,
        rejected: provenance.rejected,
        first_rejected: provenance.first_rejected,
    })?;

    let pixel_count = width as usize * height as usize;
    let mut channels: BTreeMap<String, &[u32]> = BTreeMap::new();
    for channel in &layer.channel_data.list {
        if let FlatSamples::U32(values) = &channel.sample_data {
            if values.len() != pixel_count {
                bail!("channel {} has {} samples", channel.name, values.len());
            }
            channels.insert(channel.name.to_string(), values.as_slice());
        }
    }
    // Format 1 wrote all four words; format 2 says how many it wrote (the rest are zero).
    let words = match attributes.get(SUM_WORDS) {
        None if attributes.get("ppm.state").map(String::as_str) == Some("1") => 4,
        None => bail!("attribute {SUM_WORDS} is missing"),
        Some(w) => match w.parse::<usize>() {
            Ok(w @ 1..=4) => w,
            _ => bail!("attribute {SUM_WORDS} is {w:?}, not a number of words from 1 to 4"),
        },
    };
    state_check::check_sum_channels(words, channels.keys().map(String::as_str), SUM_PREFIX)?;
    let mut sum = vec![[0u128; 3]; pixel_count];
    for (c, name) in RGB.iter().enumerate() {
        for word in 0..words {
            let channel = format!("{SUM_PREFIX}{name}.{word}");
            let values = channels
                .get(&channel)
                .with_context(|| format!("channel {channel} (u32) is missing"))?;
            for (s, v) in sum.iter_mut().zip(values.iter()) {
                s[c] |= (*v as u128) << (32 * word);
            }
        }
    }
    let film = Film::from_parts(FilmParts {
        width,
        height,
        sum,
        first_iteration: provenance.first_iteration,
        iterations: provenance.iterations,
        rejected: provenance.rejected,
        first_rejected: provenance.first_rejected,
    })?;
    let pixels: Vec<PixelChannel> = channels
        .iter()
        .filter_map(|(name, values)| {
            name.strip_prefix(PIXEL_PREFIX).map(|n| PixelChannel {
                name: n.to_string(),
                values: values.to_vec(),
            })
        })
        .collect();
    if pixels.is_empty() {
        check_image_against_sums(layer, &film)?;
    }
    Ok(SavedRender {
        provenance,
        snapshot: Snapshot { film, pixels },
    })
}

/// Without per-pixel integrator state the image is the film's average: its R, G, B must be
/// the sums divided by the iteration count, bit for bit (a file whose image and sums
/// disagree would resume or merge into another image than the one it shows).
fn check_image_against_sums(layer: &Layer<AnyChannels<FlatSamples>>, film: &Film) -> Result<()> {
    let average = film.image();
    for (c, name) in RGB.iter().enumerate() {
        let Some(channel) = layer.channel_data.list.iter().find(|ch| ch.name.eq(name)) else {
            bail!("channel {name} is missing");
        };
        let FlatSamples::F32(values) = &channel.sample_data else {
            bail!("channel {name} is not f32");
        };
        let wrong = values
            .iter()
            .zip(&average.pixels)
            .position(|(v, a)| v.to_bits() != a[c].to_bits());
        if let Some(i) = wrong {
            bail!(
                "channel {name} of pixel {i} is {}, but its sums over {} iterations give {}: \
                 the image and its state disagree",
                values[i],
                film.iterations(),
                average.pixels[i][c]
            );
        }
    }
    Ok(())
}
