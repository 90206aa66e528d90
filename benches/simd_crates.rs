//! `cargo bench --bench simd_crates --features simd-crates [-- --quick]`: the two maintained safe-SIMD crates issue
//! #57 named, on raypool's own hot loop. The eight-wide mesh search ([`Bvh8::traverse`], generic
//! over [`Lanes8`]) runs through `pulp` (the library's [`Avx8`], via [`Isa::run_lanes`]) and
//! through `fearless_simd` ([`Fearless8`] below: the same trait over its `f32x8`, run with its
//! own level detection and `dispatch!`), at AVX2 and at AVX-512, over the `mesh` scene's
//! 131,072 triangles.
//!
//! The ray set: a jittered camera ray per pixel of the `mesh` scene, and for each that hits
//! the mesh one diffuse bounce spawned from the hit (as `embree/triangles.rs` builds its set;
//! fixed seed). Before any timing every ray goes through every search, which must find the
//! same triangle at the same distance, bit for bit, as one another and as [`Mesh::closest`];
//! else the bench fails. Then one thread, in rounds: each round times the whole set through
//! pulp and fearless_simd at each level, the two of a level back to back, the one that goes
//! first turning round by round. The table gives, per level, the median over rounds of the
//! paired ratio fearless_simd's time ÷ pulp's (above 1: pulp is faster).
//!
//! `--count WAY` (`pulp-avx2`, `fearless-avx2`, …) times one pass of one search and nothing
//! else, for `valgrind --tool=callgrind --toggle-collect='*timed_pass*'` (valgrind offers no
//! AVX-512, so there only the avx2 pair runs). The figures are in `results/simd.md`.

#![forbid(unsafe_code)]

#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
fn main() {
    compare::main();
}

#[cfg(not(all(target_arch = "x86_64", not(feature = "f64"))))]
fn main() {
    eprintln!("simd_crates compares eight f32 lanes on x86-64; this build has none to compare");
}

#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
mod compare {
    use std::hint::black_box;
    use std::time::Instant;

    use fearless_simd::prelude::*;
    use fearless_simd::{Level, dispatch, f32x8};
    use rand::rngs::SmallRng;
    use rand::{RngExt, SeedableRng};
    use raypool::measure::machine::Machine;
    use raypool::measure::speedup::median;
    use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
    use raypool::tracer::accel::bvh::Bvh;
    use raypool::tracer::accel::isa::Isa;
    use raypool::tracer::accel::wide8::Bvh8;
    use raypool::tracer::camera::Camera;
    use raypool::tracer::geometry::hit::Closest;
    use raypool::tracer::geometry::triangle::{self, RayFrame, Triangles8};
    use raypool::tracer::math::aabb::{Aabb, Bounded};
    use raypool::tracer::math::lanes::{Lanes8, WithLanes8};
    use raypool::tracer::math::ray::Ray;
    use raypool::tracer::math::real::{Real, Vec3};
    use raypool::tracer::sampling::warp::random_unit_vector;
    use raypool::tracer::world::mesh::Mesh;
    use raypool::tracer::world::object::Object;

    /// Eight lanes in fearless_simd's `f32x8` at level `S` (one `ymm` register at its AVX2 and
    /// AVX-512 levels): each operation one IEEE operation, as [`Lanes8`] requires. Its `max`
    /// and `min` are documented as either operand for a NaN; at these two levels they are
    /// `vmaxps`/`vminps`, which return the second, as the trait's invariant needs.
    #[derive(Clone, Copy, Debug)]
    pub struct Fearless8<S>(S);

    impl<S: Simd> Lanes8 for Fearless8<S> {
        type V = f32x8<S>;
        #[inline(always)]
        fn load(self, a: &[f32; 8]) -> f32x8<S> {
            f32x8::simd_from(self.0, *a)
        }
        #[inline(always)]
        fn splat(self, x: f32) -> f32x8<S> {
            f32x8::splat(self.0, x)
        }
        #[inline(always)]
        fn store(self, v: f32x8<S>) -> [f32; 8] {
            v.into()
        }
        #[inline(always)]
        fn add(self, a: f32x8<S>, b: f32x8<S>) -> f32x8<S> {
            a + b
        }
        #[inline(always)]
        fn sub(self, a: f32x8<S>, b: f32x8<S>) -> f32x8<S> {
            a - b
        }
        #[inline(always)]
        fn mul(self, a: f32x8<S>, b: f32x8<S>) -> f32x8<S> {
            a * b
        }
        #[inline(always)]
        fn div(self, a: f32x8<S>, b: f32x8<S>) -> f32x8<S> {
            a / b
        }
        #[inline(always)]
        fn abs(self, a: f32x8<S>) -> f32x8<S> {
            a.abs()
        }
        #[inline(always)]
        fn max(self, a: f32x8<S>, b: f32x8<S>) -> f32x8<S> {
            a.max(b)
        }
        #[inline(always)]
        fn min(self, a: f32x8<S>, b: f32x8<S>) -> f32x8<S> {
            a.min(b)
        }
        #[inline(always)]
        fn le_mask(self, a: f32x8<S>, b: f32x8<S>) -> u32 {
            a.simd_le(b).to_bitmask() as u32
        }
        #[inline(always)]
        fn lt_mask(self, a: f32x8<S>, b: f32x8<S>) -> u32 {
            a.simd_lt(b).to_bitmask() as u32
        }
        #[inline(always)]
        fn eq_mask(self, a: f32x8<S>, b: f32x8<S>) -> u32 {
            a.simd_eq(b).to_bitmask() as u32
        }
    }

    /// The mesh's triangles in a tree of their own, built as [`Mesh::new`] builds its tree
    /// (public parts only): the same padded boxes, leaves of eight, collapsed eight-wide.
    struct Triangles {
        tree: Bvh8,
        /// Each leaf's corners and its first triangle (the rest follow in lane order).
        leaves: Vec<(Triangles8, u32)>,
        /// Each triangle's vertex indices into the mesh, in the tree's order.
        indices: Vec<[u32; 3]>,
    }

    /// A triangle while the tree is built.
    struct Building {
        indices: [u32; 3],
        bounds: Aabb,
    }

    impl Bounded for Building {
        fn bounds(&self) -> Aabb {
            self.bounds
        }
        fn centroid(&self) -> Vec3 {
            0.5 * (self.bounds.min + self.bounds.max)
        }
    }

    impl Triangles {
        fn new(mesh: &Mesh) -> Triangles {
            let corners = |t: &[u32; 3]| t.map(|i| mesh.positions()[i as usize]);
            let box_of = |t: &[u32; 3]| corners(t).iter().fold(Aabb::EMPTY, |b, &v| b.grow(v));
            let whole = mesh.triangles().iter().fold(Aabb::EMPTY, |b, t| b.union(box_of(t)));
            let pad = 0.25 * 8.0 * Real::EPSILON * whole.magnitude();
            let mut building: Vec<Building> = mesh
                .triangles()
                .iter()
                .map(|t| Building { indices: *t, bounds: box_of(t).padded(pad) })
                .collect();
            let (tree, ranges) = Bvh8::collapse(&Bvh::build_with_leaves(&mut building, triangle::LANES));
            let leaves = ranges
                .into_iter()
                .map(|range| {
                    let leaf: Vec<_> = building[range.clone()].iter().map(|t| corners(&t.indices)).collect();
                    (Triangles8::new(&leaf), range.start as u32)
                })
                .collect();
            Triangles { tree, leaves, indices: building.iter().map(|t| t.indices).collect() }
        }
    }

    /// The closest hit of one ray, with the lanes of whichever level runs it: the mesh's
    /// search (`world/mesh.rs`'s `ClosestSearch`) without the barycentric coordinates.
    #[derive(Clone, Copy)]
    struct Search<'a> {
        triangles: &'a Triangles,
        ray: &'a Ray,
    }

    impl WithLanes8 for Search<'_> {
        type Output = Option<(usize, Real)>;

        #[inline(always)]
        fn run<L: Lanes8>(self, lanes: L) -> Self::Output {
            let mut closest = Closest::none(Real::INFINITY);
            let frame = RayFrame::new(self.ray);
            self.triangles.tree.traverse(
                lanes,
                self.ray,
                &mut closest,
                #[inline(always)]
                |leaf: usize, closest: &mut Closest| {
                    let (corners, first) = &self.triangles.leaves[leaf];
                    let hits = corners.intersect(lanes, &frame, closest.bound());
                    for lane in hits.lanes() {
                        closest.offer(hits.t(lane), first + lane as u32);
                    }
                },
            );
            closest.found()
        }
    }

    /// A crate at a level: pulp through the library's [`Isa`], or fearless_simd's own level.
    #[derive(Clone, Copy)]
    enum Way {
        Pulp(Isa),
        Fearless(Level),
    }

    impl Way {
        /// The search of one ray; the level is picked per ray, as [`Mesh::closest`] picks it.
        #[inline(always)]
        fn closest(self, search: Search) -> Option<(usize, Real)> {
            match self {
                Way::Pulp(isa) => isa.run_lanes(search),
                Way::Fearless(level) => dispatch!(level, simd => search.run(Fearless8(simd))),
            }
        }
    }

    /// pulp and fearless_simd at one level, where this CPU (as each crate asks it) has it.
    struct Pair {
        level: &'static str,
        ways: [(String, Way); 2],
    }

    /// The pairs this CPU offers, and a line per level that one of the crates lacks.
    fn pairs() -> (Vec<Pair>, Vec<String>) {
        let detected = Level::new();
        let fearless = [
            ("avx2", detected.as_avx2().map(|token| token.level())),
            ("avx512", detected.as_avx512().map(|token| token.level())),
        ];
        let (mut pairs, mut missing) = (Vec::new(), Vec::new());
        for (level, theirs) in fearless {
            match (Isa::named(level), theirs) {
                (Ok(isa), Some(theirs)) => pairs.push(Pair {
                    level,
                    ways: [
                        (format!("pulp-{level}"), Way::Pulp(isa)),
                        (format!("fearless-{level}"), Way::Fearless(theirs)),
                    ],
                }),
                (ours, theirs) => missing.push(format!(
                    "{level}: pulp {}, fearless_simd {}",
                    if ours.is_ok() { "has it" } else { "lacks it" },
                    if theirs.is_some() { "has it" } else { "lacks it" }
                )),
            }
        }
        (pairs, missing)
    }

    /// One pass of `way` over `rays`: seconds, hits, and the sum of their distances (used, so
    /// that nothing is skipped). Not inlined: callgrind counts this function alone.
    #[inline(never)]
    fn timed_pass(rays: &[Ray], triangles: &Triangles, way: Way) -> (f64, usize, f32) {
        let start = Instant::now();
        let (mut hits, mut sum) = (0, 0.0);
        for ray in rays {
            if let Some((_, t)) = way.closest(Search { triangles, ray: black_box(ray) }) {
                hits += 1;
                sum += t;
            }
        }
        (start.elapsed().as_secs_f64(), hits, black_box(sum))
    }

    /// The ray set: a jittered camera ray per pixel, then a diffuse bounce from each camera
    /// ray's hit on `mesh`, spawned as the renderer spawns rays.
    fn ray_set(camera: &Camera, mesh: &Mesh, width: u32, height: u32) -> Vec<Ray> {
        let mut rng = SmallRng::seed_from_u64(1);
        let mut rays = Vec::new();
        for j in 0..height {
            for i in 0..width {
                let (x, y) = (i as Real + rng.random::<Real>(), j as Real + rng.random::<Real>());
                rays.push(camera.center_ray(x, y));
            }
        }
        for k in 0..rays.len() {
            if let Some(hit) = mesh.hit(&rays[k], Real::INFINITY, 0, Isa::BASELINE) {
                let dir = hit.normal + random_unit_vector(&mut rng);
                if dir.length_squared() > 1e-8 {
                    rays.push(hit.spawn(dir.normalize()));
                }
            }
        }
        rays
    }

    /// Every search finds what [`Mesh::closest`] finds: the same triangle (its vertices) at
    /// the same distance, bit for bit. Returns the number of hits; panics on a difference.
    fn check(rays: &[Ray], mesh: &Mesh, triangles: &Triangles, ways: &[&(String, Way)]) -> usize {
        let mut hits = 0;
        for (k, ray) in rays.iter().enumerate() {
            let expected = mesh.closest(ray, Real::INFINITY, Isa::BASELINE);
            let expected = expected.map(|(i, hit)| (mesh.triangles()[i], hit.t.to_bits()));
            hits += usize::from(expected.is_some());
            for (name, way) in ways {
                let found = way.closest(Search { triangles, ray });
                let found = found.map(|(i, t)| (triangles.indices[i], t.to_bits()));
                assert_eq!(found, expected, "ray {k}: {name} against Mesh::closest");
            }
        }
        hits
    }

    fn median_of(values: &[f64]) -> f64 {
        median(&mut values.to_vec())
    }

    pub fn main() {
        let args: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
        let quick = args.iter().any(|a| a == "--quick");
        let count = args.iter().position(|a| a == "--count").map(|i| args.get(i + 1).cloned());
        let (width, height, rounds) = if quick { (200, 150, 15) } else { (400, 300, 201) };

        let scene = builtin_scene("mesh", DEFAULT_SCENE_SEED).expect("mesh exists").to_scene();
        let mesh = scene
            .objects()
            .iter()
            .find_map(|o| match o {
                Object::Mesh(mesh, _) => Some(mesh.clone()),
                _ => None,
            })
            .expect("the mesh scene has a mesh");
        let triangles = Triangles::new(&mesh);
        let rays = ray_set(&Camera::new(&scene.camera, width, height), &mesh, width, height);
        let (pairs, missing) = pairs();
        let ways: Vec<&(String, Way)> = pairs.iter().flat_map(|p| &p.ways).collect();

        if let Some(name) = count {
            let Some((_, way)) = ways.iter().find(|(n, _)| Some(n) == name.as_ref()) else {
                let names: Vec<_> = ways.iter().map(|(n, _)| n.as_str()).collect();
                eprintln!("--count takes one of {}, not {:?}", names.join(", "), name.unwrap_or_default());
                std::process::exit(2);
            };
            let (seconds, hits, _) = timed_pass(&rays, &triangles, *way);
            println!(
                "{}: one pass, {} rays, {hits} hits, {:.1} ms",
                name.unwrap_or_default(),
                rays.len(),
                seconds * 1e3
            );
            return;
        }

        let hits = check(&rays, &mesh, &triangles, &ways);
        eprintln!("checked: {} rays, {hits} hits, the same bits through {} searches", rays.len(), ways.len());
        // seconds[pair][0 = pulp, 1 = fearless_simd], round by round.
        let mut seconds = vec![[Vec::new(), Vec::new()]; pairs.len()];
        for round in 0..rounds {
            for step in 0..pairs.len() {
                let p = (round + step) % pairs.len();
                for turn in 0..2 {
                    let side = (round + turn) % 2;
                    let (s, h, _) = timed_pass(&rays, &triangles, pairs[p].ways[side].1);
                    assert_eq!(
                        h, hits,
                        "a timed pass of {} found another number of hits",
                        pairs[p].ways[side].0
                    );
                    seconds[p][side].push(s);
                }
            }
            eprintln!("round {}/{rounds}", round + 1);
        }

        println!("Machine: {}.", Machine::current().describe());
        println!(
            "Command: `cargo bench --bench simd_crates --features simd-crates{}`; {} rays ({width} × {height} camera rays and \
             their bounces), {hits} hits; one thread, {rounds} rounds.\n",
            if quick { " -- --quick" } else { "" },
            rays.len()
        );
        println!(
            "| level | pulp median (ms) | fearless_simd median (ms) | fearless_simd ÷ pulp, median of \
             paired ratios | quartiles | rounds fearless_simd was faster |"
        );
        println!("|---|---:|---:|---:|---:|---:|");
        for (pair, [ours, theirs]) in pairs.iter().zip(&seconds) {
            let mut ratios: Vec<f64> = theirs.iter().zip(ours).map(|(t, o)| t / o).collect();
            ratios.sort_by(f64::total_cmp);
            let quartile = |q: usize| ratios[q * (ratios.len() - 1) / 4];
            println!(
                "| {} | {:.2} | {:.2} | **{:.3}** | {:.3}–{:.3} | {} of {rounds} |",
                pair.level,
                median_of(ours) * 1e3,
                median_of(theirs) * 1e3,
                quartile(2),
                quartile(1),
                quartile(3),
                ratios.iter().filter(|&&r| r < 1.0).count()
            );
        }
        for line in missing {
            println!("\nNot compared: {line}.");
        }
    }
}
