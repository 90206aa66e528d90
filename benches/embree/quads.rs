//! Quads and instances against Embree 3 (`cargo bench --bench embree --features embree`, its
//! quad tables): the second book's quads as raypool searches them (a group's runs of up to
//! eight quads, each run one eight-lane packet test, under an eight-wide tree; an instance
//! moves the ray into its group's frame) and as Embree does, with its quad geometry
//! (`RTC_GEOMETRY_TYPE_QUAD`, each quad two triangles of one leaf test) and its instances
//! (`RTC_GEOMETRY_TYPE_INSTANCE` over a scene of the group's quads): the limit a production
//! kernel sets for the second book's boxes and rooms.
//!
//! Two worlds, each the quads of a built-in scene and nothing else: `next-week`'s ground (400
//! boxes of six quads) and lamp, and `cornell`'s room, its lamp and its tall box turned 15°
//! (an instance). A fixed ray set as for the triangles (`triangles.rs`): a jittered camera ray
//! per pixel, and a diffuse bounce from each one's hit. raypool at each vector level, Embree
//! by its own choice and held to each level; one thread; the median over rounds of each
//! search's time paired with raypool's at its widest level. Before timing, every Embree device
//! must find the same hit or miss as raypool and the same distance to a relative 1e-4 for all
//! but a 1e-4 fraction of the rays (a ray through a shared edge may meet either quad, or, in
//! Embree's test, which is not watertight, neither), or the bench fails.
//!
//! Unsafe code as in `triangles.rs`: the device and scenes are made in [`EmbreeQuads::new`],
//! checked, used through `&self` and released once in `Drop`.

use std::ffi::{CStr, c_void};

use embree::sys::{
    RTCBufferType, RTCBuildQuality, RTCDevice, RTCFormat, RTCGeometryType, RTCRayHit, RTCScene,
    rtcAttachGeometry, rtcCommitGeometry, rtcCommitScene, rtcIntersect1, rtcNewDevice, rtcNewGeometry,
    rtcNewScene, rtcReleaseDevice, rtcReleaseGeometry, rtcReleaseScene, rtcSetGeometryInstancedScene,
    rtcSetGeometryTransform, rtcSetNewGeometryBuffer, rtcSetSceneBuildQuality,
};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::camera::Camera;
use raypool::tracer::geometry::Shape;
use raypool::tracer::geometry::quad::Quad;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3, to_f32};
use raypool::tracer::math::transform::Transform;
use raypool::tracer::scene::Scene;
use raypool::tracer::world::object::{Group, Object};
use raypool::tracer::world::probe::Probe;

use crate::library::{INVALID_ID, built, embree_ray, incoherent_context, no_hit};
use crate::median_of;
use crate::triangles::{distances_apart, embree_devices, pass, ray_set};

/// Quads placed together by a rigid transform: an instance, as Embree is given it.
pub struct PlacedQuads {
    transform: Transform,
    quads: Vec<Quad>,
}

/// A scene's quads and instances of quads, as raypool searches them (`group`) and as
/// Embree's scene is built from them.
struct QuadWorld {
    group: Group,
    quads: Vec<Quad>,
    instances: Vec<PlacedQuads>,
}

/// Embree's scene over some quads and instances of groups of quads.
pub struct EmbreeQuads {
    device: RTCDevice,
    scene: RTCScene,
}

/// A scene of `quads` on `device`, committed (build quality high); `instances` attached as
/// Embree instances of scenes of their quads.
///
/// # Safety
/// `device` must be live. The scene is the caller's to release.
unsafe fn quad_scene(device: RTCDevice, quads: &[Quad], instances: &[PlacedQuads]) -> RTCScene {
    // SAFETY: the buffers Embree allocates hold 4 vertices and one index quadruple a quad,
    // exactly what is written; each geometry and child scene is released once attached
    // (Embree keeps its own reference).
    unsafe {
        let scene = rtcNewScene(device);
        rtcSetSceneBuildQuality(scene, RTCBuildQuality::HIGH);
        if !quads.is_empty() {
            let geometry = rtcNewGeometry(device, RTCGeometryType::QUAD);
            let n = quads.len();
            let vertices =
                rtcSetNewGeometryBuffer(geometry, RTCBufferType::VERTEX, 0, RTCFormat::FLOAT3, 12, 4 * n)
                    .cast::<[f32; 3]>();
            let indices = rtcSetNewGeometryBuffer(geometry, RTCBufferType::INDEX, 0, RTCFormat::UINT4, 16, n)
                .cast::<[u32; 4]>();
            assert!(
                !vertices.is_null() && !indices.is_null(),
                "Embree could not allocate the quads' buffers"
            );
            for (k, quad) in quads.iter().enumerate() {
                // Embree's quad (v0, v1, v2, v3) is the triangles (v0, v1, v3) and (v2, v3, v1).
                let corners = [quad.q, quad.q + quad.u, quad.q + quad.u + quad.v, quad.q + quad.v];
                for (c, p) in corners.iter().enumerate() {
                    *vertices.add(4 * k + c) = [to_f32(p.x), to_f32(p.y), to_f32(p.z)];
                }
                let first = 4 * k as u32;
                *indices.add(k) = [first, first + 1, first + 2, first + 3];
            }
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
        }
        for PlacedQuads { transform, quads } in instances {
            let child = quad_scene(device, quads, &[]);
            let geometry = rtcNewGeometry(device, RTCGeometryType::INSTANCE);
            rtcSetGeometryInstancedScene(geometry, child);
            let matrix = column_major(transform);
            rtcSetGeometryTransform(
                geometry,
                0,
                RTCFormat::FLOAT3X4_COLUMN_MAJOR,
                matrix.as_ptr().cast::<c_void>(),
            );
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
            rtcReleaseScene(child);
        }
        rtcCommitScene(scene);
        scene
    }
}

/// `transform` as Embree's 3 × 4 column-major matrix: the images of x, y, z, then the offset.
fn column_major(transform: &Transform) -> [f32; 12] {
    let columns = [transform.vector(Vec3::X), transform.vector(Vec3::Y), transform.vector(Vec3::Z)];
    let offset = transform.point(Vec3::ZERO);
    let mut m = [0.0; 12];
    for (c, v) in columns.iter().chain([&offset]).enumerate() {
        m[3 * c..3 * c + 3].copy_from_slice(&[to_f32(v.x), to_f32(v.y), to_f32(v.z)]);
    }
    m
}

impl EmbreeQuads {
    /// Embree's scene over `quads` and `instances`, on a device made with `config`.
    pub fn new(quads: &[Quad], instances: &[PlacedQuads], config: &CStr) -> Result<EmbreeQuads, String> {
        // SAFETY: a NUL-terminated configuration string that outlives the call.
        let device = unsafe { rtcNewDevice(config.as_ptr()) };
        if device.is_null() {
            return Err("rtcNewDevice failed (is libembree3 installed?)".into());
        }
        // SAFETY: a live device; the scene is released in `Drop`.
        let scene = unsafe { quad_scene(device, quads, instances) };
        built(device, EmbreeQuads { device, scene }, "the quads")
    }

    /// The nearest hit's distance along `ray`.
    #[inline]
    pub fn closest(&self, ray: &Ray) -> Option<f32> {
        let mut rayhit = RTCRayHit { ray: embree_ray(ray), hit: no_hit() };
        let mut context = incoherent_context();
        // SAFETY: a committed scene; `context` and `rayhit` are live locals of Embree's layout.
        unsafe { rtcIntersect1(self.scene, &mut context, &mut rayhit) };
        (rayhit.hit.geomID != INVALID_ID).then_some(rayhit.ray.tfar)
    }
}

impl Drop for EmbreeQuads {
    fn drop(&mut self) {
        // SAFETY: both handles are live and released exactly once, the scene first.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

/// A scene's quads and its instances of groups of quads (the rest left out), as raypool's
/// group and as the lists Embree's scene is built from.
fn quads_of(scene: &Scene) -> QuadWorld {
    let only_quads = |objects: &[Object]| -> Option<Vec<Quad>> {
        objects.iter().map(|o| if let Object::Shape(Shape::Quad(q)) = o { Some(*q) } else { None }).collect()
    };
    let (mut objects, mut quads, mut instances) = (Vec::new(), Vec::new(), Vec::new());
    for object in scene.objects() {
        match object {
            Object::Shape(Shape::Quad(quad)) => {
                quads.push(*quad);
                objects.push(object.clone());
            }
            Object::Instance(instance) => {
                if let Some(quads) = only_quads(instance.group.objects()) {
                    instances.push(PlacedQuads { transform: instance.transform, quads });
                    objects.push(object.clone());
                }
            }
            _ => {}
        }
    }
    QuadWorld { group: Group::new(objects), quads, instances }
}

/// Rays on which raypool and `embree` disagree: hit against miss, or distances apart by more
/// than a relative 1e-4 (and 16 f32 ulps of the points' magnitude).
fn disagreements(world: &Group, embree: &EmbreeQuads, rays: &[Ray]) -> usize {
    let probe = Probe::default();
    let apart = |ray: &Ray| match (world.hit(ray, Real::INFINITY, &probe), embree.closest(ray)) {
        (Some(hit), Some(t)) => distances_apart(ray, to_f32(hit.t), t),
        (None, None) => false,
        _ => true,
    };
    rays.iter().filter(|ray| apart(ray)).count()
}

/// Runs the comparison on `scene`'s quads and returns its section (Markdown). Panics where
/// raypool and an Embree device disagree beyond the tolerance, or a timed pass counts a
/// different number of hits.
pub fn section(quick: bool, scene: &str, command: &str, machine: &str, embree_version: &str) -> String {
    let (size, rounds) = if quick { (200, 7) } else { (400, 21) };
    let file = builtin_scene(scene, DEFAULT_SCENE_SEED).expect("a built-in scene").to_scene();
    let QuadWorld { group: world, quads, instances } = quads_of(&file);
    let probe = Probe::default();
    let camera = Camera::new(&file.camera, size, size);
    let rays = ray_set(&camera, size, size, 2, |ray| world.hit(ray, Real::INFINITY, &probe));
    let levels = Isa::available();
    let devices = embree_devices();
    let embrees: Vec<EmbreeQuads> = devices
        .iter()
        .map(|(.., config, _)| EmbreeQuads::new(&quads, &instances, config).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    let allowed = (1e-4 * rays.len() as f64).floor() as usize;
    let disagreeing: Vec<usize> = embrees.iter().map(|embree| disagreements(&world, embree, &rays)).collect();
    for (count, (_, name, ..)) in disagreeing.iter().zip(&devices) {
        assert!(
            *count <= allowed,
            "{name} and raypool disagree on {count} of {} rays on {scene}'s quads",
            rays.len()
        );
    }
    // raypool at each level, widest first (the reference), then each Embree device.
    let widest = levels.len() - 1;
    let order: Vec<usize> =
        (0..levels.len()).rev().chain(levels.len()..levels.len() + embrees.len()).collect();
    let search = |k: usize| -> (f64, usize) {
        if k < levels.len() {
            let probe = Probe { isa: levels[k], ..Probe::default() };
            pass(&rays, |ray| world.hit(ray, Real::INFINITY, &probe).map(|hit| to_f32(hit.t)))
        } else {
            pass(&rays, |ray| embrees[k - levels.len()].closest(ray))
        }
    };
    let (mut seconds, mut counted) = (vec![Vec::new(); order.len()], vec![Vec::new(); order.len()]);
    for round in 0..rounds {
        for step in 0..order.len() {
            let k = order[(round + step) % order.len()];
            let (s, hits) = search(k);
            seconds[k].push(s);
            counted[k].push(hits);
        }
    }
    assert!(
        counted.iter().all(|c| c.iter().all(|&h| h == c[0])),
        "a timed pass found a different number of hits"
    );
    // This search's time over raypool's at its widest level, round by round (above 1:
    // raypool is faster).
    let paired = |k: usize| -> f64 {
        let ratios: Vec<f64> = seconds[k].iter().zip(&seconds[widest]).map(|(t, r)| t / r).collect();
        median_of(&ratios)
    };
    let boxed = if instances.is_empty() { "" } else { "; the box an instance" };
    let rows: String = order
        .iter()
        .map(|&k| {
            let label = if k < levels.len() {
                format!("raypool at {:?} (runs of 8-lane quad packets{boxed})", levels[k])
            } else {
                devices[k - levels.len()].0.replace("triangles", "quads")
            };
            format!(
                "| {label} | {:.1} | {:.2} | **{:.2}** | {} |\n",
                median_of(&seconds[k]) * 1e3,
                rays.len() as f64 / median_of(&seconds[k]) / 1e6,
                paired(k),
                counted[k][0]
            )
        })
        .collect();
    format!(
        "## Quads: `{scene}`'s {what}\n\n\
         The second book's quads, searched as raypool searches them (a group's runs of up to eight\n\
         quads, one eight-lane packet test a run, under an eight-wide tree; an instance moves the\n\
         ray into its box's frame) and by Embree 3's quad geometry (`RTC_GEOMETRY_TYPE_QUAD`, build\n\
         quality high, `rtcIntersect1`) with its instances (`RTC_GEOMETRY_TYPE_INSTANCE`): the\n\
         scene's other objects are left out. A fixed ray set: a jittered camera ray per pixel of\n\
         {size} × {size} and a diffuse bounce from each one's hit, {rays} rays; one thread; {rounds}\n\
         rounds, each timing the whole set through every search in an order that turns a step a\n\
         round. The ratio is each search's time over raypool's at its widest level in the same\n\
         round (the median over rounds; above 1: raypool finds more rays a second). Before\n\
         timing, each Embree device was checked against raypool, ray by ray (hit or miss, and\n\
         distance to a relative 1e-4): rays apart, device by device, {disagreeing:?}; the bench\n\
         fails above {allowed}.\n\n\
         Machine: {machine}; Embree {embree_version}. Command: `{command}`.\n\n\
         | search | median (ms) | Mrays/s | its time ÷ raypool's at {widest_name:?} (median of paired ratios) | hits |\n\
         |---|---:|---:|---:|---:|\n\
         {rows}",
        what = match instances.len() {
            0 => format!("{} quads", quads.len()),
            1 => format!("{} quads and its box, an instance of six more", quads.len()),
            i => format!("{} quads and {i} instances of boxes", quads.len()),
        },
        rays = rays.len(),
        widest_name = levels[widest],
    )
}
