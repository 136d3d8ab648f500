//! Writes the generated meshes of the Cornell box scenes ([`ppm_test_support::meshes`]).
//!
//! Run from the repository root: `cargo run -p ppm-scene --example make_meshes [out_dir]`
//! (default `scenes`).

use ppm_test_support::meshes::{blocks, water};
use std::path::PathBuf;

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "scenes".into()));
    let (short, tall) = blocks();
    std::fs::write(dir.join("short_block.obj"), short)?;
    std::fs::write(dir.join("tall_block.obj"), tall)?;
    std::fs::write(dir.join("water.obj"), water())?;
    Ok(())
}
