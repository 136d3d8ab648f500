//! Parameter lists, `"float fov" [45] "rgb reflectance" [0.5 0.5 0.5]`, and the typed getters
//! the build layer reads them through (pbrt-v4's `ParameterDictionary`): each getter checks
//! the declared type and the number of values, and [`ParamSet::finish`] reports any parameter
//! nobody read, with its file, line and column, so a misspelt or unsupported parameter is an
//! error rather than silently ignored.

use super::spectrum::SpectrumValue;
use super::Loc;
use crate::LoadError;
use glam::{DVec2, DVec3};
use std::cell::Cell;

/// A parameter's declared type (`"point3 P"`); pbrt-v3's names (`point`, `normal`, `color`)
/// are accepted as aliases, as pbrt-v4 does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    Integer,
    Float,
    Point2,
    Vector2,
    Point3,
    Vector3,
    Normal3,
    Rgb,
    Blackbody,
    Spectrum,
    Bool,
    String,
    Texture,
}

impl ParamType {
    pub fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "integer" => ParamType::Integer,
            "float" => ParamType::Float,
            "point2" => ParamType::Point2,
            "vector2" => ParamType::Vector2,
            "point3" | "point" => ParamType::Point3,
            "vector3" | "vector" => ParamType::Vector3,
            "normal3" | "normal" => ParamType::Normal3,
            "rgb" | "color" => ParamType::Rgb,
            "blackbody" => ParamType::Blackbody,
            "spectrum" => ParamType::Spectrum,
            "bool" => ParamType::Bool,
            "string" => ParamType::String,
            "texture" => ParamType::Texture,
            _ => return None,
        })
    }

    pub fn name(self) -> &'static str {
        match self {
            ParamType::Integer => "integer",
            ParamType::Float => "float",
            ParamType::Point2 => "point2",
            ParamType::Vector2 => "vector2",
            ParamType::Point3 => "point3",
            ParamType::Vector3 => "vector3",
            ParamType::Normal3 => "normal3",
            ParamType::Rgb => "rgb",
            ParamType::Blackbody => "blackbody",
            ParamType::Spectrum => "spectrum",
            ParamType::Bool => "bool",
            ParamType::String => "string",
            ParamType::Texture => "texture",
        }
    }

    /// Numbers per value (a point3 is three), for the numeric types.
    fn arity(self) -> usize {
        match self {
            ParamType::Point2 | ParamType::Vector2 => 2,
            ParamType::Point3 | ParamType::Vector3 | ParamType::Normal3 | ParamType::Rgb => 3,
            _ => 1,
        }
    }
}

/// A parameter's values as written.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

/// One parameter of a directive.
#[derive(Clone, Debug)]
pub struct Param {
    pub ty: ParamType,
    pub name: String,
    pub values: Values,
    /// Where its declaration (`"float fov"`) starts.
    pub loc: Loc,
}

impl Param {
    /// Checks the values against the declared type: numbers for the numeric types (a
    /// multiple of the arity, integers for `integer`, finite), strings for `string` and
    /// `texture`, `true`/`false` for `bool`, numbers or one name for `spectrum`.
    pub fn new(ty: ParamType, name: String, values: Values, loc: Loc) -> Result<Self, LoadError> {
        let decl = format!("\"{} {name}\"", ty.name());
        let bad = |what: &str| loc.error(format!("{decl}: {what}"));
        match (&values, ty) {
            (Values::Numbers(v), ParamType::Spectrum) => {
                if v.len() % 2 != 0 || v.is_empty() {
                    return Err(bad("a spectrum is (wavelength, value) pairs"));
                }
            }
            (Values::Numbers(v), ParamType::Blackbody) => {
                if v.len() != 1 {
                    return Err(bad("blackbody takes one temperature in kelvin"));
                }
            }
            (
                Values::Numbers(v),
                ParamType::Integer
                | ParamType::Float
                | ParamType::Point2
                | ParamType::Vector2
                | ParamType::Point3
                | ParamType::Vector3
                | ParamType::Normal3
                | ParamType::Rgb,
            ) => {
                if v.len() % ty.arity() != 0 {
                    return Err(bad(&format!(
                        "{} numbers, expected a multiple of {}",
                        v.len(),
                        ty.arity()
                    )));
                }
                if ty == ParamType::Integer
                    && v.iter()
                        .any(|x| x.fract() != 0.0 || x.abs() > i32::MAX as f64)
                {
                    return Err(bad("expected integers"));
                }
            }
            (Values::Strings(v), ParamType::Spectrum) if v.len() == 1 => {}
            (Values::Strings(_), ParamType::String | ParamType::Texture) => {}
            (Values::Bools(_), ParamType::Bool) => {}
            // pbrt-v4 also reads a bool written as a quoted "true" or "false".
            (Values::Strings(v), ParamType::Bool) => {
                let bools = v
                    .iter()
                    .map(|s| match s.as_str() {
                        "true" => Ok(true),
                        "false" => Ok(false),
                        _ => Err(bad(&format!("\"{s}\" is not true or false"))),
                    })
                    .collect::<Result<_, _>>()?;
                return Ok(Param {
                    ty,
                    name,
                    values: Values::Bools(bools),
                    loc,
                });
            }
            (Values::Numbers(_), _) => return Err(bad("expected strings, found numbers")),
            (Values::Strings(_), _) => return Err(bad("expected numbers, found strings")),
            (Values::Bools(_), _) => return Err(bad("expected numbers, found true/false")),
        }
        if values_len(&values) == 0 {
            return Err(bad("no values"));
        }
        Ok(Param {
            ty,
            name,
            values,
            loc,
        })
    }

    /// `"float fov"`, as messages quote it.
    pub fn decl(&self) -> String {
        format!("\"{} {}\"", self.ty.name(), self.name)
    }
}

fn values_len(v: &Values) -> usize {
    match v {
        Values::Numbers(v) => v.len(),
        Values::Strings(v) => v.len(),
        Values::Bools(v) => v.len(),
    }
}

/// A float, or a texture's name and the parameter that names it.
pub type FloatOrTexture<'a> = Result<f64, (String, &'a Param)>;

/// The parameters of one directive (its own, then the `Attribute` defaults that apply to
/// it), read through typed getters that mark what they read.
pub struct ParamSet<'a> {
    params: Vec<&'a Param>,
    /// Parameters from index `own` on come from `Attribute`: not reported when unread.
    own: usize,
    used: Vec<Cell<bool>>,
    /// The directive, as messages name it: `Shape "sphere"`.
    pub what: String,
    /// Where the directive starts.
    pub loc: Loc,
}

impl<'a> ParamSet<'a> {
    /// `own` parameters of the directive `what` at `loc`, then `defaults` (`Attribute`) for
    /// names it does not give.
    pub fn new(what: String, loc: Loc, own: &'a [Param], defaults: &'a [Param]) -> Self {
        let mut params: Vec<&Param> = own.iter().collect();
        for d in defaults {
            if !params.iter().any(|p| p.name == d.name) {
                params.push(d);
            }
        }
        ParamSet {
            used: params.iter().map(|_| Cell::new(false)).collect(),
            params,
            own: own.len(),
            what,
            loc,
        }
    }

    /// An error at the directive.
    pub fn error(&self, message: impl std::fmt::Display) -> LoadError {
        self.loc.error(format!("{}: {message}", self.what))
    }

    /// An error at a parameter.
    pub fn error_at(&self, p: &Param, message: impl std::fmt::Display) -> LoadError {
        p.loc
            .error(format!("{}: {}: {message}", self.what, p.decl()))
    }

    /// The parameter `name`, marked as read.
    pub fn get(&self, name: &str) -> Option<&'a Param> {
        let i = self.params.iter().position(|p| p.name == name)?;
        self.used[i].set(true);
        Some(self.params[i])
    }

    /// Marks parameters as read without using them (they do not change ppm's image).
    pub fn ignore(&self, names: &[&str]) {
        for n in names {
            self.get(n);
        }
    }

    /// The declared type of `name`, if given (without reading it).
    pub fn param_type(&self, name: &str) -> Option<ParamType> {
        self.params.iter().find(|p| p.name == name).map(|p| p.ty)
    }

    /// Whether `name` is given (without reading it).
    pub fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }

    fn numbers(&self, name: &str, types: &[ParamType]) -> Result<Option<&'a [f64]>, LoadError> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        if !types.contains(&p.ty) {
            let names: Vec<_> = types.iter().map(|t| t.name()).collect();
            return Err(self.error_at(p, format!("expected type {}", names.join(" or "))));
        }
        match &p.values {
            Values::Numbers(v) => Ok(Some(v)),
            _ => Err(self.error_at(p, "expected numbers")),
        }
    }

    fn one(&self, name: &str, ty: ParamType) -> Result<Option<f64>, LoadError> {
        match self.numbers(name, &[ty])? {
            None => Ok(None),
            Some([x]) => Ok(Some(*x)),
            Some(v) => Err(self.error_at(
                self.get(name).expect("read above"),
                format!("{} values, expected one", v.len()),
            )),
        }
    }

    /// A single float.
    pub fn float_opt(&self, name: &str) -> Result<Option<f64>, LoadError> {
        self.one(name, ParamType::Float)
    }

    pub fn float(&self, name: &str, default: f64) -> Result<f64, LoadError> {
        Ok(self.float_opt(name)?.unwrap_or(default))
    }

    /// Floats, any number.
    pub fn floats(&self, name: &str) -> Result<Option<&'a [f64]>, LoadError> {
        self.numbers(name, &[ParamType::Float])
    }

    /// A single integer.
    pub fn int(&self, name: &str, default: i64) -> Result<i64, LoadError> {
        Ok(self
            .one(name, ParamType::Integer)?
            .map_or(default, |x| x as i64))
    }

    /// Integers, any number (checked integral and within i32 by the parser).
    pub fn ints(&self, name: &str) -> Result<Option<Vec<i64>>, LoadError> {
        Ok(self
            .numbers(name, &[ParamType::Integer])?
            .map(|v| v.iter().map(|&x| x as i64).collect()))
    }

    /// Triples of a point, vector or normal type.
    pub fn triples(&self, name: &str, ty: ParamType) -> Result<Option<Vec<DVec3>>, LoadError> {
        Ok(self.numbers(name, &[ty])?.map(|v| {
            v.chunks_exact(3)
                .map(|c| DVec3::new(c[0], c[1], c[2]))
                .collect()
        }))
    }

    /// One point3.
    pub fn point3(&self, name: &str, default: DVec3) -> Result<DVec3, LoadError> {
        match self.triples(name, ParamType::Point3)? {
            None => Ok(default),
            Some(v) if v.len() == 1 => Ok(v[0]),
            Some(v) => Err(self.error_at(
                self.get(name).expect("read above"),
                format!("{} points, expected one", v.len()),
            )),
        }
    }

    /// Pairs of a point2 or vector2.
    pub fn point2s(&self, name: &str) -> Result<Option<Vec<DVec2>>, LoadError> {
        Ok(self
            .numbers(name, &[ParamType::Point2])?
            .map(|v| v.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect()))
    }

    /// A single bool.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, LoadError> {
        let Some(p) = self.get(name) else {
            return Ok(default);
        };
        match &p.values {
            Values::Bools(v) if v.len() == 1 && p.ty == ParamType::Bool => Ok(v[0]),
            _ => Err(self.error_at(p, "expected one bool (true or false)")),
        }
    }

    /// A single string.
    pub fn string_opt(&self, name: &str) -> Result<Option<&'a str>, LoadError> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        match &p.values {
            Values::Strings(v) if v.len() == 1 && p.ty == ParamType::String => Ok(Some(&v[0])),
            _ => Err(self.error_at(p, "expected one string")),
        }
    }

    /// A spectrum-valued parameter: `rgb`, `blackbody`, `spectrum` (samples or a name), or
    /// a `texture` (returned as its name for the caller to resolve).
    pub fn spectrum(&self, name: &str) -> Result<Option<(SpectrumValue, &'a Param)>, LoadError> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        let v = match (&p.values, p.ty) {
            (Values::Numbers(v), ParamType::Rgb) if v.len() == 3 => {
                SpectrumValue::Rgb(DVec3::new(v[0], v[1], v[2]))
            }
            (Values::Numbers(v), ParamType::Blackbody) => SpectrumValue::Blackbody(v[0]),
            (Values::Numbers(v), ParamType::Spectrum) => {
                let samples: Vec<(f64, f64)> = v.chunks_exact(2).map(|c| (c[0], c[1])).collect();
                if samples.windows(2).any(|w| w[1].0 <= w[0].0) {
                    return Err(self.error_at(p, "wavelengths must increase"));
                }
                SpectrumValue::Samples(samples)
            }
            (Values::Strings(v), ParamType::Spectrum) => SpectrumValue::Named(v[0].clone()),
            (Values::Strings(v), ParamType::Texture) if v.len() == 1 => {
                SpectrumValue::Texture(v[0].clone())
            }
            _ => {
                return Err(
                    self.error_at(p, "expected one rgb, blackbody, spectrum or texture value")
                )
            }
        };
        Ok(Some((v, p)))
    }

    /// A float-valued parameter that may be a texture: `Ok(Some(Err(name)))` for a texture.
    pub fn float_or_texture(&self, name: &str) -> Result<Option<FloatOrTexture<'a>>, LoadError> {
        match self.params.iter().find(|p| p.name == name) {
            Some(p) if p.ty == ParamType::Texture => {
                self.get(name);
                match &p.values {
                    Values::Strings(v) if v.len() == 1 => Ok(Some(Err((v[0].clone(), p)))),
                    _ => Err(self.error_at(p, "expected one texture name")),
                }
            }
            _ => Ok(self.float_opt(name)?.map(Ok)),
        }
    }

    /// Fails on the first of the directive's own parameters that nobody read.
    pub fn finish(&self) -> Result<(), LoadError> {
        for (i, p) in self.params.iter().enumerate().take(self.own) {
            if !self.used[i].get() {
                return Err(p.loc.error(format!(
                    "{}: unknown or unsupported parameter {}",
                    self.what,
                    p.decl()
                )));
            }
        }
        Ok(())
    }
}
