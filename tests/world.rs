//! Exact tests of the second book's world: answers known in closed form, so that a wrong
//! emission, quad, instance, medium or moving sphere fails them, whatever the sampling.

mod rooms;

use raypool::scenes::format::SceneFile;
use raypool::tracer::lights::LightSampling;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3, to_f64};
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::scene::Scene;
use raypool::tracer::tile::Tile;
use raypool::tracer::world::object::Probe;
use rooms::{CAMERA, assert_within_five_errors, inward_cube, lit_room, mean_and_error, quadrant_sums};

fn render(text: &str, settings: RenderSettings) -> Vec<Vec3> {
    render_scene(&parse(text), settings)
}

fn parse(text: &str) -> Scene {
    SceneFile::parse(text, "test.toml").unwrap_or_else(|e| panic!("{e}")).to_scene()
}

fn render_scene(scene: &Scene, settings: RenderSettings) -> Vec<Vec3> {
    let job = RenderJob::new(scene.clone(), settings);
    let whole = Tile { x: 0, y: 0, width: settings.width, height: settings.height };
    render_tile(&job, &SobolStreams::new(settings.seed), whole).pixels
}

#[test]
fn a_closed_box_of_emitting_reflecting_walls_has_radiance_le_times_the_geometric_sum() {
    // Every path stays in the box and every hit adds a^k·Le: after D rays Le·(1 − a^D)/(1 − a),
    // for every pixel and sample under `bsdf` (to rounding). Under `mixture` and `mis` each
    // sample is noisy but every pixel has that mean: held to 5 standard errors of the pixels'
    // spread (issue #55's review: the analytic furnaces catch ≤ 1.2% of the mean).
    let (le, a) = (0.75, 0.5);
    for depth in [1u32, 2, 5, 12] {
        let material = format!("{{ kind = \"diffuse_light\", emit = [{le}, {le}, {le}], albedo = {a} }}");
        let text = format!("{CAMERA}[background]\nkind = \"black\"\n{}", inward_cube(&material));
        let expected = le * (1.0 - f64::powi(a, depth as i32)) / (1.0 - a);
        for light_sampling in [LightSampling::Bsdf, LightSampling::Mixture, LightSampling::Mis] {
            let settings = RenderSettings {
                width: 12,
                height: 12,
                spp: 4,
                max_depth: depth,
                light_sampling,
                ..Default::default()
            };
            let values: Vec<f64> =
                render(&text, settings).iter().flat_map(|p| p.to_array().map(to_f64)).collect();
            if light_sampling == LightSampling::Bsdf {
                for c in values {
                    assert!((c - expected).abs() < 1e-5 * expected, "depth {depth}: {c} against {expected}");
                }
                continue;
            }
            let n = values.len() as f64;
            let mean = values.iter().sum::<f64>() / n;
            let spread = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            assert!(
                (mean - expected).abs() <= 5.0 * spread / n.sqrt() + 1e-5 * expected,
                "{light_sampling:?}, depth {depth}: mean {mean} against {expected} (noise {spread} a pixel)"
            );
        }
    }
}

#[test]
fn a_light_quad_covers_exactly_its_solid_angle_and_only_its_front_shines() {
    // A square light of side 0.5, parallel to the image plane at the focus distance 1: it covers
    // (0.5 / viewport)² of the image, viewport = 2·tan(30°).
    let quad = |facing_camera: bool| {
        let (u, v) = if facing_camera {
            ("[0.5, 0.0, 0.0]", "[0.0, 0.5, 0.0]")
        } else {
            ("[0.0, 0.5, 0.0]", "[0.5, 0.0, 0.0]")
        };
        format!(
            "{CAMERA}[background]\nkind = \"black\"\n[[quad]]\nq = [-0.25, -0.25, -1.0]\nu = {u}\nv = {v}\nmaterial = {{ kind = \"diffuse_light\", emit = [1.0, 1.0, 1.0] }}\n"
        )
    };
    let settings = RenderSettings { width: 64, height: 64, spp: 64, max_depth: 4, ..Default::default() };
    let pixels = render(&quad(true), settings);
    let mean = pixels.iter().map(|p| to_f64(p.x)).sum::<f64>() / pixels.len() as f64;
    let viewport = 2.0 * (30f64).to_radians().tan();
    let expected = (0.5 / viewport).powi(2);
    assert!((mean - expected).abs() < 2e-3 * expected, "covered {mean}, expected {expected}");
    let back = render(&quad(false), settings);
    assert!(back.iter().all(|p| *p == Vec3::ZERO), "a light seen from behind is black");
}

#[test]
fn a_medium_of_density_zero_changes_no_pixel() {
    let base = raypool::scenes::builtin::builtin_scene("cornell", 0).unwrap().to_toml();
    let with = format!(
        "{base}\n[[medium]]\ndensity = 0.0\nalbedo = [1.0, 1.0, 1.0]\nboundary = {{ kind = \"box\", min = [100.0, 100.0, 100.0], max = [400.0, 400.0, 400.0] }}\n"
    );
    let settings = RenderSettings { width: 24, height: 24, spp: 4, max_depth: 8, ..Default::default() };
    assert!(render(&base, settings) == render(&with, settings));
}

#[test]
fn a_moving_sphere_whose_ends_agree_renders_the_static_sphere_bit_for_bit() {
    // The moving one makes it a second-book scene (the world's search and render loop); the
    // static one is a first-book scene: the two paths agree to the bit.
    let still = raypool::scenes::builtin::builtin_scene("three-spheres", 0).unwrap();
    let mut moving = still.clone();
    moving.spheres[1].center1 = Some(moving.spheres[1].center);
    assert!(!still.to_scene().objects().iter().any(|_| true), "a first-book scene has no world");
    assert!(!moving.to_scene().is_first_book());
    let settings = RenderSettings { width: 30, height: 20, spp: 4, max_depth: 10, ..Default::default() };
    let text = |f: &SceneFile| f.to_toml();
    assert!(render(&text(&still), settings) == render(&text(&moving), settings));
}

#[test]
fn an_instance_hits_what_the_same_box_moved_by_hand_hits() {
    // A box turned a quarter about y and moved, as an instance, against the box whose corners
    // were turned and moved by hand: the same hits, to rounding, for a fan of rays.
    let box_at = |min: [f64; 3], max: [f64; 3], transform: &str| {
        format!(
            "{CAMERA}[[box]]\nmin = {min:?}\nmax = {max:?}\nmaterial = {{ kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }}\n{transform}"
        )
    };
    // (x, z) → (z, −x) turns [0, 1] × [0, 2] into [0, 2] × [−1, 0]; then moved by (−1, −0.5, −4).
    let instance = box_at(
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 2.0],
        "transform = { rotate_y = 90.0, translate = [-1.0, -0.5, -4.0] }",
    );
    let by_hand = box_at([-1.0, -0.5, -5.0], [1.0, 0.5, -4.0], "");
    let scene = |t: &str| SceneFile::parse(t, "t").unwrap().to_scene();
    let (a, b) = (scene(&instance), scene(&by_hand));
    let mut hits = 0;
    for k in 0..4000 {
        let (x, y) = ((k % 80) as Real / 40.0 - 1.0, (k / 80) as Real / 25.0 - 1.0);
        let ray = Ray::new(Vec3::new(0.1, 0.2, 0.0), Vec3::new(x, y, -4.0));
        let (ha, hb) = (a.hit_world(&ray, &Probe::default()), b.hit_world(&ray, &Probe::default()));
        match (ha, hb) {
            (Some(ha), Some(hb)) => {
                hits += 1;
                assert!((ha.t - hb.t).abs() <= 1e-5 * hb.t, "{ray:?}: t {} against {}", ha.t, hb.t);
                assert!((ha.normal - hb.normal).length() < 1e-5 && ha.front_face == hb.front_face);
                assert!((ha.point - hb.point).length() < 1e-5 * hb.t);
            }
            (None, None) => {}
            (ha, hb) => panic!("{ray:?}: the instance hit {ha:?}, the box by hand {hb:?}"),
        }
    }
    assert!(hits > 1000, "the fan must cross the box ({hits} hits)");
}

#[test]
fn every_new_scene_prints_toml_that_reads_back_to_the_same_scene() {
    for name in ["cornell", "cornell-smoke", "next-week", "quads", "perlin", "bouncing", "mesh"] {
        let file = raypool::scenes::builtin::builtin_scene(name, 5).unwrap();
        let again = SceneFile::parse(&file.to_toml(), name).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again, file, "{name}");
    }
}

#[test]
fn mangled_new_world_scene_files_are_refused_or_render_never_panic() {
    // Scene fuzzing: lines of the new scenes deleted, duplicated, or their numbers replaced by
    // extreme ones; whatever parses must render a tiny image without a panic or a NaN.
    use rand::rngs::SmallRng;
    use rand::{RngExt, SeedableRng};
    let mut rng = SmallRng::seed_from_u64(35);
    let numbers = ["0.0", "-0.0", "1e30", "-1e30", "1e-30", "nan", "inf", "-1.0", "3"];
    let (mut parsed, mut refused) = (0, 0);
    for name in ["cornell-smoke", "quads", "perlin", "cornell"] {
        let text = raypool::scenes::builtin::builtin_scene(name, 0).unwrap().to_toml();
        let lines: Vec<&str> = text.lines().collect();
        for _ in 0..150 {
            let mut mangled: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            for _ in 0..rng.random_range(1..4) {
                let at = rng.random_range(0..mangled.len());
                match rng.random_range(0..3) {
                    0 => _ = mangled.remove(at),
                    1 => mangled.insert(at, mangled[at].clone()),
                    _ => {
                        let n = numbers[rng.random_range(0..numbers.len())];
                        mangled[at] = mangled[at].replacen(|c: char| c.is_ascii_digit(), n, 1);
                    }
                }
            }
            match SceneFile::parse(&mangled.join("\n"), "mangled.toml") {
                Err(e) => {
                    assert!(!e.to_string().contains('\n'), "one line: {e}");
                    refused += 1;
                }
                Ok(file) => {
                    parsed += 1;
                    let settings =
                        RenderSettings { width: 6, height: 6, spp: 1, max_depth: 6, ..Default::default() };
                    let job = RenderJob::new(file.to_scene(), settings);
                    let whole = Tile { x: 0, y: 0, width: 6, height: 6 };
                    let pixels = render_tile(&job, &SobolStreams::new(1), whole).pixels;
                    assert!(pixels.iter().all(|p| !p.is_nan()), "{name}: NaN from\n{}", mangled.join("\n"));
                }
            }
        }
    }
    assert!(parsed > 50 && refused > 50, "both kinds exercised: {parsed} parsed, {refused} refused");
}

#[test]
fn an_absorbing_medium_lets_through_exactly_e_to_the_minus_density_times_length() {
    // A slab of black smoke (albedo 0) 2 units thick between the camera and a light that fills
    // the view: a path either crosses it (Le) or is absorbed (0), so the image's mean is
    // Le·e^(−σ·2) up to binomial noise, whose size the test computes rather than guesses.
    let (density, le) = (0.4, 1.0);
    let text = format!(
        "{CAMERA}[background]\nkind = \"black\"\n\
         [[quad]]\nq = [-50.0, -50.0, -5.0]\nu = [100.0, 0.0, 0.0]\nv = [0.0, 100.0, 0.0]\n\
         material = {{ kind = \"diffuse_light\", emit = [{le}, {le}, {le}] }}\n\
         [[medium]]\ndensity = {density}\nalbedo = [0.0, 0.0, 0.0]\n\
         boundary = {{ kind = \"box\", min = [-40.0, -40.0, -3.0], max = [40.0, 40.0, -1.0] }}\n"
    );
    let settings = RenderSettings { width: 32, height: 32, spp: 64, max_depth: 4, ..Default::default() };
    let pixels = render(&text, settings);
    let n = (32 * 32 * 64) as f64;
    let mean = pixels.iter().map(|p| to_f64(p.x)).sum::<f64>() / (32.0 * 32.0);
    // Rays cross the slab up to 30° off axis: the mean is the average of e^(−σ·2/cos θ), bound
    // by the axis and corner rays (a band 23% of the mean wide, issue #55: a coarse check).
    let (axis, corner) = (
        le * f64::exp(-density * 2.0),
        le * f64::exp(-density * 2.0 * (1.0 + 2.0 * 0.577f64.powi(2)).sqrt()),
    );
    let noise = 4.0 * (axis * (1.0 - axis) / n).sqrt();
    assert!(
        mean <= axis + noise && mean >= corner - noise,
        "mean {mean}, between {corner} and {axis} ± {noise}"
    );
    assert!(mean < 0.9 * le && mean > 0.1 * le, "the smoke both absorbs and lets through: {mean}");
}

#[test]
fn a_checker_under_a_white_sky_shows_exactly_its_two_colours() {
    // One diffuse bounce into a constant white sky: a pixel's value is the texture's colour
    // where the ray met the quad, exactly; a pixel wholly inside a cell is exactly that cell's.
    let text = format!(
        "{CAMERA}[background]\nkind = \"constant\"\ncolor = [1.0, 1.0, 1.0]\n\
         [[quad]]\nq = [-2.0, -2.0, -1.5]\nu = [4.0, 0.0, 0.0]\nv = [0.0, 4.0, 0.0]\n\
         material = {{ kind = \"lambertian\", texture = {{ kind = \"checker\", scale = 0.25, even = [0.25, 0.5, 0.75], odd = [0.5, 0.125, 0.0625] }} }}\n"
    );
    let settings = RenderSettings { width: 48, height: 48, spp: 4, max_depth: 3, ..Default::default() };
    let pixels = render(&text, settings);
    let (even, odd) = (Vec3::new(0.25, 0.5, 0.75), Vec3::new(0.5, 0.125, 0.0625));
    let pure = pixels.iter().filter(|&&p| p == even || p == odd).count();
    let both = pixels.contains(&even) && pixels.contains(&odd);
    // Cells 0.25 wide at distance 1.5 span ~6 pixels: most pixels lie inside one cell.
    assert!(both && pure > pixels.len() / 2, "{pure} of {} pixels are exactly a cell's colour", pixels.len());
    for p in &pixels {
        let mix = (p.x - odd.x) / (even.x - odd.x);
        assert!((*p - odd.lerp(even, mix)).length() < 1e-5, "{p}: a blend of the two colours only");
    }
}

/// A mesh's search (its tree, and the ray's frame made once and shared by its triangles)
/// finds exactly the hit that testing every triangle on its own finds, ties to the lower
/// index: for rays aimed at the mesh's vertices and edge midpoints (where the f64 recompute
/// and ties happen) and at random.
#[test]
fn a_mesh_search_finds_exactly_what_testing_every_triangle_finds() {
    use raypool::measure::solids::{edges, icosphere};
    use raypool::tracer::geometry::hit::Closest;
    use raypool::tracer::geometry::triangle::intersect;
    use raypool::tracer::world::mesh::Mesh;

    let (points, triangles) = icosphere(3);
    let positions: Vec<Vec3> =
        points.iter().map(|p| Vec3::new(p.x as Real, p.y as Real, p.z as Real)).collect();
    let mesh = Mesh::new(positions.clone(), vec![], vec![], triangles.clone()).expect("a closed mesh");
    let every_triangle = |ray: &Ray| {
        let mut closest = Closest::none(Real::INFINITY);
        for (k, t) in mesh.triangles().iter().enumerate() {
            if let Some(hit) = intersect(t.map(|i| mesh.positions()[i as usize]), ray, closest.bound()) {
                closest.offer(hit.t, k as u32);
            }
        }
        closest.found()
    };
    let mut targets: Vec<Vec3> = positions.clone();
    targets.extend(edges(&triangles).iter().map(|&[a, b]| 0.5 * (positions[a] + positions[b])));
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 40) as Real / (1u64 << 24) as Real * 2.0 - 1.0
    };
    let mut rays = Vec::new();
    for &target in &targets {
        let origin = Vec3::new(3.0 * uniform(), 3.0 * uniform(), 3.0 + uniform());
        rays.push(Ray::new(origin, (target - origin).normalize()));
        // From inside, as a bounce off the far wall would start.
        rays.push(Ray::new(0.1 * origin, (target - 0.1 * origin).normalize()));
    }
    for _ in 0..2000 {
        let dir = Vec3::new(uniform(), uniform(), uniform()).normalize();
        rays.push(Ray::new(Vec3::new(2.0 * uniform(), 2.0 * uniform(), 2.0 * uniform()), dir));
    }
    let mut hits = 0;
    for ray in &rays {
        let searched = mesh.closest(ray, Real::INFINITY).map(|(k, hit)| (k, hit.t));
        assert_eq!(searched, every_triangle(ray), "the search and every triangle disagree on {ray:?}");
        hits += usize::from(searched.is_some());
    }
    assert!(hits > rays.len() / 2, "only {hits} of {} rays hit: the test checks little", rays.len());
}

/// The fraction of the shutter `[0, 1)` during which `ray` meets the sphere of radius `r`
/// whose centre moves from `c0` to `c1` (in front of the ray): where the centre's distance
/// from the ray's line, a quadratic in time, is below `r`.
fn time_covered(ray: &Ray, c0: [f64; 3], c1: [f64; 3], r: f64) -> f64 {
    use glam::DVec3;
    let (o, d) =
        (DVec3::from(ray.origin.to_array().map(to_f64)), DVec3::from(ray.dir.to_array().map(to_f64)));
    let d = d.normalize();
    let across = |v: DVec3| v - v.dot(d) * d;
    let (p0, dp) = (across(DVec3::from(c0) - o), across(DVec3::from(c1) - DVec3::from(c0)));
    let (a, b, c) = (dp.dot(dp), 2.0 * p0.dot(dp), p0.dot(p0) - r * r);
    let disc = b * b - 4.0 * a * c;
    if disc <= 0.0 {
        return 0.0;
    }
    let (t0, t1) = ((-b - disc.sqrt()) / (2.0 * a), (-b + disc.sqrt()) / (2.0 * a));
    (t1.min(1.0) - t0.max(0.0)).max(0.0)
}

#[test]
fn a_moving_light_leaves_a_streak_as_bright_as_the_share_of_the_shutter_it_covers() {
    // A light sphere of radius 0.1 slides 1 unit across the view during the shutter, over a
    // black sky: a camera ray sees it for the share of the shutter its centre stays within 0.1
    // of the ray, so each pixel's mean is that share averaged over the pixel (32 × 32 points),
    // within 5 binomial standard errors + 3e-3 (power not yet measured).
    use raypool::tracer::camera::Camera;
    use raypool::tracer::sampling::sampler::Sampler;
    let (c0, c1, r) = ([-0.5, 0.0, -2.0], [0.5, 0.0, -2.0], 0.1);
    let text = format!(
        "{CAMERA}[background]\nkind = \"black\"\n[[sphere]]\ncenter = {c0:?}\ncenter1 = {c1:?}\nradius = {r}\n\
         material = {{ kind = \"diffuse_light\", emit = [1.0, 1.0, 1.0] }}\n"
    );
    let (side, spp) = (32u32, 256u32);
    let settings = RenderSettings {
        width: side,
        height: side,
        spp,
        max_depth: 1,
        sampler: Sampler::Independent,
        ..Default::default()
    };
    let pixels = render(&text, settings);
    let scene = SceneFile::parse(&text, "test.toml").unwrap().to_scene();
    let camera = Camera::new(&scene.camera, side, side);
    let grid = 32;
    let mut streak = 0;
    for j in 0..side {
        for i in 0..side {
            let at = |k: u32| (k as f64 + 0.5) / grid as f64;
            let share = (0..grid * grid)
                .map(|s| {
                    let (x, y) = (i as f64 + at(s % grid), j as f64 + at(s / grid));
                    time_covered(&camera.center_ray(x as Real, y as Real), c0, c1, r)
                })
                .sum::<f64>()
                / (grid * grid) as f64;
            let got = to_f64(pixels[(j * side + i) as usize].x);
            let sigma = (share * (1.0 - share) / spp as f64).sqrt();
            assert!(
                (got - share).abs() <= 5.0 * sigma + 3e-3,
                "pixel ({i}, {j}): {got}, expected {share} ± {sigma}"
            );
            streak += usize::from(share > 0.1);
        }
    }
    let brightest = pixels.iter().map(|p| to_f64(p.x)).fold(0.0, f64::max);
    // The streak is 1.2 units long, 16 px at this distance; the still sphere would be 3 px wide.
    assert!(streak >= 16 && brightest < 0.5, "a streak, not a sphere: {streak} px, max {brightest}");
}

/// The mean image of `scene` under `light_sampling` over 8 seeds, per quadrant and channel:
/// the mean of the 8 and its standard error.
fn quadrant_means(scene: &Scene, light_sampling: LightSampling) -> Vec<(f64, f64)> {
    let side = 16;
    let runs: Vec<Vec<f64>> = (1..=8)
        .map(|seed| {
            let settings = RenderSettings {
                width: side,
                height: side,
                spp: 64,
                seed,
                light_sampling,
                ..Default::default()
            };
            let pixels = render_scene(scene, settings);
            quadrant_sums(&pixels, side)
        })
        .collect();
    mean_and_error(&runs)
}

/// Each quadrant's mean colour under `mixture` and `mis` against `bsdf`'s, within 5 standard
/// errors from 8 renders of each: the smallest bias caught is 5.5–33% of a quadrant's mean on
/// cornell (median 19%), 1.8–12.7% on cornell-smoke (issue #55's review); elsewhere not measured.
fn assert_the_three_light_samplings_agree(name: &str, scene: &Scene) {
    let reference = quadrant_means(scene, LightSampling::Bsdf);
    for light_sampling in [LightSampling::Mixture, LightSampling::Mis] {
        let other = quadrant_means(scene, light_sampling);
        assert_within_five_errors(name, ("bsdf", &reference), (light_sampling.name(), &other));
    }
}

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
fn a_shadow_rays_search_finds_a_blocker_exactly_when_the_closest_hit_search_finds_one_nearer() {
    // `Scene::occluded` (ends at the first object found) against the closest hit, on rays
    // from points all over each scene, with search bounds around the hit's distance: through
    // instances, meshes, media (with each ray's own medium numbers) and moving spheres.
    use rand::{SeedableRng, rngs::SmallRng};
    use raypool::tracer::sampling::warp::uniform;
    for name in ["cornell", "cornell-smoke", "next-week", "mesh", "bouncing"] {
        let scene = raypool::scenes::builtin::builtin_scene(name, 0).unwrap().to_scene();
        use raypool::tracer::math::aabb::{Aabb, Bounded};
        let bounds = scene.objects().iter().map(Bounded::bounds).fold(Aabb::EMPTY, Aabb::union);
        let mut rng = SmallRng::seed_from_u64(7);
        let (mut blocked, n) = (0u64, 20_000u64);
        for k in 0..n {
            let lerp = |a: Real, b: Real, t: Real| a + (b - a) * t;
            let from = Vec3::new(
                lerp(bounds.min.x, bounds.max.x, uniform(&mut rng)),
                lerp(bounds.min.y, bounds.max.y, uniform(&mut rng)),
                lerp(bounds.min.z, bounds.max.z, uniform(&mut rng)),
            );
            let ray = Ray::new(from, raypool::tracer::sampling::warp::random_unit_vector(&mut rng));
            let probe = Probe { time: uniform(&mut rng), medium_seed: k };
            let nearest = scene.hit_world(&ray, &probe).map(|hit| hit.t);
            let t_max = match nearest {
                Some(t) if k % 2 == 0 => t * if k % 4 == 0 { 1.001 } else { 0.999 },
                _ => uniform(&mut rng) * 1_000.0,
            };
            let expected = nearest.is_some_and(|t| t < t_max);
            assert_eq!(
                scene.occluded(&ray, t_max, &probe),
                expected,
                "{name}: ray {k} {ray:?}, bound {t_max}"
            );
            blocked += u64::from(expected);
        }
        assert!(
            blocked >= n / 50 && blocked <= n * 49 / 50,
            "{name}: {blocked} of {n} blocked: both answers tried"
        );
    }
}

#[test]
fn rays_grazing_quad_edges_find_the_same_hits_through_a_tree_as_one_by_one() {
    // A quad accepts hits a few ulps past its edges (`quad::EDGE`); its box in a tree must
    // reach as far, or `--accel flat` finds hits a tree skips (seen on `cornell`'s walls).
    use rand::{SeedableRng, rngs::SmallRng};
    use raypool::tracer::geometry::quad::{EDGE, Quad, box_faces};
    use raypool::tracer::sampling::warp::uniform;
    use raypool::tracer::world::object::{Group, Object};
    let wall = |q: [f32; 3], u: [f32; 3], v: [f32; 3]| {
        let r = |a: [f32; 3]| Vec3::new(a[0] as Real, a[1] as Real, a[2] as Real);
        Quad::new(r(q), r(u), r(v), 0).unwrap()
    };
    let mut quads = vec![
        wall([555.0, 0.0, 0.0], [0.0, 555.0, 0.0], [0.0, 0.0, 555.0]),
        wall([0.0, 0.0, 555.0], [0.0, 555.0, 0.0], [0.0, 0.0, -555.0]),
        wall([0.0, 0.0, 0.0], [0.0, 0.0, 555.0], [555.0, 0.0, 0.0]),
        wall([555.0, 555.0, 555.0], [-555.0, 0.0, 0.0], [0.0, 0.0, -555.0]),
        wall([0.0, 0.0, 555.0], [555.0, 0.0, 0.0], [0.0, 555.0, 0.0]),
        wall([213.0, 554.0, 227.0], [130.0, 0.0, 0.0], [0.0, 0.0, 105.0]),
    ];
    let (a, b) = (Vec3::new(130.0, 0.0, 65.0), Vec3::new(295.0, 165.0, 230.0));
    quads.extend(box_faces(a, b, 0).unwrap());
    let objects: Vec<Object> = quads.iter().map(|&q| Object::Quad(q)).collect();
    let tree = Group::with_tree(objects.clone(), true);
    let flat = Group::with_tree(tree.objects().to_vec(), false);
    assert!(tree.has_tree() && !flat.has_tree());
    let mut rng = SmallRng::seed_from_u64(11);
    let mut grazing = 0;
    for quad in &quads {
        for k in 0..2_000 {
            // A point on or just past one of the four edges, seen from a random point.
            let along = uniform(&mut rng);
            let past = [-0.9, -0.5, 0.0, 0.5][k % 4] * EDGE;
            let (alpha, beta) = match (k / 4) % 4 {
                0 => (past, along),
                1 => (1.0 - past, along),
                2 => (along, past),
                _ => (along, 1.0 - past),
            };
            let target = quad.q + alpha * quad.u + beta * quad.v;
            let from = Vec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)) * 1_200.0
                - Vec3::splat(300.0);
            let Some(dir) = (target - from).try_normalize() else { continue };
            let ray = Ray::new(from, dir);
            let probe = Probe::default();
            let (a, b) = (tree.hit(&ray, Real::INFINITY, &probe), flat.hit(&ray, Real::INFINITY, &probe));
            let key = |h: Option<raypool::tracer::geometry::hit::Hit>| h.map(|h| (h.t, h.point, h.normal));
            assert_eq!(key(a), key(b), "ray {ray:?} at α {alpha}, β {beta}");
            grazing += usize::from(past < 0.0 && a.is_some());
        }
    }
    assert!(grazing > 1_000, "only {grazing} rays past an edge hit anything");
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

#[test]
fn a_glowing_mesh_shaded_by_tilted_normals_is_weighed_by_its_faces() {
    // A panel of two emitting triangles whose file normals lean 85° off their face: `mis`
    // weighed a bounce's hit by the leaning normal and the shadow ray's by the face's, so the
    // weights of a point did not sum to 1 (1.9% dark, found by a trial user). The image's
    // mean under `mis` against `mixture`'s (which weighs by directions, not normals), within
    // 5 standard errors from 8 renders of each (power not yet measured).
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
    let text = "[camera]\nlookfrom = [0.0, 2.5, 3.0]\nlookat = [0.0, 0.3, 0.0]\nvup = [0.0, 1.0, 0.0]\n\
                vfov = 50.0\naspect = 1.0\n[background]\nkind = \"black\"\n\
                [[mesh]]\nobj = \"ball.obj\"\nmaterial = { kind = \"lambertian\", albedo = [0.7, 0.7, 0.7] }\n\
                [[quad]]\nq = [-0.5, 1.0, -0.5]\nu = [1.0, 0.0, 0.0]\nv = [0.0, 0.0, 1.0]\n\
                material = { kind = \"diffuse_light\", emit = [4.0, 4.0, 4.0] }\n";
    let scene = scene_with_smooth_ball("lamp", 4, text);
    assert_the_three_light_samplings_agree("lamp on a smooth ball", &scene);
}
