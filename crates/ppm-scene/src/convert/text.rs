//! The YAML text `ppm convert` writes: numbers in the shortest form that reads back to the
//! same `f32` (Rust's `{:?}`, with an exponent when very small or large), strings always
//! double-quoted, one key per line.

use glam::Vec3;

/// A number that reads back to `x` exactly.
pub(crate) fn num(x: f32) -> String {
    format!("{x:?}")
}

/// `[x, y, z]`.
pub(crate) fn triple(v: Vec3) -> String {
    format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z))
}

/// `[a, b, ...]`.
pub(crate) fn list(values: &[f32]) -> String {
    let parts: Vec<String> = values.iter().map(|&x| num(x)).collect();
    format!("[{}]", parts.join(", "))
}

/// A YAML double-quoted string (names may hold any character, `#` and `:` included).
pub(crate) fn quoted(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 || c == '\u{7f}' => {
                out.push_str(&format!("\\x{:02x}", c as u32))
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Lines of YAML at increasing indents.
#[derive(Default)]
pub(crate) struct Yaml {
    pub text: String,
}

impl Yaml {
    /// `key: value` at `depth` (two spaces each).
    pub fn field(&mut self, depth: usize, key: &str, value: &str) {
        self.line(depth, &format!("{key}: {value}"));
    }

    /// One line at `depth`.
    pub fn line(&mut self, depth: usize, text: &str) {
        for _ in 0..depth {
            self.text.push_str("  ");
        }
        self.text.push_str(text);
        self.text.push('\n');
    }

    /// `# text` for each line of `text`.
    pub fn comment(&mut self, text: &str) {
        for l in text.lines() {
            self.text.push_str("# ");
            self.text.push_str(l);
            self.text.push('\n');
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly() {
        for x in [
            0.1f32,
            1.0,
            1e-30,
            3.4e38,
            -0.0,
            1.0 / 3.0,
            16777217.0,
            7e-45,
        ] {
            let back: f64 = serde_yaml_ng::from_str(&num(x)).unwrap();
            assert_eq!(
                (back as f32).to_bits(),
                x.to_bits(),
                "{x} written {}",
                num(x)
            );
        }
    }

    #[test]
    fn names_read_back_exactly() {
        for name in ["plain", "a: b # c", "q\"uo\\te", "", "tab\there", "ünï"] {
            let back: String = serde_yaml_ng::from_str(&quoted(name)).unwrap();
            assert_eq!(back, name);
        }
    }
}
