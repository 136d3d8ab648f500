//! The parse layer's output: a tree of plugin objects with typed properties, each tagged with
//! the file and line it came from. Nothing here knows about rendering; the build layer reads
//! it through [`super::props::Props`].

use crate::LoadError;
use glam::{DMat4, DVec3};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where an object or a property was written: a file and a 1-based line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    pub file: Arc<Path>,
    pub line: u32,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)
    }
}

impl Location {
    pub(crate) fn error(&self, message: impl Into<String>) -> crate::LoadError {
        crate::LoadError::Parse {
            path: self.file.to_path_buf(),
            line: self.line as usize,
            column: 0,
            message: message.into(),
        }
    }
}

/// A spectrum as written: the conversion to RGB depends on where it is used (a reflectance
/// or an emitter's radiance), so the parser keeps it raw; see `spectrum.rs`.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// `<spectrum value="0.5"/>`: the same value at every wavelength.
    Uniform(f64),
    /// `<spectrum value="400:0.1, 500:0.5, ..."/>`: (wavelength in nm, value) pairs, increasing.
    Samples(Vec<(f64, f64)>),
    /// A black body of `temperature` kelvin (Planck's law, W m^-2 sr^-1 nm^-1) times `scale`.
    Blackbody { temperature: f64, scale: f64 },
}

/// A property's value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Float(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
    /// Linear RGB (an `<rgb>`, or an `<srgb>` of Mitsuba 0.6 already linearised).
    Rgb(DVec3),
    Spectrum(Spectrum),
    Point(DVec3),
    Vector(DVec3),
    Transform(DMat4),
    /// A nested object or a resolved `<ref>`: an index into [`SceneTree::objects`].
    Object(usize),
}

impl Value {
    /// The XML element that writes this kind of value, for messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Float(_) => "float",
            Value::Integer(_) => "integer",
            Value::Boolean(_) => "boolean",
            Value::String(_) => "string",
            Value::Rgb(_) => "rgb",
            Value::Spectrum(_) => "spectrum",
            Value::Point(_) => "point",
            Value::Vector(_) => "vector",
            Value::Transform(_) => "transform",
            Value::Object(_) => "object",
        }
    }
}

/// A named property of an object. Nested objects without a `name` get `_arg_<n>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Property {
    pub name: String,
    pub value: Value,
    pub location: Location,
}

/// One plugin object: `<bsdf type="diffuse" id="white">...</bsdf>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    /// The element: `scene`, `shape`, `bsdf`, `emitter`, `sensor`, `film`, `sampler`,
    /// `integrator`, `texture`, `rfilter`, `medium`, `phase`, `volume`.
    pub class: String,
    /// The `type` attribute (`diffuse`, `obj`, ...); empty for the scene.
    pub plugin: String,
    pub id: Option<String>,
    pub properties: Vec<Property>,
    pub location: Location,
}

impl Object {
    /// `bsdf `diffuse``, for messages.
    pub fn describe(&self) -> String {
        match &self.id {
            Some(id) => format!("{} `{}` (id `{id}`)", self.class, self.plugin),
            None => format!("{} `{}`", self.class, self.plugin),
        }
    }
}

/// A parsed scene: every object (nested ones and those reached by `<ref>` included) in an
/// arena, the root being the `<scene>` element.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneTree {
    pub objects: Vec<Object>,
    pub root: usize,
    /// Every file read (the scene and its includes), in order.
    pub files: Vec<PathBuf>,
    /// The directories of the scene's `<path>` elements, the latest first.
    pub search_paths: Vec<PathBuf>,
}

impl SceneTree {
    /// The scene element.
    pub fn root(&self) -> &Object {
        &self.objects[self.root]
    }

    /// The file a plugin written in `naming_file` means by `name` (an OBJ, a texture, an
    /// envmap): `name` itself if absolute; otherwise the first that exists of: `name` in the
    /// `<path>` directories (latest first), as Mitsuba's file resolver searches them; next to
    /// `naming_file`; next to the main scene file (where Mitsuba looks for the files named in
    /// an `<include>`d file). When none exists, the path next to `naming_file`, for the error
    /// to name.
    pub fn resolve(&self, naming_file: &Path, name: &str) -> PathBuf {
        let name = Path::new(name);
        if name.is_absolute() {
            return name.to_path_buf();
        }
        let beside = |file: &Path| file.parent().unwrap_or(Path::new("")).join(name);
        self.search_paths
            .iter()
            .map(|dir| dir.join(name))
            .chain([beside(naming_file)])
            .chain(self.files.first().map(|main| beside(main)))
            .find(|p| p.exists())
            .unwrap_or_else(|| beside(naming_file))
    }
}

/// An error if an object contains itself through `<ref>`s (`<bsdf id="a"><ref id="a"/>`),
/// which forward references make possible: the build would never end. Depth-first search,
/// iterative (a chain of references may be as long as the scene).
pub(super) fn refuse_cycles(objects: &[Object]) -> Result<(), LoadError> {
    // 0: not visited, 1: on the current path, 2: done.
    let mut state = vec![0u8; objects.len()];
    let children = |o: usize| {
        objects[o].properties.iter().filter_map(|p| match p.value {
            Value::Object(c) => Some(c),
            _ => None,
        })
    };
    for start in 0..objects.len() {
        if state[start] != 0 {
            continue;
        }
        // (object, how many of its children are already pushed)
        let mut stack = vec![(start, 0usize)];
        state[start] = 1;
        while let Some(&mut (o, ref mut next)) = stack.last_mut() {
            match children(o).nth(*next) {
                Some(c) => {
                    *next += 1;
                    match state[c] {
                        0 => {
                            state[c] = 1;
                            stack.push((c, 0));
                        }
                        1 => {
                            return Err(objects[c].location.error(format!(
                                "{} contains itself through <ref>s",
                                objects[c].describe()
                            )))
                        }
                        _ => {}
                    }
                }
                None => {
                    state[o] = 2;
                    stack.pop();
                }
            }
        }
    }
    Ok(())
}
