//! Directives to a [`Description`]: the graphics state (current transform, material, area
//! light, `Attribute` defaults, reverse orientation) pushed and popped by
//! `AttributeBegin`/`AttributeEnd`, named coordinate systems, `Include`/`Import`, and object
//! instancing (each `ObjectInstance` copies the object's shapes under its transform).
//!
//! Transforms follow pbrt-v4 (`scene.cpp`, `transform.cpp`): each transform directive
//! post-multiplies the current transform matrix (CTM = CTM * T), `Transform` and
//! `ConcatTransform` take 16 numbers in column-major order (pbrt transposes the matrix it
//! reads row by row), `LookAt` is camera-from-world with camera x = normalize(up x dir): pbrt's
//! camera space is left-handed (see `build/camera.rs`).

mod directives;

pub use directives::look_at;

use super::lexer::{Lexer, Token};
use super::params::{Param, ParamType, Values};
use super::scene::{Description, Entity, MaterialEntity, MaterialRef, MediaNames, ShapeEntity};
use super::Loc;
use crate::LoadError;
use glam::DMat4;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::Arc;

/// Largest scene file read (a file of inline meshes can be large).
pub const MAX_FILE_BYTES: u64 = 1 << 30;
/// Deepest `Include`/`Import` nesting.
pub const MAX_INCLUDE_DEPTH: usize = 32;
/// Deepest `AttributeBegin` nesting.
pub const MAX_ATTRIBUTE_DEPTH: usize = 4096;
/// Most tokens over all files of a scene.
pub const MAX_TOKENS: u64 = 1 << 32;
/// Most shapes after instances are expanded.
pub const MAX_SHAPES: usize = 1 << 22;

/// The graphics state `AttributeBegin` saves.
#[derive(Clone)]
struct GraphicsState {
    ctm: DMat4,
    reverse_orientation: bool,
    material: MaterialRef,
    area_light: Option<Rc<Entity>>,
    shape_defaults: Rc<Vec<Param>>,
    light_defaults: Rc<Vec<Param>>,
    material_defaults: Rc<Vec<Param>>,
    /// The `MediumInterface` in force (`None`: no medium on either side).
    media: Option<Rc<MediaNames>>,
}

/// What pushed a saved state.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Push {
    Attribute,
    Transform,
    Object,
}

struct Parser {
    desc: Description,
    state: GraphicsState,
    pushed: Vec<(GraphicsState, Push, Loc)>,
    named_systems: HashMap<String, DMat4>,
    in_world: bool,
    /// The object being defined: its name, where, and its shapes.
    object: Option<(String, Loc, Vec<ShapeEntity>)>,
    objects: HashMap<String, Vec<ShapeEntity>>,
    /// Canonical paths of the files being read, outermost first (for cycles).
    files: Vec<PathBuf>,
    tokens: u64,
    warnings: Vec<String>,
}

/// Reads the scene file at `path` and everything it includes.
pub fn parse_file(path: &Path) -> Result<(Description, Vec<String>), LoadError> {
    let mut parser = Parser::new(path);
    parser.file(path, None)?;
    parser.finish(path)
}

/// Like [`parse_file`] for text in memory; `path` names it and locates relative files.
pub fn parse_str(text: &str, path: &Path) -> Result<(Description, Vec<String>), LoadError> {
    let mut parser = Parser::new(path);
    parser.files.push(path.to_path_buf());
    parser.text(text, path)?;
    parser.finish(path)
}

/// pbrt's default material: `diffuse` with reflectance 0.5.
fn default_material(path: &Path) -> MaterialEntity {
    MaterialEntity {
        entity: Entity {
            kind: "diffuse".into(),
            params: Vec::new(),
            loc: Loc {
                file: Arc::from(path),
                line: 0,
                column: 0,
            },
        },
        defaults: Rc::default(),
        name: Some("pbrt default diffuse".into()),
    }
}

impl Parser {
    fn new(path: &Path) -> Self {
        let desc = Description {
            materials: vec![default_material(path)],
            main_folder: path.parent().unwrap_or(Path::new("")).to_path_buf(),
            ..Description::default()
        };
        Parser {
            desc,
            state: GraphicsState {
                ctm: DMat4::IDENTITY,
                reverse_orientation: false,
                material: MaterialRef::Anonymous(0),
                area_light: None,
                shape_defaults: Rc::default(),
                light_defaults: Rc::default(),
                material_defaults: Rc::default(),
                media: None,
            },
            pushed: Vec::new(),
            named_systems: HashMap::new(),
            in_world: false,
            object: None,
            objects: HashMap::new(),
            files: Vec::new(),
            tokens: 0,
            warnings: Vec::new(),
        }
    }

    fn finish(self, path: &Path) -> Result<(Description, Vec<String>), LoadError> {
        if let Some((_, _, loc)) = self.pushed.last() {
            return Err(loc.error("AttributeBegin (or ObjectBegin) never ended"));
        }
        if !self.in_world {
            return Err(LoadError::parse(
                path,
                0,
                "the scene has no WorldBegin: pbrt-v4 scenes describe the camera, then WorldBegin, then the world",
            ));
        }
        Ok((self.desc, self.warnings))
    }

    /// Reads one file; `from` is the `Include` that names it.
    fn file(&mut self, path: &Path, from: Option<&Loc>) -> Result<(), LoadError> {
        let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        if self.files.contains(&canonical) {
            let loc = from.expect("the first file cannot repeat");
            return Err(loc.error(format!(
                "{} includes itself (through {} files)",
                path.display(),
                self.files.len()
            )));
        }
        if self.files.len() >= MAX_INCLUDE_DEPTH {
            let loc = from.expect("the first file is depth 0");
            return Err(loc.error(format!("includes nested deeper than {MAX_INCLUDE_DEPTH}")));
        }
        let bytes = crate::ply::read_bytes(path, "pbrt scene file", MAX_FILE_BYTES)?;
        let text = String::from_utf8(bytes)
            .map_err(|e| LoadError::parse(path, 0, format!("not UTF-8 text: {e}")))?;
        self.files.push(canonical);
        self.text(&text, path)?;
        self.files.pop();
        Ok(())
    }

    fn text(&mut self, text: &str, path: &Path) -> Result<(), LoadError> {
        let mut lexer = Lexer::new(text, Arc::from(path));
        while let Some((token, loc)) = self.next(&mut lexer)? {
            match token {
                Token::Word(w) => self.directive(&w, loc, &mut lexer)?,
                other => {
                    return Err(loc.error(format!(
                        "expected a directive (Shape, Material, ...), found {}",
                        other.describe()
                    )))
                }
            }
        }
        Ok(())
    }

    fn next(&mut self, lexer: &mut Lexer) -> Result<Option<(Token, Loc)>, LoadError> {
        self.tokens += 1;
        if self.tokens > MAX_TOKENS {
            return Err(lexer.here().error(format!("more than {MAX_TOKENS} tokens")));
        }
        lexer.next_token()
    }

    /// A token that must be there: `what` names what was expected.
    fn expect(&mut self, lexer: &mut Lexer, what: &str) -> Result<(Token, Loc), LoadError> {
        let here = lexer.here();
        self.next(lexer)?
            .ok_or_else(|| here.error(format!("expected {what}, found the end of the file")))
    }

    fn string(&mut self, lexer: &mut Lexer, what: &str) -> Result<(String, Loc), LoadError> {
        match self.expect(lexer, what)? {
            (Token::Str(s), loc) => Ok((s, loc)),
            (t, loc) => Err(loc.error(format!("expected {what}, found {}", t.describe()))),
        }
    }

    /// `n` numbers, bare or in brackets.
    fn numbers(&mut self, lexer: &mut Lexer, n: usize, d: &str) -> Result<Vec<f64>, LoadError> {
        let bracket = matches!(lexer.peek()?, Some((Token::Open, _)));
        if bracket {
            self.next(lexer)?;
        }
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let (t, loc) = self.expect(lexer, &format!("{n} numbers after {d}"))?;
            out.push(number(&t, &loc, &format!("{n} numbers after {d}"))?);
        }
        if bracket {
            match self.expect(lexer, "`]`")? {
                (Token::Close, _) => {}
                (t, loc) => {
                    return Err(loc.error(format!(
                        "{d} takes {n} numbers; expected `]`, found {}",
                        t.describe()
                    )))
                }
            }
        }
        Ok(out)
    }

    /// A parameter list: `"type name" value` or `"type name" [values]`, repeated.
    fn params(&mut self, lexer: &mut Lexer) -> Result<Vec<Param>, LoadError> {
        let mut params: Vec<Param> = Vec::new();
        while let Some((Token::Str(_), _)) = lexer.peek()? {
            let (decl, loc) = self.string(lexer, "a parameter")?;
            let mut parts = decl.split_whitespace();
            let (Some(ty), Some(name), None) = (parts.next(), parts.next(), parts.next()) else {
                return Err(loc.error(format!(
                    "\"{decl}\" is not a parameter declaration like \"float radius\""
                )));
            };
            let ty = ParamType::parse(ty)
                .ok_or_else(|| loc.error(format!("\"{decl}\": unknown parameter type `{ty}`")))?;
            if params.iter().any(|p| p.name == name) {
                return Err(loc.error(format!("parameter `{name}` given twice")));
            }
            let values = self.values(lexer, &decl)?;
            let values = match (ty, values) {
                (ParamType::Spectrum, Values::Strings(v)) if v.len() == 1 && is_file(&v[0]) => {
                    spectrum_file(&v[0], &loc, &self.desc.main_folder)?
                }
                (_, values) => values,
            };
            params.push(Param::new(ty, name.to_string(), values, loc)?);
        }
        Ok(params)
    }

    fn values(&mut self, lexer: &mut Lexer, decl: &str) -> Result<Values, LoadError> {
        let what = format!("a value for \"{decl}\"");
        let (first, loc) = self.expect(lexer, &what)?;
        if first != Token::Open {
            return Values::single(first, &loc, &what);
        }
        let mut values: Option<Values> = None;
        loop {
            let (t, loc) = self.expect(lexer, "`]`")?;
            if t == Token::Close {
                break;
            }
            match (&mut values, t) {
                (None, t) => values = Some(Values::single(t, &loc, &what)?),
                (Some(Values::Numbers(v)), t @ Token::Word(_)) => v.push(number(&t, &loc, &what)?),
                (Some(Values::Strings(v)), Token::Str(s)) => v.push(s),
                (Some(Values::Bools(v)), Token::Word(w)) => v.push(boolean(&w, &loc)?),
                (Some(_), t) => {
                    return Err(loc.error(format!(
                        "\"{decl}\": {} mixed with values of another kind",
                        t.describe()
                    )))
                }
            }
        }
        values.ok_or_else(|| loc.error(format!("\"{decl}\": no values")))
    }

    fn require_world(&self, d: &str, loc: &Loc, inside: bool) -> Result<(), LoadError> {
        match (self.in_world, inside) {
            (false, true) => Err(loc.error(format!("{d} must come after WorldBegin"))),
            (true, false) => Err(loc.error(format!("{d} must come before WorldBegin"))),
            _ => Ok(()),
        }
    }

    /// `Directive "kind" params`.
    fn entity(&mut self, lexer: &mut Lexer, d: &str, loc: Loc) -> Result<Entity, LoadError> {
        let (kind, _) = self.string(lexer, &format!("the type of the {d}"))?;
        let params = self.params(lexer)?;
        Ok(Entity { kind, params, loc })
    }

    /// Adds shapes; an instance's copies are moved by the CTM at `ObjectInstance` (world =
    /// instance CTM * CTM at the shape's definition, as pbrt-v4 composes them) and marked
    /// with the object they come from, so that the builder stores each mesh once.
    fn add_shapes(
        &mut self,
        shapes: impl Iterator<Item = ShapeEntity>,
        instance: Option<(DMat4, std::rc::Rc<str>)>,
    ) -> Result<(), LoadError> {
        for (k, mut s) in shapes.enumerate() {
            if self.desc.shapes.len() >= MAX_SHAPES {
                return Err(s.entity.loc.error(format!(
                    "more than {MAX_SHAPES} shapes (instances count once per copy)"
                )));
            }
            if let Some((m, object)) = &instance {
                s.instance = Some(crate::pbrt::scene::InstanceOf {
                    object: object.clone(),
                    shape: k,
                    to_world: *m,
                    definition: s.ctm,
                });
                s.ctm = *m * s.ctm;
            }
            self.desc.shapes.push(s);
        }
        Ok(())
    }

    fn concat(&mut self, m: DMat4) {
        self.state.ctm *= m;
    }
}

/// A file named in `loc`'s file: relative to that file's folder, else (pbrt-v4's rule, for
/// scenes that rely on it) to the main scene file's folder.
pub fn resolve(name: &str, loc: &Loc, main_folder: &Path) -> PathBuf {
    let name = Path::new(name);
    if name.is_absolute() {
        return name.to_path_buf();
    }
    let beside = loc.file.parent().unwrap_or(Path::new("")).join(name);
    if beside.exists() {
        return beside;
    }
    let main = main_folder.join(name);
    if main.exists() {
        main
    } else {
        beside
    }
}

/// Largest spectrum file read.
const MAX_SPECTRUM_FILE_BYTES: u64 = 16 << 20;

/// Whether a spectrum's string names a file rather than one of pbrt-v4's named spectra
/// (`metal-*`, `glass-*`, `stdillum-*`, `illum-*` and the cameras' sensor curves).
fn is_file(name: &str) -> bool {
    let named = [
        "metal-",
        "glass-",
        "stdillum-",
        "illum-",
        "canon_",
        "nikon_",
        "sony_",
        "hasselblad_",
    ];
    !named.iter().any(|p| name.starts_with(p))
}

/// A spectrum file as pbrt-v4 reads it (`PiecewiseLinearSpectrum::Read`): (wavelength,
/// value) pairs of numbers separated by white space, `#` comments; wavelengths increasing.
fn spectrum_file(name: &str, loc: &Loc, main_folder: &Path) -> Result<Values, LoadError> {
    let path = resolve(name, loc, main_folder);
    let bytes = crate::ply::read_bytes(&path, "spectrum file", MAX_SPECTRUM_FILE_BYTES)?;
    let text = String::from_utf8_lossy(&bytes);
    let mut numbers = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for word in line.split_whitespace() {
            let x = word
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    LoadError::parse(&path, i + 1, format!("`{word}` is not a number"))
                })?;
            numbers.push(x);
        }
    }
    if numbers.len() < 2 || numbers.len() % 2 != 0 {
        return Err(LoadError::parse(
            &path,
            0,
            format!(
                "{} numbers: a spectrum file holds (wavelength, value) pairs",
                numbers.len()
            ),
        ));
    }
    Ok(Values::Numbers(numbers))
}

fn number(t: &Token, loc: &Loc, what: &str) -> Result<f64, LoadError> {
    match t {
        Token::Word(w) => w
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| loc.error(format!("expected {what}, found `{w}`"))),
        t => Err(loc.error(format!("expected {what}, found {}", t.describe()))),
    }
}

fn boolean(w: &str, loc: &Loc) -> Result<bool, LoadError> {
    match w {
        "true" => Ok(true),
        "false" => Ok(false),
        _ => Err(loc.error(format!("expected true or false, found `{w}`"))),
    }
}

impl Values {
    /// The values a single token starts: numbers, strings or bools.
    fn single(t: Token, loc: &Loc, what: &str) -> Result<Values, LoadError> {
        match t {
            Token::Str(s) => Ok(Values::Strings(vec![s])),
            Token::Word(w) if w == "true" || w == "false" => Ok(Values::Bools(vec![w == "true"])),
            t @ Token::Word(_) => Ok(Values::Numbers(vec![number(&t, loc, what)?])),
            t => Err(loc.error(format!("expected {what}, found {}", t.describe()))),
        }
    }
}
