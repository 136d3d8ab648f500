//! Error against a reference during a render: when to measure it (log-spaced iterations) and
//! the samples it gives.

use ppm_core::film::Image;
use ppm_core::metrics::{error_metrics, SizeMismatch};

/// Iterations logged one by one before the spacing becomes logarithmic.
const DENSE_ITERATIONS: u64 = 16;
/// Log points per doubling of the iteration count beyond [`DENSE_ITERATIONS`].
const POINTS_PER_DOUBLING: f64 = 8.0;

/// Which iterations to measure: every one up to 16, then about 8 per doubling (16, 18, 20,
/// 22, 24, 27, ...), so a log-log plot gets evenly spaced points and a long render does not
/// spend its time measuring.
#[derive(Clone, Debug)]
pub struct LogSchedule {
    next: u64,
}

impl Default for LogSchedule {
    fn default() -> Self {
        LogSchedule { next: 1 }
    }
}

impl LogSchedule {
    /// True if `iteration` (counted from 1, called with increasing values) should be measured.
    pub fn due(&mut self, iteration: u64) -> bool {
        if iteration < self.next {
            return false;
        }
        self.next = if iteration < DENSE_ITERATIONS {
            iteration + 1
        } else {
            let step = 2f64.powf(1.0 / POINTS_PER_DOUBLING);
            ((iteration as f64 * step).ceil() as u64).max(iteration + 1)
        };
        true
    }
}

/// One measurement: the error after `iteration` iterations and `seconds` of render time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorSample {
    pub iteration: u64,
    /// Render time, without time spent measuring errors or writing files.
    pub seconds: f64,
    pub rel_mse: f64,
    pub rmse: f64,
}

impl ErrorSample {
    /// `iteration,seconds,relmse,rmse`.
    pub const CSV_HEADER: &'static str = "iteration,seconds,relmse,rmse";

    /// The sample as a CSV row (matching [`ErrorSample::CSV_HEADER`]).
    pub fn csv_row(&self) -> String {
        format!(
            "{},{:.6},{:.6e},{:.6e}",
            self.iteration, self.seconds, self.rel_mse, self.rmse
        )
    }
}

/// Measures a render against its reference on the [`LogSchedule`].
pub struct ErrorTracker {
    reference: Image,
    schedule: LogSchedule,
    last_iteration: u64,
    pub samples: Vec<ErrorSample>,
}

impl ErrorTracker {
    /// A tracker comparing against `reference`.
    pub fn new(reference: Image) -> Self {
        ErrorTracker {
            reference,
            schedule: LogSchedule::default(),
            last_iteration: 0,
            samples: Vec::new(),
        }
    }

    /// Measures `image` if the schedule says so, or if `last` (the final iteration is always
    /// measured). Returns the new sample.
    pub fn observe(
        &mut self,
        iteration: u64,
        seconds: f64,
        last: bool,
        image: impl FnOnce() -> Image,
    ) -> Result<Option<ErrorSample>, SizeMismatch> {
        let due = self.schedule.due(iteration);
        if !(due || last) || iteration == self.last_iteration {
            return Ok(None);
        }
        let m = error_metrics(&image(), &self.reference)?;
        let sample = ErrorSample {
            iteration,
            seconds,
            rel_mse: m.rel_mse,
            rmse: m.rmse,
        };
        self.last_iteration = iteration;
        self.samples.push(sample);
        Ok(Some(sample))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn schedule_is_dense_then_logarithmic() {
        let mut s = LogSchedule::default();
        let logged: Vec<u64> = (1..=64).filter(|&i| s.due(i)).collect();
        let mut expected: Vec<u64> = (1..=16).collect();
        expected.extend([18, 20, 22, 24, 27, 30, 33, 36, 40, 44, 48, 53, 58, 64]);
        assert_eq!(logged, expected);
        // About 8 per doubling far out: 2^10..2^11 holds 8 or 9 points.
        let mut s = LogSchedule::default();
        let n = (1..=2048).filter(|&i| s.due(i) && i > 1024).count();
        assert!((8..=9).contains(&n), "{n}");
    }

    #[test]
    fn tracker_measures_on_schedule_and_at_the_end() {
        let reference = Image {
            width: 1,
            height: 1,
            pixels: vec![Vec3::ONE],
        };
        let mut tracker = ErrorTracker::new(reference);
        let image = |v: f32| {
            move || Image {
                width: 1,
                height: 1,
                pixels: vec![Vec3::splat(v)],
            }
        };
        for i in 1..=17 {
            tracker.observe(i, i as f64, false, image(0.0)).unwrap();
        }
        assert_eq!(tracker.samples.len(), 16, "17 is not on the schedule");
        let last = tracker
            .observe(17, 17.0, true, image(2.0))
            .unwrap()
            .unwrap();
        // (2 - 1)^2 / (1 + 0.01) per channel; RMSE 1.
        assert_eq!(
            last,
            ErrorSample {
                iteration: 17,
                seconds: 17.0,
                rel_mse: 1.0 / 1.01,
                rmse: 1.0
            }
        );
        assert_eq!(last.csv_row(), "17,17.000000,9.900990e-1,1.000000e0");
        assert!(
            tracker
                .observe(17, 17.0, true, image(2.0))
                .unwrap()
                .is_none(),
            "no duplicate"
        );
        let wrong = || Image::new(2, 1);
        assert!(ErrorTracker::new(Image::new(1, 1))
            .observe(1, 0.0, true, wrong)
            .is_err());
    }
}
