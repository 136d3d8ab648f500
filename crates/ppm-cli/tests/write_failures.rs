//! Writes that fail: a file-size limit and a full disk are errors with a message, never a
//! kill or a lost render; the render goes to the rescue folder when it can.

mod common;

use common::process::*;
use common::*;
use std::path::Path;
use std::process::Stdio;

/// A file-size limit (`ulimit -f`) makes a write fail like a full disk, with a message and
/// status 1, instead of killing ppm with SIGXFSZ. The limit holds in the rescue folder too,
/// so the error says the render is lost, and no partial file is left in either folder.
#[cfg(unix)]
#[test]
fn a_file_size_limit_is_an_error_not_a_kill() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let rescue = dir.path().join("rescue");
    std::fs::create_dir(&rescue).unwrap();
    let out = std::process::Command::new("sh")
        .current_dir(dir.path())
        .args([
            "-c",
            "ulimit -f 1; exec \"$0\" tiny.yml -n 1",
            env!("CARGO_BIN_EXE_ppm"),
        ])
        .env("PPM_RESCUE_DIR", &rescue)
        .env("TMPDIR", &rescue)
        .env("HOME", &rescue)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        (err.contains("was replaced") || err.contains("too large"))
            && err.contains("the render is lost"),
        "{err}"
    );
    assert_eq!(
        file_names(dir.path()),
        ["rescue", "tiny.yml"],
        "no partial or temporary file"
    );
    assert!(file_names(&rescue).is_empty(), "{:?}", file_names(&rescue));
}

/// Unmounts a test's tmpfs when dropped.
struct Unmount(std::path::PathBuf);

impl Drop for Unmount {
    fn drop(&mut self) {
        let _ = std::process::Command::new("umount")
            .arg("-l")
            .arg(&self.0)
            .status();
    }
}

/// Mounts a 1 MiB tmpfs at `dir`; `None` (the test then skips) where that is not permitted.
fn small_disk(dir: &Path) -> Option<Unmount> {
    std::fs::create_dir_all(dir).unwrap();
    let mounted = std::process::Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=1m", "tmpfs"])
        .arg(dir)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    mounted.then(|| Unmount(dir.to_path_buf()))
}

/// Fills the disk holding `dir` with one file, then frees `slack` bytes of it.
fn fill_disk(dir: &Path, slack: u64) -> std::path::PathBuf {
    use std::io::Write;
    let path = dir.join("filler");
    let mut file = std::fs::File::create(&path).unwrap();
    let chunk = [0u8; 4096];
    let mut len = 0u64;
    while file.write_all(&chunk).is_ok() {
        len += chunk.len() as u64;
    }
    file.set_len(len.saturating_sub(slack)).unwrap();
    file.sync_all().unwrap();
    path
}

/// A full disk (a real one: a 1 MiB tmpfs; skipped where mounting is not permitted).
/// A final write with room for the new PNG but not the new EXR replaces neither, and says
/// so; the render is then written to the rescue folder ($TMPDIR here), from which it resumes,
/// or said to be lost when no rescue folder takes it; a failed checkpoint is a warning, the
/// render goes on and its final write succeeds.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_never_leaves_a_mismatched_pair_or_stops_the_render() {
    let dir = tempfile::tempdir().unwrap();
    tiny_scene(dir.path());
    let disk = dir.path().join("disk");
    let Some(_unmount) = small_disk(&disk) else {
        eprintln!("skipped: cannot mount a tmpfs here (needs root)");
        return;
    };
    let size = ["--width", "64", "--height", "64"];
    let render = |extra: &[&str]| {
        let mut args = vec!["tiny.yml", "-n", "1"];
        args.extend_from_slice(&size);
        args.extend_from_slice(extra);
        run(dir.path(), &args)
    };
    assert_ok(&render(&["--seed", "1", "-o", "disk/shot"]));
    let old_png = std::fs::read(disk.join("shot.png")).unwrap();
    let old_exr = std::fs::read(disk.join("shot.exr")).unwrap();
    assert!(
        old_exr.len() > old_png.len() + 16384,
        "the EXR must be the larger file for this test"
    );
    // Room for the new PNG (about the old one's size) but not the EXR.
    let filler = fill_disk(&disk, old_png.len() as u64 + 8192);
    let rescue = dir.path().join("rescue");
    std::fs::create_dir(&rescue).unwrap();
    let render_with = |tmpdir: &Path, home: &Path| {
        let mut args = vec!["tiny.yml", "-n", "1", "--seed", "2", "-o", "disk/shot"];
        args.extend_from_slice(&size);
        ppm(dir.path())
            .args(&args)
            .env("TMPDIR", tmpdir)
            .env("HOME", home)
            .env_remove("PPM_RESCUE_DIR")
            .output()
            .unwrap()
    };
    let nowhere = dir.path().join("no such folder");
    let err = assert_fails(&render_with(&nowhere, &nowhere), 1);
    assert!(
        err.contains("neither") && err.contains("the render is lost"),
        "{err}"
    );
    let err = assert_fails(&render_with(&rescue, &nowhere), 1);
    assert!(
        err.contains("neither") && err.contains("shot.exr") && err.contains("shot.png"),
        "{err}"
    );
    assert_eq!(std::fs::read(disk.join("shot.png")).unwrap(), old_png);
    assert_eq!(std::fs::read(disk.join("shot.exr")).unwrap(), old_exr);
    assert_eq!(file_names(&disk), ["filler", "shot.exr", "shot.png"]);
    std::fs::remove_file(&filler).unwrap();
    // The rescued pair is the render that could not be written: it resumes, and the EXR
    // the error names is the one on disk.
    let rescued = file_names(&rescue);
    assert_eq!(rescued.len(), 2, "{rescued:?}");
    assert!(
        rescued[0].starts_with("shot.rescued-") && rescued[0].ends_with(".exr"),
        "{rescued:?}"
    );
    assert!(
        err.contains("the render is safe in") && err.contains(&rescued[0]),
        "{err}"
    );
    let rescued_exr = rescue.join(&rescued[0]);
    let resumed = render(&[
        "--seed",
        "2",
        "--resume",
        rescued_exr.to_str().unwrap(),
        "-o",
        "resumed",
    ]);
    assert_ok(&resumed);
    let mut whole = vec!["tiny.yml", "-n", "2", "--seed", "2", "-o", "whole"];
    whole.extend_from_slice(&size);
    assert_ok(&run(dir.path(), &whole));
    assert_eq!(
        read_exr(&dir.path().join("resumed.exr")),
        read_exr(&dir.path().join("whole.exr")),
        "the rescued render resumes as if written where asked"
    );

    // Checkpoints: fill the disk after the first one, let some fail, free it, stop.
    let mut args = vec!["tiny.yml", "--time-limit", "1000", "--checkpoint", "0.01"];
    args.extend_from_slice(&size);
    args.extend_from_slice(&["-o", "disk/cp"]);
    let (child, lines) = spawn(dir.path(), &args);
    wait_for_file(&disk.join("cp.exr"));
    let filler = fill_disk(&disk, 0);
    let mut err = wait_for_line(&lines, "checkpoint not written");
    let (w, h, _) = read_exr(&disk.join("cp.exr"));
    assert_eq!((w, h), (64, 64), "the last good checkpoint is intact");
    std::fs::remove_file(&filler).unwrap();
    kill(&child, "TERM");
    let (code, rest) = finish(child, lines);
    err.push_str(&rest);
    assert_eq!(
        code,
        Some(130),
        "the render went on after the failed checkpoint: {err}"
    );
    assert!(
        err.contains("last good checkpoint is kept") && err.contains("wrote"),
        "{err}"
    );
    let (w, h, pixels) = read_exr(&disk.join("cp.exr"));
    assert_eq!((w, h), (64, 64));
    assert!(pixels.iter().flatten().all(|v| v.is_finite()));
    assert_eq!(
        file_names(&disk),
        ["cp.exr", "cp.png", "shot.exr", "shot.png"]
    );
}
