//! The bounding volume hierarchy finds exactly what testing every sphere finds.

use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};
use raypool::scenes::builtin::builtin_scene;
use raypool::tracer::bvh::Bvh;
use raypool::tracer::ray::Ray;
use raypool::tracer::real::{Real, Vec3};
use raypool::tracer::sphere::Sphere;

fn brute_force(spheres: &[Sphere], ray: &Ray) -> Option<(usize, Real)> {
    let mut best = None;
    let mut closest = Real::INFINITY;
    for (i, s) in spheres.iter().enumerate() {
        if let Some(t) = s.intersect(ray, closest) {
            closest = t;
            best = Some((i, t));
        }
    }
    best
}

fn random_vec(rng: &mut SmallRng, scale: Real) -> Vec3 {
    Vec3::new(rng.random::<Real>() - 0.5, rng.random::<Real>() - 0.5, rng.random::<Real>() - 0.5)
        * (2.0 * scale)
}

fn check_against_brute_force(mut spheres: Vec<Sphere>, rng: &mut SmallRng, scale: Real) {
    let bvh = Bvh::build(&mut spheres);
    for _ in 0..20_000 {
        let ray = Ray::new(random_vec(rng, scale), random_vec(rng, 1.0));
        let expected = brute_force(&spheres, &ray);
        let got = bvh.hit(&spheres, &ray, Real::INFINITY, Sphere::intersect);
        match (expected, got) {
            (None, None) => {}
            (Some((i, t)), Some((j, u))) => {
                // Same distance; the same sphere unless two are hit at exactly the same t.
                assert_eq!(t, u, "ray {ray:?}");
                assert!(i == j || spheres[i].intersect(&ray, Real::INFINITY) == Some(u), "ray {ray:?}");
            }
            _ => panic!("ray {ray:?}: brute force {expected:?}, BVH {got:?}"),
        }
    }
}

#[test]
fn bvh_matches_brute_force_on_random_spheres() {
    let mut rng = SmallRng::seed_from_u64(11);
    for count in [1, 2, 5, 33, 200, 1000] {
        let spheres = (0..count)
            .map(|k| Sphere {
                center: random_vec(&mut rng, 10.0),
                radius: (0.05 + rng.random::<Real>()) * if k % 7 == 0 { -1.0 } else { 1.0 },
                material: 0,
            })
            .collect();
        check_against_brute_force(spheres, &mut rng, 12.0);
    }
}

#[test]
fn bvh_matches_brute_force_on_the_final_scene() {
    let scene = builtin_scene("final", 3).unwrap().to_scene();
    assert!(scene.has_bvh(), "the final scene is large enough for a BVH");
    let mut rng = SmallRng::seed_from_u64(5);
    check_against_brute_force(scene.spheres().to_vec(), &mut rng, 14.0);
}

#[test]
fn coincident_centres_still_build() {
    let same = vec![Sphere { center: Vec3::ONE, radius: 1.0, material: 0 }; 100];
    let mut rng = SmallRng::seed_from_u64(2);
    check_against_brute_force(same, &mut rng, 4.0);
}

#[test]
fn small_scenes_skip_the_bvh() {
    for name in ["paper1", "three-spheres", "furnace"] {
        assert!(!builtin_scene(name, 0).unwrap().to_scene().has_bvh(), "{name}");
    }
}

#[test]
fn pathological_spacing_builds_a_bounded_tree() {
    // Centres at 1.2^k: each sphere lies beyond the 15/16 mark of everything before it, so
    // every SAH split can peel off a single sphere, making the tree n deep. The traversal
    // stack holds 64 entries: the build must bound the depth. (x stays below 1e15: squared
    // distances beyond ~1e19 overflow f32.)
    let spheres: Vec<Sphere> = (0..180)
        .map(|k| {
            let x = 1.2f64.powi(k) as Real;
            Sphere { center: Vec3::new(x, 0.0, 0.0), radius: 0.05 * x, material: 0 }
        })
        .collect();
    let mut copy = spheres.clone();
    let bvh = Bvh::build(&mut copy);
    assert!(bvh.depth() <= 64, "depth {} overflows the traversal stack", bvh.depth());
    for sphere in &spheres {
        // Straight down onto each sphere's top, from one radius above it.
        let (c, r) = (sphere.center, sphere.radius);
        let ray = Ray::new(Vec3::new(c.x, 2.0 * r, 0.0), Vec3::new(0.0, -1.0, 0.0));
        let hit = bvh.hit(&copy, &ray, Real::INFINITY, Sphere::intersect).unwrap_or_else(|| {
            panic!("sphere at {c:?} r {r} missed; brute force: {:?}", brute_force(&copy, &ray))
        });
        assert_eq!(Some(hit.1), brute_force(&copy, &ray).map(|h| h.1));
    }
    // A ray along the whole row must visit every level without overflowing.
    let along = Ray::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::X);
    assert_eq!(
        bvh.hit(&copy, &along, Real::INFINITY, Sphere::intersect).map(|h| h.1),
        brute_force(&copy, &along).map(|h| h.1)
    );
}
