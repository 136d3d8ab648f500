//! What SPPM saves to be resumed: its per-pixel statistics (R^2, N, tau) as exact bit patterns.
//!
//! SPPM's iteration k depends on every iteration before it through these statistics, so a
//! saved state can be continued (`--resume`) bit for bit, but slices of a render cannot be
//! merged ([`crate::integrator::Snapshot::append`] refuses states with per-pixel channels).
//! The light paths emitted so far are the photons per iteration times the iterations done;
//! the direct-light average is the snapshot's film.

use super::PixelStatistics;
use crate::integrator::PixelChannel;
use crate::StateError;

/// The statistics' f64 fields, in the order they are saved: each as two u32 channels (low
/// and high word of its bits).
const FIELDS: [&str; 5] = ["r2", "n", "tau.r", "tau.g", "tau.b"];

/// The per-pixel channels a snapshot holds: two u32 words for each of [`FIELDS`].
pub(crate) const CHANNELS: usize = 2 * FIELDS.len();

fn fields(s: &PixelStatistics) -> [f64; 5] {
    [s.r2, s.n, s.tau[0], s.tau[1], s.tau[2]]
}

/// The name of word `word` (0 low, 1 high) of field `field`.
fn channel_name(field: &str, word: usize) -> String {
    format!("sppm.{field}.{}", ["lo", "hi"][word])
}

/// The statistics as channels, bit for bit.
pub(super) fn to_channels(statistics: &[PixelStatistics]) -> Vec<PixelChannel> {
    let mut channels = Vec::with_capacity(CHANNELS);
    for (f, field) in FIELDS.iter().enumerate() {
        for word in 0..2 {
            let values = statistics
                .iter()
                .map(|s| (fields(s)[f].to_bits() >> (32 * word)) as u32)
                .collect();
            channels.push(PixelChannel {
                name: channel_name(field, word),
                values,
            });
        }
    }
    channels
}

/// The statistics of `pixels` pixels back from `channels`; an error names a missing or
/// mis-sized channel (a state saved by another algorithm, or a damaged file).
pub(super) fn from_channels(
    channels: &[PixelChannel],
    pixels: usize,
) -> Result<Vec<PixelStatistics>, StateError> {
    let word = |field: &str, word: usize| -> Result<&[u32], StateError> {
        let name = channel_name(field, word);
        let channel = channels.iter().find(|c| c.name == name).ok_or_else(|| {
            StateError::Unsupported(format!(
                "the saved state has no per-pixel channel '{name}' that sppm needs to resume \
                 (was it saved by another algorithm?)"
            ))
        })?;
        if channel.values.len() != pixels {
            return Err(StateError::Unsupported(format!(
                "per-pixel channel '{name}' has {} values for {pixels} pixels",
                channel.values.len()
            )));
        }
        Ok(&channel.values)
    };
    let mut columns = Vec::with_capacity(FIELDS.len());
    for field in FIELDS {
        columns.push((word(field, 0)?, word(field, 1)?));
    }
    if let Some(extra) = channels.iter().find(|c| {
        !FIELDS
            .iter()
            .any(|f| (0..2).any(|w| channel_name(f, w) == c.name))
    }) {
        return Err(StateError::Unsupported(format!(
            "the saved state has a per-pixel channel '{}' sppm does not use",
            extra.name
        )));
    }
    let value = |f: usize, p: usize| {
        let (lo, hi) = columns[f];
        f64::from_bits(lo[p] as u64 | (hi[p] as u64) << 32)
    };
    Ok((0..pixels)
        .map(|p| PixelStatistics {
            r2: value(0, p),
            n: value(1, p),
            tau: [value(2, p), value(3, p), value(4, p)],
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statistics_round_trip_bit_for_bit() {
        let statistics = vec![
            PixelStatistics {
                r2: 1.0 / 3.0,
                n: 17.25,
                tau: [1e-300, f64::MIN_POSITIVE, 12345.678],
            },
            PixelStatistics::new(0.125),
        ];
        let channels = to_channels(&statistics);
        assert_eq!(channels.len(), 10);
        let back = from_channels(&channels, 2).unwrap();
        for (a, b) in statistics.iter().zip(&back) {
            for (x, y) in fields(a).iter().zip(fields(b)) {
                assert_eq!(x.to_bits(), y.to_bits());
            }
        }
    }

    #[test]
    fn missing_extra_or_short_channels_are_refused() {
        let statistics = vec![PixelStatistics::new(0.5); 3];
        let mut channels = to_channels(&statistics);
        assert!(from_channels(&channels, 4).is_err());
        channels.push(PixelChannel {
            name: "radius2".into(),
            values: vec![0; 3],
        });
        assert!(from_channels(&channels, 3).is_err());
        channels.pop();
        channels.remove(3);
        let e = from_channels(&channels, 3).unwrap_err().to_string();
        assert!(e.contains("sppm.n.hi"), "{e}");
    }
}
