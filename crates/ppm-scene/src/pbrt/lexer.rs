//! pbrt-v4's scene-file tokens: quoted strings (with `\` escapes), brackets, and bare words
//! (directive names, numbers, `true`/`false`); `#` starts a comment to the end of the line.
//! Each token keeps its 1-based line and column for messages.

use super::Loc;
use crate::LoadError;
use std::path::Path;
use std::sync::Arc;

/// One token of a scene file.
#[derive(Clone, Debug, PartialEq)]
pub enum Token {
    /// `"..."`, escapes resolved.
    Str(String),
    /// A bare word: a directive name, a number, `true` or `false`.
    Word(String),
    Open,
    Close,
}

impl Token {
    /// The token as a message quotes it.
    pub fn describe(&self) -> String {
        match self {
            Token::Str(s) => format!("\"{}\"", shorten(s)),
            Token::Word(w) => format!("`{}`", shorten(w)),
            Token::Open => "`[`".into(),
            Token::Close => "`]`".into(),
        }
    }
}

/// At most 40 characters of `s` (messages quote input, which may be huge).
fn shorten(s: &str) -> String {
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}...", &s[..i]),
        None => s.to_string(),
    }
}

/// Splits one file's text into tokens, lazily (a file of inline meshes may hold hundreds of
/// millions of numbers: no token list is ever built).
pub struct Lexer<'a> {
    text: &'a [u8],
    pos: usize,
    line: u32,
    /// Byte offset where the current line starts (columns count bytes, 1-based).
    line_start: usize,
    file: Arc<Path>,
    peeked: Option<(Token, Loc)>,
}

impl<'a> Lexer<'a> {
    pub fn new(text: &'a str, file: Arc<Path>) -> Self {
        // A UTF-8 byte order mark is not part of the scene.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        Lexer {
            text: text.as_bytes(),
            pos: 0,
            line: 1,
            line_start: 0,
            file,
            peeked: None,
        }
    }

    /// The place of the next byte.
    pub fn here(&self) -> Loc {
        Loc {
            file: self.file.clone(),
            line: self.line,
            column: (self.pos - self.line_start + 1) as u32,
        }
    }

    /// The next token without consuming it.
    pub fn peek(&mut self) -> Result<Option<&(Token, Loc)>, LoadError> {
        if self.peeked.is_none() {
            self.peeked = self.scan()?;
        }
        Ok(self.peeked.as_ref())
    }

    /// The next token and where it starts; `None` at the end of the file.
    pub fn next_token(&mut self) -> Result<Option<(Token, Loc)>, LoadError> {
        match self.peeked.take() {
            Some(t) => Ok(Some(t)),
            None => self.scan(),
        }
    }

    fn scan(&mut self) -> Result<Option<(Token, Loc)>, LoadError> {
        // Skip white space and comments.
        while let Some(&c) = self.text.get(self.pos) {
            match c {
                b'\n' => {
                    self.pos += 1;
                    self.line += 1;
                    self.line_start = self.pos;
                }
                b' ' | b'\t' | b'\r' | b'\x0c' | b'\x0b' => self.pos += 1,
                b'#' => {
                    while self.text.get(self.pos).is_some_and(|&c| c != b'\n') {
                        self.pos += 1;
                    }
                }
                _ => break,
            }
        }
        let Some(&c) = self.text.get(self.pos) else {
            return Ok(None);
        };
        let loc = self.here();
        let token = match c {
            b'[' => {
                self.pos += 1;
                Token::Open
            }
            b']' => {
                self.pos += 1;
                Token::Close
            }
            b'"' => Token::Str(self.string(&loc)?),
            _ => {
                let start = self.pos;
                while self.text.get(self.pos).is_some_and(|&c| {
                    !matches!(c, b' ' | b'\t' | b'\r' | b'\n' | b'[' | b']' | b'"' | b'#')
                        && !c.is_ascii_control()
                }) {
                    self.pos += 1;
                }
                if self.pos == start {
                    return Err(loc.error(format!("unexpected control character {c:#04x}")));
                }
                // Bytes were split at ASCII delimiters only, so this is whole UTF-8.
                let word = std::str::from_utf8(&self.text[start..self.pos])
                    .map_err(|_| loc.error("invalid UTF-8"))?;
                Token::Word(word.to_string())
            }
        };
        Ok(Some((token, loc)))
    }

    /// A quoted string from the opening quote at `self.pos`; a line break inside is an error
    /// (it is almost always a missing closing quote).
    fn string(&mut self, loc: &Loc) -> Result<String, LoadError> {
        self.pos += 1;
        let mut out = Vec::new();
        loop {
            let Some(&c) = self.text.get(self.pos) else {
                return Err(loc.error("string not closed before the end of the file"));
            };
            self.pos += 1;
            match c {
                b'"' => break,
                b'\n' => return Err(loc.error("string not closed on its line")),
                b'\\' => {
                    let Some(&e) = self.text.get(self.pos) else {
                        return Err(loc.error("string not closed before the end of the file"));
                    };
                    self.pos += 1;
                    out.push(match e {
                        b'n' => b'\n',
                        b't' => b'\t',
                        b'r' => b'\r',
                        b'b' => 8,
                        b'f' => 12,
                        b'\\' | b'"' | b'\'' => e,
                        b'\n' => return Err(loc.error("string not closed on its line")),
                        other => {
                            return Err(loc.error(format!(
                                "unknown escape `\\{}` in a string",
                                other as char
                            )))
                        }
                    });
                }
                _ => out.push(c),
            }
        }
        String::from_utf8(out).map_err(|_| loc.error("invalid UTF-8 in a string"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tokens(text: &str) -> Result<Vec<(Token, u32, u32)>, LoadError> {
        let mut lexer = Lexer::new(text, Arc::from(Path::new("t.pbrt")));
        let mut out = Vec::new();
        while let Some((t, loc)) = lexer.next_token()? {
            out.push((t, loc.line, loc.column));
        }
        Ok(out)
    }

    #[test]
    fn words_strings_brackets_and_comments_with_their_places() {
        let t = tokens("Shape \"sphere\" # a comment \"not a string\"\n  \"float radius\" [2.5]")
            .unwrap();
        let w = |s: &str| Token::Word(s.into());
        let s = |s: &str| Token::Str(s.into());
        assert_eq!(
            t,
            vec![
                (w("Shape"), 1, 1),
                (s("sphere"), 1, 7),
                (s("float radius"), 2, 3),
                (Token::Open, 2, 18),
                (w("2.5"), 2, 19),
                (Token::Close, 2, 22),
            ]
        );
    }

    #[test]
    fn escapes_and_unclosed_strings() {
        assert_eq!(
            tokens(r#""a\"b\\c""#).unwrap()[0].0,
            Token::Str("a\"b\\c".into())
        );
        let e = tokens("Shape\n  \"sphere").unwrap_err().to_string();
        assert_eq!(
            e,
            "t.pbrt:2:3: string not closed before the end of the file"
        );
        let e = tokens("\"a\nb\"").unwrap_err().to_string();
        assert_eq!(e, "t.pbrt:1:1: string not closed on its line");
        assert!(tokens("\"\\q\"")
            .unwrap_err()
            .to_string()
            .contains("unknown escape"));
    }
}
