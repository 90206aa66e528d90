//! Every way of finding a hit in the second book's world finds the same one: an instance and
//! the same box moved by hand, a mesh's tree and every triangle tested alone, the shadow
//! rays' search and the closest hit, a tree and a flat list at the edges of quads.

mod rooms;

use raypool::scenes::format::SceneFile;
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::world::object::Probe;
use rooms::CAMERA;

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
        let searched = mesh.closest(ray, Real::INFINITY, Isa::best()).map(|(k, hit)| (k, hit.t));
        assert_eq!(searched, every_triangle(ray), "the search and every triangle disagree on {ray:?}");
        hits += usize::from(searched.is_some());
    }
    assert!(hits > rays.len() / 2, "only {hits} of {} rays hit: the test checks little", rays.len());
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
            let probe = Probe { time: uniform(&mut rng), medium_seed: k, ..Default::default() };
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
    let objects: Vec<Object> = quads.iter().map(|&q| Object::shape(q)).collect();
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
fn a_group_with_a_medium_breaks_ties_between_surfaces_by_their_order_in_the_group() {
    // With a medium, a group searches its surfaces through a second tree, of their own boxes
    // (the medium asked last), whose leaves may hold them in another order than the group's:
    // a tie must still go to the object earlier in the group ([`Closest`]'s rule, which the
    // search without a tree follows), not to the earlier lane of a leaf. Pairs of quads in
    // the floor's plane, one large facing up and one small facing down inside it: rays from
    // below through the small one meet both at the same distance, and `front_face` shows
    // which won.
    use rand::{SeedableRng, rngs::SmallRng};
    use raypool::tracer::geometry::quad::Quad;
    use raypool::tracer::geometry::sphere::Sphere;
    use raypool::tracer::math::aabb::Bounded;
    use raypool::tracer::sampling::warp::uniform;
    use raypool::tracer::world::object::{Group, Medium, Object};
    let pairs: Vec<[Object; 2]> = (0..1_200)
        .map(|k| {
            let q = Vec3::new((k % 40) as Real * 50.0, 0.0, (k / 40) as Real * 50.0);
            let large = Quad::new(q, Vec3::new(0.0, 0.0, 40.0), Vec3::new(40.0, 0.0, 0.0), 0).unwrap();
            let small = Quad::new(q, Vec3::new(10.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 10.0), 0).unwrap();
            [large, small].map(Object::shape)
        })
        .collect();
    let mut objects: Vec<Object> = pairs.iter().flatten().cloned().collect();
    let fog = Sphere { center: Vec3::ZERO, radius: 5_000.0, material: 0 };
    let boundary = Group::new(vec![Object::shape(fog)]);
    objects.push(Object::Medium(Box::new(Medium { boundary, density: 1e-6, material: 0, id: 0 })));
    let tree = Group::new(objects);
    assert!(tree.has_tree());
    // Whether each pair's large quad comes first in the group, as the group ordered them.
    let place = |o: &Object| tree.objects().iter().position(|p| p.bounds() == o.bounds()).unwrap();
    let large_first: Vec<bool> = pairs.iter().map(|[large, small]| place(large) < place(small)).collect();
    let mut rng = SmallRng::seed_from_u64(17);
    let mut ties = [0; 2];
    for k in 0..20_000u64 {
        let pair = (k % 1_200) as usize;
        let corner = Vec3::new((pair % 40) as Real * 50.0, 0.0, (pair / 40) as Real * 50.0);
        let target = corner + Vec3::new(uniform(&mut rng) * 10.0, 0.0, uniform(&mut rng) * 10.0);
        let offset = Vec3::new(uniform(&mut rng), -1.0 - 10.0 * uniform(&mut rng), uniform(&mut rng));
        let ray = Ray::new(target + 30.0 * offset, -offset);
        let probe = Probe { time: 0.0, medium_seed: k, ..Default::default() };
        let Some(hit) = tree.hit(&ray, Real::INFINITY, &probe).filter(|h| h.point.y == 0.0) else { continue };
        let first = large_first[pair];
        assert_eq!(hit.front_face, !first, "ray {k}: the quad later in the group won a tie: {hit:?}");
        ties[usize::from(first)] += 1;
    }
    assert!(ties.iter().all(|&n| n > 1_000), "ties with the small quad first, the large first: {ties:?}");
}

#[test]
fn a_packet_of_quads_finds_bit_for_bit_what_each_quad_finds_alone() {
    // `QuadPacket` runs `Quad::intersect`'s arithmetic in eight lanes at every vector level:
    // the same hits, the same distance and `(α, β)` to the bit and the same face met, for
    // axis-aligned quads (a box's faces, the walls) and tilted ones, rays aimed on, inside and
    // just past the edges; and its nearest lane is the least `(distance, lane)`, as offering
    // the lanes one by one to `Closest` finds.
    use rand::{SeedableRng, rngs::SmallRng};
    use raypool::tracer::accel::isa::Isa;
    use raypool::tracer::geometry::hit::Closest;
    use raypool::tracer::geometry::quad::{EDGE, Quad, box_faces};
    use raypool::tracer::geometry::quads::{QuadHits, QuadPacket};
    use raypool::tracer::math::lanes::{Lanes8, WithLanes8};
    use raypool::tracer::sampling::warp::{random_unit_vector, uniform};
    struct Test<'a>(&'a QuadPacket, Ray, Real);
    impl WithLanes8 for Test<'_> {
        type Output = QuadHits;
        fn run<L: Lanes8>(self, lanes: L) -> QuadHits {
            self.0.intersect(lanes, &self.1, self.2)
        }
    }
    let levels = Isa::available();
    let mut rng = SmallRng::seed_from_u64(13);
    let mut point = |scale: Real| Vec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)) * scale;
    let mut quads: Vec<Quad> = box_faces(point(100.0), point(100.0) + Vec3::splat(20.0), 0).unwrap().to_vec();
    while quads.len() < 12 {
        quads.extend(Quad::new(
            point(100.0),
            point(60.0) - Vec3::splat(30.0),
            point(60.0) - Vec3::splat(30.0),
            0,
        ));
    }
    let (mut hits, mut edges) = (0, 0);
    for k in 0..60_000 {
        let lanes = [k % 12, (k + 5) % 12, (k / 12) % 12, (k / 7 + 3) % 12, (k / 3) % 12, (k + 9) % 12];
        let present = k % 5 != 0;
        let packet = QuadPacket::new(&lanes.map(|i| (present || i % 2 == 0).then_some(&quads[i])));
        let target = &quads[lanes[k % lanes.len()]];
        let past = [-0.5, 0.0, 0.5, 0.25][k % 4] * EDGE;
        let along = uniform(&mut rng);
        let (alpha, beta) = if k % 3 == 0 { (past, along) } else { (along, 1.0 - past) };
        let aim = target.q + alpha * target.u + beta * target.v;
        let from = aim + random_unit_vector(&mut rng) * (1.0 + 300.0 * uniform(&mut rng));
        let Some(dir) = (aim - from).try_normalize() else { continue };
        let ray = Ray::new(from, dir);
        let t_max = if k % 2 == 0 { Real::INFINITY } else { 200.0 * uniform(&mut rng) };
        let isa = levels[k % levels.len()];
        let found = isa.run_lanes(Test(&packet, ray, t_max));
        let mut closest = Closest::none(t_max);
        assert_eq!(found.mask >> lanes.len(), 0, "ray {k}: a lane with no quad was hit");
        for (lane, &i) in lanes.iter().enumerate() {
            let alone = (present || i % 2 == 0).then(|| quads[i].intersect(&ray, t_max)).flatten();
            assert_eq!(found.mask >> lane & 1 == 1, alone.is_some(), "ray {k}, lane {lane}");
            if let Some((t, a, b)) = alone {
                let lane_of = |v: [Real; 8]| v[lane].to_bits();
                assert_eq!(
                    (lane_of(found.t), lane_of(found.alpha), lane_of(found.beta)),
                    (t.to_bits(), a.to_bits(), b.to_bits()),
                    "ray {k}, lane {lane} at {isa:?}"
                );
                let front = ray.dir.dot(quads[i].normal()) < 0.0;
                assert_eq!(found.front >> lane & 1 == 1, front, "ray {k}, lane {lane}: which face");
                closest.offer(t, lane as u32);
                hits += 1;
                edges += usize::from(!(0.0..=1.0).contains(&a) || !(0.0..=1.0).contains(&b));
            }
        }
        assert_eq!(found.nearest(), closest.found().map(|(lane, _)| lane), "ray {k}");
    }
    assert!(hits > 50_000 && edges > 1_000, "{hits} hits, {edges} past an edge: the test checks little");
}

#[test]
fn smoke_in_a_box_is_never_met_outside_the_box() {
    // A ray that reaches a box at an edge may meet one of its faces from behind first, as a
    // ray leaving the box would (a face's edge is accepted a few ulps past its plane); the
    // medium took such a ray as starting inside and drew its scattering point anywhere
    // between the ray's start and that edge: smoke in front of the camera (found on
    // `cornell-smoke`). Rays from far off, each aimed at a point of one of the box's four
    // vertical edges: every scattering point must lie in the box. It fails where the medium
    // may start sooner than its boundary's box (`Medium::hit`; how many points lay outside
    // then: `results/perf.md`, eighteenth pass).
    use rand::{SeedableRng, rngs::SmallRng};
    use raypool::tracer::geometry::quad::box_faces;
    use raypool::tracer::sampling::warp::uniform;
    use raypool::tracer::world::object::{Group, Medium, Object};
    let (min, max) = (Vec3::ZERO, Vec3::new(165.0, 330.0, 165.0));
    let faces = box_faces(min, max, 0).unwrap();
    let boundary = Group::new(faces.into_iter().map(Object::shape).collect());
    let smoke = Medium { boundary, density: 0.01, material: 0, id: 0 };
    let mut rng = SmallRng::seed_from_u64(5);
    let (mut scattered, mut outside) = (0, Vec::new());
    for k in 0..400_000u64 {
        // An edge (x, z) ∈ {0, 165}², a point on it, and a start about 1,200 units away,
        // up to 135° about the edge from the diagonal out of the box: within 45° the ray
        // enters the box at the edge, beyond it passes the box at that edge only.
        let corner =
            Vec3::new(if k & 1 == 0 { 0.0 } else { 165.0 }, 0.0, if k & 2 == 0 { 0.0 } else { 165.0 });
        let target = corner + Vec3::new(0.0, 330.0 * uniform(&mut rng), 0.0);
        let outward = Vec3::new(corner.x - 82.5, 0.0, corner.z - 82.5).normalize();
        let turn = 3.0 * raypool::tracer::math::real::consts::FRAC_PI_4 * (2.0 * uniform(&mut rng) - 1.0);
        let away = Vec3::new(
            outward.x * turn.cos() - outward.z * turn.sin(),
            0.3 * (uniform(&mut rng) - 0.5),
            outward.x * turn.sin() + outward.z * turn.cos(),
        );
        let ray = Ray::new(target + 1_200.0 * away, -away);
        let probe = Probe { time: 0.0, medium_seed: k, ..Default::default() };
        let Some(hit) = smoke.hit(&ray, Real::INFINITY, &probe) else { continue };
        scattered += 1;
        let slack = Vec3::splat(1e-3);
        if hit.point.cmplt(min - slack).any() || hit.point.cmpgt(max + slack).any() {
            outside.push((k, hit.point));
        }
    }
    assert!(scattered > 1_000, "only {scattered} rays scattered in the smoke");
    assert!(
        outside.is_empty(),
        "{} of {scattered} scattering points outside the box, e.g. {:?}",
        outside.len(),
        &outside[..outside.len().min(3)]
    );
}
