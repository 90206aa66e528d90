//! Numerical stress cases for the second book's shapes (quads, triangle meshes, discs,
//! instances), counted ray by ray rather than judged from pixels: rays aimed exactly at the
//! shared edges and vertices of closed solids must never slip through them ([`leaks`]); rays
//! spawned off a quad, a triangle or a disc far from the origin must never meet it again,
//! whichever side they leave by
//! ([`acne`]); thin boxes met by grazing rays must be hit exactly where an f64 slab test says
//! they are ([`thin`]). Each case also runs through an [`Instance`] that rotates and moves
//! the shape. `cargo bench --bench stability` tabulates them ([`table`], `results/stability.md`);
//! `tests/stability.rs` asserts the headline counts at a smaller number of rays.

use std::f64::consts::TAU;
use std::sync::Arc;

use glam::DVec3;

use crate::measure::solids::{cube, edges, icosphere};
use crate::tracer::accel::isa::Isa;
use crate::tracer::geometry::disc::Disc;
use crate::tracer::geometry::quad::{Quad, box_faces};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, from_dvec3, to_dvec3};
use crate::tracer::math::transform::Transform;
use crate::tracer::sampling::independent::mix;
use crate::tracer::world::mesh::Mesh;
use crate::tracer::world::object::Group;
use crate::tracer::world::object::Instance;
use crate::tracer::world::object::{Object, Probe};

/// A closed solid whose seams [`leaks`] aims at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solid {
    /// The unit icosahedron subdivided three times (1280 triangles, 642 shared vertices).
    Icosphere,
    /// The cube `[-1, 1]³` as 12 triangles on 8 shared vertices (each face split on a diagonal).
    TriangleCube,
    /// The cube `[-1, 1]³` as six quads (`box_faces`): closed only through their edge tolerance.
    QuadBox,
}

/// Where on a solid the rays are aimed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aim {
    /// A random point of a random edge two faces share.
    Edges,
    /// A random vertex (for the quad box, a corner three faces share).
    Vertices,
}

/// A flat shape for [`acne`] (and, as a box's faces, [`thin`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flat {
    /// A parallelogram, or a box of six.
    Quad,
    /// A one-triangle mesh, or a box of twelve.
    Triangle,
    /// A disc of radius 0.5 in the parallelogram's plane, at its centre ([`acne`] only).
    Disc,
}

/// What [`acne`] counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Acne {
    /// Rays aimed at the shape's inside that missed it (none expected).
    pub missed: u64,
    /// Rays spawned to the hit's own side that met the shape again (self-intersection).
    pub acne: u64,
    /// Rays spawned through the shape (the refracted side) that met it again.
    pub blocked: u64,
}

/// What [`thin`] counts, against an exact f64 slab test of the same box and ray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Thin {
    /// Rays that surely cross the box (by more than the margin) but found no hit.
    pub missed: u64,
    /// Rays that surely miss the box (by more than the margin) but found a hit.
    pub false_hits: u64,
    /// Rays within the margin of an edge, which may go either way (not judged).
    pub ambiguous: u64,
}

/// One line of the table: a case, its rays and its failures (the headline count).
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// What is tested.
    pub case: String,
    /// Rays shot.
    pub rays: u64,
    /// Rays that went wrong: leaks, acne + blocked, or misses + false hits.
    pub failures: u64,
    /// The failures broken down, and what was not judged.
    pub detail: String,
}

/// A reproducible stream of uniform numbers.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn f(&mut self) -> f64 {
        self.0 += 1;
        (mix(self.0) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }

    fn index(&mut self, len: usize) -> usize {
        ((self.f() * len as f64) as usize).min(len - 1)
    }

    pub(crate) fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length_squared();
            if l > 1e-4 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }
}

/// The rigid placement of the instanced cases: turned 30° about y, then 20° about x, then
/// moved by `offset`.
pub fn placement(offset: DVec3) -> Transform {
    Transform::rotate_y(30.0).then(&Transform::rotate_x(20.0)).then_translate(from_dvec3(offset))
}

/// Where the instanced solids and thin boxes are moved to.
pub(crate) const NEAR: DVec3 = DVec3::new(1.0, 0.5, -1.0);

/// The objects as the world, or as one instance placed by `placed`.
pub(crate) fn world(objects: Vec<Object>, placed: Option<Transform>) -> Group {
    match placed {
        None => Group::new(objects),
        Some(t) => Group::new(vec![Object::Instance(Box::new(Instance::new(t, Group::new(objects))))]),
    }
}

/// The ray from outside through `target` (in the shape's own frame, coming from direction
/// `from`), placed in the world's frame by `placed`: the target and the start `target + 3·from`
/// are placed in f64, the start rounded to the renderer's numbers, and the direction taken from
/// the rounded start to the exact target, so the ray passes within rounding of the target
/// however far from the origin it is.
pub(crate) fn aimed(target: DVec3, from: DVec3, placed: Option<Transform>) -> Ray {
    let (target, from) = match placed {
        None => (target, from),
        Some(t) => {
            let column = |a: Vec3| to_dvec3(t.vector(a));
            let turn = |x: DVec3| column(Vec3::X) * x.x + column(Vec3::Y) * x.y + column(Vec3::Z) * x.z;
            (turn(target) + to_dvec3(t.point(Vec3::ZERO)), turn(from))
        }
    };
    let origin = from_dvec3(target + 3.0 * from);
    Ray::new(origin, from_dvec3((target - to_dvec3(origin)).normalize()))
}

/// Whether `ray` meets anything in `world`, searched with the vector level `isa`.
pub(crate) fn hits(world: &Group, ray: &Ray, isa: Isa) -> bool {
    world.hit(ray, Real::INFINITY, &Probe { isa, ..Probe::default() }).is_some()
}

/// A mesh object from f64 positions, rounded to the renderer's numbers; also returns the
/// rounded positions in f64.
fn mesh((positions, triangles): (Vec<DVec3>, Vec<[u32; 3]>)) -> (Object, Vec<DVec3>, Vec<[u32; 3]>) {
    let real: Vec<Vec3> = positions.iter().map(|&p| from_dvec3(p)).collect();
    let exact = real.iter().map(|&p| to_dvec3(p)).collect();
    let m = Mesh::new(real, vec![], vec![], triangles.clone()).expect("a valid mesh");
    (Object::Mesh(Arc::new(m), 0), exact, triangles)
}

/// A direction from outside into `solid` through its surface point `p`, never within
/// 0.1 (cosine) of grazing any face that `p` lies on.
fn inward(solid: Solid, p: DVec3, rng: &mut Rng) -> DVec3 {
    loop {
        let mut d = rng.unit();
        if solid == Solid::Icosphere {
            let c = d.dot(p.normalize());
            if c.abs() > 0.3 {
                return -c.signum() * d;
            }
            continue;
        }
        let mut ok = true;
        for k in 0..3 {
            if p[k].abs() == 1.0 {
                d[k] = -d[k].abs() * p[k].signum();
                ok &= d[k].abs() > 0.1;
            }
        }
        if ok {
            return d;
        }
    }
}

/// Rays from outside aimed exactly at `solid`'s shared edges or vertices, in its own frame or
/// through an instance (`placed`): returns how many of `rays` missed it entirely.
///
/// ```
/// use raypool::measure::stress_shapes::{Aim, Solid, leaks};
/// use raypool::tracer::accel::isa::Isa;
/// assert_eq!(leaks(Solid::Icosphere, Aim::Edges, false, 1000, Isa::best()), 0);
/// ```
pub fn leaks(solid: Solid, aim: Aim, placed: bool, rays: u64, isa: Isa) -> u64 {
    let cube = || mesh(cube(DVec3::splat(-1.0), DVec3::splat(1.0)));
    let (object, positions, triangles) = match solid {
        Solid::Icosphere => mesh(icosphere(3)),
        _ => cube(),
    };
    let mut seams = edges(&triangles);
    let objects = if solid == Solid::QuadBox {
        // The box's own twelve edges (not the triangles' diagonals): one coordinate varies.
        seams.retain(|&[a, b]| (positions[a] - positions[b]).cmpeq(DVec3::ZERO).bitmask().count_ones() == 2);
        let faces = box_faces(Vec3::splat(-1.0), Vec3::splat(1.0), 0).expect("a valid box");
        faces.map(Object::shape).to_vec()
    } else {
        vec![object]
    };
    let placed = placed.then(|| placement(NEAR));
    let world = world(objects, placed);
    let mut rng = Rng(0x5EA7 + solid as u64 * 16 + aim as u64);
    let mut leaks = 0;
    for _ in 0..rays {
        let p = match aim {
            Aim::Edges => {
                let [a, b] = seams[rng.index(seams.len())];
                positions[a] + (positions[b] - positions[a]) * rng.f()
            }
            Aim::Vertices => positions[rng.index(positions.len())],
        };
        let dir = inward(solid, p, &mut rng);
        leaks += !hits(&world, &aimed(p, -dir, placed), isa) as u64;
    }
    leaks
}

/// A unit direction on `n`'s side; one in four within 0.006° to 6° of grazing.
fn hemisphere(n: DVec3, rng: &mut Rng) -> DVec3 {
    let d = rng.unit();
    let d = if d.dot(n) < 0.0 { -d } else { d };
    let tangent = (d - n * d.dot(n)).normalize_or_zero();
    if rng.f() < 0.25 && tangent != DVec3::ZERO {
        let c = 10f64.powf(rng.range(-4.0, -1.0));
        return tangent * (1.0 - c * c).sqrt() + n * c;
    }
    d
}

/// A tilted unit-sized quad, triangle or disc `distance` from the origin along (1, 1, 1) (as
/// its own coordinates, or through an instance that turns it and moves it there): rays hit it
/// from both sides, and from each hit one ray is spawned back to the hit's side and one
/// through it. None may meet the shape again.
///
/// ```
/// use raypool::measure::stress_shapes::{Flat, acne};
/// let a = acne(Flat::Quad, 1e4, false, 1000, raypool::tracer::accel::isa::Isa::best());
/// assert_eq!((a.missed, a.acne, a.blocked), (0, 0, 0));
/// ```
pub fn acne(flat: Flat, distance: f64, placed: bool, rays: u64, isa: Isa) -> Acne {
    let far = DVec3::splat(distance);
    let (placed, corner) = if placed { (Some(placement(far)), DVec3::ZERO) } else { (None, far) };
    let (q, u, v) =
        (from_dvec3(corner), from_dvec3(DVec3::new(1.0, 0.3, 0.2)), from_dvec3(DVec3::new(-0.2, 1.0, 0.5)));
    let disc = Disc::new(q + 0.5 * (u + v), u.cross(v), 0.5, 0).expect("a valid disc");
    let object = match flat {
        Flat::Quad => Object::shape(Quad::new(q, u, v, 0).expect("a valid quad")),
        Flat::Triangle => mesh((vec![to_dvec3(q), to_dvec3(q + u), to_dvec3(q + v)], vec![[0, 1, 2]])).0,
        Flat::Disc => Object::shape(disc),
    };
    let world = world(vec![object], placed);
    // The edges as the shape has them (a triangle's corners `q + u` are rounded); a disc's
    // points are drawn about its centre, in a frame of its plane.
    let (q, u, v) = match flat {
        Flat::Quad => (to_dvec3(q), to_dvec3(u), to_dvec3(v)),
        Flat::Triangle => (to_dvec3(q), to_dvec3(q + u) - to_dvec3(q), to_dvec3(q + v) - to_dvec3(q)),
        Flat::Disc => {
            let (n, first) = (to_dvec3(disc.normal()), to_dvec3(u).normalize());
            (to_dvec3(disc.center), first, n.cross(first))
        }
    };
    let n = u.cross(v).normalize();
    let mut rng = Rng(0xAC7E + flat as u64 * 16 + distance.log10() as u64 + placed.is_some() as u64 * 256);
    let mut out = Acne::default();
    let probe = Probe { isa, ..Probe::default() };
    for _ in 0..rays {
        // A point at least 0.02 (in units of the edges, or of the diameter) inside the shape.
        let (a, b) = loop {
            let (a, b) = (rng.range(0.02, 0.98), rng.range(0.02, 0.98));
            let inside = match flat {
                Flat::Quad => true,
                Flat::Triangle => a + b <= 0.98,
                Flat::Disc => (a - 0.5).hypot(b - 0.5) <= 0.48,
            };
            if inside {
                break if flat == Flat::Disc { (a - 0.5, b - 0.5) } else { (a, b) };
            }
        };
        let p = q + a * u + b * v;
        let w = loop {
            let w = rng.unit();
            if w.dot(n).abs() > 0.1 {
                break w;
            }
        };
        let Some(hit) = world.hit(&aimed(p, w, placed), Real::INFINITY, &probe) else {
            out.missed += 1;
            continue;
        };
        let side = to_dvec3(hit.normal).normalize();
        out.acne += hits(&world, &hit.spawn(from_dvec3(hemisphere(side, &mut rng))), isa) as u64;
        out.blocked += hits(&world, &hit.spawn(from_dvec3(hemisphere(-side, &mut rng))), isa) as u64;
    }
    out
}

/// Whether the ray `o + t·d`, `t ≥ 0`, meets the box `[lo, hi]` (exact slab test in f64;
/// an empty box is never met).
fn slab(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> bool {
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if lo[k] > hi[k] {
            return false;
        }
        if d[k] == 0.0 {
            if o[k] < lo[k] || o[k] > hi[k] {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        (t0, t1) = (t0.max(a.min(b)), t1.min(a.max(b)));
    }
    t0 <= t1
}

/// A 1 × `thickness` × 1 box (six quads, or twelve triangles) and rays aimed at and around
/// it, half of them within 10⁻⁷ to 10⁻¹ (slope) of parallel to its large faces: each hit or
/// miss is checked against an exact slab test of the same box (corners as rounded) and the
/// same ray (as rounded, taken back to the box's frame in f64 when `placed`). Rays within
/// 16 ε (32 ε when placed) of an edge are not judged.
pub fn thin(flat: Flat, thickness: f64, placed: bool, rays: u64, isa: Isa) -> Thin {
    let (lo, hi) = (DVec3::new(-0.5, -thickness / 2.0, -0.5), DVec3::new(0.5, thickness / 2.0, 0.5));
    let (lo, hi) = (to_dvec3(from_dvec3(lo)), to_dvec3(from_dvec3(hi)));
    let objects = match flat {
        Flat::Quad => {
            box_faces(from_dvec3(lo), from_dvec3(hi), 0).expect("a valid box").map(Object::shape).to_vec()
        }
        Flat::Triangle => vec![mesh(cube(lo, hi)).0],
        Flat::Disc => panic!("a box has no disc faces: thin takes a quad or a triangle"),
    };
    let transform = placement(NEAR);
    let placed = placed.then_some(transform);
    let world = world(objects, placed);
    // The placement in f64, from the very numbers the instance uses.
    let columns = [Vec3::X, Vec3::Y, Vec3::Z].map(|a| to_dvec3(transform.vector(a)));
    let offset = to_dvec3(transform.point(Vec3::ZERO));
    let back = |x: DVec3| DVec3::new(columns[0].dot(x), columns[1].dot(x), columns[2].dot(x));
    let margin = 16.0 * f64::from(Real::EPSILON) * if placed.is_some() { 2.0 } else { 1.0 };
    let mut rng =
        Rng(0x7417 + flat as u64 * 16 + (-thickness.log10()) as u64 + placed.is_some() as u64 * 256);
    let mut out = Thin::default();
    for _ in 0..rays {
        let target = DVec3::new(rng.range(-0.6, 0.6), rng.range(-1.5, 1.5) * thickness, rng.range(-0.6, 0.6));
        let dir = if rng.f() < 0.5 {
            let (a, slope) = (rng.range(0.0, TAU), 10f64.powf(rng.range(-7.0, -1.0)));
            let sign = if rng.f() < 0.5 { -1.0 } else { 1.0 };
            DVec3::new(a.cos(), sign * slope, a.sin()).normalize()
        } else {
            rng.unit()
        };
        let r = aimed(target, -dir, placed);
        let (mut o, mut d) = (to_dvec3(r.origin), to_dvec3(r.dir));
        if placed.is_some() {
            (o, d) = (back(o - offset), back(d));
        }
        let sure = slab(o, d, lo + margin, hi - margin);
        let maybe = slab(o, d, lo - margin, hi + margin);
        let got = hits(&world, &r, isa);
        match (sure, maybe, got) {
            (true, _, false) => out.missed += 1,
            (_, false, true) => out.false_hits += 1,
            (false, true, _) => out.ambiguous += 1,
            _ => {}
        }
    }
    out
}

/// Every case at `rays` rays each, searched with the vector level `isa`, in the order of the
/// table.
pub fn table(rays: u64, isa: Isa) -> Vec<Row> {
    let mut rows = Vec::new();
    for placed in [false, true] {
        let how = if placed { ", through an instance" } else { "" };
        for (solid, name) in [
            (Solid::Icosphere, "closed icosphere, 1280 triangles"),
            (Solid::TriangleCube, "cube of 12 triangles"),
            (Solid::QuadBox, "box of 6 quads"),
        ] {
            for (aim, at) in [(Aim::Edges, "shared edges"), (Aim::Vertices, "shared vertices")] {
                let n = leaks(solid, aim, placed, rays, isa);
                let case = format!("leaks: {name}, rays at {at}{how}");
                rows.push(Row { case, rays, failures: n, detail: format!("{n} leaks") });
            }
        }
        for (flat, name) in [(Flat::Quad, "quad"), (Flat::Triangle, "triangle"), (Flat::Disc, "disc")] {
            for distance in [1e4, 1e5, 1e6] {
                let a = acne(flat, distance, placed, rays, isa);
                rows.push(Row {
                    case: format!("acne: tilted {name} {distance:.0e} from the origin{how}"),
                    rays,
                    failures: a.acne + a.blocked + a.missed,
                    detail: format!("{} acne, {} blocked, {} primary misses", a.acne, a.blocked, a.missed),
                });
            }
        }
        for (flat, name) in [(Flat::Quad, "6 quads"), (Flat::Triangle, "12 triangles")] {
            for thickness in [1e-3, 1e-4, 1e-5] {
                let t = thin(flat, thickness, placed, rays, isa);
                rows.push(Row {
                    case: format!("thin box of {name}, thickness {thickness:.0e}, grazing rays{how}"),
                    rays,
                    failures: t.missed + t.false_hits,
                    detail: format!(
                        "{} missed, {} false hits, {} within the margin",
                        t.missed, t.false_hits, t.ambiguous
                    ),
                });
            }
        }
    }
    rows
}
