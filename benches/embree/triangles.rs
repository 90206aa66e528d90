//! Triangles against Embree 3 (`cargo bench --bench embree --features embree`, its second
//! table): the `mesh` scene's 131,072-triangle mesh searched by raypool's own four-wide tree
//! and watertight test ([`Mesh::closest`]) and by Embree's triangle tree
//! (`RTC_GEOMETRY_TYPE_TRIANGLE`, built from the same positions and indices, build quality
//! high, Embree's default scene flags).
//!
//! A second-book scene does not render through a swappable closest-hit function, so this
//! compares the hit search itself, over a fixed ray set recorded once: a camera ray through a
//! jittered point of every pixel of the `mesh` scene, and for each that hits the mesh one
//! diffuse bounce spawned from the hit as the renderer spawns it. Only the mesh is searched
//! (not the scene's two spheres). One thread; each round times the whole set through both,
//! in an order that alternates round by round, and the table gives the median over rounds
//! of the paired ratio of rays per second. Before any timing, both must find the same hit or
//! miss for every ray and the same distance to a relative 1e-4 (or to 16 f32 ulps of the
//! ray's origin's magnitude, for the short bounces that meet a neighbour), but for at most a 1e-4
//! fraction of the rays (a ray on a shared edge may meet either triangle, or, in Embree's
//! non-watertight test, neither), or the bench fails.
//!
//! Unsafe code as in `library.rs`: the device and scene are created in
//! [`EmbreeTriangles::new`], checked, used through `&self` and released once in `Drop`;
//! the buffers are Embree's own (`rtcSetNewGeometryBuffer`), filled before the commit.

use std::hint::black_box;
use std::ptr;
use std::time::Instant;

use embree::sys::{
    RTCBufferType, RTCBuildQuality, RTCDevice, RTCError, RTCFormat, RTCGeometryType, RTCRayHit, RTCScene,
    rtcAttachGeometry, rtcCommitGeometry, rtcCommitScene, rtcGetDeviceError, rtcIntersect1, rtcNewDevice,
    rtcNewGeometry, rtcNewScene, rtcReleaseDevice, rtcReleaseGeometry, rtcReleaseScene,
    rtcSetNewGeometryBuffer, rtcSetSceneBuildQuality,
};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::camera::Camera;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3, to_f32};
use raypool::tracer::world::mesh::Mesh;
use raypool::tracer::world::object::Object;

use crate::library::{INVALID_ID, embree_ray, incoherent_context, no_hit};
use crate::median_of;

/// Embree's triangle tree over one mesh.
pub struct EmbreeTriangles {
    device: RTCDevice,
    scene: RTCScene,
}

impl EmbreeTriangles {
    /// Embree's tree over `triangles` (indices into `positions`), build quality high.
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<EmbreeTriangles, String> {
        // SAFETY: a null configuration string is Embree's default device.
        let device = unsafe { rtcNewDevice(ptr::null()) };
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
        let built = EmbreeTriangles { device, scene };
        // SAFETY: a live device.
        match unsafe { rtcGetDeviceError(device) } {
            RTCError::NONE => Ok(built),
            error => Err(format!("Embree could not build the mesh: {error:?}")),
        }
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

/// The fixed ray set: a jittered camera ray per pixel of a `width × height` image of the
/// scene, then a diffuse bounce (normal + unit vector, as a Lambertian surface scatters) from
/// each camera ray's hit on `mesh`, spawned off the surface as the renderer spawns rays.
fn ray_set(camera: &Camera, mesh: &Mesh, width: u32, height: u32) -> Vec<Ray> {
    let mut state = 1u64;
    let mut rays = Vec::new();
    for j in 0..height {
        for i in 0..width {
            let (x, y) = (i as Real + uniform(&mut state), j as Real + uniform(&mut state));
            rays.push(camera.center_ray(x, y));
        }
    }
    let camera_rays = rays.len();
    for k in 0..camera_rays {
        if let Some(hit) = mesh.hit(&rays[k], Real::INFINITY, 0) {
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
        match (mesh.closest(ray, Real::INFINITY), embree.closest(ray)) {
            (Some((_, ours)), Some((_, t))) => {
                hits += 1;
                let ours = to_f32(ours.t);
                // A relative 1e-4, but never below the f32 rounding of the points involved
                // (16 ulps of their magnitude): a bounce meeting its neighbour 1e-4 away.
                let magnitude = to_f32(ray.origin.abs().max_element()) + t.abs();
                let tolerance = (1e-4 * ours.abs().max(t.abs())).max(16.0 * f32::EPSILON * magnitude);
                if (ours - t).abs() > tolerance {
                    distance += 1;
                }
            }
            (None, None) => {}
            _ => hit_miss += 1,
        }
    }
    (hit_miss, distance, hits)
}

/// One timed pass over `rays`: seconds, and the hits counted (so that nothing is skipped).
fn pass(rays: &[Ray], closest: impl Fn(&Ray) -> Option<f32>) -> (f64, usize) {
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

/// Runs the comparison and returns the results' section (Markdown). Panics where the two
/// disagree beyond the tolerance, or a timed pass counts a different number of hits.
pub fn section(quick: bool, command: &str, machine: &str, embree_version: &str) -> String {
    let (width, height, rounds) = if quick { (300, 200, 7) } else { (600, 400, 21) };
    let scene = builtin_scene("mesh", DEFAULT_SCENE_SEED).expect("mesh exists").to_scene();
    let mesh = scene
        .objects()
        .iter()
        .find_map(|o| match o {
            Object::Mesh(mesh, _) => Some(mesh.clone()),
            _ => None,
        })
        .expect("the mesh scene has a mesh");
    let camera = Camera::new(&scene.camera, width, height);
    let rays = ray_set(&camera, &mesh, width, height);
    let camera_rays = (width * height) as usize;
    let embree = EmbreeTriangles::new(mesh.positions(), mesh.triangles()).unwrap_or_else(|e| panic!("{e}"));

    let (hit_miss, distance, hits) = disagreements(&mesh, &embree, &rays);
    let allowed = (1e-4 * rays.len() as f64).floor() as usize;
    assert!(
        hit_miss + distance <= allowed,
        "Embree's triangles and raypool's mesh disagree on {hit_miss} hits or misses and {distance} \
         distances of {} rays (at most {allowed} allowed)",
        rays.len()
    );

    let ours = |ray: &Ray| mesh.closest(ray, Real::INFINITY).map(|(_, h)| to_f32(h.t));
    let theirs = |ray: &Ray| embree.closest(ray).map(|(_, t)| t);
    let (mut seconds, mut counted) = ([Vec::new(), Vec::new()], [Vec::new(), Vec::new()]);
    for round in 0..rounds {
        for step in 0..2 {
            let k = (round + step) % 2;
            let (s, h) = if k == 0 { pass(&rays, ours) } else { pass(&rays, theirs) };
            eprintln!("triangles round {}/{rounds}: {}: {s:.3} s", round + 1, ["raypool", "Embree"][k]);
            seconds[k].push(s);
            counted[k].push(h);
        }
    }
    let (our_hits, their_hits) = (counted[0][0], counted[1][0]);
    assert!(
        counted[0].iter().all(|&h| h == our_hits) && counted[1].iter().all(|&h| h == their_hits),
        "a timed pass found a different number of hits"
    );
    let ratios: Vec<f64> = seconds[1].iter().zip(&seconds[0]).map(|(e, r)| e / r).collect();
    let (lo, hi) = ratios.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    let mrays = |k: usize| rays.len() as f64 / median_of(&seconds[k]) / 1e6;
    let runs = |k: usize| seconds[k].iter().map(|s| format!("{:.1}", s * 1e3)).collect::<Vec<_>>().join(", ");
    format!(
        "## Triangles: the `mesh` scene's mesh\n\n\
         raypool's mesh search ([`Mesh::closest`]: its own four-wide tree, leaves of 4 whose\n\
         watertight test runs in four SIMD lanes) against Embree's triangle geometry (`RTC_GEOMETRY_TYPE_TRIANGLE`, build\n\
         quality high, default scene flags, `rtcIntersect1` with an incoherent context), over\n\
         the same positions and indices: {tris} triangles. The search only, mesh only (the\n\
         scene's two spheres are not searched). A fixed ray set, recorded once: a jittered camera\n\
         ray per pixel of {width} × {height} ({camera_rays}), plus one diffuse bounce spawned from\n\
         each that hits the mesh ({bounces}): {n} rays, {hits} of them hit. One thread; {rounds}\n\
         rounds, each timing the whole set through both, the order alternating.\n\n\
         Machine: {machine}; Embree {embree_version}.\n\
         Command: `{command}`.\n\n\
         | search | runs (ms) | median (ms) | Mrays/s | × Embree's rays/s (median of paired ratios) | range of paired ratios | hits |\n\
         |---|---|---:|---:|---:|---:|---:|\n\
         | raypool (4-wide tree, watertight test) | {r0} | {m0:.1} | {v0:.2} | **{ratio:.2}** | {lo:.2}–{hi:.2} | {our_hits} |\n\
         | Embree triangles + Embree tree | {r1} | {m1:.1} | {v1:.2} | **1.00** | | {their_hits} |\n\n\
         Before timing, every ray went through both: {hit_miss} found a hit where the other found\n\
         none and {distance} hit at distances more than a relative 1e-4 (and more than 16 f32\n\
         ulps of the ray origin's magnitude) apart (the bench fails\n\
         above {allowed}, a 1e-4 fraction of the rays).\n",
        tris = mesh.triangle_count(),
        bounces = rays.len() - camera_rays,
        n = rays.len(),
        r0 = runs(0),
        r1 = runs(1),
        m0 = median_of(&seconds[0]) * 1e3,
        m1 = median_of(&seconds[1]) * 1e3,
        v0 = mrays(0),
        v1 = mrays(1),
        ratio = median_of(&ratios),
    )
}
