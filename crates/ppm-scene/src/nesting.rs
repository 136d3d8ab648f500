//! A cap on how deeply a scene file nests, checked on the raw text before the YAML parser
//! sees it.
//!
//! The YAML parser builds every nested level before the schema can reject the first one, so
//! a hostile file nested 100,000 levels deep costs it tens of seconds (and deep recursion).
//! Scene format v1 nests at most 5 levels (`objects`, an item, a field, a list of numbers),
//! so anything past [`MAX_NESTING`] is refused at once, naming the line and column.
//!
//! The count is conservative: flow collections (`[`, `{`) outside quotes and comments, plus
//! block levels (each indentation deeper than the enclosing one, and each `- ` item marker).

use crate::LoadError;
use std::path::Path;

/// Deepest nesting a scene file may have (far above what format v1 uses).
pub const MAX_NESTING: usize = 64;

/// `Err` naming the place where `text` first nests deeper than [`MAX_NESTING`] levels.
pub fn check_nesting(text: &str, path: &Path) -> Result<(), LoadError> {
    // Columns of the enclosing block levels; flow depth carries over lines.
    let mut blocks: Vec<usize> = Vec::new();
    let mut flow = 0usize;
    for (index, line) in text.lines().enumerate() {
        let too_deep = |column: usize| {
            Err(LoadError::Parse {
                path: path.to_path_buf(),
                line: index + 1,
                column: column + 1,
                message: format!(
                    "nested more than {MAX_NESTING} levels deep (a scene file needs at most 5); \
                     refused before parsing"
                ),
            })
        };
        let bytes = line.as_bytes();
        let indent = bytes.iter().take_while(|&&b| b == b' ').count();
        let content = &bytes[indent..];
        if flow == 0 && !content.is_empty() && content[0] != b'#' {
            while blocks.last().is_some_and(|&c| c >= indent) {
                blocks.pop();
            }
            blocks.push(indent);
            // `- - - x`: each item marker opens one more level on the same line.
            let mut column = indent;
            while bytes.get(column) == Some(&b'-') && bytes.get(column + 1) == Some(&b' ') {
                column += 2;
                while bytes.get(column) == Some(&b' ') {
                    column += 1;
                }
                blocks.push(column);
                if blocks.len() > MAX_NESTING {
                    return too_deep(column);
                }
            }
            if blocks.len() > MAX_NESTING {
                return too_deep(indent);
            }
        }
        let mut quote: Option<u8> = None;
        for (column, &b) in bytes.iter().enumerate() {
            match (quote, b) {
                (Some(q), _) if b == q => quote = None,
                (Some(_), _) => {}
                (None, b'"' | b'\'') => quote = Some(b),
                (None, b'#') if column == 0 || bytes[column - 1] == b' ' => break,
                (None, b'[' | b'{') => {
                    flow += 1;
                    if blocks.len() + flow > MAX_NESTING {
                        return too_deep(column);
                    }
                }
                (None, b']' | b'}') => flow = flow.saturating_sub(1),
                _ => {}
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> Result<(), String> {
        check_nesting(text, Path::new("s.yml")).map_err(|e| e.to_string())
    }

    #[test]
    fn ordinary_scenes_pass() {
        check("camera: { position: [0, 1, 2], fov: 40 }\nobjects:\n  - { type: quad, corner: [1, 2, 3] }\n  - type: sphere\n    center: [0, 0, 0]\n# [[[[ a comment\nname: \"[[[[[\"\n").unwrap();
        // The line itself is one block level.
        let n = MAX_NESTING - 1;
        let deep_but_allowed = "[".repeat(n) + &"]".repeat(n);
        check(&deep_but_allowed).unwrap();
    }

    #[test]
    fn deep_flow_block_and_item_nesting_fail_with_the_place() {
        let flow = format!("a: {}", "[".repeat(100_000));
        let err = check(&flow).unwrap_err();
        assert!(
            err.starts_with("s.yml:1:") && err.contains("64 levels"),
            "{err}"
        );
        let block: String = (0..100).map(|i| format!("{}k:\n", " ".repeat(i))).collect();
        let err = check(&block).unwrap_err();
        assert!(err.starts_with("s.yml:65:"), "{err}");
        let items = "- ".repeat(1000) + "x\n";
        let err = check(&items).unwrap_err();
        assert!(err.starts_with("s.yml:1:"), "{err}");
        let maps = "{a: ".repeat(70);
        assert!(check(&maps).is_err());
    }
}
