//! Numerical stress tests (issue #6): no NaN or infinite pixel anywhere, and energy exactly
//! conserved where the answer is known, in f32, at scales from 10⁻³ to 10⁵. The cases and
//! their known answers are in `raypool::measure::stress`; here raypool's robust method must pass all
//! of them. (`cargo bench --bench stability` shows how the book's method fares.) The second
//! book's shapes are checked ray by ray (`raypool::measure::stress_shapes`): no ray aimed at a
//! closed mesh's shared edges or vertices slips through, and no ray spawned off a quad or a
//! triangle 10⁴ from the origin meets it again.

mod deadline;

use deadline::within;
use glam::DVec3;
use raypool::measure::stress::{StressCase, cases};
use raypool::measure::stress_shapes::{self, Aim, Flat, Solid};
use raypool::measure::stress_smooth;
use raypool::scenes::builtin::builtin_scene;
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::geometry::sphere::Intersection;
use raypool::tracer::math::real::to_dvec3;
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::independent::{PerSample, PerSamplePixel};
use raypool::tracer::sampling::sampler::Sampler;
use raypool::tracer::sampling::sampler::{PixelStreams, RandomStreams};
use raypool::tracer::tile::Tile;

fn case(name: &str) -> StressCase {
    cases().into_iter().find(|c| c.name.starts_with(name)).unwrap_or_else(|| panic!("no case '{name}'"))
}

/// No NaN, nothing darker than the floor or brighter than the ceiling.
fn assert_exact(case: &StressCase) -> raypool::measure::stress::Outcome {
    let o = case.run(Intersection::Robust);
    assert_eq!(o.non_finite, 0, "{}: {o:?}", case.name);
    assert_eq!(o.dark, 0, "{}: pixels below {} (acne, energy lost): {o:?}", case.name, case.floor);
    assert_eq!(o.bright, 0, "{}: pixels above {} (energy made): {o:?}", case.name, case.ceiling);
    o
}

/// The furnace cases must show both the sphere (exactly its albedo) and the sky (exactly 1),
/// or passing would prove nothing.
fn assert_furnace(name: &str) {
    let case = case(name);
    let o = assert_exact(&case);
    let values = (case.size * case.size * 3) as usize;
    assert!(o.at_floor > values / 4 && o.at_one > values / 10, "{name}: {o:?} of {values} values");
}

#[test]
fn furnace_holds_from_a_millimetre_to_a_kilometre_and_far_from_the_origin() {
    within("the renders of the four furnace cases to finish", move || {
        for name in
            ["furnace, unit", "furnace, scaled by 1e-3", "furnace, scaled by 1e3", "furnace, translated 1e4"]
        {
            assert_furnace(name);
        }
    });
}

#[test]
fn grazing_rays_along_the_silhouette_stay_between_sphere_and_sky() {
    within("the grazing-rays render to finish", move || {
        assert_furnace("grazing rays");
    });
}

#[test]
fn huge_ground_spheres_show_no_acne() {
    within("the renders of the huge ground spheres to finish", move || {
        for name in ["ground sphere of radius 1e4", "ground sphere of radius 1e5"] {
            let o = assert_exact(&case(name));
            assert!(o.at_floor > 0, "{name}: the ground must be in view: {o:?}");
        }
    });
}

#[test]
fn clear_glass_under_a_white_sky_renders_white() {
    within("the renders of the glass cases to finish", move || {
        for name in ["glass: solid", "glass: hollow", "glass inside glass", "glass of ior 1"] {
            assert_exact(&case(name));
        }
    });
}

#[test]
fn a_camera_exactly_on_a_surface_sees_past_it() {
    within("the render from a camera on a surface to finish", move || {
        assert_exact(&case("ray origins exactly on a surface"));
    });
}

#[test]
fn degenerate_materials_stay_finite() {
    within("the renders of the degenerate materials to finish", move || {
        for c in cases().iter().filter(|c| c.name.starts_with("degenerate")) {
            assert_exact(c);
        }
    });
}

#[test]
fn the_textbook_method_fails_where_raypool_does_not() {
    within("the textbook method's render of the ground sphere to finish", move || {
        // The comparison is only worth showing if it shows something: in f32 the book's fixed
        // t_min = 0.001 and textbook quadratic lose energy on the huge ground sphere.
        if cfg!(feature = "f64") {
            return; // f64 rescues much of the textbook method; the table shows by how much.
        }
        let o = case("ground sphere of radius 1e4").run(Intersection::Textbook);
        assert!(o.dark > 0 || o.non_finite > 0, "the textbook method passed: {o:?}");
    });
}

#[test]
fn rays_at_the_seams_of_a_closed_triangle_mesh_never_slip_through() {
    within("2·10⁴ rays at each kind of seam, at every vector level, to be traced", move || {
        for (isa, placed) in Isa::available().into_iter().flat_map(|isa| [(isa, false), (isa, true)]) {
            for solid in [Solid::Icosphere, Solid::TriangleCube] {
                for aim in [Aim::Edges, Aim::Vertices] {
                    let leaks = stress_shapes::leaks(solid, aim, placed, 20_000, isa);
                    assert_eq!(
                        leaks, 0,
                        "{solid:?} at its {aim:?} at {isa:?}, through an instance: {placed}"
                    );
                }
            }
        }
    });
}

#[test]
fn quads_triangles_and_discs_1e4_from_the_origin_show_no_acne() {
    within("2·10⁴ hits and their spawned rays, at every vector level, to be traced", move || {
        for (isa, placed) in Isa::available().into_iter().flat_map(|isa| [(isa, false), (isa, true)]) {
            for flat in [Flat::Quad, Flat::Triangle, Flat::Disc] {
                let a = stress_shapes::acne(flat, 1e4, placed, 20_000, isa);
                assert_eq!(
                    a,
                    stress_shapes::Acne::default(),
                    "{flat:?} at {isa:?}, through an instance: {placed}"
                );
            }
        }
    });
}

#[test]
fn bounces_off_a_mesh_shaded_by_its_vertex_normals_never_meet_it_again() {
    within("2·10⁴ bounces off the smooth icosphere to be traced", move || {
        for placed in [false, true] {
            let s = stress_smooth::self_hits(3, placed, 20_000, Isa::best());
            assert_eq!((s.missed, s.from_departure), (0, 0), "through an instance: {placed}");
            // The case bites: from the flat facets, some of the same bounces do meet it.
            assert!(s.from_facet > 0, "through an instance: {placed}: {s:?}");
        }
    });
}

/// Sample `s` of a pixel drawn from stream `first + s`: lets one pixel's samples be averaged in
/// separate renders.
struct From {
    streams: PerSample,
    first: u64,
}

impl RandomStreams for From {
    type Pixel<'a> = FromPixel;

    fn pixel(&self, pixel: u64) -> FromPixel {
        FromPixel { pixel: self.streams.pixel(pixel), first: self.first }
    }
}

/// One pixel of [`From`].
struct FromPixel {
    pixel: PerSamplePixel,
    first: u64,
}

impl PixelStreams for FromPixel {
    type Stream<'a> = <PerSamplePixel as PixelStreams>::Stream<'a>;

    fn stream(&self, sample: u64) -> Self::Stream<'_> {
        self.pixel.stream(self.first + sample)
    }
}

#[test]
fn a_pixel_of_a_quarter_million_samples_is_the_mean_of_its_parts() {
    // The whole view of three-spheres in one pixel: sky, glass and gold, so samples vary from
    // 0 to over 1. Its mean over 2^18 samples must equal the mean of the means of its four
    // quarters, each 2^16 of the same samples. A running sum in f32 failed this by up to
    // 4e-4 relative at 2^18 and 1.3e-3 at 2^20 (results/accumulation.md): near a sum of
    // 10^5, f32's spacing rounds every sample added.
    let scene = builtin_scene("three-spheres", 0).unwrap().to_scene();
    let streams = PerSample { seed: 7 };
    let tile = Tile { x: 0, y: 0, width: 1, height: 1 };
    let mean_of = |first: u64, spp: u32| {
        let settings = RenderSettings {
            width: 1,
            height: 1,
            spp,
            max_depth: 50,
            seed: 7,
            sampler: Sampler::Independent,
            ..Default::default()
        };
        let job = RenderJob::new(scene.clone(), settings);
        to_dvec3(render_tile(&job, &From { streams, first }, tile).pixels[0])
    };
    let quarter = 1 << 16;
    let whole = mean_of(0, 4 * quarter);
    let parts = (0..4).map(|k| mean_of(u64::from(k * quarter), quarter)).sum::<DVec3>() / 4.0;
    let relative = ((whole - parts) / parts).abs().max_element();
    // Each mean is rounded once to f32 for the output: a few parts in 10^7 at most.
    assert!(relative < 1e-6, "whole {whole:?} against parts {parts:?}: {relative:e} relative");
}
