//! A numerical stress case for meshes shaded by their vertex normals: an interpolated normal
//! leans away from the flat facet under it, so a bounce drawn about it may point below the
//! facet and meet its own mesh again, a ray that should have left. Counted ray by ray on a
//! convex mesh, where no bounce should meet the mesh: from [`Hit::spawn`], which leaves from
//! the smooth surface the normals describe ([`Hit::departure`]), and, for comparison, from the
//! facet itself (the hit's point moved off by its offset, as rays left before the departure
//! point). `cargo bench --bench stability` tabulates it with the other shapes' cases.
//!
//! [`Hit::spawn`]: crate::tracer::geometry::hit::Hit::spawn
//! [`Hit::departure`]: crate::tracer::geometry::hit::Hit::departure

use std::sync::Arc;

use crate::measure::solids::icosphere;
use crate::measure::stress_shapes::{NEAR, Rng, Row, aimed, hits, placement, world};
use crate::tracer::accel::isa::Isa;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, from_dvec3};
use crate::tracer::world::mesh::Mesh;
use crate::tracer::world::object::{Object, Probe};

/// What [`self_hits`] counts: bounces that met the mesh again.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SelfHits {
    /// Rays that missed the mesh on the way in (none expected).
    pub missed: u64,
    /// Bounces spawned as the renderer spawns them that met the mesh again.
    pub from_departure: u64,
    /// The same bounces started from the facet instead.
    pub from_facet: u64,
}

/// The unit icosphere subdivided `levels` times, with its vertices' own directions as normals
/// (a convex mesh shaded as a round ball), as its own world or through an instance: `rays`
/// rays from outside through random points inside it, and from each hit one Lambertian bounce
/// about the shading normal (normal plus a random unit vector, as the renderer's).
///
/// ```
/// use raypool::measure::stress_smooth::self_hits;
/// let counts = self_hits(1, false, 2000, raypool::tracer::accel::isa::Isa::best());
/// assert_eq!((counts.missed, counts.from_departure), (0, 0));
/// assert!(counts.from_facet > 0, "from the facets, some bounces meet the ball again");
/// ```
pub fn self_hits(levels: u32, placed: bool, rays: u64, isa: Isa) -> SelfHits {
    let (positions, triangles) = icosphere(levels);
    let normals = positions.iter().map(|p| from_dvec3(p.normalize())).collect();
    let positions = positions.iter().map(|&p| from_dvec3(p)).collect();
    let mesh = Mesh::new(positions, normals, vec![], triangles).expect("an icosphere");
    let placed = placed.then(|| placement(NEAR));
    let world = world(vec![Object::Mesh(Arc::new(mesh), 0)], placed);
    let mut rng = Rng(0x5400_0000 + u64::from(levels) * 16 + u64::from(placed.is_some()));
    let mut out = SelfHits::default();
    for _ in 0..rays {
        let (target, from) = (0.5 * rng.unit(), rng.unit());
        let probe = Probe { isa, ..Probe::default() };
        let Some(hit) = world.hit(&aimed(target, from, placed), Real::INFINITY, &probe) else {
            out.missed += 1;
            continue;
        };
        let dir = (hit.normal + from_dvec3(rng.unit())).normalize_or_zero();
        if dir == Vec3::ZERO {
            continue;
        }
        out.from_departure += u64::from(hits(&world, &hit.spawn(dir), isa));
        let facet = Ray { origin: hit.point + hit.offset * hit.normal, dir };
        out.from_facet += u64::from(hits(&world, &facet, isa));
    }
    out
}

/// The case's rows for `cargo bench --bench stability`: the icosphere of 1,280 triangles, as
/// its own world and through an instance, searched with the vector level `isa`.
pub fn rows(rays: u64, isa: Isa) -> Vec<Row> {
    [false, true]
        .into_iter()
        .map(|placed| {
            let s = self_hits(3, placed, rays, isa);
            let how = if placed { ", through an instance" } else { "" };
            Row {
                case: format!(
                    "self-hits: icosphere of 1280 triangles shaded by vertex normals, Lambertian bounces{how}"
                ),
                rays,
                failures: s.missed + s.from_departure,
                detail: format!(
                    "{} met the mesh again ({} had they left from the facet), {} primary misses",
                    s.from_departure, s.from_facet, s.missed
                ),
            }
        })
        .collect()
}
