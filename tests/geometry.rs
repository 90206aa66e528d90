//! Ray–sphere intersection and camera geometry.

use raypool::tracer::camera::{Camera, CameraSettings};
use raypool::tracer::geometry::sphere::Sphere;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};

fn unit_sphere() -> Sphere {
    Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }
}

fn close(a: Real, b: Real) -> bool {
    (a - b).abs() <= 1e-5 * (1.0 + b.abs())
}

#[test]
fn ray_from_outside_hits_the_near_side() {
    let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
    let t = unit_sphere().intersect(&ray, Real::INFINITY).expect("must hit");
    assert!(close(t, 4.0), "t = {t}");
    let hit = unit_sphere().hit_at(&ray, t);
    assert!(hit.front_face);
    assert!((hit.normal - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
}

#[test]
fn ray_from_inside_hits_the_far_side_with_a_back_face() {
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    let t = unit_sphere().intersect(&ray, Real::INFINITY).expect("must hit");
    assert!(close(t, 1.0), "t = {t}");
    let hit = unit_sphere().hit_at(&ray, t);
    assert!(!hit.front_face);
    // The normal is turned to face the ray: inwards.
    assert!((hit.normal - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn sphere_behind_the_origin_is_missed() {
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z);
    assert_eq!(unit_sphere().intersect(&ray, Real::INFINITY), None);
}

#[test]
fn ray_passing_beside_is_missed_and_tangent_ray_touches() {
    let beside = Ray::new(Vec3::new(0.0, 1.001, -5.0), Vec3::Z);
    assert_eq!(unit_sphere().intersect(&beside, Real::INFINITY), None);
    let tangent = Ray::new(Vec3::new(0.0, 1.0, -5.0), Vec3::Z);
    let t = unit_sphere().intersect(&tangent, Real::INFINITY).expect("a tangent ray touches");
    assert!(close(t, 5.0), "t = {t}");
}

#[test]
fn t_max_limits_the_hit() {
    let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
    assert_eq!(unit_sphere().intersect(&ray, 3.9), None);
    assert!(unit_sphere().intersect(&ray, 4.1).is_some());
}

#[test]
fn negative_radius_is_a_shell_with_inward_normals() {
    let shell = Sphere { center: Vec3::ZERO, radius: -1.0, material: 0 };
    let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
    let t = shell.intersect(&ray, Real::INFINITY).expect("same surface");
    let hit = shell.hit_at(&ray, t);
    assert!(close(t, 4.0));
    assert!(!hit.front_face, "the outside of a shell is its back");
    assert!(hit.normal.dot(ray.dir) < 0.0, "normals always face the ray");
}

#[test]
fn huge_distant_sphere_is_hit_accurately_in_f32() {
    // paper2's ground: radius 1e4 centred 1e4 below the origin, seen from 10 units up.
    let ground = Sphere { center: Vec3::new(0.0, -10_000.0, 0.0), radius: 10_000.0, material: 0 };
    let ray = Ray::new(Vec3::new(0.0, 10.0, 0.0), Vec3::new(0.0, -1.0, 0.0));
    let t = ground.intersect(&ray, Real::INFINITY).expect("must hit");
    assert!((t - 10.0).abs() < 2e-3, "t = {t}");
}

#[test]
fn spawned_rays_do_not_rehit_their_own_sphere() {
    for (center, radius) in
        [(Vec3::ZERO, 1e-3), (Vec3::ZERO, 1.0), (Vec3::new(0.0, -1e4, 0.0), 1e4), (Vec3::splat(1e4), 1.0)]
    {
        let sphere = Sphere { center, radius, material: 0 };
        let from = center + Vec3::new(0.3, 1.0, 0.2) * (3.0 * radius);
        let ray = Ray::new(from, center - from);
        let t = sphere.intersect(&ray, Real::INFINITY).unwrap();
        let hit = sphere.hit_at(&ray, t);
        // Leave in a grazing-but-outward direction: must escape.
        let tangent = hit.normal.cross(Vec3::X).normalize();
        let out = hit.spawn((tangent + 0.01 * hit.normal).normalize());
        assert_eq!(sphere.intersect(&out, Real::INFINITY), None, "re-hit at radius {radius}");
        // Refract straight in: must hit the far side at about one diameter.
        let inward = hit.spawn(-hit.normal);
        let through = sphere.intersect(&inward, Real::INFINITY).expect("far side");
        assert!((through - 2.0 * radius).abs() < 1e-2 * radius, "{through} vs {}", 2.0 * radius);
    }
}

fn camera_settings() -> CameraSettings {
    CameraSettings {
        lookfrom: [13.0, 2.0, 3.0],
        lookat: [0.0, 0.0, 0.0],
        vup: [0.0, 1.0, 0.0],
        vfov: 20.0,
        aperture: 0.0,
        focus_dist: Some(10.0),
        aspect: 1.5,
    }
}

#[test]
fn centre_pixel_ray_points_at_lookat() {
    let s = camera_settings();
    let camera = Camera::new(&s, 300, 200);
    let ray = camera.center_ray(150.0, 100.0);
    let expected = (Vec3::ZERO - Vec3::new(13.0, 2.0, 3.0)).normalize();
    assert!((ray.dir - expected).length() < 1e-6, "{:?} vs {expected:?}", ray.dir);
}

#[test]
fn pixel_squares_tile_the_viewport_exactly() {
    // The image's left and right edges are exactly ±vfov·aspect/2 apart: no W/(W−1) stretch.
    let s = CameraSettings {
        lookfrom: [0.0, 0.0, 0.0],
        lookat: [0.0, 0.0, -1.0],
        vfov: 90.0,
        ..camera_settings()
    };
    let camera = Camera::new(&s, 200, 100);
    let left = camera.center_ray(0.0, 50.0).dir;
    let right = camera.center_ray(200.0, 50.0).dir;
    let top = camera.center_ray(100.0, 0.0).dir;
    // vfov 90 → half height = focus; width = 2 × height → half width = 2 × focus.
    assert!(close(left.x / -left.z, -2.0) && close(right.x / -right.z, 2.0), "{left:?} {right:?}");
    assert!(close(top.y / -top.z, 1.0), "{top:?}");
}

#[test]
fn camera_rays_are_unit_length_and_start_on_the_lens() {
    use rand::SeedableRng;
    let s = CameraSettings { aperture: 0.5, ..camera_settings() };
    let camera = Camera::new(&s, 64, 48);
    let mut rng = rand::rngs::SmallRng::seed_from_u64(7);
    for k in 0..1000 {
        let ray = camera.ray(k % 64, k % 48, &mut rng);
        assert!((ray.dir.length() - 1.0).abs() < 1e-5);
        let off = ray.origin - Vec3::new(13.0, 2.0, 3.0);
        assert!(off.length() <= 0.25 + 1e-5, "origin off the lens: {off:?}");
        assert!(
            off.dot(Vec3::new(13.0, 2.0, 3.0).normalize()).abs() < 1e-4,
            "lens is a disk across the view"
        );
    }
}

/// A plain f64 Möller–Trumbore test, the reference for the four-lane watertight test away
/// from edges: `(t, b1, b2, |cos|)` of a hit in front of the origin.
fn reference_hit(p: [Vec3; 3], ray: &Ray) -> Option<(f64, f64, f64, f64)> {
    let d = |v: Vec3| glam::DVec3::new(v.x as f64, v.y as f64, v.z as f64);
    let (o, dir) = (d(ray.origin), d(ray.dir));
    let (e1, e2) = (d(p[1]) - d(p[0]), d(p[2]) - d(p[0]));
    let h = dir.cross(e2);
    let det = e1.dot(h);
    let s = o - d(p[0]);
    let b1 = s.dot(h) / det;
    let q = s.cross(e1);
    let b2 = dir.dot(q) / det;
    let t = e2.dot(q) / det;
    let cos = e1.cross(e2).normalize().dot(dir).abs();
    (b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 && t > 0.0).then_some((t, b1, b2, cos))
}

#[test]
fn eight_triangles_in_one_test_each_find_what_they_find_alone_and_what_the_reference_finds() {
    use raypool::tracer::geometry::triangle::{RayFrame, Triangles8, intersect};
    use raypool::tracer::math::lanes::Scalar8;
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut uniform = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 40) as Real / (1u64 << 24) as Real
    };
    let point = |scale: Real, uniform: &mut dyn FnMut() -> Real| {
        Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5) * scale
    };
    let (mut checked, mut hits) = (0, 0);
    for round in 0..4000 {
        let count = 1 + round % 8;
        let triangles: Vec<[Vec3; 3]> =
            (0..count).map(|_| [0; 3].map(|_| point(2.0, &mut uniform))).collect();
        // Aimed at a point of one of them (just outside it now and then), from anywhere.
        let aim = triangles[round % count];
        let (u, v) = (uniform() * 1.2 - 0.1, uniform() * 1.2 - 0.1);
        let target = aim[0] + u * (aim[1] - aim[0]) + (1.0 - u) * v * (aim[2] - aim[0]);
        let origin = point(6.0, &mut uniform);
        let ray = Ray::new(origin, (target - origin).normalize());
        let packet = Triangles8::new(&triangles).intersect(Scalar8, &RayFrame::new(&ray), Real::INFINITY);
        let found: Vec<usize> = packet.lanes().collect();
        assert!(found.iter().all(|&lane| lane < count), "round {round}: a spare lane hit");
        for (lane, &triangle) in triangles.iter().enumerate() {
            let alone = intersect(triangle, &ray, Real::INFINITY);
            assert_eq!(found.contains(&lane), alone.is_some(), "round {round}, lane {lane}");
            if let Some(alone) = alone {
                assert_eq!(packet.hit(lane), alone, "round {round}, lane {lane}: bit for bit");
            }
        }
        for (k, &p) in triangles.iter().enumerate() {
            let ours = intersect(p, &ray, Real::INFINITY);
            match reference_hit(p, &ray) {
                // Near an edge, rounding may decide either way: not compared.
                Some((_, b1, b2, _)) if b1.min(b2).min(1.0 - b1 - b2) < 1e-4 => continue,
                Some((t, b1, b2, cos)) => {
                    let ours = ours.unwrap_or_else(|| panic!("round {round}, triangle {k}: missed"));
                    // f32 rounding of the corners, magnified where the ray grazes the plane.
                    let tolerance = 1e-5 * t.max(1.0) / cos.max(1e-3);
                    assert!((ours.t as f64 - t).abs() <= tolerance, "t {} against {t} (cos {cos})", ours.t);
                    let [_, o1, o2] = ours.barycentric;
                    assert!((o1 as f64 - b1).abs() < 1e-3 && (o2 as f64 - b2).abs() < 1e-3);
                    hits += 1;
                }
                None => {
                    if let Some(ours) = ours {
                        // Only a grazing miss of the reference may be our hit.
                        let near_edge = ours.barycentric.iter().any(|&b| b.abs() < 1e-4);
                        assert!(
                            near_edge,
                            "round {round}, triangle {k}: a hit the reference misses: {ours:?}"
                        );
                    }
                }
            }
            checked += 1;
        }
    }
    assert!(
        checked > 9000 && hits > 2000,
        "{checked} compared, {hits} hits: the rays must meet the triangles"
    );
}
