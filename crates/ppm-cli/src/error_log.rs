//! Error against a reference during a render: when to measure it (log-spaced iterations) and
//! the samples it gives.

use crate::output;
use anyhow::Result;
use ppm_core::film::Image;
use ppm_core::metrics::{error_metrics, SizeMismatch};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

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

/// The `--error-log` CSV being written. A line that cannot be written (a full disk) ends the
/// log, not the render: [`ErrorLog::record`] hands back the warning to print.
pub struct ErrorLog<W: Write> {
    out: Option<W>,
    path: PathBuf,
}

impl ErrorLog<BufWriter<File>> {
    /// Opens the log and writes its header. A render that continues an earlier one of
    /// `continues_after` iterations (`--resume`, > 0) keeps the rows the file has for those
    /// iterations, so that the log goes on where that render's left off; rows past them
    /// (logged after the checkpoint it resumes) are dropped, and a file that is not such a
    /// log is replaced, as for any other run.
    pub fn open(path: &Path, continues_after: u64) -> Result<Self> {
        let kept: Vec<String> = match continues_after {
            0 => Vec::new(),
            _ => std::fs::read_to_string(path)
                .ok()
                .filter(|text| text.lines().next() == Some(ErrorSample::CSV_HEADER))
                .map(|text| {
                    text.lines()
                        .skip(1)
                        .take_while(|row| {
                            row.split(',')
                                .next()
                                .and_then(|i| i.parse::<u64>().ok())
                                .is_some_and(|i| i <= continues_after)
                        })
                        .map(str::to_string)
                        .collect()
                })
                .unwrap_or_default(),
        };
        let mut out = output::create_log(path)?;
        output::log_line(&mut out, path, ErrorSample::CSV_HEADER)?;
        for row in &kept {
            output::log_line(&mut out, path, row)?;
        }
        Ok(ErrorLog {
            out: Some(out),
            path: path.to_path_buf(),
        })
    }
}

impl<W: Write> ErrorLog<W> {
    /// Appends a sample's row and flushes it. On failure the log is closed for good and the
    /// warning to print is returned; the render goes on.
    pub fn record(&mut self, sample: &ErrorSample) -> Option<String> {
        let out = self.out.as_mut()?;
        let written = writeln!(out, "{}", sample.csv_row()).and_then(|_| out.flush());
        written.err().map(|e| {
            self.out = None;
            format!(
                "warning: cannot write {}: {e}; the error log stops here, the render goes on",
                self.path.display()
            )
        })
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

    /// A writer that accepts `room` bytes, then fails as a full disk does.
    struct FullAfter {
        room: usize,
    }

    impl Write for FullAfter {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if buf.len() > self.room {
                return Err(std::io::Error::from_raw_os_error(28)); // ENOSPC
            }
            self.room -= buf.len();
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    /// A log that fills the disk stops with one warning and never fails the render.
    #[test]
    fn a_full_disk_ends_the_log_with_a_warning() {
        let sample = |iteration| ErrorSample {
            iteration,
            seconds: 1.0,
            rel_mse: 0.5,
            rmse: 0.25,
        };
        let row = sample(1).csv_row().len() + 1;
        let mut log = ErrorLog {
            out: Some(FullAfter { room: 2 * row }),
            path: PathBuf::from("run.csv"),
        };
        assert_eq!(log.record(&sample(1)), None);
        assert_eq!(log.record(&sample(2)), None);
        let warning = log.record(&sample(3)).expect("the third row does not fit");
        assert!(
            warning.contains("run.csv") && warning.contains("render goes on"),
            "{warning}"
        );
        assert!(log.out.is_none());
        assert_eq!(log.record(&sample(4)), None, "one warning, then silence");
    }

    /// A resumed render's log keeps the rows of the iterations it continues, and only those.
    #[test]
    fn a_resumed_log_keeps_the_rows_it_continues() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run.csv");
        let rows = ["1,0.1,1e0,1e0", "2,0.2,5e-1,5e-1", "3,0.3,3e-1,3e-1"];
        let file = |rows: &[&str]| format!("{}\n{}\n", ErrorSample::CSV_HEADER, rows.join("\n"));
        std::fs::write(&path, file(&rows)).unwrap();
        drop(ErrorLog::open(&path, 2).unwrap());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), file(&rows[..2]));
        // A fresh render (nothing continued) starts the log over.
        drop(ErrorLog::open(&path, 0).unwrap());
        let header_only = format!("{}\n", ErrorSample::CSV_HEADER);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), header_only);
    }
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
