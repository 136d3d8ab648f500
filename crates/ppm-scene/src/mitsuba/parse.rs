//! Mitsuba XML (versions 0.5/0.6 and 2/3) to a [`SceneTree`]: elements, `$name`
//! substitution with `<default>`s and the caller's defines, `<include>`, `<path>`, `id` and
//! `<ref>`,
//! transforms, colours and spectra, and the upgrade of old property names (`names.rs`).
//! Nothing here knows what a plugin means.
//!
//! Limits keep hostile input finite: [`MAX_FILE_BYTES`] per file, [`MAX_DEPTH`] nested
//! elements, [`MAX_INCLUDE_DEPTH`] nested includes and [`MAX_INCLUDES`] in all, and a
//! bound on the XML nodes of one file.

use super::names::camel_to_snake;
use super::tree::{Location, Object, Property, SceneTree, Spectrum, Value};
mod transform_element;

use super::values::{parse_hex_colour, parse_number, parse_spectrum, parse_triple, srgb_to_linear};
use crate::LoadError;
use roxmltree::{Document, Node, ParsingOptions};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Largest XML file read, in bytes.
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// Deepest nesting of elements.
pub const MAX_DEPTH: usize = 64;
/// Deepest chain of `<include>`s.
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// Most `<include>`s in one scene.
pub const MAX_INCLUDES: usize = 256;
/// Most XML nodes in one file.
const MAX_NODES: u32 = 4_000_000;
/// A `<ref>` to an id not yet defined is `Value::Object(FORWARD + k)`, k its index in
/// `Parser::forward`, until the whole scene is read.
const FORWARD: usize = usize::MAX / 2;

/// Object elements (a plugin each).
const CLASSES: &[&str] = &[
    "shape",
    "bsdf",
    "emitter",
    "sensor",
    "film",
    "sampler",
    "integrator",
    "texture",
    "rfilter",
    "medium",
    "phase",
    "volume",
];

/// Reads and parses the scene at `path`; `defines` (name, value) set `$name` and override
/// the file's `<default>`s.
pub fn parse_file(path: &Path, defines: &[(String, String)]) -> Result<SceneTree, LoadError> {
    let text = read_xml(path, "Mitsuba scene file")?;
    parse_str(&text, path, defines)
}

/// Parses scene text already in memory; `path` names it and locates its relative files.
pub fn parse_str(
    text: &str,
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneTree, LoadError> {
    let mut parser = Parser {
        objects: Vec::new(),
        ids: HashMap::new(),
        params: defines.iter().cloned().collect(),
        files: vec![path.to_path_buf()],
        include_stack: vec![canonical(path)],
        includes: 0,
        search_paths: Vec::new(),
        forward: Vec::new(),
    };
    let root = parser.parse_document(text, path)?;
    parser.resolve_forward_refs()?;
    super::tree::refuse_cycles(&parser.objects)?;
    Ok(SceneTree {
        objects: parser.objects,
        root,
        files: parser.files,
        search_paths: parser.search_paths,
    })
}

fn canonical(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
}

/// A whole XML file as text, refusing non-regular files and files over [`MAX_FILE_BYTES`].
fn read_xml(path: &Path, what: &str) -> Result<String, LoadError> {
    let io = |source| LoadError::Io {
        path: path.to_path_buf(),
        what: what.to_string(),
        source,
    };
    let meta = std::fs::metadata(path).map_err(io)?;
    if meta.is_file() && meta.len() > MAX_FILE_BYTES {
        return Err(LoadError::parse(
            path,
            0,
            format!(
                "the file is {} bytes, more than the {MAX_FILE_BYTES} an XML scene may have",
                meta.len()
            ),
        ));
    }
    crate::obj::read_text(path, what)
}

/// One XML file being read.
struct File<'d, 'i> {
    doc: &'d Document<'i>,
    path: Arc<Path>,
    /// Written for Mitsuba 0.5/0.6: property names are upgraded.
    old_names: bool,
}

impl File<'_, '_> {
    fn location(&self, node: Node) -> Location {
        Location {
            file: self.path.clone(),
            line: self.doc.text_pos_at(node.range().start).row,
        }
    }
}

struct Parser {
    objects: Vec<Object>,
    /// Objects by `id`, registered when their element closes.
    ids: HashMap<String, usize>,
    /// `$name` values: the caller's defines, then the files' `<default>`s.
    params: HashMap<String, String>,
    files: Vec<PathBuf>,
    /// The files being read, outermost first (canonical paths), to refuse include cycles.
    include_stack: Vec<PathBuf>,
    includes: usize,
    /// Directories of `<path value="...">`, the latest first.
    search_paths: Vec<PathBuf>,
    /// `<ref>`s met before the object they name: (id, where the `<ref>` is).
    forward: Vec<(String, Location)>,
}

impl Parser {
    /// Parses one file whose root is `<scene version=...>`; returns the scene object.
    fn parse_document(&mut self, text: &str, path: &Path) -> Result<usize, LoadError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let options = ParsingOptions {
            allow_dtd: false,
            nodes_limit: MAX_NODES,
            ..ParsingOptions::default()
        };
        let doc = Document::parse_with_options(text, options).map_err(|e| LoadError::Parse {
            path: path.to_path_buf(),
            line: e.pos().row as usize,
            column: e.pos().col as usize,
            message: format!("not well-formed XML: {e}"),
        })?;
        let root = doc.root_element();
        let mut file = File {
            doc: &doc,
            path: Arc::from(path),
            old_names: false,
        };
        let location = file.location(root);
        if root.tag_name().name() != "scene" {
            return Err(location.error(format!(
                "the root element is <{}>, expected <scene version=\"...\">",
                root.tag_name().name()
            )));
        }
        let version = root.attribute("version").ok_or_else(|| {
            location.error("<scene> needs a `version` attribute (such as version=\"3.0.0\")")
        })?;
        let major = version
            .split('.')
            .next()
            .and_then(|m| m.trim().parse::<u32>().ok())
            .ok_or_else(|| location.error(format!("invalid version `{version}`")))?;
        file.old_names = major < 2;
        let scene = self.new_object("scene", String::new(), None, location);
        self.parse_children(&file, root, scene, 1)?;
        Ok(scene)
    }

    fn new_object(
        &mut self,
        class: &str,
        plugin: String,
        id: Option<String>,
        location: Location,
    ) -> usize {
        self.objects.push(Object {
            class: class.to_string(),
            plugin,
            id,
            properties: Vec::new(),
            location,
        });
        self.objects.len() - 1
    }

    /// An attribute with `$name`s substituted.
    fn attr(&self, file: &File, node: Node, name: &str) -> Result<Option<String>, LoadError> {
        match node.attribute(name) {
            None => Ok(None),
            Some(raw) => self.substitute(raw).map(Some).map_err(|m| {
                file.location(node)
                    .error(format!("attribute `{name}` of <{}>: {m}", tag(node)))
            }),
        }
    }

    /// A required attribute.
    fn need(&self, file: &File, node: Node, name: &str) -> Result<String, LoadError> {
        self.attr(file, node, name)?.ok_or_else(|| {
            file.location(node)
                .error(format!("<{}> needs a `{name}` attribute", tag(node)))
        })
    }

    /// `text` with every `$name` (letters, digits, `_`) replaced by its value.
    fn substitute(&self, text: &str) -> Result<String, String> {
        if !text.contains('$') {
            return Ok(text.to_string());
        }
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let end = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..end];
            if name.is_empty() {
                return Err("a `$` must be followed by a parameter name".into());
            }
            let value = self.params.get(name).ok_or_else(|| {
                format!(
                    "undefined parameter `${name}` (give it a <default name=\"{name}\" value=\"...\"/> or define it when loading)"
                )
            })?;
            out.push_str(value);
            rest = &after[end..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// A property's name as the build layer sees it (upgraded in old files).
    fn property_name(&self, file: &File, name: String) -> String {
        if file.old_names {
            camel_to_snake(&name)
        } else {
            name
        }
    }

    fn add_property(
        &mut self,
        owner: usize,
        name: String,
        value: Value,
        location: Location,
    ) -> Result<(), LoadError> {
        if let Some(first) = self.objects[owner]
            .properties
            .iter()
            .find(|p| p.name == name)
        {
            return Err(location.error(format!(
                "property `{name}` is given twice (first at line {})",
                first.location.line
            )));
        }
        self.objects[owner].properties.push(Property {
            name,
            value,
            location,
        });
        Ok(())
    }

    /// Name of an unnamed nested object: `_arg_<n>`, n counting the owner's properties.
    fn anonymous(&self, owner: usize) -> String {
        format!("_arg_{}", self.objects[owner].properties.len())
    }

    fn parse_children(
        &mut self,
        file: &File,
        node: Node,
        owner: usize,
        depth: usize,
    ) -> Result<(), LoadError> {
        for child in node.children().filter(|n| n.is_element()) {
            self.parse_element(file, child, owner, depth)?;
        }
        Ok(())
    }

    fn parse_element(
        &mut self,
        file: &File,
        node: Node,
        owner: usize,
        depth: usize,
    ) -> Result<(), LoadError> {
        let location = file.location(node);
        if depth > MAX_DEPTH {
            return Err(location.error(format!("elements are nested more than {MAX_DEPTH} deep")));
        }
        let tag = tag(node);
        if CLASSES.contains(&tag) || (tag == "spectrum" && node.attribute("type").is_some()) {
            return self.parse_object(file, node, owner, depth);
        }
        let name = |p: &Self| -> Result<String, LoadError> {
            Ok(p.property_name(file, p.need(file, node, "name")?))
        };
        let value = |p: &Self| p.need(file, node, "value");
        let bad = |what: &str, v: &str| location.error(format!("<{tag}>: {what} `{v}`"));
        let value = match tag {
            "default" => {
                let name = self.need(file, node, "name")?;
                let value = value(self)?;
                self.params.entry(name).or_insert(value);
                return Ok(());
            }
            "include" => return self.include(file, node, owner, depth),
            "path" => return self.search_path(file, node, owner),
            "ref" => {
                let id = self.need(file, node, "id")?;
                let name = match self.attr(file, node, "name")? {
                    Some(n) => self.property_name(file, n),
                    None => self.anonymous(owner),
                };
                // Mitsuba 3 resolves references once the whole scene is read, so a `<ref>`
                // may come before the object it names (mitsuba-data's Cornell box refers to
                // its emitter before defining it).
                let target = match self.ids.get(&id) {
                    Some(&target) => target,
                    None => {
                        self.forward.push((id, location.clone()));
                        FORWARD + self.forward.len() - 1
                    }
                };
                return self.add_property(owner, name, Value::Object(target), location);
            }
            "float" => {
                let v = value(self)?;
                Value::Float(parse_number(&v).ok_or_else(|| bad("not a finite number", &v))?)
            }
            "integer" => {
                let v = value(self)?;
                Value::Integer(v.trim().parse().map_err(|_| bad("not an integer", &v))?)
            }
            "boolean" => {
                let v = value(self)?;
                Value::Boolean(match v.trim().to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(bad("not `true` or `false`", &v)),
                })
            }
            "string" => Value::String(value(self)?),
            "rgb" | "color" => {
                let v = value(self)?;
                Value::Rgb(parse_triple(&v).ok_or_else(|| bad("expected 1 or 3 numbers", &v))?)
            }
            "srgb" => {
                let v = value(self)?;
                let encoded = parse_hex_colour(&v)
                    .or_else(|| parse_triple(&v))
                    .ok_or_else(|| bad("expected #rrggbb, 1 or 3 numbers", &v))?;
                Value::Rgb(encoded.map(srgb_to_linear))
            }
            "spectrum" => {
                if self.attr(file, node, "filename")?.is_some() {
                    return Err(location.error(
                        "<spectrum filename=...>: spectra from files are not supported yet",
                    ));
                }
                let v = value(self)?;
                Value::Spectrum(parse_spectrum(&v).map_err(|m| bad(&m, &v))?)
            }
            "blackbody" => {
                let t = self.need(file, node, "temperature")?;
                let temperature = parse_number(t.trim().trim_end_matches(['k', 'K']))
                    .filter(|t| *t > 0.0)
                    .ok_or_else(|| bad("not a positive temperature", &t))?;
                let scale = match self.attr(file, node, "scale")? {
                    Some(s) => parse_number(&s).ok_or_else(|| bad("not a finite number", &s))?,
                    None => 1.0,
                };
                Value::Spectrum(Spectrum::Blackbody { temperature, scale })
            }
            "point" | "vector" => {
                let v = self.parse_xyz(file, node, 0.0)?;
                if tag == "point" {
                    Value::Point(v)
                } else {
                    Value::Vector(v)
                }
            }
            "transform" => Value::Transform(self.parse_transform(file, node)?),
            _ => return Err(location.error(format!("unknown element <{tag}>"))),
        };
        let name = name(self)?;
        self.add_property(owner, name, value, location)
    }

    /// `<shape type="obj" id="..." name="...">...</shape>`, added to `owner` by name.
    fn parse_object(
        &mut self,
        file: &File,
        node: Node,
        owner: usize,
        depth: usize,
    ) -> Result<(), LoadError> {
        let location = file.location(node);
        let tag = tag(node);
        let plugin = self.need(file, node, "type")?;
        let id = self.attr(file, node, "id")?;
        let class = if tag == "spectrum" { "texture" } else { tag };
        let index = self.new_object(class, plugin.clone(), id.clone(), location.clone());
        if tag == "spectrum" && plugin == "blackbody" {
            // Mitsuba 3's `<spectrum type="blackbody"><float name="temperature" .../>`:
            // kept as a spectrum value, as 0.6's `<blackbody>` is.
            self.parse_children(file, node, index, depth + 1)?;
            let props = std::mem::take(&mut self.objects[index].properties);
            self.objects.pop();
            let mut temperature = None;
            for p in props {
                match (p.name.as_str(), p.value) {
                    ("temperature", Value::Float(t)) if t > 0.0 => temperature = Some(t),
                    (name, _) => {
                        return Err(p.location.error(format!(
                            "spectrum `blackbody` takes only a positive float `temperature`, not `{name}`"
                        )))
                    }
                }
            }
            let temperature = temperature.ok_or_else(|| {
                location.error("spectrum `blackbody` needs a float `temperature`")
            })?;
            let name = self.property_name(file, self.need(file, node, "name")?);
            let value = Value::Spectrum(Spectrum::Blackbody {
                temperature,
                scale: 1.0,
            });
            return self.add_property(owner, name, value, location);
        }
        self.parse_children(file, node, index, depth + 1)?;
        if let Some(id) = id {
            if let Some(&first) = self.ids.get(&id) {
                return Err(location.error(format!(
                    "id `{id}` is already used at {}",
                    self.objects[first].location
                )));
            }
            self.ids.insert(id, index);
        }
        let name = match self.attr(file, node, "name")? {
            Some(n) => self.property_name(file, n),
            None => self.anonymous(owner),
        };
        self.add_property(owner, name, Value::Object(index), location)
    }

    /// `<include filename="..."/>`: the included scene's elements join `owner`.
    fn include(
        &mut self,
        file: &File,
        node: Node,
        owner: usize,
        depth: usize,
    ) -> Result<(), LoadError> {
        let location = file.location(node);
        let name = self.need(file, node, "filename")?;
        let path = file.path.parent().unwrap_or(Path::new("")).join(&name);
        self.includes += 1;
        if self.includes > MAX_INCLUDES {
            return Err(location.error(format!("more than {MAX_INCLUDES} <include>s")));
        }
        if self.include_stack.len() > MAX_INCLUDE_DEPTH {
            return Err(location.error(format!(
                "<include>s nested more than {MAX_INCLUDE_DEPTH} deep"
            )));
        }
        let key = canonical(&path);
        if self.include_stack.contains(&key) {
            return Err(location.error(format!(
                "<include filename=\"{name}\">: the file includes itself (through {})",
                self.include_stack
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" -> ")
            )));
        }
        let text = read_xml(&path, &format!("included file ({location})"))?;
        self.include_stack.push(key);
        self.files.push(path.clone());
        let included = self.parse_document(&text, &path)?;
        self.include_stack.pop();
        // Move the included scene's properties to `owner`, then drop its empty scene object
        // (the last object created if it has no children; otherwise leave it unreachable).
        let properties = std::mem::take(&mut self.objects[included].properties);
        for p in properties {
            let name = if p.name.starts_with("_arg_") {
                self.anonymous(owner)
            } else {
                p.name
            };
            self.add_property(owner, name, p.value, p.location)?;
        }
        let _ = depth;
        Ok(())
    }

    /// Points the `<ref>`s met before their object at it, now that every id is known.
    fn resolve_forward_refs(&mut self) -> Result<(), LoadError> {
        for object in &mut self.objects {
            for p in &mut object.properties {
                if let Value::Object(i) = &mut p.value {
                    if *i >= FORWARD {
                        let (id, location) = &self.forward[*i - FORWARD];
                        *i = *self.ids.get(id).ok_or_else(|| {
                            location.error(format!(
                                "<ref id=\"{id}\">: no object of the scene has this id"
                            ))
                        })?;
                    }
                }
            }
        }
        Ok(())
    }

    /// `<path value="dir"/>`, a child of a `<scene>`: `dir` (relative to the file that names
    /// it) is searched for the files plugins name, before the directory of the file naming
    /// them, and after the `<path>`s that follow it (Mitsuba 3 prepends each to its file
    /// resolver). The directory must exist, as in Mitsuba.
    fn search_path(&mut self, file: &File, node: Node, owner: usize) -> Result<(), LoadError> {
        let location = file.location(node);
        if self.objects[owner].class != "scene" {
            return Err(location.error("<path> must be a child of <scene>"));
        }
        let value = self.need(file, node, "value")?;
        let dir = file.path.parent().unwrap_or(Path::new("")).join(&value);
        if !dir.is_dir() {
            return Err(location.error(format!(
                "<path value=\"{value}\">: no directory {}",
                dir.display()
            )));
        }
        self.search_paths.insert(0, dir);
        Ok(())
    }
}

fn tag<'a>(node: Node<'a, '_>) -> &'a str {
    node.tag_name().name()
}
