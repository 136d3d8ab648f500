//! Refusing a render that cannot fit in memory, before allocating it: the integrator states
//! what it will allocate ([`Renderer::memory_estimate`]), this compares it with the memory
//! available, and a render that does not fit ends with an error naming the setting to lower,
//! instead of "memory allocation failed" and SIGABRT half-way.

use crate::process_limits::gib;
use anyhow::{bail, Context, Result};
use ppm_core::integrator::{MemoryPart, RenderSettings, Renderer, Snapshot};
use ppm_core::scene::Scene;

/// Environment variable that replaces the available memory (bytes, or with a K, M, G or T
/// suffix in powers of 1024) by a budget for the whole process, the scene already loaded
/// included: set it to allow a render the check refuses, or to test.
pub const MEMORY_LIMIT_VAR: &str = "PPM_MEMORY_LIMIT";

/// Bytes per pixel the output step allocates besides the snapshot: the f32 RGB image it
/// writes, the EXR's f32 RGB channels and the 8-bit PNG.
const OUTPUT_BYTES_PER_PIXEL: u64 = 12 + 12 + 3;

/// Where the limit came from and its value.
struct Limit {
    bytes: u64,
    source: String,
    /// The limit is the whole process's (`PPM_MEMORY_LIMIT`), not what is still free.
    whole_process: bool,
}

/// Errors if the render of `scene` with `settings` needs more memory than is available.
pub fn check(scene: &Scene, settings: &RenderSettings) -> Result<()> {
    let Some(limit) = limit()? else {
        return Ok(()); // nothing known about the machine: no check
    };
    let estimate = Renderer::memory_estimate(scene, settings);
    let (w, h) = (scene.camera.width, scene.camera.height);
    // What the process holds already (the scene and its BVH, loaded before this check):
    // part of a PPM_MEMORY_LIMIT budget; MemAvailable has it taken off already.
    let loaded = if limit.whole_process {
        crate::progress::rss_bytes().unwrap_or(0)
    } else {
        0
    };
    let saved = Snapshot::estimate_bytes(w, h, settings.algorithm);
    let total = loaded.saturating_add(peak_bytes(estimate.total(), saved, w as u64 * h as u64));
    if total <= limit.bytes {
        return Ok(());
    }
    let mut parts: Vec<String> = estimate
        .items
        .iter()
        .map(|item| format!("{} {}", part_name(item.part), gib(item.bytes)))
        .collect();
    parts.push(format!("saving the render state {}", gib(saved)));
    if limit.whole_process {
        parts.push(format!("the loaded scene {}", gib(loaded)));
    }
    let culprit = match estimate.largest().map(|item| item.part) {
        Some(MemoryPart::Photons) => format!(
            "--photons {} (light paths per iteration; or render.photons in the scene)",
            settings.photons
        ),
        Some(MemoryPart::Pilot) => {
            "the pilot photon map of the default radius (--radius with a number, or footprint)"
                .to_string()
        }
        _ => format!("the resolution {w}x{h} (--width/--height, or the scene's resolution)"),
    };
    bail!(
        "not enough memory: this render needs about {} ({}) but {} is available ({}); \
         lower {culprit}, or set {MEMORY_LIMIT_VAR} to override",
        gib(total),
        parts.join(", "),
        gib(limit.bytes),
        limit.source
    )
}

/// The most a render of `pixels` pixels holds at once, from what its renderer allocates
/// (`renderer`): at its end the renderer and the `snapshot` it hands over for saving
/// ([`Snapshot::estimate_bytes`]); then, the renderer gone, the snapshot, its copy as EXR
/// channels (each sum as at most four u32 words: the film's own size), the ZIP-compressed
/// blocks the encoder may hold before they are written (at most the channels' size again:
/// data that does not compress) and the images.
fn peak_bytes(renderer: u64, snapshot: u64, pixels: u64) -> u64 {
    let images = pixels.saturating_mul(OUTPUT_BYTES_PER_PIXEL);
    let ending = renderer.saturating_add(snapshot);
    let writing = snapshot.saturating_mul(3).saturating_add(images);
    ending.max(writing)
}

fn part_name(part: MemoryPart) -> &'static str {
    match part {
        MemoryPart::Image => "image buffers",
        MemoryPart::Photons => "photon buffer and grid",
        MemoryPart::Pilot => "the photons radius's pilot photon map",
    }
}

/// Virtual memory the render maps after the check besides its buffers, which RLIMIT_AS
/// counts: the worker threads' stacks (2 MiB each in Rust) and the output step's encoders.
/// 256 MiB covers 64 threads and leaves half for the rest.
const LATER_MAPPINGS: u64 = 256 << 20;

/// The memory a render may use: [`MEMORY_LIMIT_VAR`] if set, else the least of MemAvailable
/// from /proc/meminfo and what is left under the process's own limits
/// ([`crate::process_limits`]: `ulimit -v`, `ulimit -d`, a cgroup's memory limit); `None`
/// where none of them is known.
fn limit() -> Result<Option<Limit>> {
    if let Ok(value) = std::env::var(MEMORY_LIMIT_VAR) {
        let bytes = parse_bytes(&value).with_context(|| {
            format!("{MEMORY_LIMIT_VAR}={value}: expected a number of bytes, e.g. 8G or 500M")
        })?;
        return Ok(Some(Limit {
            bytes,
            source: format!("{MEMORY_LIMIT_VAR}={value}"),
            whole_process: true,
        }));
    }
    let free = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|meminfo| mem_available(&meminfo))
        .map(|bytes| Limit {
            bytes,
            source: "MemAvailable in /proc/meminfo".to_string(),
            whole_process: false,
        });
    let own = crate::process_limits::limits().into_iter().map(|l| {
        let later = if l.source.starts_with("RLIMIT_AS") {
            LATER_MAPPINGS
        } else {
            0
        };
        Limit {
            bytes: l.left.saturating_sub(later),
            source: if later > 0 {
                format!("{}, less {} for thread stacks", l.source, gib(later))
            } else {
                l.source
            },
            whole_process: false,
        }
    });
    Ok(free.into_iter().chain(own).min_by_key(|l| l.bytes))
}

/// MemAvailable (given in kB) from the text of /proc/meminfo, in bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// `123`, `64K`, `500M`, `8G`, `1T` (powers of 1024; an optional `B` or `iB` after the unit).
fn parse_bytes(s: &str) -> Option<u64> {
    let s = s.trim();
    let s = s
        .strip_suffix("iB")
        .or_else(|| s.strip_suffix('B'))
        .unwrap_or(s);
    let (digits, shift) = match s.chars().last()?.to_ascii_uppercase() {
        'K' => (&s[..s.len() - 1], 10),
        'M' => (&s[..s.len() - 1], 20),
        'G' => (&s[..s.len() - 1], 30),
        'T' => (&s[..s.len() - 1], 40),
        _ => (s, 0),
    };
    let n: u64 = digits.trim().parse().ok()?;
    n.checked_mul(1u64 << shift)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_sizes_parse() {
        assert_eq!(parse_bytes("123"), Some(123));
        assert_eq!(parse_bytes("64K"), Some(64 << 10));
        assert_eq!(parse_bytes("500M"), Some(500 << 20));
        assert_eq!(parse_bytes("8G"), Some(8 << 30));
        assert_eq!(parse_bytes("8GiB"), Some(8 << 30));
        assert_eq!(parse_bytes("2t"), Some(2 << 40));
        for bad in ["", "G", "-1", "1.5G", "lots", "99999999999T"] {
            assert_eq!(parse_bytes(bad), None, "{bad}");
        }
    }

    #[test]
    fn mem_available_is_read_in_bytes() {
        let text = "MemTotal:       24000000 kB\nMemFree:  100 kB\nMemAvailable:   22000000 kB\n";
        assert_eq!(mem_available(text), Some(22_000_000 * 1024));
        assert_eq!(mem_available("MemTotal: 1 kB\n"), None);
    }
}
