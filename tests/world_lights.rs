//! Lights wherever the world puts them (inside instances, as mesh triangles, moving): the
//! three light samplings converge to the same image, and a pixel's value depends on its own
//! samples only, whatever the tiles and their order.

mod rooms;

use raypool::scenes::format::SceneFile;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::Vec3;
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::tile::Tile;
use rooms::{assert_the_three_light_samplings_agree, lit_room, parse};

#[test]
fn the_three_light_samplings_converge_to_the_same_image() {
    // The Cornell box (a quad light) and its smoky twin (light through media).
    for scene in ["cornell", "cornell-smoke"] {
        let text = raypool::scenes::builtin::builtin_scene(scene, 0).unwrap().to_toml();
        assert_the_three_light_samplings_agree(scene, &parse(&text));
    }
}

#[test]
fn lights_inside_instances_mesh_triangles_and_moving_lights_are_aimed_at_without_bias() {
    // All four lights of the room are lights, and the three estimators still agree.
    let text = lit_room();
    let scene = parse(&text);
    assert_eq!(scene.lights().len(), 4, "the group's quad and triangle, the triangle, the sphere");
    assert_the_three_light_samplings_agree("room", &scene);
}

#[test]
fn the_lit_room_renders_the_same_pixels_whatever_the_tiles_and_their_order() {
    // What every mode, thread count and shard relies on, on the lights found inside groups,
    // meshes and motion: a pixel's value depends on its own samples only. The whole image
    // against 3 × 3 tiles rendered last to first, under each light sampling and sampler.
    use raypool::tracer::sampling::independent::PerSample;
    for light_sampling in [LightSampling::Bsdf, LightSampling::Mixture, LightSampling::Mis] {
        let scene = SceneFile::parse(&lit_room(), "test.toml").unwrap_or_else(|e| panic!("{e}")).to_scene();
        let settings =
            RenderSettings { width: 24, height: 24, spp: 8, seed: 5, light_sampling, ..Default::default() };
        let job = RenderJob::new(scene, settings);
        for sobol in [true, false] {
            let render = |tile: Tile| {
                if sobol {
                    render_tile(&job, &SobolStreams::new(5), tile).pixels
                } else {
                    render_tile(&job, &PerSample { seed: 5 }, tile).pixels
                }
            };
            let whole = render(Tile { x: 0, y: 0, width: 24, height: 24 });
            assert!(whole.iter().any(|p| *p != Vec3::ZERO), "the room is lit");
            for k in (0..9u32).rev() {
                let tile = Tile { x: (k % 3) * 8, y: (k / 3) * 8, width: 8, height: 8 };
                for (j, p) in render(tile).iter().enumerate() {
                    let (x, y) = (tile.x + j as u32 % 8, tile.y + j as u32 / 8);
                    assert!(
                        *p == whole[(y * 24 + x) as usize],
                        "{light_sampling:?}, sobol {sobol}: pixel {x}, {y}"
                    );
                }
            }
        }
    }
}
