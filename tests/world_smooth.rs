//! Meshes shaded by their files' vertex normals, which lean off the flat facets: a bounce,
//! a light sample and the light's own weight must all follow the surface the normals
//! describe (`Mesh::lift`, `Hit::departure`) or the image comes out darker than it is.

mod rooms;

use raypool::scenes::format::SceneFile;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::real::{Real, Vec3, to_f64};
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::scene::Scene;
use raypool::tracer::tile::Tile;
use raypool::tracer::world::object::Probe;
use rooms::{CAMERA, assert_the_three_light_samplings_agree, inward_cube};

#[test]
fn a_glowing_mesh_shaded_by_tilted_normals_is_weighed_by_its_faces() {
    // A panel of two emitting triangles whose file normals lean 85° off their face: `mis`
    // weighed a bounce's hit by the leaning normal and the shadow ray's by the face's, so the
    // weights of a point did not sum to 1 (1.9% dark, found by a trial user). The image's
    // mean under `mis` against `mixture`'s (which weighs by directions, not normals), within
    // 5 standard errors from 8 renders of each: that catches a bias of 0.47% (printed;
    // measured at 0db8597).
    let dir = std::env::temp_dir().join(format!("raypool-world-tilt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("panel.obj"),
        "v -0.98 0.98 -0.98\nv 0.98 0.98 -0.98\nv 0.98 0.98 0.98\nv -0.98 0.98 0.98\nvn 0.996207 -0.087018 0\n\
         f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n",
    )
    .unwrap();
    let text = format!(
        "{CAMERA}[background]\nkind = \"black\"\n{room}[[mesh]]\nobj = \"panel.obj\"\n\
         material = {{ kind = \"diffuse_light\", emit = [1.0, 1.0, 1.0] }}\n",
        room = inward_cube("{ kind = \"lambertian\", albedo = [0.7, 0.7, 0.7] }"),
    );
    std::fs::write(dir.join("room.toml"), text).unwrap();
    let means = |light_sampling: LightSampling| {
        let runs: Vec<f64> = (1..=8)
            .map(|seed| {
                let scene =
                    SceneFile::read(&dir.join("room.toml")).unwrap_or_else(|e| panic!("{e}")).to_scene();
                let settings = RenderSettings {
                    width: 32,
                    height: 32,
                    spp: 64,
                    seed,
                    light_sampling,
                    ..Default::default()
                };
                let job = RenderJob::new(scene, settings);
                let pixels =
                    render_tile(&job, &SobolStreams::new(seed), Tile { x: 0, y: 0, width: 32, height: 32 })
                        .pixels;
                pixels.iter().map(|p| to_f64(p.x + p.y + p.z) / 3.0).sum::<f64>() / pixels.len() as f64
            })
            .collect();
        let mean = runs.iter().sum::<f64>() / 8.0;
        let variance = runs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 7.0;
        (mean, (variance / 8.0).sqrt())
    };
    let ((a, sa), (b, sb)) = (means(LightSampling::Mixture), means(LightSampling::Mis));
    std::fs::remove_dir_all(&dir).ok();
    assert!(a > 0.05, "the room is lit: {a}");
    eprintln!("mixture {a:.5}, mis {b:.5}: catches a bias of {:.2}%", 500.0 * sa.hypot(sb) / a);
    assert!((a - b).abs() <= 5.0 * (sa * sa + sb * sb).sqrt(), "mixture {a} ± {sa}, mis {b} ± {sb}");
}

/// A sphere of radius 1 as a mesh of `rings` × `2·rings` cells (OBJ text) whose vertex
/// normals point straight out: a convex mesh shaded as if it were round.
fn smooth_ball_obj(rings: usize) -> String {
    let segments = 2 * rings;
    let mut obj = String::new();
    for j in 0..=rings {
        let theta = std::f64::consts::PI * j as f64 / rings as f64;
        for i in 0..segments {
            let phi = std::f64::consts::TAU * i as f64 / segments as f64;
            let p = [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()];
            obj += &format!("v {} {} {}\nvn {} {} {}\n", p[0], p[1], p[2], p[0], p[1], p[2]);
        }
    }
    let vertex = |i: usize, j: usize| j * segments + i % segments + 1;
    for j in 0..rings {
        for i in 0..segments {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            // Outward winding; the poles' cells are single triangles.
            if j != 0 {
                obj += &format!("f {a}//{a} {c}//{c} {b}//{b}\n");
            }
            if j != rings - 1 {
                obj += &format!("f {a}//{a} {d}//{d} {c}//{c}\n");
            }
        }
    }
    obj
}

/// The scene `text`, read from a file beside `ball.obj`, a [`smooth_ball_obj`] of `rings`
/// (both written to a folder of their own, removed once the scene is loaded).
fn scene_with_smooth_ball(name: &str, rings: usize, text: &str) -> Scene {
    let dir = std::env::temp_dir().join(format!("raypool-world-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("ball.obj"), smooth_ball_obj(rings)).unwrap();
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let scene = SceneFile::read(&dir.join("scene.toml")).unwrap_or_else(|e| panic!("{e}")).to_scene();
    std::fs::remove_dir_all(&dir).ok();
    scene
}

#[test]
fn a_smooth_shaded_mesh_ball_in_the_white_furnace_renders_exactly_its_albedo() {
    // Every bounce off a convex lambertian surface under a uniform sky escapes to the sky, so
    // every pixel wholly on the ball is its albedo, 0.5, to the bit. Its vertex normals lean
    // several degrees off its flat facets, and a bounce drawn about such a normal can point below
    // the facet it leaves: spawned from the facet it met the ball again and came out darker
    // (before `Mesh::lift`: 695 of 4,618 ball pixels of a 100 × 100, 64 spp render, down to
    // 0.484). Bounces now leave from the smooth surface the normals describe.
    let text = "[camera]\nlookfrom = [0.0, 0.0, 5.0]\nlookat = [0.0, 0.0, 0.0]\nvup = [0.0, 1.0, 0.0]\n\
                    vfov = 30.0\naspect = 1.0\n[background]\nkind = \"constant\"\ncolor = [1.0, 1.0, 1.0]\n\
                    [[mesh]]\nobj = \"ball.obj\"\nmaterial = { kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }\n";
    let scene = scene_with_smooth_ball("furnace", 12, text);
    let (size, spp) = (48, 64);
    let settings = RenderSettings { width: size, height: size, spp, seed: 5, ..Default::default() };
    let job = RenderJob::new(scene, settings);
    let whole = Tile { x: 0, y: 0, width: size, height: size };
    let pixels = render_tile(&job, &SobolStreams::new(settings.seed), whole).pixels;
    let mut on_ball = 0;
    for j in 0..size as usize {
        for i in 0..size as usize {
            // Wholly on the ball: a 5 × 5 grid of points across the pixel, corners included,
            // all hit it.
            let all_hit = (0..25).all(|k| {
                let (x, y) = (i as Real + (k % 5) as Real / 4.0, j as Real + (k / 5) as Real / 4.0);
                job.scene.hit_world(&job.camera.center_ray(x, y), &Probe::default()).is_some()
            });
            if all_hit {
                on_ball += 1;
                let p = pixels[j * size as usize + i];
                assert_eq!(p, Vec3::splat(0.5), "pixel ({i}, {j}) of the ball");
            }
        }
    }
    assert!(on_ball > 300, "only {on_ball} pixels wholly on the ball");
}

#[test]
fn a_lamp_touching_a_coarse_smooth_mesh_ball_gets_the_same_light_under_all_three_samplings() {
    // A 4 × 8-cell ball shaded by its vertex normals, whose smooth surface (`Mesh::lift`) reaches up
    // to 8% of its radius outside the sphere, with a lamp resting on its top. Raising only the rays'
    // start left the light samples drawn from the facet: `mis` came out 2.6% darker than `bsdf` (6
    // seeds, 64 × 64, 256 spp, standard error 0.1%). Now the light sample, its shadow ray, its
    // density and the bounce all start from one raised point (`Hit::departure`).
    // At these settings the test catches 7–10% of the image's mean (see the helper): it would
    // not see that 2.6% again; a guard against gross faults only.
    let text = "[camera]\nlookfrom = [0.0, 2.5, 3.0]\nlookat = [0.0, 0.3, 0.0]\nvup = [0.0, 1.0, 0.0]\n\
                vfov = 50.0\naspect = 1.0\n[background]\nkind = \"black\"\n\
                [[mesh]]\nobj = \"ball.obj\"\nmaterial = { kind = \"lambertian\", albedo = [0.7, 0.7, 0.7] }\n\
                [[quad]]\nq = [-0.5, 1.0, -0.5]\nu = [1.0, 0.0, 0.0]\nv = [0.0, 0.0, 1.0]\n\
                material = { kind = \"diffuse_light\", emit = [4.0, 4.0, 4.0] }\n";
    let scene = scene_with_smooth_ball("lamp", 4, text);
    assert_the_three_light_samplings_agree("lamp on a smooth ball", &scene);
}
