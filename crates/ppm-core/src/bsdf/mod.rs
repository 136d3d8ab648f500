//! BSDFs: a closed set of scattering models behind one enum.
//!
//! # The contract (every model follows it)
//! - Directions are unit vectors in the local shading frame: `z` is the shading normal, turned
//!   to the side of the geometric normal. `wo` points away from the surface toward the viewer
//!   (camera paths) or back along the path (light paths); `wi` points toward where light comes
//!   from (camera paths) or where the photon goes next (light paths).
//! - [`Bsdf::eval`] returns f(wo, wi) **without** the cosine factor.
//! - [`Bsdf::pdf`] is the solid-angle density with which [`Bsdf::sample`] produces `wi`.
//! - Delta lobes (mirror, glass) have `eval = 0` and `pdf = 0`: only `sample` produces them,
//!   flagged [`Lobe::Specular`], with `pdf` set to the discrete probability of the lobe choice.
//! - `sample` returns `wi`, the weight `f * |cos(wi)| / pdf`, the pdf and the lobe.
//! - [`TransportMode`] tells camera paths (radiance) from light paths (importance). Only
//!   refraction differs: radiance is scaled by 1/eta^2 on camera paths, photons carry flux
//!   unscaled. Shading-normal asymmetry on light paths is corrected by
//!   [`shading_normal_correction`] (Veach 1997, sec. 5.3).
//! - Lobes: [`Bsdf::flags`] says which kinds a model has ([`BsdfFlags`]), and the model splits
//!   into its diffuse part ([`Bsdf::diffuse_part`], Lambertian: what photon mapping
//!   density-estimates) and its non-diffuse part ([`Bsdf::non_diffuse_part`], the glossy and
//!   specular lobes: what is traced). The two parts sum to the whole:
//!   `eval = diffuse.eval + non_diffuse.eval`. Integrators ask these and never name a model.
//! - diffuse, phong and mirror are two-sided: with `wo.z < 0` they act as if the surface were
//!   flipped, so camera and light paths agree for any pair of directions. glass is one-sided
//!   in the sense that `wo.z > 0` means outside (entering the medium of `ior`), and so is
//!   dielectric (`z > 0` is the exterior medium). conductor and plastic reflect on the front
//!   side only (`wo.z > 0`) and are black from behind, as in Mitsuba 3; [`TwoSided`] makes them
//!   two-sided. thindielectric is two-sided.
//! - Microfacet lobes (rough conductor, dielectric, plastic) and plastic's base seen through
//!   its coating are [`Lobe::Glossy`]: not Lambertian, so traced rather than density-estimated.
//!   A model may mix delta and non-delta lobes (smooth plastic): `eval` and `pdf` are those of
//!   the non-delta lobes, the pdf scaled by the probability of choosing them.

mod beckmann;
mod conductor;
mod dielectric;
mod diffuse;
mod flags;
mod fresnel;
mod glass;
pub mod metals;
pub mod microfacet;
mod mirror;
mod phong;
mod plastic;
mod thin_dielectric;
mod twosided;

pub use beckmann::Beckmann;
pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use flags::BsdfFlags;
pub use fresnel::{fresnel_conductor, fresnel_dielectric, fresnel_diffuse_reflectance};
pub use glass::Glass;
pub use microfacet::{Ggx, Microfacet};
pub use mirror::Mirror;
pub use phong::Phong;
pub use plastic::Plastic;
pub use thin_dielectric::ThinDielectric;
pub use twosided::{FrontSided, TwoSided};

use glam::{Vec2, Vec3};

/// Which quantity a path carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Camera paths: radiance flows toward the eye.
    Radiance,
    /// Light paths (photons): importance flows toward the eye, flux away from the light.
    Importance,
}

/// The kind of lobe a sample came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    Diffuse,
    Glossy,
    /// A Dirac delta (mirror reflection, smooth refraction).
    Specular,
}

/// The result of sampling a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled direction (local frame).
    pub wi: Vec3,
    /// f * |cos(wi)| / pdf; for delta lobes the ratio of the delta's coefficients.
    pub weight: Vec3,
    /// Solid-angle pdf (non-delta lobes) or discrete lobe probability (delta lobes).
    pub pdf: f32,
    pub lobe: Lobe,
}

/// A scattering model.
#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    Diffuse(Diffuse),
    Mirror(Mirror),
    Glass(Glass),
    Phong(Phong),
    Conductor(Conductor),
    Dielectric(Dielectric),
    ThinDielectric(ThinDielectric),
    Plastic(Plastic),
    TwoSidedConductor(TwoSided<Conductor>),
    TwoSidedPlastic(TwoSided<Plastic>),
}

impl Bsdf {
    /// Lambertian with the given albedo.
    pub fn diffuse(albedo: Vec3) -> Self {
        Bsdf::Diffuse(Diffuse { albedo })
    }
    /// Perfect mirror times `color`.
    pub fn mirror(color: Vec3) -> Self {
        Bsdf::Mirror(Mirror { color })
    }
    /// Smooth dielectric of index `ior` against vacuum, transmission tinted by `color`.
    pub fn glass(ior: f32, color: Vec3) -> Self {
        Bsdf::Glass(Glass { ior, color })
    }
    /// Diffuse lobe plus the normalized modified Phong lobe.
    pub fn phong(diffuse: Vec3, specular: Vec3, exponent: f32) -> Self {
        Bsdf::Phong(Phong::new(diffuse, specular, exponent))
    }
    /// A conductor of complex index `eta + i k`, smooth (`roughness` None) or GGX-rough,
    /// tinted by `specular_reflectance`.
    pub fn conductor(
        eta: Vec3,
        k: Vec3,
        specular_reflectance: Vec3,
        roughness: Option<Microfacet>,
    ) -> Self {
        Bsdf::Conductor(Conductor {
            eta,
            k,
            specular_reflectance,
            roughness,
        })
    }
    /// A dielectric interface of relative index `eta = int_ior / ext_ior`, smooth or rough,
    /// with untinted reflection and transmission.
    pub fn dielectric(eta: f32, roughness: Option<Microfacet>) -> Self {
        Bsdf::Dielectric(Dielectric {
            eta,
            specular_reflectance: Vec3::ONE,
            specular_transmittance: Vec3::ONE,
            roughness,
        })
    }
    /// A thin dielectric sheet of relative index `eta`, untinted.
    pub fn thin_dielectric(eta: f32) -> Self {
        Bsdf::ThinDielectric(ThinDielectric {
            eta,
            specular_reflectance: Vec3::ONE,
            specular_transmittance: Vec3::ONE,
        })
    }
    /// A plastic: a Lambertian base of albedo `diffuse` under a coating of relative index
    /// `eta` whose reflection is tinted by `specular`; smooth or rough.
    pub fn plastic(diffuse: Vec3, specular: Vec3, eta: f32, roughness: Option<Microfacet>) -> Self {
        Bsdf::Plastic(Plastic::new(diffuse, specular, eta, roughness))
    }
    /// The same BSDF seen from both sides: conductor and plastic wrapped in [`TwoSided`];
    /// the models that are already two-sided (diffuse, mirror, phong, thin dielectric)
    /// unchanged. `None` for the refracting ones (glass, dielectric), whose two sides are
    /// two different media.
    pub fn two_sided(self) -> Option<Self> {
        match self {
            Bsdf::Conductor(b) => Some(Bsdf::TwoSidedConductor(TwoSided(b))),
            Bsdf::Plastic(b) => Some(Bsdf::TwoSidedPlastic(TwoSided(b))),
            Bsdf::Diffuse(_)
            | Bsdf::Mirror(_)
            | Bsdf::Phong(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::TwoSidedConductor(_)
            | Bsdf::TwoSidedPlastic(_) => Some(self),
            Bsdf::Glass(_) | Bsdf::Dielectric(_) => None,
        }
    }

    /// f(wo, wi), without the cosine; zero for delta lobes.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        match self {
            Bsdf::Diffuse(b) => b.eval(wo, wi),
            Bsdf::Mirror(_) | Bsdf::Glass(_) | Bsdf::ThinDielectric(_) => Vec3::ZERO,
            Bsdf::Phong(b) => b.eval(wo, wi),
            Bsdf::Conductor(b) => b.eval(wo, wi),
            Bsdf::Dielectric(b) => b.eval(wo, wi, mode),
            Bsdf::Plastic(b) => b.eval(wo, wi),
            Bsdf::TwoSidedConductor(b) => b.eval(wo, wi),
            Bsdf::TwoSidedPlastic(b) => b.eval(wo, wi),
        }
    }

    /// Solid-angle pdf of `sample` producing `wi`; zero for delta lobes.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse(b) => b.pdf(wo, wi),
            Bsdf::Mirror(_) | Bsdf::Glass(_) | Bsdf::ThinDielectric(_) => 0.0,
            Bsdf::Phong(b) => b.pdf(wo, wi),
            Bsdf::Conductor(b) => b.pdf(wo, wi),
            Bsdf::Dielectric(b) => b.pdf(wo, wi),
            Bsdf::Plastic(b) => b.pdf(wo, wi),
            Bsdf::TwoSidedConductor(b) => b.pdf(wo, wi),
            Bsdf::TwoSidedPlastic(b) => b.pdf(wo, wi),
        }
    }

    /// Samples `wi` given `wo`; `u_lobe` chooses a lobe, `u` the direction within it.
    /// `None` when the sample carries no energy (e.g. below the horizon). Always inlined
    /// into the tracers' loops, whatever the crate's split into codegen units.
    #[inline(always)]
    pub fn sample(
        &self,
        wo: Vec3,
        u_lobe: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        match self {
            Bsdf::Diffuse(b) => b.sample(wo, u),
            Bsdf::Mirror(b) => b.sample(wo),
            Bsdf::Glass(b) => b.sample(wo, u_lobe, mode),
            Bsdf::Phong(b) => b.sample(wo, u_lobe, u),
            Bsdf::Conductor(b) => b.sample(wo, u),
            Bsdf::Dielectric(b) => b.sample(wo, u_lobe, u, mode),
            Bsdf::ThinDielectric(b) => b.sample(wo, u_lobe),
            Bsdf::Plastic(b) => b.sample(wo, u_lobe, u),
            Bsdf::TwoSidedConductor(b) => b.sample(wo, u_lobe, u),
            Bsdf::TwoSidedPlastic(b) => b.sample(wo, u_lobe, u),
        }
    }

    /// The kinds of lobes this BSDF has (see [`BsdfFlags`]); every lobe `sample` can return
    /// is among them.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        match self {
            Bsdf::Diffuse(b) => b.flags(),
            Bsdf::Mirror(b) => b.flags(),
            Bsdf::Glass(b) => b.flags(),
            Bsdf::Phong(b) => b.flags(),
            Bsdf::Conductor(b) => b.flags(),
            Bsdf::Dielectric(b) => b.flags(),
            Bsdf::ThinDielectric(b) => b.flags(),
            Bsdf::Plastic(b) => b.flags(),
            Bsdf::TwoSidedConductor(b) => b.flags(),
            Bsdf::TwoSidedPlastic(b) => b.flags(),
        }
    }

    /// The Lambertian part of the BSDF, `None` if it has none: what photon mapping
    /// density-estimates (f = albedo / pi leaves the photon sum). With
    /// [`Bsdf::non_diffuse_part`] it sums to the whole.
    #[inline]
    pub fn diffuse_part(&self) -> Option<Diffuse> {
        match self {
            Bsdf::Diffuse(b) => Some(*b),
            Bsdf::Mirror(_) | Bsdf::Glass(_) => None,
            Bsdf::Phong(b) => b.diffuse_part(),
            // No Lambertian lobe: plastic's base is seen through its coating (glossy).
            Bsdf::Conductor(_)
            | Bsdf::Dielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::Plastic(_)
            | Bsdf::TwoSidedConductor(_)
            | Bsdf::TwoSidedPlastic(_) => None,
        }
    }

    /// The glossy and specular lobes, `None` if there are none: what photon mapping traces
    /// rather than density-estimates. A BSDF of its own: sampling it samples
    /// only those lobes, and its pdf is that of its own sampling.
    #[inline]
    pub fn non_diffuse_part(&self) -> Option<Bsdf> {
        match self {
            Bsdf::Diffuse(_) => None,
            Bsdf::Mirror(_) | Bsdf::Glass(_) => Some(*self),
            Bsdf::Phong(b) => b.glossy_part().map(Bsdf::Phong),
            Bsdf::Conductor(_)
            | Bsdf::Dielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::Plastic(_)
            | Bsdf::TwoSidedConductor(_)
            | Bsdf::TwoSidedPlastic(_) => (!self.flags().is_empty()).then_some(*self),
        }
    }

    /// The probability that [`Bsdf::sample`] picks the diffuse part: 1 for a diffuse BSDF, 0
    /// for one without a diffuse part, for a phong surface the diffuse part's share of the
    /// two albedos' luminances. A walk that must take one part or the other takes it with
    /// this probability, so its weight, albedo / probability, stays near the total albedo.
    #[inline]
    pub fn diffuse_probability(&self) -> f32 {
        match self {
            Bsdf::Diffuse(_) => 1.0,
            Bsdf::Mirror(_) | Bsdf::Glass(_) => 0.0,
            Bsdf::Phong(b) => 1.0 - b.glossy_probability(),
            Bsdf::Conductor(_)
            | Bsdf::Dielectric(_)
            | Bsdf::ThinDielectric(_)
            | Bsdf::Plastic(_)
            | Bsdf::TwoSidedConductor(_)
            | Bsdf::TwoSidedPlastic(_) => 0.0,
        }
    }

    /// True if every lobe is a delta (mirror, glass): no photons are stored and no light is
    /// sampled at such a vertex.
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.flags().is_specular_only()
    }
}

/// Veach's correction for shading normals on light paths (thesis, eq. 5.19): the adjoint BSDF
/// with shading normals is f(wi, wo) |wo . ns| |wi . ng| / (|wo . ng| |wi . ns|) relative to
/// the radiance one. Multiply a photon's throughput by this after sampling `wi` (the direction
/// it leaves along) from `wo` (the direction it arrived from, reversed). All vectors world-space.
/// Returns 1 in radiance mode. Returns 0 if either direction lies in the geometric plane (or
/// in the shading plane, where the BSDF weight already vanishes), so the result is always finite.
#[inline]
pub fn shading_normal_correction(
    mode: TransportMode,
    wo: Vec3,
    wi: Vec3,
    ng: Vec3,
    ns: Vec3,
) -> f32 {
    if mode == TransportMode::Radiance {
        return 1.0;
    }
    let num = wo.dot(ns).abs() * wi.dot(ng).abs();
    let den = wo.dot(ng).abs() * wi.dot(ns).abs();
    let c = num / den;
    // den == 0 (a direction in either plane) gives inf or NaN: no energy crosses there.
    if den > 0.0 && c.is_finite() {
        c
    } else {
        0.0
    }
}

/// Mirror reflection of `w` about the local normal (the `z` axis): (-x, -y, z).
#[inline]
pub fn reflect(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Refracts `w` (pointing away from the surface) through an interface of normal `n` on `w`'s
/// side (`w . n > 0`), into the other side; `eta` is the index of the other side over `w`'s.
/// `None` on total internal reflection or if `w` is behind `n`.
///
/// Snell's law, sin_t = sin_w / eta: `wt = -w / eta + (cos_w / eta - cos_t) n`.
#[inline]
pub fn refract_about(w: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_w = w.dot(n);
    if cos_w.is_nan() || cos_w <= 0.0 {
        return None;
    }
    let sin2_t = (1.0 - cos_w * cos_w).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta + (cos_w / eta - cos_t) * n)
}

/// Luminance of linear sRGB (Rec. 709 weights), used for lobe selection and Russian roulette.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}
