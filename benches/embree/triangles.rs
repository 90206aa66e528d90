//! Triangles against Embree 3 (`cargo bench --bench embree --features embree`, its
//! triangle tables): the `mesh` scene's 131,072-triangle mesh, and its terrain again at 768 ×
//! 768 cells (1,179,648 triangles, a tree past the caches), searched by raypool's own
//! eight-wide tree and watertight test ([`Mesh::closest`]) at each vector level the CPU has,
//! and by Embree's triangle tree (`RTC_GEOMETRY_TYPE_TRIANGLE`, built from the same positions
//! and indices, build quality high, Embree's default scene flags): on Embree's default device,
//! which picks its code for the CPU at run time (AVX2 or AVX-512 and an eight-wide tree where
//! the CPU has them), and on devices held to each level (`isa=sse2`, `avx2`, `avx512`).
//!
//! A second-book scene does not render through a swappable closest-hit function, so this
//! compares the hit search itself, over a fixed ray set recorded once: a camera ray through a
//! jittered point of every pixel of the `mesh` scene, and for each that hits the mesh one
//! diffuse bounce spawned from the hit as the renderer spawns it. Only the mesh is searched
//! (not the scene's two spheres). One thread; each round times the whole set through all
//! three, in an order that turns round by round, and the table gives the median over rounds
//! of the paired ratio of rays per second. Before any timing, each Embree device and raypool
//! must find the same hit or miss for every ray and the same distance to a relative 1e-4 (or
//! to 16 f32 ulps of the ray's origin's magnitude, for the short bounces that meet a
//! neighbour), but for at most a 1e-4 fraction of the rays (a ray on a shared edge may meet either triangle, or, in Embree's
//! non-watertight test, neither), or the bench fails.
//!
//! Unsafe code as in `library.rs`: the device and scene are created in
//! [`EmbreeTriangles::new`], checked, used through `&self` and released once in `Drop`;
//! the buffers are Embree's own (`rtcSetNewGeometryBuffer`), filled before the commit.

use std::ffi::CStr;
use std::hint::black_box;
use std::ptr;
use std::time::Instant;

use embree::sys::{
    RTCBufferType, RTCBuildQuality, RTCDevice, RTCFormat, RTCGeometryType, RTCRayHit, RTCScene,
    rtcAttachGeometry, rtcCommitGeometry, rtcCommitScene, rtcIntersect1, rtcNewDevice, rtcNewGeometry,
    rtcNewScene, rtcReleaseDevice, rtcReleaseGeometry, rtcReleaseScene, rtcSetNewGeometryBuffer,
    rtcSetSceneBuildQuality,
};
use raypool::scenes::assets::GeneratedMesh;
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::camera::Camera;
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3, to_f32};
use raypool::tracer::world::mesh::Mesh;
use raypool::tracer::world::object::Object;

use crate::library::{INVALID_ID, built, embree_ray, incoherent_context, no_hit};
use crate::median_of;

/// Embree's triangle tree over one mesh.
pub struct EmbreeTriangles {
    device: RTCDevice,
    scene: RTCScene,
}

impl EmbreeTriangles {
    /// Embree's tree over `triangles` (indices into `positions`), build quality high, on a
    /// device made with `config` (Embree's configuration string; "" for its defaults).
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]], config: &CStr) -> Result<EmbreeTriangles, String> {
        // SAFETY: a NUL-terminated configuration string that outlives the call.
        let device = unsafe { rtcNewDevice(config.as_ptr()) };
        if device.is_null() {
            return Err("rtcNewDevice failed (is libembree3 installed?)".into());
        }
        // SAFETY: `device` is live; the buffers Embree allocates hold `positions.len()` and
        // `triangles.len()` items of 12 bytes, exactly what is written; the geometry is
        // released once attached, the scene in `Drop`.
        let scene = unsafe {
            let scene = rtcNewScene(device);
            rtcSetSceneBuildQuality(scene, RTCBuildQuality::HIGH);
            let geometry = rtcNewGeometry(device, RTCGeometryType::TRIANGLE);
            let vertices = rtcSetNewGeometryBuffer(
                geometry,
                RTCBufferType::VERTEX,
                0,
                RTCFormat::FLOAT3,
                12,
                positions.len(),
            )
            .cast::<[f32; 3]>();
            let indices = rtcSetNewGeometryBuffer(
                geometry,
                RTCBufferType::INDEX,
                0,
                RTCFormat::UINT3,
                12,
                triangles.len(),
            )
            .cast::<[u32; 3]>();
            if vertices.is_null() || indices.is_null() {
                rtcReleaseGeometry(geometry);
                rtcReleaseScene(scene);
                rtcReleaseDevice(device);
                return Err("Embree could not allocate the mesh's buffers".into());
            }
            for (k, p) in positions.iter().enumerate() {
                *vertices.add(k) = [to_f32(p.x), to_f32(p.y), to_f32(p.z)];
            }
            ptr::copy_nonoverlapping(triangles.as_ptr(), indices, triangles.len());
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
            rtcCommitScene(scene);
            scene
        };
        built(device, EmbreeTriangles { device, scene }, "the mesh")
    }

    /// The nearest triangle along `ray` as `(triangle, t)`.
    #[inline]
    pub fn closest(&self, ray: &Ray) -> Option<(u32, f32)> {
        let mut rayhit = RTCRayHit { ray: embree_ray(ray), hit: no_hit() };
        let mut context = incoherent_context();
        // SAFETY: a committed scene; `context` and `rayhit` are live locals of Embree's layout.
        unsafe { rtcIntersect1(self.scene, &mut context, &mut rayhit) };
        (rayhit.hit.primID != INVALID_ID).then_some((rayhit.hit.primID, rayhit.ray.tfar))
    }
}

impl Drop for EmbreeTriangles {
    fn drop(&mut self) {
        // SAFETY: both handles are live and released exactly once, the scene first.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

/// splitmix64: reproducible numbers in [0, 1) with no generator state to share.
fn uniform(state: &mut u64) -> Real {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as Real / (1u64 << 24) as Real
}

/// A uniformly random unit vector (rejection from the cube).
fn unit_vector(state: &mut u64) -> Vec3 {
    loop {
        let v = Vec3::new(uniform(state), uniform(state), uniform(state)) * 2.0 - Vec3::ONE;
        let l = v.length_squared();
        if l > 1e-6 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

/// A fixed ray set: a jittered camera ray per pixel of a `width × height` image of the scene
/// (jittered by numbers from `seed`), then a diffuse bounce (normal + unit vector, as a
/// Lambertian surface scatters) from each camera ray's hit found by `hit`, spawned off the
/// surface as the renderer spawns rays.
pub(crate) fn ray_set(
    camera: &Camera,
    width: u32,
    height: u32,
    seed: u64,
    hit: impl Fn(&Ray) -> Option<Hit>,
) -> Vec<Ray> {
    let mut state = seed;
    let mut rays = Vec::new();
    for j in 0..height {
        for i in 0..width {
            let (x, y) = (i as Real + uniform(&mut state), j as Real + uniform(&mut state));
            rays.push(camera.center_ray(x, y));
        }
    }
    let camera_rays = rays.len();
    for k in 0..camera_rays {
        if let Some(hit) = hit(&rays[k]) {
            let dir = hit.normal + unit_vector(&mut state);
            if dir.length_squared() > 1e-8 {
                rays.push(hit.spawn(dir.normalize()));
            }
        }
    }
    rays
}

/// What the two searches disagree on: hit against miss, and distances apart by more than a
/// relative 1e-4.
fn disagreements(mesh: &Mesh, embree: &EmbreeTriangles, rays: &[Ray]) -> (usize, usize, usize) {
    let (mut hit_miss, mut distance, mut hits) = (0, 0, 0);
    for ray in rays {
        match (mesh.closest(ray, Real::INFINITY, Isa::BASELINE), embree.closest(ray)) {
            (Some((_, ours)), Some((_, t))) => {
                hits += 1;
                distance += usize::from(distances_apart(ray, to_f32(ours.t), t));
            }
            (None, None) => {}
            _ => hit_miss += 1,
        }
    }
    (hit_miss, distance, hits)
}

/// Whether two searches' distances along `ray` are apart: by more than a relative 1e-4, and
/// more than the f32 rounding of the points involved (16 ulps of their magnitude: a bounce
/// meeting its neighbour 1e-4 away).
pub(crate) fn distances_apart(ray: &Ray, ours: f32, theirs: f32) -> bool {
    let magnitude = to_f32(ray.origin.abs().max_element()) + theirs.abs();
    (ours - theirs).abs() > (1e-4 * ours.abs().max(theirs.abs())).max(16.0 * f32::EPSILON * magnitude)
}

/// One timed pass over `rays`: seconds, and the hits counted (so that nothing is skipped).
pub(crate) fn pass(rays: &[Ray], closest: impl Fn(&Ray) -> Option<f32>) -> (f64, usize) {
    let start = Instant::now();
    let mut hits = 0;
    let mut sum = 0.0f32;
    for ray in rays {
        if let Some(t) = closest(black_box(ray)) {
            hits += 1;
            sum += t;
        }
    }
    black_box(sum);
    (start.elapsed().as_secs_f64(), hits)
}

/// The Embree devices raypool is compared with: its own choice of instruction set (on a CPU
/// with AVX2 or AVX-512, an eight-wide tree), then held to each level raypool runs at (its
/// configuration string `isa=…`), with the name of that level (`None`: its own choice).
pub(crate) const EMBREE_DEVICES: [(&str, &str, &CStr, Option<&str>); 4] = [
    ("Embree triangles + Embree tree, its own CPU dispatch", "Embree", c"", None),
    ("Embree held to SSE2 (`isa=sse2`)", "Embree held to SSE2", c"isa=sse2", Some("sse2")),
    ("Embree held to AVX2 (`isa=avx2`)", "Embree held to AVX2", c"isa=avx2", Some("avx2")),
    ("Embree held to AVX-512 (`isa=avx512`)", "Embree held to AVX-512", c"isa=avx512", Some("avx512")),
];
/// [`EMBREE_DEVICES`] but those held to a level this CPU does not have.
pub(crate) fn embree_devices()
-> Vec<&'static (&'static str, &'static str, &'static CStr, Option<&'static str>)> {
    EMBREE_DEVICES.iter().filter(|(.., level)| level.is_none_or(|name| Isa::named(name).is_ok())).collect()
}

/// Runs the comparison and returns the results' section (Markdown). Panics where raypool and
/// an Embree device disagree beyond the tolerance, or a timed pass counts a different number
/// of hits.
pub fn section(
    quick: bool,
    command: &str,
    machine: &str,
    embree_version: &str,
    cells: Option<u32>,
) -> String {
    let (width, height, rounds) = if quick { (300, 200, 7) } else { (600, 400, 21) };
    let mut file = builtin_scene("mesh", DEFAULT_SCENE_SEED).expect("mesh exists");
    if let Some(cells) = cells {
        if let Some(GeneratedMesh::Terrain { cells: c, .. }) = file.shapes.meshes[0].generate.as_mut() {
            *c = cells;
        }
    }
    let scene = file.to_scene();
    let mesh = scene
        .objects()
        .iter()
        .find_map(|o| match o {
            Object::Mesh(mesh, _) => Some(mesh.clone()),
            _ => None,
        })
        .expect("the mesh scene has a mesh");
    let camera = Camera::new(&scene.camera, width, height);
    let rays = ray_set(&camera, width, height, 1, |ray| mesh.hit(ray, Real::INFINITY, 0, Isa::BASELINE));
    let camera_rays = (width * height) as usize;
    // The levels this CPU has: raypool at each, and Embree held to each.
    let levels = Isa::available();
    let devices = embree_devices();
    let embrees: Vec<EmbreeTriangles> = devices
        .iter()
        .map(|(_, _, config, _)| {
            EmbreeTriangles::new(mesh.positions(), mesh.triangles(), config).unwrap_or_else(|e| panic!("{e}"))
        })
        .collect();

    let allowed = (1e-4 * rays.len() as f64).floor() as usize;
    let checks: Vec<(usize, usize)> = embrees
        .iter()
        .zip(&devices)
        .map(|(embree, (_, name, ..))| {
            let (hit_miss, distance, _) = disagreements(&mesh, embree, &rays);
            assert!(
                hit_miss + distance <= allowed,
                "{name} and raypool's mesh disagree on {hit_miss} hits or misses and {distance} \
                 distances of {} rays (at most {allowed} allowed)",
                rays.len()
            );
            (hit_miss, distance)
        })
        .collect();

    // raypool at each level (sse2 first), then each Embree device; each round starts one
    // further on.
    let ours = levels.len();
    let searches = ours + embrees.len();
    let search = |k: usize| -> (f64, usize) {
        if k < ours {
            pass(&rays, |ray| mesh.closest(ray, Real::INFINITY, levels[k]).map(|(_, h)| to_f32(h.t)))
        } else {
            pass(&rays, |ray| embrees[k - ours].closest(ray).map(|(_, t)| t))
        }
    };
    let name =
        |k: usize| if k < ours { format!("raypool at {:?}", levels[k]) } else { devices[k - ours].1.into() };
    let (mut seconds, mut counted) = (vec![Vec::new(); searches], vec![Vec::new(); searches]);
    for round in 0..rounds {
        for step in 0..searches {
            let k = (round + step) % searches;
            let (s, h) = search(k);
            eprintln!("triangles round {}/{rounds}: {}: {s:.3} s", round + 1, name(k));
            seconds[k].push(s);
            counted[k].push(h);
        }
    }
    assert!(
        counted.iter().all(|c| c.iter().all(|&h| h == c[0])),
        "a timed pass found a different number of hits"
    );
    let rows: Vec<String> = (0..searches)
        .map(|k| {
            // raypool's rays/s over this search's, round by round: its time over raypool's.
            let ratios: Vec<f64> = seconds[k].iter().zip(&seconds[0]).map(|(t, r)| t / r).collect();
            let (lo, hi) = ratios.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &r| (lo.min(r), hi.max(r)));
            let runs = seconds[k].iter().map(|s| format!("{:.1}", s * 1e3)).collect::<Vec<_>>().join(", ");
            let median = median_of(&seconds[k]);
            let (ratio, range) = if k == 0 {
                ("1.00".to_owned(), String::new())
            } else {
                (format!("{:.2}", median_of(&ratios)), format!("{lo:.2}–{hi:.2}"))
            };
            let label = if k < ours {
                format!("raypool at {:?} (8-wide tree, watertight test)", levels[k])
            } else {
                devices[k - ours].0.to_owned()
            };
            format!(
                "| {label} | {runs} | {:.1} | {:.2} | **{ratio}** | {range} | {} |\n",
                median * 1e3,
                rays.len() as f64 / median / 1e6,
                counted[k][0]
            )
        })
        .collect();
    // Each level beside Embree held to it, and beside Embree's own choice: Embree's time over
    // raypool's, round by round (above 1: raypool finds more rays a second).
    let paired = |ours: usize, theirs: usize| -> String {
        let ratios: Vec<f64> = seconds[theirs].iter().zip(&seconds[ours]).map(|(t, r)| t / r).collect();
        format!("{:.2}", median_of(&ratios))
    };
    let level_rows: Vec<String> = levels
        .iter()
        .enumerate()
        .map(|(k, isa)| {
            let held = devices.iter().position(|(.., level)| *level == Some(isa.name()));
            let held = held.map_or("–".to_owned(), |d| paired(k, ours + d));
            format!(
                "| {isa:?} | {:.1} | **{held}** | **{}** |\n",
                median_of(&seconds[k]) * 1e3,
                paired(k, ours)
            )
        })
        .collect();
    let checked: Vec<String> = checks
        .iter()
        .zip(&devices)
        .map(|((hit_miss, distance), (_, name, ..))| {
            format!("against {name}, {hit_miss} rays hit in one and not the other and {distance} at distances apart")
        })
        .collect();
    format!(
        "## Triangles: {title}\n\n\
         raypool's mesh search ([`Mesh::closest`]: its own eight-wide tree, leaves of up to 8 whose\n\
         watertight test runs in eight SIMD lanes) against Embree's triangle geometry (`RTC_GEOMETRY_TYPE_TRIANGLE`, build\n\
         quality high, default scene flags, `rtcIntersect1` with an incoherent context), over\n\
         the same positions and indices: {tris} triangles. The search only, mesh only (the\n\
         scene's two spheres are not searched). A fixed ray set, recorded once: a jittered camera\n\
         ray per pixel of {width} × {height} ({camera_rays}), plus one diffuse bounce spawned from\n\
         each that hits the mesh ({bounces}): {n} rays. One thread; {rounds} rounds, each timing\n\
         the whole set through every search, in an order that turns one step a round.\n\n\
         raypool at each vector level this CPU has (`RAYPOOL_ISA`: the same code compiled again\n\
         with AVX2 or AVX-512 enabled, chosen at run time; the same hits at every level), and\n\
         Embree as it runs by default (it picks its code for the CPU at run time) and held to\n\
         each of those levels by its configuration string (`isa=…`).\n\n\
         Machine: {machine}; Embree {embree_version}.\n\
         Command: `{command}`.\n\n\
         | raypool's level | raypool's median (ms) | × Embree held to that level (rays/s, median of paired ratios) | × Embree's own choice |\n\
         |---|---:|---:|---:|\n\
         {level_rows}\n\
         Every search, against raypool at sse2 (the build's own instructions):\n\n\
         | search | runs (ms) | median (ms) | Mrays/s | raypool sse2's rays/s ÷ this search's (median of paired ratios) | range of paired ratios | hits |\n\
         |---|---|---:|---:|---:|---:|---:|\n\
         {rows}\n\
         Before timing, every ray went through raypool and each Embree device, the hits compared\n\
         (distances apart: by more than a relative 1e-4 and more than 16 f32 ulps of the ray\n\
         origin's magnitude): {checked}. The bench fails above {allowed}, a 1e-4 fraction of the\n\
         rays.\n",
        title = match cells {
            None => "the `mesh` scene's mesh".to_owned(),
            Some(cells) => format!(
                "the `mesh` scene's terrain at {cells} × {cells} cells, to see a tree past the caches"
            ),
        },
        tris = mesh.triangle_count(),
        bounces = rays.len() - camera_rays,
        n = rays.len(),
        rows = rows.concat(),
        level_rows = level_rows.concat(),
        checked = checked.join("; "),
    )
}
