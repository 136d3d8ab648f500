//! Errors raised while building a scene in code.

use thiserror::Error;

/// Why a scene (or one of its parts) cannot be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    /// The camera cannot form an orthonormal basis or has an unusable field of view.
    #[error("degenerate camera: {0}")]
    DegenerateCamera(String),
    /// Width or height is zero or absurdly large.
    #[error("invalid resolution {width}x{height}: each side must be in 1..={max}")]
    Resolution { width: u32, height: u32, max: u32 },
    /// A value that must be finite and non-negative is not.
    #[error("invalid value for {field}: {value} ({why})")]
    InvalidValue {
        field: String,
        value: String,
        why: String,
    },
    /// A light whose power (per channel, in watts) is not finite in f32 or exceeds
    /// [`crate::light::MAX_LIGHT_POWER`]: photon fluxes and density estimates would overflow
    /// to infinity and be dropped, and the light would render black.
    #[error(
        "{light}: emitted power {power:.3e} W exceeds the supported {max:.0e} W \
         (the renderer computes in f32; lower the emission or intensity, or scale the scene)"
    )]
    LightPower { light: String, power: f64, max: f64 },
    /// A light whose emitted radiance, intensity or irradiance exceeds
    /// [`crate::light::MAX_EMISSION`]: its samples would pass the film's exact range and be
    /// dropped.
    #[error(
        "{light}: `{field}` {value:.3e} exceeds the supported {max:.3e} (2^40): the film adds \
         each sample exactly up to 2^56 (7.2e16) and keeps a factor 2^16 for the estimators' \
         gain over what a light emits; lower `{field}`, or choose larger units"
    )]
    LightEmission {
        light: String,
        field: &'static str,
        value: f64,
        max: f64,
    },
    /// A primitive names a material index that does not exist.
    #[error("material index {0} is out of range")]
    MissingMaterial(u32),
}

/// Why a saved render state cannot be continued or joined with another.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum StateError {
    /// The state's image size is not the render's.
    #[error("the saved state is {saved_width}x{saved_height} but the render is {width}x{height}")]
    Size {
        saved_width: u32,
        saved_height: u32,
        width: u32,
        height: u32,
    },
    /// A per-pixel array has the wrong number of entries.
    #[error("the saved state's {what} has {got} entries, expected {expected}")]
    Length {
        what: String,
        got: usize,
        expected: usize,
    },
    /// Two slices of iterations do not follow each other.
    #[error(
        "iterations {next_first}..{next_end} do not follow iterations {first}..{end} \
         (expected the next slice to start at {end})"
    )]
    NotContiguous {
        first: u64,
        end: u64,
        next_first: u64,
        next_end: u64,
    },
    /// The integrator carries per-pixel state that cannot be merged, or does not know a
    /// saved per-pixel channel.
    #[error("{0}")]
    Unsupported(String),
}
