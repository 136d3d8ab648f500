//! What kinds of lobes a BSDF has, in the spirit of pbrt-v4's `BxDFFlags`.

/// A set of lobe properties: the hemisphere a lobe scatters into (reflection, transmission)
/// and its kind (diffuse, glossy, specular). Integrators ask these instead of naming models:
/// photon mapping density-estimates the diffuse lobe and traces the others, the path tracer
/// samples no light where every lobe is specular.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct BsdfFlags(u8);

impl BsdfFlags {
    /// No lobe at all (a black surface).
    pub const NONE: BsdfFlags = BsdfFlags(0);
    /// Some lobe scatters to `wo`'s side of the surface.
    pub const REFLECTION: BsdfFlags = BsdfFlags(1);
    /// Some lobe scatters through the surface.
    pub const TRANSMISSION: BsdfFlags = BsdfFlags(1 << 1);
    /// A Lambertian lobe: f constant, what photon mapping density-estimates.
    pub const DIFFUSE: BsdfFlags = BsdfFlags(1 << 2);
    /// A non-delta lobe that is not Lambertian (e.g. Phong's): traced, not density-estimated.
    pub const GLOSSY: BsdfFlags = BsdfFlags(1 << 3);
    /// A Dirac delta lobe (mirror reflection, smooth refraction): only `sample` finds it.
    pub const SPECULAR: BsdfFlags = BsdfFlags(1 << 4);

    /// True if every flag of `other` is set.
    #[inline]
    pub fn contains(self, other: BsdfFlags) -> bool {
        self.0 & other.0 == other.0
    }

    /// True if any flag of `other` is set.
    #[inline]
    pub fn intersects(self, other: BsdfFlags) -> bool {
        self.0 & other.0 != 0
    }

    /// True if no flag is set.
    #[inline]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// True if the BSDF has some lobe and all of its lobes are deltas.
    #[inline]
    pub fn is_specular_only(self) -> bool {
        self.contains(BsdfFlags::SPECULAR)
            && !self.intersects(BsdfFlags::DIFFUSE | BsdfFlags::GLOSSY)
    }
}

impl std::ops::BitOr for BsdfFlags {
    type Output = BsdfFlags;
    #[inline]
    fn bitor(self, rhs: BsdfFlags) -> BsdfFlags {
        BsdfFlags(self.0 | rhs.0)
    }
}

impl std::ops::BitOrAssign for BsdfFlags {
    #[inline]
    fn bitor_assign(&mut self, rhs: BsdfFlags) {
        self.0 |= rhs.0;
    }
}
