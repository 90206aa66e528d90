//! A scene's spheres inside Intel Embree 3, the hit library production CPU renderers use, so
//! that raypool's own path tracer can find its hits there instead (`cargo bench --bench
//! embree --features embree`, and `tests/embree.rs`).
//!
//! Two ways, each an [`EmbreeSpheres`]:
//! - [`Variant::EmbreeSpheres`]: Embree's own sphere primitive (`RTC_GEOMETRY_TYPE_SPHERE_POINT`)
//!   in its own tree: everything is Embree's up to the hit distance.
//! - [`Variant::EmbreeTree`]: Embree's tree over "user" primitives whose test is raypool's
//!   [`Sphere::intersect`], called back by Embree: the two trees compared with one sphere test.
//!
//! Either way Embree only answers "which sphere, how far"; the hit record is raypool's
//! ([`Sphere::hit_at`]), so the paths are the same rays as far as the hit distances agree.
//!
//! **The project's only `unsafe` code** (the library itself forbids it): calls into Embree's C
//! API through the `embree` crate's declarations (`embree::sys`). What keeps them sound, said
//! once here and again at each block:
//! - the device and scene handles are created in [`EmbreeSpheres::new`], checked non-null,
//!   used only through `&self`, and released once, in `Drop`;
//! - Embree's intersect callback reads the spheres through a pointer to the slice that
//!   `EmbreeSpheres<'a>` borrows for `'a`, so the spheres outlive every call that can reach it;
//! - the ray-hit record passed to `rtcIntersect1` is a local, 16-byte aligned by its type.

use std::ffi::c_void;
use std::marker::PhantomData;
use std::ptr;

use embree::sys::{
    RTCBounds, RTCBoundsFunctionArguments, RTCBufferType, RTCBuildQuality, RTCDevice, RTCError, RTCFormat,
    RTCGeometryType, RTCHit, RTCIntersectContext, RTCIntersectContextFlags, RTCIntersectFunctionNArguments,
    RTCRay, RTCRayHit, RTCScene, rtcAttachGeometry, rtcCommitGeometry, rtcCommitScene, rtcGetDeviceError,
    rtcIntersect1, rtcNewDevice, rtcNewGeometry, rtcNewScene, rtcReleaseDevice, rtcReleaseGeometry,
    rtcReleaseScene, rtcSetGeometryBoundsFunction, rtcSetGeometryIntersectFunction, rtcSetGeometryUserData,
    rtcSetGeometryUserPrimitiveCount, rtcSetNewGeometryBuffer, rtcSetSceneBuildQuality,
};
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::geometry::sphere::Sphere;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3, to_f32};

/// `RTC_INVALID_GEOMETRY_ID`: "no hit" in a hit record.
pub const INVALID_ID: u32 = u32::MAX;

/// Which of Embree's parts find the hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Embree's sphere primitive in Embree's tree.
    EmbreeSpheres,
    /// Embree's tree, raypool's sphere test (a user geometry).
    EmbreeTree,
}

impl Variant {
    /// Both, in the order the benchmark's table lists them.
    pub const ALL: [Variant; 2] = [Variant::EmbreeSpheres, Variant::EmbreeTree];

    /// The table's name for it.
    pub fn name(self) -> &'static str {
        match self {
            Variant::EmbreeSpheres => "Embree spheres + Embree tree",
            Variant::EmbreeTree => "raypool sphere test + Embree tree",
        }
    }
}

/// A committed Embree scene of `spheres` (primitive `i` is `spheres[i]`).
pub struct EmbreeSpheres<'a> {
    device: RTCDevice,
    scene: RTCScene,
    spheres: &'a [Sphere],
    /// The scene's callbacks read `spheres` through a raw pointer: tie it to `'a`.
    _borrow: PhantomData<&'a [Sphere]>,
}

impl<'a> EmbreeSpheres<'a> {
    /// Builds Embree's tree (build quality high) over `spheres`; fails with Embree's error
    /// (e.g. an unsupported CPU).
    pub fn new(spheres: &'a [Sphere], variant: Variant) -> Result<EmbreeSpheres<'a>, String> {
        // SAFETY: a null configuration string is Embree's default device.
        let device = unsafe { rtcNewDevice(ptr::null()) };
        if device.is_null() {
            return Err("rtcNewDevice failed (is libembree3 installed, and does this CPU have SSE2?)".into());
        }
        // SAFETY: `device` is a live device; every handle made here is released in `Drop`
        // (the scene) or once attached (the geometry, which the scene then keeps).
        let scene = unsafe {
            let scene = rtcNewScene(device);
            rtcSetSceneBuildQuality(scene, RTCBuildQuality::HIGH);
            let geometry = match variant {
                Variant::EmbreeSpheres => sphere_points(device, spheres),
                Variant::EmbreeTree => user_spheres(device, spheres),
            };
            rtcCommitGeometry(geometry);
            rtcAttachGeometry(scene, geometry);
            rtcReleaseGeometry(geometry);
            rtcCommitScene(scene);
            scene
        };
        built(device, EmbreeSpheres { device, scene, spheres, _borrow: PhantomData }, "the scene")
    }

    /// The closest hit along `ray`, found by Embree, recorded by raypool.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut rayhit = RTCRayHit { ray: embree_ray(ray), hit: no_hit() };
        let mut context = incoherent_context();
        // SAFETY: a committed scene; `context` and `rayhit` are live locals of Embree's layout.
        unsafe { rtcIntersect1(self.scene, &mut context, &mut rayhit) };
        let index = rayhit.hit.primID;
        (index != INVALID_ID).then(|| self.spheres[index as usize].hit_at(ray, rayhit.ray.tfar as Real))
    }
}

impl Drop for EmbreeSpheres<'_> {
    fn drop(&mut self) {
        // SAFETY: both handles are live and released exactly once, the scene first.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

/// Embree's sphere primitive: a buffer of (x, y, z, radius) (radius unsigned: a hollow
/// shell's sign matters only to its normal, which raypool's hit record gives).
///
/// # Safety
/// `device` must be live; the caller commits and releases the geometry.
unsafe fn sphere_points(device: RTCDevice, spheres: &[Sphere]) -> embree::sys::RTCGeometry {
    // SAFETY: Embree allocates `spheres.len()` items of 16 bytes and returns them, 16-byte
    // aligned, for us to fill before the geometry is committed.
    unsafe {
        let geometry = rtcNewGeometry(device, RTCGeometryType::SPHERE_POINT);
        let buffer =
            rtcSetNewGeometryBuffer(geometry, RTCBufferType::VERTEX, 0, RTCFormat::FLOAT4, 16, spheres.len());
        let points = std::slice::from_raw_parts_mut(buffer.cast::<[f32; 4]>(), spheres.len());
        for (point, s) in points.iter_mut().zip(spheres) {
            *point = [to_f32(s.center.x), to_f32(s.center.y), to_f32(s.center.z), to_f32(s.radius.abs())];
        }
        geometry
    }
}

/// A user geometry of `spheres.len()` primitives whose bounds and test are raypool's.
///
/// # Safety
/// `device` must be live, and `spheres` must outlive the geometry (the callbacks read it).
unsafe fn user_spheres(device: RTCDevice, spheres: &[Sphere]) -> embree::sys::RTCGeometry {
    // SAFETY: the user pointer is the slice's first sphere; `spheres.len()` primitives, so
    // Embree only asks for indices the slice holds.
    unsafe {
        let geometry = rtcNewGeometry(device, RTCGeometryType::USER);
        rtcSetGeometryUserPrimitiveCount(geometry, spheres.len() as u32);
        rtcSetGeometryUserData(geometry, spheres.as_ptr() as *mut c_void);
        rtcSetGeometryBoundsFunction(geometry, Some(sphere_bounds), ptr::null_mut());
        rtcSetGeometryIntersectFunction(geometry, Some(sphere_intersect));
        geometry
    }
}

/// Embree asks for primitive `primID`'s box while building.
unsafe extern "C" fn sphere_bounds(args: *const RTCBoundsFunctionArguments) {
    // SAFETY: Embree passes valid arguments; `geometryUserPtr` is the spheres' slice (see
    // `user_spheres`) and `primID` below its length.
    unsafe {
        let args = &*args;
        let sphere = &*args.geometryUserPtr.cast::<Sphere>().add(args.primID as usize);
        let (lo, hi) = (sphere.center - sphere.radius.abs(), sphere.center + sphere.radius.abs());
        *args.bounds_o = RTCBounds {
            lower_x: to_f32(lo.x),
            lower_y: to_f32(lo.y),
            lower_z: to_f32(lo.z),
            align0: 0.0,
            upper_x: to_f32(hi.x),
            upper_y: to_f32(hi.y),
            upper_z: to_f32(hi.z),
            align1: 0.0,
        };
    }
}

/// Embree's traversal reached primitive `primID`: raypool's test, bounded by the ray's
/// current `tfar`; a hit shortens the ray and records the sphere.
unsafe extern "C" fn sphere_intersect(args: *const RTCIntersectFunctionNArguments) {
    // SAFETY: `rtcIntersect1` calls back with N = 1, where the ray-hit "N" layout is that of
    // one `RTCRayHit`; `valid` holds N flags; the user pointer is as in `sphere_bounds`.
    unsafe {
        let args = &*args;
        if args.N != 1 || *args.valid == 0 {
            return;
        }
        let rayhit = &mut *args.rayhit.cast::<RTCRayHit>();
        let sphere = &*args.geometryUserPtr.cast::<Sphere>().add(args.primID as usize);
        let r = &rayhit.ray;
        let ray = Ray {
            origin: Vec3::new(r.org_x as Real, r.org_y as Real, r.org_z as Real),
            dir: Vec3::new(r.dir_x as Real, r.dir_y as Real, r.dir_z as Real),
        };
        if let Some(t) = sphere.intersect(&ray, r.tfar as Real) {
            rayhit.ray.tfar = to_f32(t);
            rayhit.hit = RTCHit { primID: args.primID, geomID: args.geomID, ..no_hit() };
        }
    }
}

/// `scene` (which holds `device`) if Embree reports no error on `device`, else that error,
/// naming `what` (dropping `scene` releases its handles).
pub fn built<T>(device: RTCDevice, scene: T, what: &str) -> Result<T, String> {
    // SAFETY: the caller's device, live while `scene` holds it.
    match unsafe { rtcGetDeviceError(device) } {
        RTCError::NONE => Ok(scene),
        error => Err(format!("Embree could not build {what}: {error:?}")),
    }
}

/// `ray` in Embree's layout: from its origin (t = 0; raypool spawns rays off the surface) to
/// infinity.
pub fn embree_ray(ray: &Ray) -> RTCRay {
    RTCRay {
        org_x: to_f32(ray.origin.x),
        org_y: to_f32(ray.origin.y),
        org_z: to_f32(ray.origin.z),
        tnear: 0.0,
        dir_x: to_f32(ray.dir.x),
        dir_y: to_f32(ray.dir.y),
        dir_z: to_f32(ray.dir.z),
        time: 0.0,
        tfar: f32::INFINITY,
        mask: u32::MAX,
        id: 0,
        flags: 0,
    }
}

/// A hit record that says "nothing hit".
pub fn no_hit() -> RTCHit {
    RTCHit {
        Ng_x: 0.0,
        Ng_y: 0.0,
        Ng_z: 0.0,
        u: 0.0,
        v: 0.0,
        primID: INVALID_ID,
        geomID: INVALID_ID,
        instID: [INVALID_ID],
    }
}

/// `rtcInitIntersectContext`, which is an inline function of Embree's header (not in the
/// library): incoherent rays, no filter, no instance.
pub fn incoherent_context() -> RTCIntersectContext {
    RTCIntersectContext { flags: RTCIntersectContextFlags::INCOHERENT, filter: None, instID: [INVALID_ID] }
}
