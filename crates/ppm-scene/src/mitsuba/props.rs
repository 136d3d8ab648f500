//! Typed access to one object's properties, as Mitsuba's `Properties` gives it: each getter
//! marks what it read, and [`Props::finish`] reports any property nobody read, so a typo
//! (`<float name="radiusx">`) is an error naming it, never silently ignored.

use super::spectrum::{self, Role};
use super::tree::{Location, Object, Property, SceneTree, Value};
use crate::LoadError;
use glam::{DMat4, DVec3};
use std::cell::Cell;

/// The properties of one object of a [`SceneTree`].
pub struct Props<'a> {
    pub tree: &'a SceneTree,
    pub object: &'a Object,
    read: Vec<Cell<bool>>,
}

impl<'a> Props<'a> {
    pub fn new(tree: &'a SceneTree, index: usize) -> Self {
        let object = &tree.objects[index];
        Props {
            tree,
            object,
            read: vec![Cell::new(false); object.properties.len()],
        }
    }

    /// Where the object was written.
    pub fn location(&self) -> &Location {
        &self.object.location
    }

    /// An error at the object's element.
    pub fn error(&self, message: impl Into<String>) -> LoadError {
        self.object.location.error(message.into())
    }

    /// The property `name`, marked as read.
    pub fn get(&self, name: &str) -> Option<&'a Property> {
        let i = self.object.properties.iter().position(|p| p.name == name)?;
        self.read[i].set(true);
        Some(&self.object.properties[i])
    }

    fn wrong_type(&self, p: &Property, expected: &str) -> LoadError {
        p.location.error(format!(
            "property `{}` of {} is a {}, expected {expected}",
            p.name,
            self.object.describe(),
            p.value.kind()
        ))
    }

    /// A float (an integer is accepted too).
    pub fn float_opt(&self, name: &str) -> Result<Option<f64>, LoadError> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Float(v) => Ok(Some(v)),
                Value::Integer(v) => Ok(Some(v as f64)),
                _ => Err(self.wrong_type(p, "a float")),
            },
        }
    }

    pub fn float(&self, name: &str, default: f64) -> Result<f64, LoadError> {
        Ok(self.float_opt(name)?.unwrap_or(default))
    }

    pub fn integer_opt(&self, name: &str) -> Result<Option<i64>, LoadError> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Integer(v) => Ok(Some(v)),
                _ => Err(self.wrong_type(p, "an integer")),
            },
        }
    }

    pub fn integer(&self, name: &str, default: i64) -> Result<i64, LoadError> {
        Ok(self.integer_opt(name)?.unwrap_or(default))
    }

    pub fn boolean(&self, name: &str, default: bool) -> Result<bool, LoadError> {
        match self.get(name) {
            None => Ok(default),
            Some(p) => match p.value {
                Value::Boolean(v) => Ok(v),
                _ => Err(self.wrong_type(p, "a boolean")),
            },
        }
    }

    pub fn string_opt(&self, name: &str) -> Result<Option<&'a str>, LoadError> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match &p.value {
                Value::String(v) => Ok(Some(v)),
                _ => Err(self.wrong_type(p, "a string")),
            },
        }
    }

    pub fn point_opt(&self, name: &str) -> Result<Option<DVec3>, LoadError> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Point(v) | Value::Vector(v) => Ok(Some(v)),
                _ => Err(self.wrong_type(p, "a point")),
            },
        }
    }

    pub fn transform(&self, name: &str) -> Result<DMat4, LoadError> {
        match self.get(name) {
            None => Ok(DMat4::IDENTITY),
            Some(p) => match p.value {
                Value::Transform(m) => Ok(m),
                _ => Err(self.wrong_type(p, "a transform")),
            },
        }
    }

    /// A colour: an `rgb`, a `spectrum` (converted for `role`), or a float (grey). A texture
    /// is an error naming it ("not supported yet").
    pub fn colour_opt(&self, name: &str, role: Role) -> Result<Option<DVec3>, LoadError> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        let rgb = match &p.value {
            Value::Rgb(c) => *c,
            Value::Float(v) => DVec3::splat(*v),
            Value::Spectrum(s) => spectrum::to_rgb(s, role).map_err(|m| {
                p.location.error(format!(
                    "property `{}` of {}: {m}",
                    p.name,
                    self.object.describe()
                ))
            })?,
            Value::Object(i) => {
                let o = &self.tree.objects[*i];
                return Err(o.location.error(format!(
                    "{} (as `{}` of {}) is not supported yet: ppm takes a constant colour here",
                    o.describe(),
                    p.name,
                    self.object.describe()
                )));
            }
            _ => return Err(self.wrong_type(p, "a colour (rgb, spectrum or float)")),
        };
        Ok(Some(rgb))
    }

    pub fn colour(&self, name: &str, default: DVec3, role: Role) -> Result<DVec3, LoadError> {
        Ok(self.colour_opt(name, role)?.unwrap_or(default))
    }

    /// Nested or referenced objects of element `class` (`bsdf`, `emitter`, ...), in order,
    /// marked as read.
    pub fn objects(&self, class: &str) -> Vec<usize> {
        let mut out = Vec::new();
        for (i, p) in self.object.properties.iter().enumerate() {
            if let Value::Object(o) = p.value {
                if self.tree.objects[o].class == class {
                    self.read[i].set(true);
                    out.push(o);
                }
            }
        }
        out
    }

    /// Marks properties as read that ppm accepts and ignores (output formats and the like).
    pub fn ignore(&self, names: &[&str]) {
        for name in names {
            self.get(name);
        }
    }

    /// Fails on the first property nobody read: "unreferenced property `foo` of bsdf
    /// `diffuse` at scene.xml:12".
    pub fn finish(self) -> Result<(), LoadError> {
        let unread = self
            .object
            .properties
            .iter()
            .zip(&self.read)
            .find(|(_, r)| !r.get());
        match unread {
            None => Ok(()),
            Some((p, _)) => {
                let what = match p.value {
                    Value::Object(o) => format!("{} ", self.tree.objects[o].describe()),
                    _ => String::new(),
                };
                Err(p.location.error(format!(
                    "unreferenced property {what}`{}` of {} at {}: ppm does not read it (misspelt, or not supported yet)",
                    p.name,
                    self.object.describe(),
                    self.object.location
                )))
            }
        }
    }
}
