//! Running `ppm` as a child process: real signals sent with `kill`, stderr read line by line,
//! and waits guarded against a hang (two minutes), never used as timings.

use super::ppm;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Sends `signal` (TERM, HUP, INT...) to the child.
pub fn kill(child: &Child, signal: &str) {
    let status = std::process::Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
}

/// Spawns `ppm args` in `dir` with stderr read line by line into a channel.
pub fn spawn(dir: &Path, args: &[&str]) -> (Child, mpsc::Receiver<String>) {
    let mut child = ppm(dir).args(args).stderr(Stdio::piped()).spawn().unwrap();
    let (send, receive) = mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).split(b'\n').map_while(Result::ok) {
            let _ = send.send(String::from_utf8_lossy(&line).into_owned());
        }
    });
    (child, receive)
}

/// Waits (at most two minutes, a guard against a hang, not a timing) for a stderr line
/// containing `needle`; returns the lines read so far.
pub fn wait_for_line(lines: &mpsc::Receiver<String>, needle: &str) -> String {
    let mut seen = String::new();
    let deadline = Instant::now() + Duration::from_secs(120);
    while Instant::now() < deadline {
        if let Ok(line) = lines.recv_timeout(Duration::from_millis(100)) {
            seen.push_str(&line);
            seen.push('\n');
            if line.contains(needle) {
                return seen;
            }
        }
    }
    panic!("no line with {needle:?} on stderr: {seen}");
}

/// Waits for the child to exit (a two-minute guard against a hang); returns its status and
/// the rest of its stderr.
pub fn finish(mut child: Child, lines: mpsc::Receiver<String>) -> (Option<i32>, String) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            std::thread::sleep(Duration::from_millis(50));
            let rest: Vec<String> = lines.try_iter().collect();
            return (status.code(), rest.join("\n"));
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("ppm did not stop within two minutes of the stop request");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Polls (two-minute guard) until `path` exists.
pub fn wait_for_file(path: &Path) {
    let deadline = Instant::now() + Duration::from_secs(120);
    while !path.exists() {
        assert!(
            Instant::now() < deadline,
            "{} never appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}
