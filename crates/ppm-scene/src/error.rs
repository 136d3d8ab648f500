//! Load errors. Every message starts with the file it is about, then the line (and column)
//! or the field path inside that file, compiler style: `scenes/box.yml:12:5: ...`.

use ppm_core::SceneError;
use std::fmt;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a scene could not be loaded. The message names the file and the line, field or path.
#[derive(Debug, Error)]
pub enum LoadError {
    /// A file could not be opened or read: the scene itself or an OBJ it references
    /// (`what` says which, and from where).
    #[error("{}: cannot read {what}: {source}", path.display())]
    Io {
        path: PathBuf,
        what: String,
        source: std::io::Error,
    },

    /// Malformed text at a known place: YAML syntax or schema (unknown key, wrong type, value
    /// out of range), or a bad OBJ/MTL statement. `line` and `column` are 1-based; 0 = unknown.
    #[error("{}: {message}", Place(path, *line, *column))]
    Parse {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },

    /// A well-formed value that does not make sense in context, named by its field path
    /// (`objects[2].material`, `camera`, ...).
    #[error("{}: {field}: {message}", path.display())]
    Invalid {
        path: PathBuf,
        field: String,
        message: String,
    },

    /// The core rejected the assembled scene (should not happen after validation).
    #[error("{}: {source}", path.display())]
    Scene { path: PathBuf, source: SceneError },
}

impl LoadError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            LoadError::Io { path, .. }
            | LoadError::Parse { path, .. }
            | LoadError::Invalid { path, .. }
            | LoadError::Scene { path, .. } => path,
        }
    }

    pub(crate) fn parse(path: &Path, line: usize, message: impl Into<String>) -> Self {
        LoadError::Parse {
            path: path.to_path_buf(),
            line,
            column: 0,
            message: message.into(),
        }
    }

    pub(crate) fn invalid(
        path: &Path,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        LoadError::Invalid {
            path: path.to_path_buf(),
            field: field.into(),
            message: message.into(),
        }
    }

    /// A serde_yaml_ng error, with its " at line L column C" moved to the front.
    pub(crate) fn yaml(path: &Path, error: serde_yaml_ng::Error) -> Self {
        let mut message = error.to_string();
        let (line, column) = match error.location() {
            Some(loc) => {
                let suffix = format!(" at line {} column {}", loc.line(), loc.column());
                message = message.replacen(&suffix, "", 1);
                (loc.line(), loc.column())
            }
            None => (0, 0),
        };
        LoadError::Parse {
            path: path.to_path_buf(),
            line,
            column,
            message: shorten_quotes(&message),
        }
    }
}

/// Longest piece of the input that a message quotes, in characters.
const MAX_QUOTE: usize = 60;

/// `message` with every quoted string (`"..."`, with `\` escapes, as serde quotes values)
/// cut to [`MAX_QUOTE`] characters and its first line: serde_yaml_ng quotes the offending value
/// whole, and a file that is not YAML (an OBJ) is one 40 KB string to it.
fn shorten_quotes(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(512));
    let mut chars = message.chars();
    while let Some(c) = chars.next() {
        out.push(c);
        if c != '"' {
            continue;
        }
        // Inside a quote: copy up to MAX_QUOTE characters of its first line.
        let (mut kept, mut cut) = (0, false);
        while let Some(c) = chars.next() {
            if c == '"' {
                break;
            }
            let escaped = if c == '\\' { chars.next() } else { None };
            if escaped == Some('n') || c == '\n' {
                cut = true;
            }
            if !cut && kept < MAX_QUOTE {
                out.push(c);
                out.extend(escaped);
                kept += 1;
            } else {
                cut = true;
            }
        }
        if cut {
            out.push_str("...");
        }
        out.push('"');
    }
    out
}

/// `file`, `file:line` or `file:line:column`.
struct Place<'a>(&'a Path, usize, usize);

impl fmt::Display for Place<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0.display())?;
        if self.1 > 0 {
            write!(f, ":{}", self.1)?;
            if self.2 > 0 {
                write!(f, ":{}", self.2)?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quotes_are_cut_to_one_short_line() {
        let short = r#"invalid type: string "a \"b\"", expected a sequence"#;
        assert_eq!(shorten_quotes(short), short);
        let long = format!(
            "invalid type: string \"{}\", expected x",
            "v 1 2 3 ".repeat(100)
        );
        let cut = shorten_quotes(&long);
        assert_eq!(
            cut,
            format!(
                "invalid type: string \"{}...\", expected x",
                &"v 1 2 3 ".repeat(8)[..60]
            )
        );
        assert_eq!(
            shorten_quotes(r#"unknown "first\nsecond" here"#),
            r#"unknown "first..." here"#
        );
    }
}
