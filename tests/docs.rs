//! The documentation stays true to the repository: the README is a short manual with the
//! sections others extend, every relative link in the Markdown files reaches a file (and a
//! heading, for `file#anchor` links), and the README's scene example loads without warnings.

use std::fs;
use std::path::{Path, PathBuf};

/// The repository's root (this crate lives in `tests/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The Markdown files whose links are checked: the README, ARCHITECTURE.md and docs/*.md.
fn markdown_files() -> Vec<PathBuf> {
    let root = root();
    let mut files = vec![root.join("README.md"), root.join("ARCHITECTURE.md")];
    let mut docs: Vec<PathBuf> = fs::read_dir(root.join("docs"))
        .expect("docs/ exists")
        .map(|e| e.expect("readable docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    files
}

/// The lines of `markdown` outside fenced code blocks.
fn prose_lines(markdown: &str) -> impl Iterator<Item = &str> {
    let mut in_code = false;
    markdown.lines().filter(move |line| {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            return false;
        }
        !in_code
    })
}

/// Markdown headings as GitHub anchors them: lower case, characters other than letters,
/// digits, `-`, `_` and spaces dropped, spaces turned into `-`.
fn anchors(markdown: &str) -> Vec<String> {
    prose_lines(markdown)
        .filter(|line| line.starts_with('#'))
        .map(|line| {
            line.trim_start_matches('#')
                .trim()
                .to_lowercase()
                .chars()
                .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
                .map(|c| if c == ' ' { '-' } else { c })
                .collect()
        })
        .collect()
}

/// The targets of `[text](target)` and `![alt](target)` links outside code blocks.
fn link_targets(markdown: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in prose_lines(markdown) {
        let mut rest = line;
        while let Some(start) = rest.find("](") {
            let after = &rest[start + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn readme_is_a_short_manual_with_the_shared_sections() {
    let readme = read(&root().join("README.md"));
    assert!(
        readme.len() <= 12 * 1024,
        "README.md is {} bytes: it is a user's manual of about 12 KB at most; measurements go \
         to docs/performance.md",
        readme.len()
    );
    let headings = anchors(&readme);
    for section in [
        "two-commands",
        "install",
        "choosing-an-algorithm",
        "troubleshooting",
        "never-lost",
        "command-line",
        "speed-and-error",
    ] {
        assert!(
            headings.iter().any(|h| h == section),
            "README.md has no section #{section}"
        );
    }
    for command in [
        "cargo run --release -- cornell_box_water.yml -n 100",
        "cargo test",
    ] {
        assert!(readme.contains(command), "README.md lost `{command}`");
    }
    assert!(root().join("scenes/cornell_box_water.yml").is_file());
}

#[test]
fn relative_links_reach_files_and_headings() {
    let mut broken = Vec::new();
    for file in markdown_files() {
        let text = read(&file);
        let dir = file.parent().expect("a file has a folder");
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let linked = if path.is_empty() {
                file.clone()
            } else {
                dir.join(path)
            };
            if !linked.exists() {
                broken.push(format!("{}: {target}: no such file", file.display()));
                continue;
            }
            if let Some(anchor) = anchor {
                if !anchors(&read(&linked)).iter().any(|h| h == anchor) {
                    broken.push(format!("{}: {target}: no such heading", file.display()));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn readme_scene_example_loads_without_warnings() {
    let readme = read(&root().join("README.md"));
    let start = readme
        .find("```yaml\n")
        .expect("README.md has a YAML scene example")
        + "```yaml\n".len();
    let end = start + readme[start..].find("```").expect("the YAML block ends");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("readme_example");
    fs::create_dir_all(&dir).unwrap();
    // The example names room.obj with MTL materials: a floor quad with one material.
    fs::write(
        dir.join("room.obj"),
        "mtllib room.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nusemtl floor\nf 1 4 3 2\n",
    )
    .unwrap();
    fs::write(dir.join("room.mtl"), "newmtl floor\nKd 0.7 0.7 0.7\n").unwrap();
    let scene_path = dir.join("scene.yml");
    fs::write(&scene_path, &readme[start..end]).unwrap();
    let loaded = ppm_scene::load_scene(&scene_path)
        .unwrap_or_else(|e| panic!("the README's scene example does not load: {e}"));
    assert!(
        loaded.warnings.is_empty(),
        "the README's scene example loads with warnings: {:?}",
        loaded.warnings
    );
    assert_eq!(
        (loaded.scene.camera.width, loaded.scene.camera.height),
        (512, 512)
    );
}

#[test]
fn anchors_and_links_are_parsed_as_github_does() {
    assert_eq!(
        anchors(
            "# A b\n```\n# not a heading\n```\n## Scenes shipped in `scenes/`\n### 11:21: x (abc)"
        ),
        ["a-b", "scenes-shipped-in-scenes", "1121-x-abc"]
    );
    assert_eq!(
        link_targets("see [a](x.md) and ![](img/p.png)\n```\n[no](skip.md)\n```\n[b](y.md#h)"),
        ["x.md", "img/p.png", "y.md#h"]
    );
}
