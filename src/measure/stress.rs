//! Numerical stress cases: scenes whose exact answer is known, at scales and angles where
//! floating point breaks naive ray tracers.
//!
//! Every case is lit by a uniform white sky, so every correct pixel lies between a known
//! floor and 1: a diffuse sphere of albedo `a` renders exactly `a` (every scattered ray
//! escapes: a convex surface cannot see itself), clear glass renders exactly 1. A pixel below
//! the floor lost energy: a scattered ray re-hit the surface it left ("acne"). A NaN means
//! the maths broke down. `tests/stability.rs` asserts that raypool passes them all;
//! `cargo bench --bench stability` tabulates them for the book's method too
//! (`results/stability.md`).

use std::sync::Arc;

use crate::files::image::Image;
use crate::scenes::format::{BackgroundSpec, MaterialRef, MaterialSpec, SceneFile};
use crate::scenes::world::SphereSpec;
use crate::schedule::frame::Frame;
use crate::schedule::modes::{Schedule, render};
use crate::schedule::random::{RngChoice, RngSource};
use crate::tracer::camera::CameraSettings;
use crate::tracer::geometry::sphere::Intersection;
use crate::tracer::math::real::to_f64;
use crate::tracer::render::{RenderJob, RenderSettings};
use crate::tracer::sampling::sampler::Sampler;

/// Values within this of the floor or of 1 count as exact.
pub const TOLERANCE: f64 = 1e-3;

/// One scene with its correct range of pixel values.
#[derive(Clone, Debug)]
pub struct StressCase {
    /// What it tests.
    pub name: String,
    /// The scene.
    pub scene: SceneFile,
    /// The darkest correct value (the albedo, 1 for clear glass; 0 where only finiteness
    /// is known).
    pub floor: f64,
    /// The brightest correct value (1 under a white sky; infinite where unknown).
    pub ceiling: f64,
    /// Square image side, pixels.
    pub size: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Maximum rays per path.
    pub depth: u32,
}

/// What a render of a case got wrong.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Pixels with a NaN or infinite channel.
    pub non_finite: usize,
    /// Pixels with a channel below the floor (energy lost: acne).
    pub dark: usize,
    /// Pixels with a channel above the ceiling (energy made).
    pub bright: usize,
    /// The largest distance of a finite channel value outside `[floor, ceiling]`.
    pub worst: f64,
    /// Channel values equal to the floor (within [`TOLERANCE`]): the surface itself.
    pub at_floor: usize,
    /// Channel values equal to 1 (within [`TOLERANCE`]): the sky.
    pub at_one: usize,
}

impl StressCase {
    /// Renders the case with `intersection` and counts what is wrong.
    ///
    /// ```
    /// use raypool::{measure::stress, tracer::geometry::sphere::Intersection};
    /// let unit = stress::cases().into_iter().find(|c| c.name == "furnace, unit").unwrap();
    /// let outcome = unit.run(Intersection::Robust);
    /// assert_eq!((outcome.non_finite, outcome.dark, outcome.bright), (0, 0, 0));
    /// ```
    pub fn run(&self, intersection: Intersection) -> Outcome {
        let settings = RenderSettings {
            width: self.size,
            height: self.size,
            spp: self.spp,
            max_depth: self.depth,
            seed: 3,
            sampler: Sampler::Independent,
            ..RenderSettings::default()
        };
        let scene = self.scene.to_scene().with_intersection(intersection);
        let rng = RngSource::new(&settings, RngChoice::PerSample);
        let frame = Arc::new(Frame::new(RenderJob::new(scene, settings), rng, 2, 8, Arc::new(|_| {})));
        self.judge(&render(&frame, &Schedule::Stealing).image)
    }

    fn judge(&self, image: &Image) -> Outcome {
        let mut o = Outcome { non_finite: 0, dark: 0, bright: 0, worst: 0.0, at_floor: 0, at_one: 0 };
        for pixel in &image.pixels {
            let values = pixel.to_array().map(to_f64);
            if values.iter().any(|v| !v.is_finite()) {
                o.non_finite += 1;
                continue;
            }
            o.dark += values.iter().any(|&v| v < self.floor - TOLERANCE) as usize;
            o.bright += values.iter().any(|&v| v > self.ceiling + TOLERANCE) as usize;
            for v in values {
                o.worst = o.worst.max(self.floor - v).max(v - self.ceiling);
                o.at_floor += ((v - self.floor).abs() <= TOLERANCE) as usize;
                o.at_one += ((v - 1.0).abs() <= TOLERANCE) as usize;
            }
        }
        o
    }
}

const WHITE: BackgroundSpec = BackgroundSpec::Constant { color: [1.0; 3] };

fn sphere(center: [f64; 3], radius: f64, material: MaterialSpec) -> SphereSpec {
    SphereSpec { center, radius, material: MaterialRef::Inline(material), center1: None }
}

fn grey() -> MaterialSpec {
    MaterialSpec::lambertian([0.5; 3])
}

fn glass() -> MaterialSpec {
    MaterialSpec::glass(1.5)
}

fn camera(lookfrom: [f64; 3], lookat: [f64; 3], vfov: f64) -> CameraSettings {
    let d = ((0..3).map(|i| (lookfrom[i] - lookat[i]).powi(2)).sum::<f64>()).sqrt();
    CameraSettings {
        lookfrom,
        lookat,
        vup: [0.0, 1.0, 0.0],
        vfov,
        aperture: 0.0,
        focus_dist: Some(d),
        aspect: 1.0,
    }
}

fn under_white_sky(camera: CameraSettings, spheres: Vec<SphereSpec>) -> SceneFile {
    let mut scene = SceneFile::new(camera, WHITE);
    scene.shapes.spheres = spheres;
    scene
}

/// The grey furnace sphere, scaled by `scale` and moved by `offset`.
fn furnace(scale: f64, offset: [f64; 3]) -> SceneFile {
    let at = |v: [f64; 3]| [0, 1, 2].map(|i| offset[i] + v[i] * scale);
    under_white_sky(
        camera(at([0.0, 0.0, 5.0]), at([0.0; 3]), 30.0),
        vec![sphere(at([0.0; 3]), scale, grey())],
    )
}

/// Every case, in the order of the table.
pub fn cases() -> Vec<StressCase> {
    let case = |name: &str, scene, floor, ceiling, (size, spp, depth)| StressCase {
        name: name.into(),
        scene,
        floor,
        ceiling,
        size,
        spp,
        depth,
    };
    let small = (40, 8, 50);
    let mut cases = vec![
        case("furnace, unit", furnace(1.0, [0.0; 3]), 0.5, 1.0, small),
        case("furnace, scaled by 1e-3", furnace(1e-3, [0.0; 3]), 0.5, 1.0, small),
        case("furnace, scaled by 1e3", furnace(1e3, [0.0; 3]), 0.5, 1.0, small),
        case("furnace, translated 1e4 away", furnace(1.0, [1e4; 3]), 0.5, 1.0, small),
        case("grazing rays: silhouette at 160 × 160", furnace(1.0, [0.0; 3]), 0.5, 1.0, (160, 4, 50)),
    ];
    for radius in [1e4, 1e5] {
        // The camera 1 unit above a grey ground sphere, looking down at the ground ahead.
        let ground = vec![sphere([0.0, -radius, 0.0], radius, grey())];
        let scene = under_white_sky(camera([0.0, 1.0, 0.0], [0.0, 0.0, -4.0], 40.0), ground);
        cases.push(case(
            &format!("ground sphere of radius {radius:.0e}, camera 1 above"),
            scene,
            0.5,
            1.0,
            small,
        ));
    }
    let eye = camera([0.0, 0.0, 5.0], [0.0; 3], 30.0);
    for (name, spheres) in [
        ("glass: solid (total internal reflection)", vec![sphere([0.0; 3], 1.0, glass())]),
        (
            "glass: hollow shell (negative radius)",
            vec![sphere([0.0; 3], 1.0, glass()), sphere([0.0; 3], -0.9, glass())],
        ),
        ("glass inside glass", vec![sphere([0.0; 3], 1.0, glass()), sphere([0.2, 0.1, 0.0], 0.4, glass())]),
        ("glass of ior 1", vec![sphere([0.0; 3], 1.0, MaterialSpec::glass(1.0))]),
    ] {
        cases.push(case(name, under_white_sky(eye.clone(), spheres), 1.0, 1.0, (40, 8, 200)));
    }
    // The eye exactly on the unit sphere's surface, looking away from it: all sky.
    let on_surface =
        under_white_sky(camera([0.0, 0.0, 1.0], [0.0, 0.0, 6.0], 30.0), vec![sphere([0.0; 3], 1.0, grey())]);
    cases.push(case("ray origins exactly on a surface", on_surface, 1.0, 1.0, (32, 4, 50)));
    for (name, material) in [
        ("degenerate: fuzz 5 (acts as 1)", MaterialSpec::Metal { albedo: [0.8; 3], fuzz: 5.0 }),
        ("degenerate: black albedo", MaterialSpec::lambertian([0.0; 3])),
        ("degenerate: albedo above 1", MaterialSpec::lambertian([1.5; 3])),
        ("degenerate: ior 1e-3", MaterialSpec::glass(1e-3)),
    ] {
        let floor = sphere([0.0, -101.0, 0.0], 100.0, MaterialSpec::Metal { albedo: [0.9; 3], fuzz: 1.0 });
        let scene = under_white_sky(eye.clone(), vec![sphere([0.0; 3], 1.0, material), floor]);
        cases.push(case(name, scene, 0.0, f64::INFINITY, (32, 4, 50)));
    }
    cases
}
