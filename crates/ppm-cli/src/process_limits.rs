//! The memory this process may still allocate under its own limits, besides the machine's free
//! memory: `ulimit -v` and `ulimit -d` (RLIMIT_AS, RLIMIT_DATA) and a cgroup's memory limit
//! (v2 `memory.max`, v1 `memory.limit_in_bytes`, as a container or a batch system sets).
//!
//! Each limit is compared with what the process uses of it already, so what is returned is
//! what is left: RLIMIT_AS caps the virtual size (VmSize in /proc/self/status, which counts
//! the binary's mappings and every thread's stack), RLIMIT_DATA the private writable mappings
//! (VmData, Linux 4.7 and later: the heap and the anonymous mappings large buffers live in),
//! a cgroup the memory charged to it (`memory.current`, v1 `memory.usage_in_bytes`), which
//! other processes of the cgroup share. An allocation beyond one of them fails however much
//! RAM is free, and Rust's default answer to a failed allocation is to abort the process.

use std::path::Path;

/// One limit and what is left of it, for the message that names it.
#[derive(Clone, Debug, PartialEq)]
pub struct LeftOf {
    /// Bytes still available under the limit.
    pub left: u64,
    /// The limit, in words (`RLIMIT_AS (ulimit -v) 1.00 GiB, 0.25 GiB in use`).
    pub source: String,
}

/// Limits above this are "unlimited" (cgroup v1 writes 2^63 rounded to a page for none).
const UNLIMITED: u64 = 1 << 60;

/// What is left under each of this process's memory limits that is set (none: an empty list).
pub fn limits() -> Vec<LeftOf> {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let mut found = Vec::new();
    let rlimits = [
        (libc::RLIMIT_AS, "RLIMIT_AS (ulimit -v)", "VmSize:"),
        (libc::RLIMIT_DATA, "RLIMIT_DATA (ulimit -d)", "VmData:"),
    ];
    for (resource, name, key) in rlimits {
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes one rlimit through the valid pointer it is given.
        let ok = unsafe { libc::getrlimit(resource, &mut limit) } == 0;
        let soft = (ok && limit.rlim_cur != libc::RLIM_INFINITY).then_some(limit.rlim_cur);
        let soft = soft.filter(|&s| s < UNLIMITED);
        if let (Some(limit), Some(used)) = (soft, status_bytes(&status, key)) {
            found.push(left_of(name, limit, used));
        }
    }
    if let Ok(cgroups) = std::fs::read_to_string("/proc/self/cgroup") {
        found.extend(cgroup_limits(&cgroups, Path::new("/sys/fs/cgroup")));
    }
    found
}

fn left_of(name: &str, limit: u64, used: u64) -> LeftOf {
    LeftOf {
        left: limit.saturating_sub(used),
        source: format!("{name} {}, {} in use", gib(limit), gib(used)),
    }
}

/// `bytes` in GiB with two decimals, as the memory messages print it.
pub(crate) fn gib(bytes: u64) -> String {
    format!("{:.2} GiB", bytes as f64 / (1u64 << 30) as f64)
}

/// The `<key>  1234 kB` line of /proc/self/status, in bytes.
pub(crate) fn status_bytes(status: &str, key: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb.saturating_mul(1024))
}

/// The memory limits of the cgroups in `/proc/self/cgroup` (text `cgroups`) under the cgroup
/// file system mounted at `root`: for v2 (`0::/path`) the group and each ancestor with a
/// `memory.max` (the tightest binds), for v1 the `memory` controller's group.
fn cgroup_limits(cgroups: &str, root: &Path) -> Vec<LeftOf> {
    let read = |path: &Path| -> Option<u64> {
        let text = std::fs::read_to_string(path).ok()?;
        text.trim().parse().ok()
    };
    let mut found = Vec::new();
    for line in cgroups.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(id), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        let relative = path.trim_start_matches('/');
        if id == "0" && controllers.is_empty() {
            // v2: the group and its ancestors, each possibly limited ("max": not).
            let mut group = root.join(relative);
            loop {
                let max = read(&group.join("memory.max"));
                let current = read(&group.join("memory.current"));
                if let (Some(max), Some(current)) = (max, current) {
                    if max < UNLIMITED {
                        found.push(left_of(
                            &format!("cgroup memory.max of {}", group.display()),
                            max,
                            current,
                        ));
                    }
                }
                if group == root || !group.pop() || !group.starts_with(root) {
                    break;
                }
            }
        } else if controllers.split(',').any(|c| c == "memory") {
            let group = root.join("memory").join(relative);
            let limit = read(&group.join("memory.limit_in_bytes"));
            let usage = read(&group.join("memory.usage_in_bytes"));
            if let (Some(limit), Some(usage)) = (limit, usage) {
                if limit < UNLIMITED {
                    found.push(left_of(
                        &format!("cgroup memory.limit_in_bytes of {}", group.display()),
                        limit,
                        usage,
                    ));
                }
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cgroup_limits_are_read_for_v1_and_v2_with_ancestors() {
        let root = tempfile::tempdir().unwrap();
        let write = |path: &str, text: &str| {
            let path = root.path().join(path);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        };
        // v2: the job's group is unlimited, its parent allows 4 GiB of which 1 GiB is used.
        write("batch/job/memory.max", "max\n");
        write("batch/job/memory.current", "1000\n");
        write("batch/memory.max", "4294967296\n");
        write("batch/memory.current", "1073741824\n");
        let v2 = cgroup_limits("0::/batch/job\n", root.path());
        assert_eq!(v2.len(), 1, "{v2:?}");
        assert_eq!(v2[0].left, 3 << 30);
        assert!(v2[0].source.contains("memory.max") && v2[0].source.contains("batch"));
        // v1: the memory controller's group; "unlimited" is a huge number.
        write("memory/docker/memory.limit_in_bytes", "2147483648\n");
        write("memory/docker/memory.usage_in_bytes", "1073741824\n");
        let v1 = cgroup_limits("5:cpu:/\n4:memory:/docker\n", root.path());
        assert_eq!(v1.len(), 1, "{v1:?}");
        assert_eq!(v1[0].left, 1 << 30);
        write("memory/free/memory.limit_in_bytes", "9223372036854771712\n");
        write("memory/free/memory.usage_in_bytes", "1\n");
        assert_eq!(cgroup_limits("4:memory:/free\n", root.path()), []);
    }

    #[test]
    fn status_lines_are_read_in_bytes() {
        let status = "VmPeak:\t  200 kB\nVmSize:\t  100 kB\nVmData:\t 50 kB\n";
        assert_eq!(status_bytes(status, "VmSize:"), Some(100 * 1024));
        assert_eq!(status_bytes(status, "VmData:"), Some(50 * 1024));
        assert_eq!(status_bytes(status, "VmRSS:"), None);
    }
}
