//! The technique sets the VCM code renders with: SmallVCM's algorithms (light tracing,
//! bidirectional path tracing, bidirectional photon mapping, vertex connection and merging)
//! as subsets of VCM's sampling techniques, each weighted by MIS over exactly its own set.

/// Which of VCM's sampling techniques an iteration runs. The four sets are the only values:
/// the MIS weights of [`super::mis`] are derived (and tested) for them.
///
/// | set | light tracing | connections (NEE, vertex connections, emission) | merging |
/// |---|---|---|---|
/// | [`Techniques::VCM`] | yes | yes | yes |
/// | [`Techniques::BPT`] | yes | yes | no |
/// | [`Techniques::BPM`] | no | no | at every non-delta camera vertex |
/// | [`Techniques::LT`] | yes (weight 1) | no | no |
///
/// Without connections, the emission a camera subpath finds counts only while every vertex
/// before it was a delta lobe (the pixel's first hit included): no other technique of the set
/// samples those paths. See docs/vcm.md.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Techniques {
    light_tracing: bool,
    connection: bool,
    merging: bool,
}

impl Techniques {
    /// Vertex connection and merging: every technique.
    pub const VCM: Techniques = Techniques {
        light_tracing: true,
        connection: true,
        merging: true,
    };
    /// Bidirectional path tracing: emission, next-event estimation, vertex connections and
    /// light tracing; no merging.
    pub const BPT: Techniques = Techniques {
        light_tracing: true,
        connection: true,
        merging: false,
    };
    /// Bidirectional photon mapping: merging at every non-delta camera vertex, and the
    /// emission of purely specular camera subpaths.
    pub const BPM: Techniques = Techniques {
        light_tracing: false,
        connection: false,
        merging: true,
    };
    /// Light tracing: light subpaths connected to the camera, and the emission of purely
    /// specular camera subpaths (a light seen directly or in a mirror).
    pub const LT: Techniques = Techniques {
        light_tracing: true,
        connection: false,
        merging: false,
    };
    /// Every set, VCM first.
    pub const ALL: [Techniques; 4] = [
        Techniques::VCM,
        Techniques::BPT,
        Techniques::BPM,
        Techniques::LT,
    ];

    /// Light subpath vertices connected to the pinhole (splatted to the pixel they project to).
    pub fn light_tracing(self) -> bool {
        self.light_tracing
    }

    /// Next-event estimation, connections of camera and light vertices, and emission found by
    /// camera subpaths, weighted against each other.
    pub fn connection(self) -> bool {
        self.connection
    }

    /// Vertex merging: a density estimate of the light vertices within the radius.
    pub fn merging(self) -> bool {
        self.merging
    }

    /// The set's name as SmallVCM's algorithms are called: `vcm`, `bpt`, `bpm`, `lt`.
    pub fn name(self) -> &'static str {
        match (self.light_tracing, self.connection, self.merging) {
            (true, true, true) => "vcm",
            (true, true, false) => "bpt",
            (false, false, true) => "bpm",
            _ => "lt",
        }
    }

    /// Light subpath vertices are stored (for connections or merging).
    pub(super) fn stores_light_vertices(self) -> bool {
        self.connection || self.merging
    }

    /// Camera subpaths go on past their first non-delta vertex (they connect or merge there).
    pub(super) fn extends_camera_paths(self) -> bool {
        self.connection || self.merging
    }
}
