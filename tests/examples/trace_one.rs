use ppm_core::bsdf::{Lobe, TransportMode};
use ppm_core::geometry::Ray;
use ppm_core::integrator::{emission_mis_weight, estimate_direct, ShadingFrame};
use ppm_core::prelude::*;
use ppm_core::sampling::Rng;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (iteration, px, py): (u64, u32, u32) = (args[1].parse().unwrap(), args[2].parse().unwrap(), args[3].parse().unwrap());
    let mut b = ppm_tests::load_small("cornell_box_glossy.yml", 256, 256);
    b.camera.set_resolution(256, 256).unwrap();
    let scene = b.build().unwrap();
    let settings = RenderSettings { algorithm: Algorithm::Path, seed: 1000003, ..RenderSettings::new(&scene) };
    let pixel = (py * 256 + px) as u64;
    let mut rng = Rng::new(settings.seed, iteration, pixel);
    let film = Vec2::new(px as f32, py as f32) + rng.uniform2();
    let mut ray = scene.camera.generate_ray(film);
    let mut l = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    let (mut prev_specular, mut prev_pdf, mut prev_p) = (true, 0.0f32, ray.origin);
    for depth in 0..=settings.max_depth {
        let Some(hit) = scene.intersect(&ray) else { println!("miss"); break };
        let material = scene.material(&hit);
        let wo = -ray.dir;
        println!("depth {depth}: t {} p {} ng {} ns {} mat {} wo {}", hit.t, hit.p, hit.ng, hit.ns, material.name, wo);
        if material.is_emissive() && wo.dot(hit.ng) > 0.0 {
            let w = if prev_specular { 1.0 } else { emission_mis_weight(&scene, prev_p, prev_pdf, &hit) };
            l += throughput * material.emission * w;
            println!("  emission w {w} -> L {l}");
        }
        let sf = ShadingFrame::new(&hit, wo);
        println!("  wo_local {}", sf.wo);
        if !material.bsdf.is_delta() {
            let (ld, _) = estimate_direct(&scene, &hit, &sf, wo, &material.bsdf, &mut rng, true);
            l += throughput * ld;
            println!("  direct {ld} -> L {l}");
        }
        let (u_lobe, u) = (rng.uniform(), rng.uniform2());
        let Some(s) = material.bsdf.sample(sf.wo, u_lobe, u, TransportMode::Radiance) else { println!("  no sample"); break };
        let wi = sf.frame.to_world(s.wi);
        println!("  sample wi_local {} weight {} pdf {} lobe {:?} (u_lobe {u_lobe} u {u})", s.wi, s.weight, s.pdf, s.lobe);
        if !sf.consistent(&hit, wo, wi, s.wi) { println!("  inconsistent"); break; }
        throughput *= s.weight;
        prev_specular = s.lobe == Lobe::Specular;
        prev_pdf = s.pdf;
        prev_p = hit.p;
        if depth + 1 >= settings.rr_depth {
            let survive = throughput.max_element().min(1.0);
            if survive.is_nan() || rng.uniform() >= survive { println!("  rr end"); break; }
            throughput /= survive;
        }
        println!("  throughput {throughput}");
        ray = Ray::spawn(hit.p, hit.ng, wi);
    }
    println!("L = {l}");
}
