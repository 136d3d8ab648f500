//! The directives, one arm each: transforms, the graphics state, includes, object
//! instances, and the entities (camera, shapes, lights, materials, textures) recorded with
//! the state they were declared under.

use super::{resolve, Parser, Push, MAX_ATTRIBUTE_DEPTH};
use crate::pbrt::lexer::{Lexer, Token};
use crate::pbrt::params::Param;
use crate::pbrt::scene::{
    Entity, LightEntity, MaterialEntity, MaterialRef, MediaNames, ShapeEntity, TextureEntity,
};
use crate::pbrt::Loc;
use crate::LoadError;
use glam::{DMat4, DVec3, DVec4};
use std::rc::Rc;

impl Parser {
    pub(super) fn directive(
        &mut self,
        d: &str,
        loc: Loc,
        lexer: &mut Lexer,
    ) -> Result<(), LoadError> {
        match d {
            "Identity" => self.state.ctm = DMat4::IDENTITY,
            "Translate" => {
                let v = self.numbers(lexer, 3, d)?;
                self.concat(DMat4::from_translation(DVec3::new(v[0], v[1], v[2])));
            }
            "Scale" => {
                let v = self.numbers(lexer, 3, d)?;
                self.concat(DMat4::from_scale(DVec3::new(v[0], v[1], v[2])));
            }
            "Rotate" => {
                let v = self.numbers(lexer, 4, d)?;
                let axis = DVec3::new(v[1], v[2], v[3])
                    .try_normalize()
                    .ok_or_else(|| loc.error("Rotate: the axis is zero"))?;
                self.concat(DMat4::from_axis_angle(axis, v[0].to_radians()));
            }
            "LookAt" => {
                let v = self.numbers(lexer, 9, d)?;
                let m = look_at(
                    DVec3::new(v[0], v[1], v[2]),
                    DVec3::new(v[3], v[4], v[5]),
                    DVec3::new(v[6], v[7], v[8]),
                )
                .ok_or_else(|| {
                    loc.error("LookAt: the eye equals the target, or up is parallel to the view")
                })?;
                self.concat(m);
            }
            "Transform" | "ConcatTransform" => {
                let v = self.numbers(lexer, 16, d)?;
                let m = DMat4::from_cols_array(&v.try_into().expect("16 numbers"));
                if d == "Transform" {
                    self.state.ctm = m;
                } else {
                    self.concat(m);
                }
            }
            "CoordinateSystem" => {
                let (name, _) = self.string(lexer, "a coordinate system name")?;
                self.named_systems.insert(name, self.state.ctm);
            }
            "CoordSysTransform" => {
                let (name, nloc) = self.string(lexer, "a coordinate system name")?;
                self.state.ctm = *self.named_systems.get(&name).ok_or_else(|| {
                    nloc.error(format!(
                        "CoordSysTransform: no coordinate system \"{name}\""
                    ))
                })?;
            }
            "ActiveTransform" => match self.expect(lexer, "All, StartTime or EndTime")? {
                (Token::Word(w), _) if w == "All" => {}
                (t, loc) => {
                    return Err(loc.error(format!(
                        "ActiveTransform {}: motion blur is not supported yet",
                        t.describe()
                    )))
                }
            },
            "TransformTimes" => {
                self.numbers(lexer, 2, d)?;
            }
            "ReverseOrientation" => self.state.reverse_orientation ^= true,
            "AttributeBegin" | "TransformBegin" => {
                if self.pushed.len() >= MAX_ATTRIBUTE_DEPTH {
                    return Err(loc.error(format!("{d} nested deeper than {MAX_ATTRIBUTE_DEPTH}")));
                }
                let kind = if d == "AttributeBegin" {
                    Push::Attribute
                } else {
                    Push::Transform
                };
                self.pushed.push((self.state.clone(), kind, loc));
            }
            "AttributeEnd" | "TransformEnd" => {
                let want = if d == "AttributeEnd" {
                    Push::Attribute
                } else {
                    Push::Transform
                };
                match self.pushed.pop() {
                    Some((state, kind, _)) if kind == want => {
                        if kind == Push::Transform {
                            self.state.ctm = state.ctm;
                        } else {
                            self.state = state;
                        }
                    }
                    Some((_, _, begin)) => {
                        return Err(
                            loc.error(format!("{d} does not match the block begun at {begin}"))
                        )
                    }
                    None => return Err(loc.error(format!("{d} without a matching begin"))),
                }
            }
            "WorldBegin" => {
                if self.in_world {
                    return Err(loc.error("a second WorldBegin"));
                }
                self.in_world = true;
                self.state.ctm = DMat4::IDENTITY;
                self.named_systems.insert("world".into(), DMat4::IDENTITY);
            }
            "WorldEnd" => {}
            "Include" | "Import" => {
                let (name, nloc) = self.string(lexer, "a file name")?;
                let path = resolve(&name, &loc, &self.desc.main_folder);
                self.file(&path, Some(&nloc))?;
            }
            "Option" => {
                let params = self.params(lexer)?;
                self.desc.options.extend(params);
            }
            "ColorSpace" => {
                let (name, nloc) = self.string(lexer, "a colour space name")?;
                if name != "srgb" {
                    return Err(nloc.error(format!(
                        "ColorSpace \"{name}\" is not supported yet (ppm renders in linear sRGB)"
                    )));
                }
            }
            "Camera" | "Film" | "Sampler" | "Integrator" | "PixelFilter" | "Accelerator" => {
                self.require_world(d, &loc, false)?;
                let entity = self.entity(lexer, d, loc)?;
                let slot = match d {
                    "Camera" => {
                        let ctm = self.state.ctm;
                        self.named_systems.insert("camera".into(), ctm.inverse());
                        self.desc.camera_media = self.state.media.clone();
                        if self.desc.camera.is_some() {
                            return Err(entity.loc.error("a second Camera"));
                        }
                        self.desc.camera = Some((entity, ctm));
                        return Ok(());
                    }
                    "Film" => &mut self.desc.film,
                    "Sampler" => &mut self.desc.sampler,
                    "Integrator" => &mut self.desc.integrator,
                    "PixelFilter" => &mut self.desc.filter,
                    _ => &mut self.desc.accelerator,
                };
                if slot.is_some() {
                    return Err(entity.loc.error(format!("a second {d}")));
                }
                *slot = Some(entity);
            }
            "Shape" => {
                self.require_world(d, &loc, true)?;
                let entity = Rc::new(self.entity(lexer, d, loc)?);
                let shape = ShapeEntity {
                    entity,
                    defaults: self.state.shape_defaults.clone(),
                    ctm: self.state.ctm,
                    reverse_orientation: self.state.reverse_orientation,
                    material: self.state.material.clone(),
                    area_light: self.state.area_light.clone(),
                    instance: None,
                    media: self.state.media.clone(),
                };
                match &mut self.object {
                    Some((name, _, shapes)) => {
                        if shape.area_light.is_some() {
                            return Err(shape.entity.loc.error(format!(
                                "a shape with an area light inside object \"{name}\": pbrt-v4 does not support area lights in instances"
                            )));
                        }
                        shapes.push(shape);
                    }
                    None => self.add_shapes(std::iter::once(shape), None)?,
                }
            }
            "ObjectBegin" => {
                self.require_world(d, &loc, true)?;
                let (name, _) = self.string(lexer, "an object name")?;
                if let Some((outer, begin, _)) = &self.object {
                    return Err(loc.error(format!(
                        "ObjectBegin \"{name}\" inside object \"{outer}\" (begun at {begin})"
                    )));
                }
                if self.pushed.len() >= MAX_ATTRIBUTE_DEPTH {
                    return Err(loc.error("ObjectBegin nested too deep"));
                }
                self.pushed
                    .push((self.state.clone(), Push::Object, loc.clone()));
                self.object = Some((name, loc, Vec::new()));
            }
            "ObjectEnd" => {
                let Some((name, _, shapes)) = self.object.take() else {
                    return Err(loc.error("ObjectEnd without ObjectBegin"));
                };
                match self.pushed.pop() {
                    Some((state, Push::Object, _)) => self.state = state,
                    _ => return Err(loc.error("ObjectEnd does not match its ObjectBegin")),
                }
                if self.objects.insert(name.clone(), shapes).is_some() {
                    return Err(loc.error(format!("object \"{name}\" defined twice")));
                }
            }
            "ObjectInstance" => {
                self.require_world(d, &loc, true)?;
                let (name, nloc) = self.string(lexer, "an object name")?;
                if self.object.is_some() {
                    return Err(loc.error("ObjectInstance inside an ObjectBegin"));
                }
                let shapes = self
                    .objects
                    .get(&name)
                    .ok_or_else(|| nloc.error(format!("ObjectInstance: no object \"{name}\"")))?
                    .clone();
                let ctm = self.state.ctm;
                let object: Rc<str> = name.into();
                self.add_shapes(shapes.into_iter(), Some((ctm, object)))?;
            }
            "LightSource" => {
                self.require_world(d, &loc, true)?;
                let entity = self.entity(lexer, d, loc)?;
                self.desc.lights.push(LightEntity {
                    entity,
                    defaults: self.state.light_defaults.clone(),
                    ctm: self.state.ctm,
                });
            }
            "AreaLightSource" => {
                self.require_world(d, &loc, true)?;
                self.state.area_light = Some(Rc::new(self.entity(lexer, d, loc)?));
            }
            "Material" => {
                self.require_world(d, &loc, true)?;
                let entity = self.entity(lexer, d, loc)?;
                self.desc.materials.push(MaterialEntity {
                    entity,
                    defaults: self.state.material_defaults.clone(),
                    name: None,
                });
                self.state.material = MaterialRef::Anonymous(self.desc.materials.len() - 1);
            }
            "MakeNamedMaterial" => {
                self.require_world(d, &loc, true)?;
                let (name, _) = self.string(lexer, "a material name")?;
                let params = self.params(lexer)?;
                if self.desc.named_materials.contains_key(&name) {
                    return Err(loc.error(format!("named material \"{name}\" defined twice")));
                }
                let material = MaterialEntity {
                    entity: Entity {
                        kind: String::new(),
                        params,
                        loc,
                    },
                    defaults: self.state.material_defaults.clone(),
                    name: Some(name.clone()),
                };
                self.desc.named_materials.insert(name, material);
            }
            "NamedMaterial" => {
                self.require_world(d, &loc, true)?;
                let (name, nloc) = self.string(lexer, "a material name")?;
                self.state.material = MaterialRef::Named(name, nloc);
            }
            "Texture" => {
                self.require_world(d, &loc, true)?;
                let (name, _) = self.string(lexer, "a texture name")?;
                let (value_type, tloc) = self.string(lexer, "\"float\" or \"spectrum\"")?;
                if !matches!(value_type.as_str(), "float" | "spectrum") {
                    return Err(tloc.error(format!(
                        "Texture \"{name}\": type \"{value_type}\" is not float or spectrum"
                    )));
                }
                let entity = self.entity(lexer, d, loc)?;
                if self.desc.textures.contains_key(&name) {
                    return Err(entity
                        .loc
                        .error(format!("texture \"{name}\" defined twice")));
                }
                self.desc.textures.insert(
                    name.clone(),
                    TextureEntity {
                        name,
                        value_type,
                        entity,
                    },
                );
            }
            "Attribute" => {
                self.require_world(d, &loc, true)?;
                let (target, tloc) =
                    self.string(lexer, "shape, light, material, medium or texture")?;
                let params = self.params(lexer)?;
                let slot = match target.as_str() {
                    "shape" => &mut self.state.shape_defaults,
                    "light" => &mut self.state.light_defaults,
                    "material" => &mut self.state.material_defaults,
                    "medium" | "texture" => {
                        return Err(tloc.error(format!(
                            "Attribute \"{target}\" is not supported yet"
                        )))
                    }
                    _ => {
                        return Err(tloc.error(format!(
                            "Attribute \"{target}\": expected shape, light, material, medium or texture"
                        )))
                    }
                };
                let mut merged: Vec<Param> = params.clone();
                merged.extend(
                    slot.iter()
                        .filter(|p| !params.iter().any(|q| q.name == p.name))
                        .cloned(),
                );
                *slot = Rc::new(merged);
            }
            "MakeNamedMedium" => {
                let (name, _) = self.string(lexer, "a medium name")?;
                let params = self.params(lexer)?;
                if self.desc.media.contains_key(&name) {
                    return Err(loc.error(format!("medium \"{name}\" defined twice")));
                }
                let entity = Entity {
                    kind: String::new(),
                    params,
                    loc,
                };
                self.desc.media.insert(name, entity);
            }
            "MediumInterface" => {
                // One name is both sides; two are inside, then outside.
                let (inside, _) = self.string(lexer, "a medium name")?;
                let outside = match lexer.peek()? {
                    Some((Token::Str(_), _)) => self.string(lexer, "a medium name")?.0,
                    _ => inside.clone(),
                };
                self.state.media = (!inside.is_empty() || !outside.is_empty()).then(|| {
                    Rc::new(MediaNames {
                        inside,
                        outside,
                        loc,
                    })
                });
            }
            _ => return Err(loc.error(format!("unknown directive `{d}`"))),
        }
        Ok(())
    }
}

/// pbrt's LookAt: camera-from-world for an eye at `eye` looking at `target` with `up`
/// (pbrt-v4 `transform.cpp`): world-from-camera has columns right = normalize(up x dir),
/// newUp = dir x right, dir, eye.
pub fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (target - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(eye.x, eye.y, eye.z, 1.0),
    );
    Some(world_from_camera.inverse())
}
