//! A fingerprint of a loaded scene, recorded in every rendered image so that `--resume` and
//! `ppm merge` can refuse to join renders of different scenes.
//!
//! The fingerprint is FNV-1a (64-bit) over a text that [`Fingerprint`] writes field by field
//! from one explicit list: camera, materials (with their textures, every texel), triangle
//! meshes (every vertex, normal and index, so OBJ files are included; their uvs when a
//! material is textured), spheres, lights of every kind and render defaults. Nothing
//! is hashed through a `Debug` implementation, so no derive decides whether old renders
//! resume. The text is the one ppm wrote before the fingerprint was explicit (then the
//! `Debug` text of the same values), so the fingerprints of scenes saved by earlier
//! versions are unchanged; a test pins them. A new kind of content adds its own fields only
//! when present (a spot light writes `SpotLight { ... }` in the list of lights), so scenes
//! without it keep their fingerprint (instanced meshes and their placements are written
//! after the spheres only when there are placements). Floats are written in Rust's shortest round-trip form,
//! so two scenes hash alike exactly when they hold the same values; comments, whitespace and
//! file names do not count.
//!
//! FNV-1a is not collision resistant against a forger; it guards against honest mistakes
//! (a part of another scene), which is what it is used for.

use glam::Vec3;
use ppm_core::bsdf::{
    Beckmann, Bsdf, Conductor, Dielectric, Diffuse, Ggx, Glass, Microfacet, Mirror, Phong, Plastic,
    ThinDielectric, TwoSided,
};
use ppm_core::camera::Camera;
use ppm_core::geometry::{MeshInstance, Sphere, TriangleMesh};
use ppm_core::integrator::{Algorithm, Radius};
use ppm_core::light::{
    EnvironmentLight, EnvironmentMap, Light, PointLight, SphereLight, SpotLight, TriangleLight,
};
use ppm_core::material::Material;
use ppm_core::medium::MediumInterface;
use ppm_core::scene::{RenderDefaults, SceneBuilder};
use ppm_core::texture::{Texture, UvTransform};
use std::fmt::Write;

/// The fingerprint of everything the renderer will see of the scene (see the module
/// documentation).
pub fn content_hash(builder: &SceneBuilder) -> u64 {
    let mut f = Fingerprint::new();
    let SceneBuilder {
        camera,
        materials,
        meshes,
        spheres,
        instanced_meshes,
        instances,
        lights,
        defaults,
        // Where the builder's coordinates sit in the world: the image does not depend on it.
        world_offset: _,
    } = builder;
    f.camera(camera);
    f.list(materials, Fingerprint::material);
    // Texture coordinates change the image only through textures: without a textured
    // material they are left out, so scenes keep the fingerprint they had before meshes
    // kept them.
    let textured = materials.iter().any(|m| m.textures.is_some());
    f.list(meshes, |f, m| f.mesh(m, textured));
    f.list(spheres, Fingerprint::sphere);
    if !instances.is_empty() {
        f.text("Instanced");
        f.list(instanced_meshes, |f, m| f.mesh(m, textured));
        f.list(instances, Fingerprint::instance);
    }
    f.list(lights, Fingerprint::light);
    f.defaults(defaults);
    f.hash
}

/// The FNV-1a state and the writer of each value it takes. Values are written as
/// `Name { field: value, ... }`, lists as `[a, b]`, vectors as `Vec3(x, y, z)`.
struct Fingerprint {
    hash: u64,
}

/// One `Name { ... }` record being written; [`Record::end`] closes it.
struct Record<'a> {
    f: &'a mut Fingerprint,
    fields: usize,
}

impl Record<'_> {
    /// One field: its name, then what `value` writes.
    fn field(mut self, name: &str, value: impl FnOnce(&mut Fingerprint)) -> Self {
        self.f.text(if self.fields == 0 { " { " } else { ", " });
        self.f.text(name);
        self.f.text(": ");
        value(self.f);
        self.fields += 1;
        self
    }

    fn end(self) {
        if self.fields > 0 {
            self.f.text(" }");
        }
    }
}

impl Fingerprint {
    fn new() -> Self {
        Fingerprint {
            hash: 0xcbf2_9ce4_8422_2325,
        }
    }

    fn text(&mut self, s: &str) {
        self.bytes(s.as_bytes());
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.hash ^= byte as u64;
            self.hash = self.hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Shortest round-trip form (`1.0`, `0.73`, `1e-7`).
    fn f32(&mut self, x: f32) {
        let _ = write!(self, "{x:?}");
    }

    fn u32(&mut self, x: u32) {
        let _ = write!(self, "{x}");
    }

    fn bool(&mut self, x: bool) {
        self.text(if x { "true" } else { "false" });
    }

    /// A quoted string with Rust's escapes.
    fn string(&mut self, s: &str) {
        let _ = write!(self, "{s:?}");
    }

    fn vec3(&mut self, v: Vec3) {
        self.text("Vec3(");
        self.f32(v.x);
        self.text(", ");
        self.f32(v.y);
        self.text(", ");
        self.f32(v.z);
        self.text(")");
    }

    fn option<T: Copy>(&mut self, x: Option<T>, some: impl FnOnce(&mut Self, T)) {
        match x {
            Some(x) => {
                self.text("Some(");
                some(self, x);
                self.text(")");
            }
            None => self.text("None"),
        }
    }

    fn list<T>(&mut self, items: &[T], mut each: impl FnMut(&mut Self, &T)) {
        self.text("[");
        for (i, item) in items.iter().enumerate() {
            if i > 0 {
                self.text(", ");
            }
            each(self, item);
        }
        self.text("]");
    }

    fn record(&mut self, name: &str) -> Record<'_> {
        self.text(name);
        Record { f: self, fields: 0 }
    }

    /// `Variant(` ... `)` around what `inner` writes.
    fn variant(&mut self, name: &str, inner: impl FnOnce(&mut Self)) {
        self.text(name);
        self.text("(");
        inner(self);
        self.text(")");
    }

    fn camera(&mut self, c: &Camera) {
        let (right, up, forward, tan_half_fov) = c.frame();
        let record = self
            .record("Camera")
            .field("position", |f| f.vec3(c.position))
            .field("right", |f| f.vec3(right))
            .field("up", |f| f.vec3(up))
            .field("forward", |f| f.vec3(forward))
            .field("tan_half_fov", |f| f.f32(tan_half_fov))
            .field("width", |f| f.u32(c.width))
            .field("height", |f| f.u32(c.height));
        // A pinhole writes no lens, so pinhole scenes keep the fingerprint they always had.
        let record = if c.is_pinhole() {
            record
        } else {
            record
                .field("lens_radius", |f| f.f32(c.lens_radius()))
                .field("focus_distance", |f| f.f32(c.focus_distance()))
        };
        record.end();
    }

    fn material(&mut self, m: &Material) {
        let Material {
            bsdf,
            emission,
            name,
            textures,
            medium,
        } = m;
        let record = self
            .record("Material")
            .field("bsdf", |f| f.bsdf(bsdf))
            .field("emission", |f| f.vec3(*emission))
            .field("name", |f| f.string(name));
        // Only when textured, so that constant materials keep their fingerprint.
        let record = match textures {
            Some(t) => record.field("textures", |f| {
                f.list(t.slots(), |f, (slot, texture)| {
                    f.text(slot.name());
                    f.text(": ");
                    f.texture(texture);
                })
            }),
            None => record,
        };
        // Absorbing media are written only when present, so that scenes without them keep
        // the fingerprint they had before media existed.
        let record = if medium.is_clear() {
            record
        } else {
            let MediumInterface { interior, exterior } = medium;
            record.field("medium", |f| {
                f.record("MediumInterface")
                    .field("interior", |f| f.vec3(*interior))
                    .field("exterior", |f| f.vec3(*exterior))
                    .end()
            })
        };
        record.end();
    }

    /// A texture: its model, parameters and (for a bitmap) every texel's bits, so that a
    /// changed image file changes the fingerprint.
    fn texture(&mut self, t: &Texture) {
        let transform = |f: &mut Self, u: &UvTransform| f.list(&u.m, |f, x| f.f32(*x));
        match t {
            Texture::Constant(c) => self.variant("Constant", |f| f.vec3(*c)),
            Texture::Checkerboard(c) => self
                .record("Checkerboard")
                .field("color0", |f| f.vec3(c.color0))
                .field("color1", |f| f.vec3(c.color1))
                .field("transform", |f| transform(f, &c.transform))
                .end(),
            Texture::Bitmap(b) => {
                let (w, h) = b.size();
                self.record("Bitmap")
                    .field("size", |f| f.list(&[w, h], |f, x| f.u32(*x)))
                    .field("filter", |f| f.text(&format!("{:?}", b.filter)))
                    .field("wrap", |f| f.text(&format!("{:?}", b.wrap)))
                    .field("transform", |f| transform(f, &b.transform))
                    .field("texels", |f| {
                        for t in b.texels() {
                            for x in t.to_array() {
                                f.bytes(&x.to_bits().to_le_bytes());
                            }
                        }
                    })
                    .end()
            }
        }
    }

    fn bsdf(&mut self, b: &Bsdf) {
        match b {
            Bsdf::Diffuse(Diffuse { albedo }) => self.variant("Diffuse", |f| {
                f.record("Diffuse")
                    .field("albedo", |f| f.vec3(*albedo))
                    .end()
            }),
            Bsdf::Mirror(Mirror { color }) => self.variant("Mirror", |f| {
                f.record("Mirror").field("color", |f| f.vec3(*color)).end()
            }),
            Bsdf::Glass(Glass { ior, color }) => self.variant("Glass", |f| {
                f.record("Glass")
                    .field("ior", |f| f.f32(*ior))
                    .field("color", |f| f.vec3(*color))
                    .end()
            }),
            Bsdf::Phong(Phong {
                diffuse,
                specular,
                exponent,
            }) => self.variant("Phong", |f| {
                f.record("Phong")
                    .field("diffuse", |f| f.vec3(*diffuse))
                    .field("specular", |f| f.vec3(*specular))
                    .field("exponent", |f| f.f32(*exponent))
                    .end()
            }),
            Bsdf::Conductor(c) => self.variant("Conductor", |f| f.conductor(c)),
            Bsdf::Dielectric(Dielectric {
                eta,
                specular_reflectance,
                specular_transmittance,
                roughness,
            }) => self.variant("Dielectric", |f| {
                f.record("Dielectric")
                    .field("eta", |f| f.f32(*eta))
                    .field("specular_reflectance", |f| f.vec3(*specular_reflectance))
                    .field("specular_transmittance", |f| {
                        f.vec3(*specular_transmittance)
                    })
                    .field("roughness", |f| f.roughness(roughness))
                    .end()
            }),
            Bsdf::ThinDielectric(ThinDielectric {
                eta,
                specular_reflectance,
                specular_transmittance,
            }) => self.variant("ThinDielectric", |f| {
                f.record("ThinDielectric")
                    .field("eta", |f| f.f32(*eta))
                    .field("specular_reflectance", |f| f.vec3(*specular_reflectance))
                    .field("specular_transmittance", |f| {
                        f.vec3(*specular_transmittance)
                    })
                    .end()
            }),
            Bsdf::Plastic(p) => self.variant("Plastic", |f| f.plastic(p)),
            Bsdf::TwoSidedConductor(TwoSided(c)) => {
                self.variant("TwoSidedConductor", |f| f.conductor(c))
            }
            Bsdf::TwoSidedPlastic(TwoSided(p)) => self.variant("TwoSidedPlastic", |f| f.plastic(p)),
        }
    }

    fn conductor(&mut self, c: &Conductor) {
        let Conductor {
            eta,
            k,
            specular_reflectance,
            roughness,
        } = c;
        self.record("Conductor")
            .field("eta", |f| f.vec3(*eta))
            .field("k", |f| f.vec3(*k))
            .field("specular_reflectance", |f| f.vec3(*specular_reflectance))
            .field("roughness", |f| f.roughness(roughness))
            .end();
    }

    /// A plastic by its parameters (the rest of its fields are computed from them).
    fn plastic(&mut self, p: &Plastic) {
        self.record("Plastic")
            .field("diffuse_reflectance", |f| f.vec3(p.diffuse_reflectance))
            .field("specular_reflectance", |f| f.vec3(p.specular_reflectance))
            .field("eta", |f| f.f32(p.eta))
            .field("roughness", |f| f.roughness(&p.roughness))
            .end();
    }

    /// `None`, `Some(Ggx { alpha_x: .., alpha_y: .. })` or
    /// `Some(Beckmann { alpha_x: .., alpha_y: .. })`: GGX is written as it was before Beckmann
    /// existed (no distribution field), so the scenes of earlier versions keep their
    /// fingerprint.
    fn roughness(&mut self, r: &Option<Microfacet>) {
        match r {
            None => self.text("None"),
            Some(Microfacet::Ggx(Ggx { alpha_x, alpha_y })) => self.variant("Some", |f| {
                f.record("Ggx")
                    .field("alpha_x", |f| f.f32(*alpha_x))
                    .field("alpha_y", |f| f.f32(*alpha_y))
                    .end()
            }),
            Some(Microfacet::Beckmann(Beckmann { alpha_x, alpha_y })) => {
                self.variant("Some", |f| {
                    f.record("Beckmann")
                        .field("alpha_x", |f| f.f32(*alpha_x))
                        .field("alpha_y", |f| f.f32(*alpha_y))
                        .end()
                })
            }
        }
    }

    /// A mesh; its texture coordinates only when `with_uvs` and it has some.
    fn mesh(&mut self, m: &TriangleMesh, with_uvs: bool) {
        let TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
            materials,
        } = m;
        let record = self
            .record("TriangleMesh")
            .field("positions", |f| f.list(positions, |f, p| f.vec3(*p)))
            .field("normals", |f| f.list(normals, |f, n| f.vec3(*n)))
            .field("indices", |f| {
                f.list(indices, |f, tri| f.list(tri, |f, i| f.u32(*i)))
            })
            .field("materials", |f| f.list(materials, |f, m| f.u32(*m)));
        if with_uvs && !uvs.is_empty() {
            record.field("uvs", |f| {
                f.list(uvs, |f, t| {
                    f.f32(t.x);
                    f.text(" ");
                    f.f32(t.y);
                })
            })
        } else {
            record
        }
        .end();
    }

    /// A placement: the mesh's index and the 16 entries of its transform, column by column.
    fn instance(&mut self, p: &MeshInstance) {
        let MeshInstance { mesh, to_world } = p;
        self.record("MeshInstance")
            .field("mesh", |f| f.u32(*mesh))
            .field("to_world", |f| {
                f.list(&to_world.to_cols_array(), |f, x| f.text(&format!("{x:?}")))
            })
            .end();
    }

    fn sphere(&mut self, s: &Sphere) {
        let Sphere {
            center,
            radius,
            material,
            inward,
        } = s;
        self.record("Sphere")
            .field("center", |f| f.vec3(*center))
            .field("radius", |f| f.f32(*radius))
            .field("material", |f| f.u32(*material))
            .field("inward", |f| f.bool(*inward))
            .end();
    }

    /// A light of the builder's list. Point lights write what their list wrote before there
    /// were other kinds; each other model writes its own record.
    fn light(&mut self, light: &Light) {
        match light {
            Light::Point(PointLight {
                position,
                intensity,
            }) => self
                .record("PointLight")
                .field("position", |f| f.vec3(*position))
                .field("intensity", |f| f.vec3(*intensity))
                .end(),
            Light::Spot(spot) => self.spot(spot),
            Light::Environment(light) => self.environment(light),
            // The disk of origins is set from the geometry when the scene is built; the
            // file gives the direction and the irradiance.
            Light::Directional(light) => self
                .record("DirectionalLight")
                .field("direction", |f| f.vec3(light.direction()))
                .field("irradiance", |f| f.vec3(light.irradiance))
                .end(),
            // The builder refuses these (area lights come from emissive materials), but a
            // fingerprint is taken before building: they are written in full all the same.
            Light::Triangle(TriangleLight {
                tri,
                normal,
                area,
                le,
                prim,
            }) => self
                .record("TriangleLight")
                .field("v", |f| f.list(&tri.v, |f, v| f.vec3(*v)))
                .field("normal", |f| f.vec3(*normal))
                .field("area", |f| f.f32(*area))
                .field("le", |f| f.vec3(*le))
                .field("prim", |f| f.u32(*prim))
                .end(),
            Light::Sphere(SphereLight { sphere, le, prim }) => self
                .record("SphereLight")
                .field("sphere", |f| f.sphere(sphere))
                .field("le", |f| f.vec3(*le))
                .field("prim", |f| f.u32(*prim))
                .end(),
        }
    }

    /// An environment light: its map (the constant colour, or the image's size and every
    /// texel), its scale and its rotation (row by row); the bounding sphere comes from the
    /// geometry when the scene is built.
    fn environment(&mut self, light: &EnvironmentLight) {
        let (map, scale, rotation) = light.parts();
        let rows = rotation.transpose().to_cols_array_2d().map(Vec3::from);
        let record = self.record("EnvironmentLight");
        let record = match map {
            EnvironmentMap::Constant(c) => record.field("color", |f| f.vec3(*c)),
            EnvironmentMap::Image(m) => {
                let (w, h) = m.size();
                record
                    .field("size", |f| f.list(&[w as u32, h as u32], |f, x| f.u32(*x)))
                    .field("texels", |f| f.list(m.texels(), |f, t| f.vec3(*t)))
            }
            EnvironmentMap::EqualArea(m) => record
                .field("equal_area_size", |f| f.u32(m.size() as u32))
                .field("texels", |f| f.list(m.texels(), |f, t| f.vec3(*t))),
        };
        record
            .field("scale", |f| f.f32(scale))
            .field("rotation", |f| f.list(&rows, |f, r| f.vec3(*r)))
            .end();
    }

    fn spot(&mut self, s: &SpotLight) {
        self.record("SpotLight")
            .field("position", |f| f.vec3(s.position))
            .field("direction", |f| f.vec3(s.direction()))
            .field("intensity", |f| f.vec3(s.intensity))
            .field("cone_angle", |f| f.f32(s.cone_angle()))
            .field("falloff_start", |f| f.f32(s.falloff_start()))
            .end();
    }

    /// The render defaults; `algorithm` and `crop` only when the file names them, so that
    /// scenes without them keep the fingerprint they had before the fields existed.
    fn defaults(&mut self, d: &RenderDefaults) {
        let RenderDefaults {
            max_depth,
            photons,
            radius,
            alpha,
            algorithm,
            crop,
        } = *d;
        let record = self
            .record("RenderDefaults")
            .field("max_depth", |f| f.u32(max_depth))
            .field("photons", |f| f.option(photons, Self::u32))
            // As before `photons` existed (a world radius, or None for `auto` and for no
            // radius, which meant `auto`), so that earlier scenes keep their fingerprints and
            // their saved renders still resume; `photons`, which no earlier scene names, by
            // its word.
            .field("radius", |f| match radius {
                Some(Radius::World(r)) => f.option(Some(r), Self::f32),
                Some(Radius::Photons) => f.text("Some(photons)"),
                Some(Radius::Auto) | None => f.text("None"),
            })
            .field("alpha", |f| f.f32(alpha));
        let record = match algorithm {
            Some(a) => record.field("algorithm", |f| {
                f.text(match a {
                    Algorithm::Path => "Path",
                    Algorithm::Ppm => "Ppm",
                    Algorithm::Sppm => "Sppm",
                    Algorithm::Vcm => "Vcm",
                    Algorithm::Bpt => "Bpt",
                    Algorithm::Bpm => "Bpm",
                    Algorithm::Lt => "Lt",
                })
            }),
            None => record,
        };
        // Also only when the file has one.
        let record = match crop {
            Some(c) => record.field("crop", |f| {
                f.text(&format!(
                    "[{}, {}, {}, {}] of width {}",
                    c.x0, c.x1, c.y0, c.y1, c.full_width
                ))
            }),
            None => record,
        };
        record.end();
    }
}

/// Lets `write!` format numbers straight into the hash, without building the text.
impl Write for Fingerprint {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.text(s);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_reference_values() {
        // Published test vectors of FNV-1a 64.
        let hash = |s: &str| {
            let mut h = Fingerprint::new();
            h.text(s);
            h.hash
        };
        assert_eq!(hash(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(hash("a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(hash("foobar"), 0x8594_4171_f739_67e8);
    }
}
