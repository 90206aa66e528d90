//! Numerical stress tests (issue #6, first part): no NaN or infinite pixel anywhere, and
//! energy exactly conserved where the answer is known, in f32, at scales from 10⁻³ to 10⁵.
//!
//! A diffuse sphere of albedo `a` under a uniform white sky renders exactly `a`: every ray
//! that hits it scatters once and escapes (a convex surface cannot see itself). A darker
//! pixel means a scattered ray re-hit the surface it left ("acne"); a NaN means the maths
//! broke down. Clear glass under a white sky renders exactly 1.

use std::sync::Arc;

use raypool::camera::CameraSettings;
use raypool::frame::{Frame, RngSource};
use raypool::image::Image;
use raypool::real::to_f64;
use raypool::render::{RenderJob, RenderSettings};
use raypool::sampler::PerSample;
use raypool::scene_file::{BackgroundSpec, MaterialRef, MaterialSpec, SceneFile, SphereSpec};
use raypool::schedule::{Schedule, render};

const WHITE: BackgroundSpec = BackgroundSpec::Constant { color: [1.0; 3] };

fn sphere(center: [f64; 3], radius: f64, material: MaterialSpec) -> SphereSpec {
    SphereSpec { center, radius, material: MaterialRef::Inline(material) }
}

fn camera(lookfrom: [f64; 3], lookat: [f64; 3], vfov: f64) -> CameraSettings {
    let d = ((0..3).map(|i| (lookfrom[i] - lookat[i]).powi(2)).sum::<f64>()).sqrt();
    CameraSettings { lookfrom, lookat, vup: [0.0, 1.0, 0.0], vfov, aperture: 0.0, focus_dist: d, aspect: 1.0 }
}

fn render_file(scene: SceneFile, size: u32, spp: u32, depth: u32) -> Image {
    scene.validate().expect("a valid test scene");
    let settings =
        RenderSettings { width: size, height: size, spp, max_depth: depth, seed: 3, ..Default::default() };
    let rng = RngSource::PerSample(PerSample { seed: 3 });
    let frame = Arc::new(Frame::new(RenderJob::new(scene.to_scene(), settings), rng, 2, 8, Arc::new(|_| {})));
    render(&frame, &Schedule::Stealing).image
}

fn values(image: &Image) -> impl Iterator<Item = f64> + '_ {
    image.pixels.iter().flat_map(|p| p.to_array()).map(to_f64)
}

fn assert_finite(image: &Image, case: &str) {
    let bad = values(image).filter(|v| !v.is_finite() || *v < 0.0).count();
    assert_eq!(bad, 0, "{case}: {bad} NaN, infinite or negative channel values");
}

/// Every channel is `albedo` (sphere) or 1 (sky) within 1e-3, or, at the silhouette, between.
fn assert_furnace(image: &Image, albedo: f64, case: &str) {
    assert_finite(image, case);
    let (mut on_sphere, mut sky) = (0, 0);
    for v in values(image) {
        assert!(
            v >= albedo - 1e-3 && v <= 1.0 + 1e-3,
            "{case}: value {v} outside [{albedo}, 1]: energy lost or made"
        );
        if (v - albedo).abs() <= 1e-3 {
            on_sphere += 1;
        } else if (v - 1.0).abs() <= 1e-3 {
            sky += 1;
        }
    }
    let n = image.pixels.len() * 3;
    assert!(on_sphere > n / 4 && sky > n / 10, "{case}: {on_sphere} sphere and {sky} sky values of {n}");
}

fn furnace(scale: f64, offset: [f64; 3]) -> SceneFile {
    let at = |v: [f64; 3]| [offset[0] + v[0] * scale, offset[1] + v[1] * scale, offset[2] + v[2] * scale];
    SceneFile {
        camera: camera(at([0.0, 0.0, 5.0]), at([0.0, 0.0, 0.0]), 30.0),
        background: WHITE,
        materials: Default::default(),
        spheres: vec![sphere(at([0.0; 3]), scale, MaterialSpec::Lambertian { albedo: [0.5; 3] })],
    }
}

#[test]
fn furnace_holds_from_a_millimetre_to_a_kilometre_and_far_from_the_origin() {
    for (scale, offset, case) in [
        (1.0, [0.0; 3], "unit"),
        (1e-3, [0.0; 3], "scaled by 1e-3"),
        (1e3, [0.0; 3], "scaled by 1e3"),
        (1.0, [1e4, 1e4, 1e4], "translated 1e4 away"),
    ] {
        assert_furnace(&render_file(furnace(scale, offset), 40, 8, 50), 0.5, case);
    }
}

#[test]
fn huge_ground_spheres_show_no_acne() {
    for radius in [1e4, 1e5] {
        // A grey ground of radius 1e4 or 1e5 under a white sky, the camera 1 unit above it,
        // looking down at the ground ahead.
        let scene = SceneFile {
            camera: camera([0.0, 1.0, 0.0], [0.0, 0.0, -4.0], 40.0),
            background: WHITE,
            materials: Default::default(),
            spheres: vec![sphere([0.0, -radius, 0.0], radius, MaterialSpec::Lambertian { albedo: [0.5; 3] })],
        };
        let image = render_file(scene, 40, 8, 50);
        assert_finite(&image, "ground");
        let worst = values(&image).fold(f64::INFINITY, f64::min);
        assert!(worst >= 0.5 - 1e-3, "radius {radius}: a ground pixel of {worst} < 0.5: acne");
    }
}

#[test]
fn grazing_rays_along_the_silhouette_stay_between_sphere_and_sky() {
    // Many pixels straddle the edge at 160 × 160.
    assert_furnace(&render_file(furnace(1.0, [0.0; 3]), 160, 4, 50), 0.5, "silhouette");
}

#[test]
fn clear_glass_under_a_white_sky_renders_white() {
    let glass = || MaterialSpec::Dielectric { ior: 1.5 };
    let cases = [
        ("solid glass", vec![sphere([0.0; 3], 1.0, glass())]),
        ("hollow glass shell", vec![sphere([0.0; 3], 1.0, glass()), sphere([0.0; 3], -0.9, glass())]),
        ("glass inside glass", vec![sphere([0.0; 3], 1.0, glass()), sphere([0.2, 0.1, 0.0], 0.4, glass())]),
        ("ior 1", vec![sphere([0.0; 3], 1.0, MaterialSpec::Dielectric { ior: 1.0 })]),
    ];
    for (case, spheres) in cases {
        let scene = SceneFile {
            camera: camera([0.0, 0.0, 5.0], [0.0; 3], 30.0),
            background: WHITE,
            materials: Default::default(),
            spheres,
        };
        let image = render_file(scene, 40, 8, 200);
        assert_finite(&image, case);
        let worst = values(&image).fold(f64::INFINITY, f64::min);
        assert!(worst >= 1.0 - 1e-3, "{case}: darkest value {worst}: light lost inside the glass");
    }
}

#[test]
fn degenerate_materials_stay_finite() {
    let cases = [
        ("fuzz 5 (acts as 1)", MaterialSpec::Metal { albedo: [0.8; 3], fuzz: 5.0 }),
        ("black albedo", MaterialSpec::Lambertian { albedo: [0.0; 3] }),
        ("albedo above 1", MaterialSpec::Lambertian { albedo: [1.5; 3] }),
        ("tiny ior", MaterialSpec::Dielectric { ior: 1e-3 }),
    ];
    for (case, material) in cases {
        let scene = SceneFile {
            camera: camera([0.0, 0.0, 5.0], [0.0; 3], 30.0),
            background: WHITE,
            materials: Default::default(),
            spheres: vec![
                sphere([0.0; 3], 1.0, material),
                sphere([0.0, -101.0, 0.0], 100.0, MaterialSpec::Metal { albedo: [0.9; 3], fuzz: 1.0 }),
            ],
        };
        assert_finite(&render_file(scene, 32, 4, 50), case);
    }
}

#[test]
fn a_camera_exactly_on_a_surface_sees_past_it() {
    // The eye sits exactly on the unit sphere's surface, looking straight out: the sphere is
    // behind the camera, so every pixel must be sky.
    let scene = SceneFile {
        camera: camera([0.0, 0.0, 1.0], [0.0, 0.0, 6.0], 30.0),
        background: WHITE,
        materials: Default::default(),
        spheres: vec![sphere([0.0; 3], 1.0, MaterialSpec::Lambertian { albedo: [0.5; 3] })],
    };
    let image = render_file(scene, 32, 4, 50);
    assert_finite(&image, "camera on surface");
    let dark = values(&image).filter(|v| (*v - 1.0).abs() > 1e-3).count();
    assert_eq!(dark, 0, "{dark} values re-hit the surface the camera stands on");
}
