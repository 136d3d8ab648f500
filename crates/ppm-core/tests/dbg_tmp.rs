use glam::Vec3;
use ppm_core::geometry::*;
#[test]
fn dbg() {
    let o = Vec3::new(1.5427064e-5, 1.1952756e-5, 7.356198e-12);
    let d = Vec3::new(-0.69266707, -0.66154623, 0.28734788);
    let tris = [
        Triangle { v: [Vec3::ZERO, Vec3::Z, Vec3::new(1.0,0.0,1.0)] },
        Triangle { v: [Vec3::ZERO, Vec3::new(1.0,0.0,1.0), Vec3::X] },
    ];
    for t in &tris { println!("{:?}", intersect_triangle(t, o, d, f32::INFINITY)); }
}
