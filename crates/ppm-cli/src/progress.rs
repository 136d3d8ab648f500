//! What the user sees while and after rendering: a progress bar on stderr and a one-line
//! summary with speeds and memory.

use crate::process_limits::status_bytes;
use crate::render_loop::{LoopTotals, StopRule};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A progress bar on stderr, counting iterations, or render time under a time limit.
/// (indicatif draws nothing when stderr is not a terminal.)
pub struct Progress {
    bar: ProgressBar,
    by_time: bool,
}

impl Progress {
    /// A bar for a render that stops by `stop`; `label` names it (e.g. the algorithm).
    pub fn new(stop: &StopRule, label: &str) -> Self {
        let (length, by_time, template) = match stop.time_limit {
            // Milliseconds of render time, the iteration count in the message.
            Some(limit) => (
                (limit * 1000.0).ceil() as u64,
                true,
                "{prefix} [{bar:30}] {elapsed} of {len_s}, {msg}",
            ),
            None => (
                stop.iterations.unwrap_or(0),
                false,
                "{prefix} [{bar:30}] {pos}/{len} iterations, {elapsed} elapsed, {eta} left {msg}",
            ),
        };
        // Hidden from the start under -q: a bar made visible and hidden afterwards has
        // already drawn itself once (setting its prefix redraws it).
        let target = if crate::console::quiet() {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr()
        };
        let bar = ProgressBar::with_draw_target(Some(length), target);
        let style = ProgressStyle::with_template(&template.replace("{len_s}", &format_limit(stop)))
            .expect("progress template is valid")
            .progress_chars("=> ");
        bar.set_style(style);
        bar.set_prefix(label.to_string());
        Progress { bar, by_time }
    }

    /// Shows the state after an iteration.
    pub fn update(&self, totals: &LoopTotals) {
        if self.by_time {
            self.bar.set_position((totals.seconds * 1000.0) as u64);
            self.bar
                .set_message(format!("{} iterations", totals.iterations));
        } else {
            self.bar.set_position(totals.iterations);
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

fn format_limit(stop: &StopRule) -> String {
    stop.time_limit.map(|t| format!("{t}s")).unwrap_or_default()
}

/// The process's peak resident memory in bytes (`VmHWM`, Linux only).
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm(&status)
}

/// The memory the process holds now (VmRSS), on Linux; `None` elsewhere.
pub fn rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status_bytes(&status, "VmRSS:")
}

/// The `VmHWM:  1234 kB` line of /proc/self/status, in bytes.
fn parse_vm_hwm(status: &str) -> Option<u64> {
    status_bytes(status, "VmHWM:")
}

/// What the summary reports about a finished render.
pub struct Summary<'a> {
    pub width: u32,
    pub height: u32,
    pub algorithm: &'a str,
    pub totals: &'a LoopTotals,
    pub rejected: u64,
    pub render_state_bytes: usize,
    pub peak_rss_bytes: Option<u64>,
}

impl Summary<'_> {
    /// One line: resolution, algorithm, iterations, time, rays/s (closest-hit + shadow rays over
    /// render seconds), photons/s (light paths, photon mapping only), rejected samples, memory.
    pub fn line(&self) -> String {
        let t = self.totals;
        let per_second = |n: u64| {
            if t.seconds > 0.0 {
                n as f64 / t.seconds
            } else {
                0.0
            }
        };
        let mut s = format!(
            "{}x{} {}: {} iterations in {:.2} s, {} rays/s",
            self.width,
            self.height,
            self.algorithm,
            t.iterations,
            t.seconds,
            si(per_second(t.rays + t.shadow_rays)),
        );
        if t.light_paths > 0 {
            s += &format!(", {} photons/s", si(per_second(t.light_paths)));
        }
        s += &format!(", {} rejected samples", self.rejected);
        s += &format!(", render state {}", mib(self.render_state_bytes as u64));
        if let Some(peak) = self.peak_rss_bytes {
            s += &format!(", peak memory {}", mib(peak));
        }
        s
    }

    /// Where the render time went: each pass's seconds, share of the render time and, for the
    /// passes that trace rays, their rays per second (closest-hit and shadow), e.g.
    /// `passes: photon 1.20 s (40%, 2.00 M rays/s), grid 0.10 s (3%), eye 1.60 s (53%,
    /// 1.00 M rays/s), film 0.10 s (3%)`. Comparing a pass's rays/s with the path tracer's
    /// shows what the pass spends beyond tracing rays (the eye pass: the gather). Passes that
    /// took no time (the path tracer has no photon pass) are left out.
    pub fn passes_line(&self) -> String {
        let t = self.totals;
        let p = &t.passes;
        let total = p.total();
        let eye_rays = t.rays - t.photon_rays + t.shadow_rays;
        let parts: Vec<String> = [
            ("photon", p.photon, Some(t.photon_rays)),
            ("grid", p.grid, None),
            ("eye", p.eye, Some(eye_rays)),
            ("film", p.film, None),
        ]
        .iter()
        .filter(|(_, seconds, _)| *seconds > 0.0)
        .map(|&(name, seconds, rays)| {
            let share = 100.0 * seconds / total;
            match rays {
                Some(rays) => format!(
                    "{name} {seconds:.2} s ({share:.0}%, {} rays/s)",
                    si(rays as f64 / seconds)
                ),
                None => format!("{name} {seconds:.2} s ({share:.0}%)"),
            }
        })
        .collect();
        format!("passes: {}", parts.join(", "))
    }
}

/// A rate with an SI prefix: 1234567 -> "1.23 M".
fn si(v: f64) -> String {
    let (scale, prefix) = match v {
        v if v >= 1e9 => (1e9, " G"),
        v if v >= 1e6 => (1e6, " M"),
        v if v >= 1e3 => (1e3, " k"),
        _ => (1.0, ""),
    };
    format!("{:.2}{prefix}", v / scale)
}

fn mib(bytes: u64) -> String {
    format!("{:.1} MiB", bytes as f64 / (1024.0 * 1024.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use ppm_core::integrator::PassTimes;

    #[test]
    fn vm_hwm_is_parsed_in_bytes() {
        let status = "Name:\tppm\nVmPeak:\t  9000 kB\nVmHWM:\t    2048 kB\nVmRSS:\t 1024 kB\n";
        assert_eq!(parse_vm_hwm(status), Some(2048 * 1024));
        assert_eq!(parse_vm_hwm("Name: x\n"), None);
        #[cfg(target_os = "linux")]
        assert!(peak_rss_bytes().unwrap() > 1024 * 1024);
    }

    /// Rates below a thousand have no prefix and no second space ("0.00 rays/s").
    #[test]
    fn rates_take_one_space_before_the_unit() {
        assert_eq!(format!("{} rays/s", si(0.0)), "0.00 rays/s");
        assert_eq!(format!("{} rays/s", si(999.0)), "999.00 rays/s");
        assert_eq!(format!("{} rays/s", si(1234.0)), "1.23 k rays/s");
        assert_eq!(format!("{} rays/s", si(2.5e9)), "2.50 G rays/s");
    }

    #[test]
    fn summary_line_reports_speeds() {
        let totals = LoopTotals {
            iterations: 10,
            seconds: 2.0,
            rays: 3_000_000,
            photon_rays: 1_000_000,
            shadow_rays: 1_000_000,
            light_paths: 500_000,
            photons: 900_000,
            passes: PassTimes {
                photon: 0.5,
                grid: 0.1,
                eye: 1.3,
                film: 0.1,
            },
            interrupted: false,
        };
        let summary = Summary {
            width: 64,
            height: 48,
            algorithm: "ppm",
            totals: &totals,
            rejected: 3,
            render_state_bytes: 3 * 1024 * 1024,
            peak_rss_bytes: Some(100 * 1024 * 1024),
        };
        assert_eq!(
            summary.line(),
            "64x48 ppm: 10 iterations in 2.00 s, 2.00 M rays/s, 250.00 k photons/s, 3 rejected samples, \
             render state 3.0 MiB, peak memory 100.0 MiB"
        );
        assert_eq!(
            summary.passes_line(),
            "passes: photon 0.50 s (25%, 2.00 M rays/s), grid 0.10 s (5%), \
             eye 1.30 s (65%, 2.31 M rays/s), film 0.10 s (5%)"
        );
    }
}
