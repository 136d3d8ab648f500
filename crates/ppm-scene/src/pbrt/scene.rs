//! The parse layer's output: the scene's entities, each with the transform and graphics
//! state it was declared under (pbrt-v4's `BasicSceneBuilder` produces the same list of
//! "scene entities"). Nothing here knows about rendering.

use super::params::Param;
use super::Loc;
use glam::DMat4;
use std::collections::HashMap;
use std::rc::Rc;

/// A directive with a type and parameters: `Shape "sphere" "float radius" [2]`.
#[derive(Clone, Debug)]
pub struct Entity {
    /// `sphere`, `perspective`, `diffuse`...
    pub kind: String,
    pub params: Vec<Param>,
    pub loc: Loc,
}

/// Which material a shape uses.
#[derive(Clone, Debug)]
pub enum MaterialRef {
    /// An index into [`Description::materials`] (`Material`, or pbrt's default diffuse).
    Anonymous(usize),
    /// A `NamedMaterial`, resolved when the scene is built (pbrt-v4 allows the definition to
    /// come later in the file).
    Named(String, Loc),
}

/// A shape with its place and looks.
#[derive(Clone, Debug)]
pub struct ShapeEntity {
    pub entity: Rc<Entity>,
    /// `Attribute "shape"` defaults in force.
    pub defaults: Rc<Vec<Param>>,
    /// World from object.
    pub ctm: DMat4,
    pub reverse_orientation: bool,
    pub material: MaterialRef,
    /// The `AreaLightSource` in force.
    pub area_light: Option<Rc<Entity>>,
    /// For a copy made by `ObjectInstance`: which shape of which object it is, and the
    /// transforms it composes (`ctm` = instance * definition).
    pub instance: Option<InstanceOf>,
    /// The `MediumInterface` in force, when it names a medium.
    pub media: Option<Rc<MediaNames>>,
}

/// A `MediumInterface "inside" "outside"`: the media on the side opposite the surface's
/// normal and on its side ("" for none), and where the directive is.
#[derive(Clone, Debug)]
pub struct MediaNames {
    pub inside: String,
    pub outside: String,
    pub loc: Loc,
}

/// A shape as an `ObjectInstance` placed it.
#[derive(Clone, Debug)]
pub struct InstanceOf {
    /// The object's name and the shape's place in it: the key of the shared mesh.
    pub object: Rc<str>,
    pub shape: usize,
    /// The CTM at `ObjectInstance` (world from instance).
    pub to_world: DMat4,
    /// The CTM at the shape's definition inside `ObjectBegin` (instance from object).
    pub definition: DMat4,
}

/// A `LightSource` and the transform it was declared under.
#[derive(Clone, Debug)]
pub struct LightEntity {
    pub entity: Entity,
    pub defaults: Rc<Vec<Param>>,
    pub ctm: DMat4,
}

/// A `Material` or `MakeNamedMaterial` (whose kind is its `"string type"` parameter).
#[derive(Clone, Debug)]
pub struct MaterialEntity {
    pub entity: Entity,
    pub defaults: Rc<Vec<Param>>,
    /// The name of a named material.
    pub name: Option<String>,
}

/// A `Texture "name" "spectrum" "class" ...`.
#[derive(Clone, Debug)]
pub struct TextureEntity {
    pub name: String,
    /// `float` or `spectrum`.
    pub value_type: String,
    /// Its class (`imagemap`, `constant`...) and parameters.
    pub entity: Entity,
}

/// Everything a pbrt-v4 scene file declares.
#[derive(Debug, Default)]
pub struct Description {
    /// The camera and camera-from-world (the CTM at `Camera`).
    pub camera: Option<(Entity, DMat4)>,
    pub film: Option<Entity>,
    pub sampler: Option<Entity>,
    pub integrator: Option<Entity>,
    pub filter: Option<Entity>,
    pub accelerator: Option<Entity>,
    /// `Option` directives.
    pub options: Vec<Param>,
    /// Shapes; each `ObjectInstance` adds a copy of its object's shapes, marked with
    /// [`ShapeEntity::instance`] (the builder places a mesh copy as an instance).
    pub shapes: Vec<ShapeEntity>,
    pub lights: Vec<LightEntity>,
    /// Anonymous materials; index 0 is pbrt's default (`diffuse`, reflectance 0.5).
    pub materials: Vec<MaterialEntity>,
    pub named_materials: HashMap<String, MaterialEntity>,
    pub textures: HashMap<String, TextureEntity>,
    /// `MakeNamedMedium` by name (its kind is its `"string type"` parameter).
    pub media: HashMap<String, Entity>,
    /// The `MediumInterface` in force at `Camera`: its outside is the camera's medium.
    pub camera_media: Option<Rc<MediaNames>>,
    /// The folder of the scene file named on the command line (pbrt-v4 resolves relative
    /// file names against it).
    pub main_folder: std::path::PathBuf,
}
