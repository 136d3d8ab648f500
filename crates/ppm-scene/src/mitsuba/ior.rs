//! Named indices of refraction, as Mitsuba's `dielectric` accepts them (`int_ior="bk7"`).
//! Values at about 589 nm from the usual references (Hecht, Optics; the CRC Handbook).

/// (name, index) pairs.
pub const NAMED_IOR: &[(&str, f64)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index named `name` (case-insensitive).
pub fn lookup(name: &str) -> Option<f64> {
    let name = name.trim().to_ascii_lowercase();
    NAMED_IOR.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
}

/// The names, for messages.
pub fn names() -> String {
    NAMED_IOR
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}
