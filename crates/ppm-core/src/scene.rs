//! The scene description: camera, materials, geometry and lights. Immutable during a render.

use crate::bsdf::{Bsdf, BsdfFlags};
use crate::camera::Camera;
use crate::geometry::{Geometry, Hit, MeshInstance, Ray, Sphere, TriangleMesh};
use crate::light::{EmissionSample, Light, LightKind, PointLight};
use crate::material::Material;
use crate::sampling::Distribution1D;
use crate::SceneError;
use glam::{DMat3, DMat4, Vec2, Vec3};

/// Render defaults a scene file may carry (`render:` in scene format v1).
#[derive(Clone, Copy, PartialEq)]
pub struct RenderDefaults {
    /// Longest light or eye path, in bounces.
    pub max_depth: u32,
    /// Light paths per photon-mapping iteration; `None` leaves it to the algorithm.
    pub photons: Option<u32>,
    /// Initial gather radius: a world radius, `auto` (each pixel's from its footprint,
    /// [`crate::integrator::Radius::Auto`]) or `photons`; `None` (no radius in the file) leaves
    /// it to the default ([`crate::integrator::Radius::Photons`]).
    pub radius: Option<crate::integrator::Radius>,
    /// Radius reduction parameter of progressive photon mapping.
    pub alpha: f32,
    /// The integrator the file asks for (`render.algorithm`); `None`: the front end's default.
    pub algorithm: Option<crate::integrator::Algorithm>,
    /// The pixels the file asks to render (`render.pixel_bounds`, a Mitsuba film's crop
    /// window, pbrt-v4's `cropwindow`), a window of the camera's image; `None`: all of them.
    /// The image written is the window's size, each pixel the full render's.
    pub crop: Option<crate::pixel_bounds::PixelBounds>,
}

/// As derived, except that `algorithm` and `crop` are left out when `None`: the scene fingerprint that
/// saved renders record (`ppm_scene::content_hash`) hashes this text, and a scene that names
/// no algorithm must keep the fingerprint it had before the field existed, so that its saved
/// renders still resume and merge.
impl std::fmt::Debug for RenderDefaults {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut s = f.debug_struct("RenderDefaults");
        s.field("max_depth", &self.max_depth)
            .field("photons", &self.photons)
            .field("radius", &self.radius)
            .field("alpha", &self.alpha);
        if let Some(algorithm) = &self.algorithm {
            s.field("algorithm", algorithm);
        }
        if let Some(crop) = &self.crop {
            s.field("crop", crop);
        }
        s.finish()
    }
}

impl Default for RenderDefaults {
    fn default() -> Self {
        RenderDefaults {
            max_depth: 32,
            photons: None,
            radius: None,
            alpha: 2.0 / 3.0,
            algorithm: None,
            crop: None,
        }
    }
}

/// A scene ready to render.
pub struct Scene {
    pub camera: Camera,
    pub materials: Vec<Material>,
    pub geometry: Geometry,
    /// Every light: the area lights of the emissive primitives (in primitive order), then
    /// the builder's lights in the order they were added.
    pub lights: Vec<Light>,
    pub defaults: RenderDefaults,
    /// Where the world origin went: the scene is stored relative to the camera (everything
    /// translated by -camera position), see [`SceneBuilder::build`]. World = stored + origin.
    pub origin: Vec3,
    /// Light selection proportional to power (mean over channels).
    light_distribution: Distribution1D,
    /// Light index of each emissive primitive (u32::MAX for the others), by global prim id.
    prim_light: Vec<u32>,
    /// True if some material bounds an absorbing medium; otherwise every transmittance is 1
    /// and [`Scene::transmittance`] returns at once.
    absorbing: bool,
    /// Index of the environment light ([`LightKind::Infinite`]), if the scene has one.
    environment: Option<u32>,
}

/// Collects the parts of a scene, then builds the BVH and the lights.
pub struct SceneBuilder {
    pub camera: Camera,
    pub materials: Vec<Material>,
    pub meshes: Vec<TriangleMesh>,
    pub spheres: Vec<Sphere>,
    /// Meshes placed by [`SceneBuilder::instances`] (in their object space), each stored
    /// once however often it is placed.
    pub instanced_meshes: Vec<TriangleMesh>,
    /// Placements of `instanced_meshes` (see [`SceneBuilder::add_instance`]).
    pub instances: Vec<MeshInstance>,
    /// The lights that are not emissive geometry (point, spot and directional lights), in the order of
    /// the scene file's `lights:` list; area lights come from the materials' emission.
    pub lights: Vec<Light>,
    pub defaults: RenderDefaults,
    /// Where the builder's origin lies in the world: world = builder coordinates + this.
    /// Zero unless the caller made its coordinates relative in higher precision than f32
    /// (the scene loader subtracts the camera position in f64), which [`Scene::origin`]
    /// then includes.
    pub world_offset: Vec3,
}

impl SceneBuilder {
    /// An empty scene seen by `camera`.
    pub fn new(camera: Camera) -> Self {
        SceneBuilder {
            camera,
            materials: Vec::new(),
            meshes: Vec::new(),
            spheres: Vec::new(),
            instanced_meshes: Vec::new(),
            instances: Vec::new(),
            lights: Vec::new(),
            defaults: RenderDefaults::default(),
            world_offset: Vec3::ZERO,
        }
    }

    /// Adds a material and returns its index.
    pub fn add_material(&mut self, material: Material) -> u32 {
        self.materials.push(material);
        self.materials.len() as u32 - 1
    }

    /// Adds a triangle mesh.
    pub fn add_mesh(&mut self, mesh: TriangleMesh) {
        self.meshes.push(mesh);
    }

    /// Adds a sphere.
    pub fn add_sphere(&mut self, sphere: Sphere) {
        self.spheres.push(sphere);
    }

    /// Adds a mesh (in its object space) to be placed by [`SceneBuilder::add_instance`], and
    /// returns its index. Not rendered until placed.
    pub fn add_instanced_mesh(&mut self, mesh: TriangleMesh) -> u32 {
        self.instanced_meshes.push(mesh);
        self.instanced_meshes.len() as u32 - 1
    }

    /// Places instanced mesh `mesh` by the affine object-to-world transform `to_world`,
    /// without copying its triangles (a two-level BVH; see `geometry/bvh/instances.rs`).
    /// A mesh with an emissive material is copied into the flat level instead, one copy
    /// per placement, so that each placement is an area light of its own area.
    pub fn add_instance(&mut self, mesh: u32, to_world: DMat4) {
        self.instances.push(MeshInstance { mesh, to_world });
    }

    /// True if the scene has a light: a non-area light, or an emissive material on a sphere
    /// or a triangle. The importers warn of a black image without one.
    pub fn has_light(&self) -> bool {
        let emits = |m: u32| self.materials[m as usize].is_emissive();
        let placed = |i: usize| self.instances.iter().any(|p| p.mesh as usize == i);
        !self.lights.is_empty()
            || self.spheres.iter().any(|s| emits(s.material))
            || self
                .meshes
                .iter()
                .any(|mesh| mesh.materials.iter().any(|&m| emits(m)))
            || (self.instanced_meshes.iter().enumerate())
                .any(|(i, mesh)| placed(i) && mesh.materials.iter().any(|&m| emits(m)))
    }

    /// Adds a light that is not emissive geometry (a point, spot or directional light). An area light
    /// added here is refused by [`SceneBuilder::build`]: area lights are made from the
    /// materials' emission, so that the geometry a camera path hits and the light agree.
    pub fn add_light(&mut self, light: Light) {
        self.lights.push(light);
    }

    /// Adds a point light ([`SceneBuilder::add_light`]).
    pub fn add_point_light(&mut self, light: PointLight) {
        self.add_light(Light::Point(light));
    }

    /// Builds the BVH and one area light per emissive primitive.
    ///
    /// The scene is stored camera-relative (as pbrt-v4 does): every position is translated by
    /// minus the camera position. Translating the whole scene leaves the image unchanged, and
    /// f32 coordinates are then small where precision matters, so a scene placed 10^5 units
    /// from the origin renders like the same scene at the origin.
    pub fn build(mut self) -> Result<Scene, SceneError> {
        let origin = self.camera.position;
        for mesh in &mut self.meshes {
            for p in &mut mesh.positions {
                *p -= origin;
            }
        }
        for s in &mut self.spheres {
            s.center -= origin;
        }
        for l in &mut self.lights {
            l.translate(-origin);
        }
        // Placements move with the rest: the translation composed in f64, so that an
        // identity placement stays exactly the identity when the camera is at the origin.
        if origin != Vec3::ZERO {
            let shift = DMat4::from_translation(-origin.as_dvec3());
            for p in &mut self.instances {
                p.to_world = shift * p.to_world;
            }
        }
        self.camera = self.camera.with_position(Vec3::ZERO);
        let n_mat = self.materials.len() as u32;
        let all_meshes = self.meshes.iter().chain(&self.instanced_meshes);
        for m in all_meshes.flat_map(|m| m.materials.iter()) {
            if *m >= n_mat {
                return Err(SceneError::MissingMaterial(*m));
            }
        }
        self.flatten_emissive_instances()?;
        if let Some(s) = self.spheres.iter().find(|s| s.material >= n_mat) {
            return Err(SceneError::MissingMaterial(s.material));
        }
        let geometry = Geometry::with_instances(
            &self.meshes,
            &self.spheres,
            &self.instanced_meshes,
            &self.instances,
        )?;
        // Lights that need the scene's extent (a directional light's disk of origins) take
        // it now, before their power is checked and used for light selection.
        for l in &mut self.lights {
            l.preprocess(geometry.bounds());
        }
        let n_tri = geometry.triangle_count() as u32;
        let n_prim = n_tri + geometry.sphere_count() as u32;
        let mut lights = Vec::new();
        let mut prim_light = vec![u32::MAX; n_prim as usize];
        for prim in 0..n_prim {
            let light = if prim < n_tri {
                let (tri, m) = geometry.triangle(prim);
                let le = self.materials[m as usize].emission;
                if le.max_element() > 0.0 {
                    Light::triangle(tri, le, prim)
                } else {
                    None
                }
            } else {
                let sphere = *geometry.sphere(prim);
                let le = self.materials[sphere.material as usize].emission;
                (le.max_element() > 0.0).then(|| Light::sphere(sphere, le, prim))
            };
            if let Some(light) = light {
                prim_light[prim as usize] = lights.len() as u32;
                lights.push(light);
            }
        }
        for (i, light) in self.lights.iter().enumerate() {
            if light.kind() == LightKind::Area {
                return Err(SceneError::InvalidValue {
                    field: format!("light {i}"),
                    value: light.name().to_string(),
                    why: "area lights are made from emissive materials, not added as lights".into(),
                });
            }
        }
        // Powers are checked where they are computed: an overflowing one would give NaN
        // selection weights and infinite photon fluxes, which the film drops: a black render.
        // Area lights are named by their primitive, the others by their place in the list.
        let area_lights = lights.iter().map(|l| (l, None));
        let added = self.lights.iter().enumerate().map(|(i, l)| (l, Some(i)));
        for (light, index) in area_lights.chain(added) {
            if let Err(power) = light.check_power() {
                return Err(SceneError::LightPower {
                    light: self.describe_light(light, index, &geometry),
                    power,
                    max: crate::light::MAX_LIGHT_POWER as f64,
                });
            }
            if let Err((field, value)) = light.check_emission() {
                return Err(SceneError::LightEmission {
                    light: self.describe_light(light, index, &geometry),
                    field,
                    value,
                    max: crate::light::MAX_EMISSION as f64,
                });
            }
        }
        // One environment at most: a ray that leaves the scene sees one radiance, and the
        // escaped path's MIS weight is against that light's sampling alone.
        let infinite: Vec<usize> = (self.lights.iter().enumerate())
            .filter(|(_, l)| l.kind() == LightKind::Infinite)
            .map(|(i, _)| i)
            .collect();
        if infinite.len() > 1 {
            return Err(SceneError::InvalidValue {
                field: format!("light {}", infinite[1]),
                value: self.lights[infinite[1]].name().to_string(),
                why: format!(
                    "a scene has at most one environment light (light {} is one already)",
                    infinite[0]
                ),
            });
        }
        let environment = infinite.first().map(|&i| (lights.len() + i) as u32);
        lights.extend_from_slice(&self.lights);
        let weights: Vec<f32> = lights
            .iter()
            .map(|l| l.power().element_sum() / 3.0)
            .collect();
        let absorbing = self.materials.iter().any(|m| !m.medium.is_clear());
        Ok(Scene {
            absorbing,
            camera: self.camera,
            materials: self.materials,
            geometry,
            light_distribution: Distribution1D::new(&weights),
            lights,
            defaults: self.defaults,
            origin: origin + self.world_offset,
            prim_light,
            environment,
        })
    }
}

impl SceneBuilder {
    /// Copies the placements of emissive instanced meshes into the flat level (one mesh per
    /// placement, moved as `ppm_scene`'s `place_mesh` moves one: points by M, shading
    /// normals by M^-T, the winding reversed for a mirroring M so the emitting side is the
    /// transformed one) and drops them from the instances: each copy is then an area light
    /// with its own area and power, which light sampling and photon emission need.
    fn flatten_emissive_instances(&mut self) -> Result<(), SceneError> {
        let materials = &self.materials;
        let emissive: Vec<bool> = (self.instanced_meshes.iter())
            .map(|mesh| (mesh.materials.iter()).any(|&m| materials[m as usize].is_emissive()))
            .collect();
        self.flatten_instances_of(&emissive)
    }

    /// Copies every placement into the flat level, as [`SceneBuilder::build`] copies those
    /// of emissive meshes: the scene of copies that the instances stand for (what a writer
    /// without instances writes).
    pub fn flatten_instances(&mut self) -> Result<(), SceneError> {
        self.flatten_instances_of(&vec![true; self.instanced_meshes.len()])
    }

    /// Copies the placements of the instanced meshes marked in `copy` into the flat level.
    fn flatten_instances_of(&mut self, copy: &[bool]) -> Result<(), SceneError> {
        let emissive = copy;
        if !emissive.iter().any(|&e| e) {
            return Ok(());
        }
        let mut kept = Vec::with_capacity(self.instances.len());
        for (i, p) in self.instances.iter().enumerate() {
            match emissive.get(p.mesh as usize) {
                Some(true) => {
                    let mut mesh = self.instanced_meshes[p.mesh as usize].clone();
                    place(&mut mesh, p.to_world).map_err(|why| SceneError::InvalidValue {
                        field: format!("instance {i}"),
                        value: format!("{:?}", p.to_world),
                        why: why.into(),
                    })?;
                    self.meshes.push(mesh);
                }
                _ => kept.push(*p),
            }
        }
        self.instances = kept;
        Ok(())
    }

    /// A light named for an error message: its model and primitive and material (area
    /// lights), or its model, `index` in the builder's list and what sets its power.
    fn describe_light(&self, light: &Light, index: Option<usize>, geometry: &Geometry) -> String {
        let material = |m: u32| {
            let name = &self.materials[m as usize].name;
            if name.is_empty() {
                format!("material {m}")
            } else {
                format!("material `{name}`")
            }
        };
        match (light.prim(), index) {
            (Some(prim), _) => {
                let m = if (prim as usize) < geometry.triangle_count() {
                    geometry.triangle(prim).1
                } else {
                    geometry.sphere(prim).material
                };
                format!("{} {prim} ({})", light.name(), material(m))
            }
            (None, Some(i)) => format!("{} {i} ({})", light.name(), light.describe()),
            (None, None) => format!("{} ({})", light.name(), light.describe()),
        }
    }
}

/// Moves `mesh` by the affine `m` in double precision: points by `m`, shading normals by its
/// inverse transpose, and the winding reversed when `m` mirrors (det < 0), so that the
/// geometric normal cross(v1 - v0, v2 - v0) is the transformed one (cross(M a, M b) =
/// det(M) M^-T (a x b)), as an instance's hit has it.
fn place(mesh: &mut TriangleMesh, m: DMat4) -> Result<(), &'static str> {
    let linear = DMat3::from_mat4(m);
    let det = linear.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err("the transform is singular or not finite");
    }
    for x in &mut mesh.positions {
        *x = m.transform_point3(x.as_dvec3()).as_vec3();
    }
    if mesh.positions.iter().any(|x| !x.is_finite()) {
        return Err("the transform takes the mesh out of single-precision range");
    }
    let normal_matrix = linear.inverse().transpose();
    for n in &mut mesh.normals {
        *n = (normal_matrix * n.as_dvec3()).normalize_or_zero().as_vec3();
    }
    if det < 0.0 {
        for t in &mut mesh.indices {
            t.swap(1, 2);
        }
    }
    Ok(())
}

impl Scene {
    /// Closest hit along a ray.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.geometry.intersect(ray)
    }

    /// True if the segment is blocked.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.geometry.occluded(ray)
    }

    /// The material at a hit.
    #[inline]
    pub fn material(&self, hit: &Hit) -> &Material {
        &self.materials[hit.material as usize]
    }

    /// The BSDF at a hit: the material's, with its textured colours (if any) evaluated at
    /// the hit's texture coordinates, which are computed only then.
    #[inline(always)]
    pub fn bsdf(&self, hit: &Hit) -> Bsdf {
        let material = self.material(hit);
        match &material.textures {
            None => material.bsdf,
            Some(_) => material.bsdf_at(self.geometry.texture_uv(hit)),
        }
    }

    /// Beer-Lambert transmittance of a segment of length `t` with one end at `hit`, lying on
    /// the side of `hit`'s surface that `w` (leaving the surface) points into: `exp(-sigma_a
    /// t)` with `sigma_a` of that side's medium ([`crate::medium`], the stateless rule).
    /// For the segment a ray `ray` travelled to its hit: `transmittance(&hit, -ray.dir,
    /// hit.t)`; for a shadow ray or a connection leaving `hit` toward a point at distance
    /// `d` along `w`: `transmittance(&hit, w, d)`. Exactly 1 (at the cost of one predictable
    /// branch) in a scene without absorption.
    #[inline(always)]
    pub fn transmittance(&self, hit: &Hit, w: Vec3, t: f32) -> Vec3 {
        if !self.absorbing {
            return Vec3::ONE;
        }
        let sigma_a = self.material(hit).medium.toward(w, hit.ng);
        crate::medium::transmittance(sigma_a, t)
    }

    /// [`Scene::transmittance`] of the segment from `hit` to `target` (a light's point, another
    /// subpath's vertex, the camera): the medium on the side of `hit` the segment leaves
    /// into, over the distance between them. An unoccluded segment crosses no surface, so
    /// this is also the medium at `target`'s end.
    #[inline(always)]
    pub fn transmittance_to(&self, hit: &Hit, target: Vec3) -> Vec3 {
        if !self.absorbing {
            return Vec3::ONE;
        }
        let d = target - hit.p;
        self.transmittance(hit, d, d.length())
    }

    /// True if some surface bounds an absorbing medium.
    #[inline]
    pub fn has_absorption(&self) -> bool {
        self.absorbing
    }

    /// Chooses a light in proportion to its power: (light, probability). `None` without lights.
    #[inline]
    pub fn choose_light(&self, u: f32) -> Option<(&Light, f32)> {
        if self.light_distribution.is_empty() {
            return None;
        }
        let (i, pmf) = self.light_distribution.sample(u);
        Some((&self.lights[i], pmf))
    }

    /// The light of an emissive primitive and the probability that [`Scene::choose_light`]
    /// picks it; `None` if the primitive does not emit.
    #[inline]
    pub(crate) fn light_of_prim(&self, prim: u32) -> Option<(&Light, f32)> {
        let i = *self.prim_light.get(prim as usize)?;
        (i != u32::MAX).then(|| {
            (
                &self.lights[i as usize],
                self.light_distribution.pmf(i as usize),
            )
        })
    }

    /// The environment light ([`LightKind::Infinite`]) and the probability that
    /// [`Scene::choose_light`] picks it; `None` without one. What a ray that leaves the scene
    /// sees.
    #[inline]
    pub fn environment(&self) -> Option<(&Light, f32)> {
        let i = self.environment? as usize;
        Some((&self.lights[i], self.light_distribution.pmf(i)))
    }

    /// Total emitted power of all lights, per channel.
    pub fn total_power(&self) -> Vec3 {
        self.lights.iter().map(|l| l.power()).sum()
    }

    /// Samples the start of a light path: a light in proportion to its power, then a point and
    /// a direction on it. The flux is Le cos / (p_light p_area p_dir).
    /// Always inlined into the light-path tracer (once per path; a call there since the
    /// lights were split one file per model).
    #[inline(always)]
    pub fn sample_emission(
        &self,
        u_light: f32,
        u_pos: Vec2,
        u_dir: Vec2,
    ) -> Option<EmissionSample> {
        let (light, p_light) = self.choose_light(u_light)?;
        let mut s = light.sample_emission(u_pos, u_dir);
        s.flux /= p_light;
        Some(s)
    }

    /// True if the scene has a delta light (a point, spot or directional light:
    /// [`LightKind::is_delta`])
    /// and a surface whose material has a perfectly specular lobe (mirror, glass). Light from
    /// a delta light that meets such a lobe before a diffuse or glossy surface (its caustics,
    /// its image in a mirror, its light through glass) is carried by paths a unidirectional
    /// path tracer never samples: a camera path cannot hit a point (or a direction), and
    /// light sampling cannot connect through a delta lobe. That light is missing from a
    /// path-traced image; photon mapping and VCM trace it from the light.
    pub fn has_delta_light_behind_specular(&self) -> bool {
        if !self.lights.iter().any(|l| l.is_delta()) {
            return false;
        }
        let specular = |m: u32| {
            let flags = self.materials[m as usize].bsdf.flags();
            flags.contains(BsdfFlags::SPECULAR)
        };
        let g = &self.geometry;
        let triangles = g.triangle_count();
        g.instance_materials().iter().any(|&m| specular(m))
            || (0..triangles).any(|i| specular(g.triangle(i as u32).1))
            || (0..g.sphere_count()).any(|i| specular(g.sphere((triangles + i) as u32).material))
    }

    /// Length of the diagonal of the scene's bounding box.
    pub fn diagonal(&self) -> f32 {
        let (lo, hi) = self.geometry.bounds();
        let d = (hi - lo).length();
        if d.is_finite() {
            d
        } else {
            1.0
        }
    }
}
