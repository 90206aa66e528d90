//! Triangle meshes, as pbrt keeps them: flat and indexed. The vertices' positions (and,
//! when the file gives them, normals and texture coordinates) are stored once; a triangle is
//! three indices into them, never three copied points. A mesh keeps its own tree
//! over its triangles and is one object in its scene's (or group's) tree.
//!
//! Triangles are tested with the watertight test (`geometry/triangle.rs`), so a closed mesh
//! has no cracks between neighbours; new rays start a few ulps of the mesh's own magnitude
//! off it, as off a sphere. Each leaf of the tree (up to eight triangles) also keeps its
//! triangles' corners copied lane by lane, a [`Triangles8`], so that a leaf is one eight-lane
//! test reading one 288-byte block, not eight tests each gathering three vertices through
//! their indices (Embree keeps its leaves so, four to a block). The tree is eight-wide
//! ([`Bvh8`]); its slab tests and its leaves' tests run in the eight lanes of the scene's
//! vector level: one AVX register where the CPU has it, so a leaf of eight costs what a leaf
//! of four would.

use crate::tracer::accel::bvh::Bvh;
use crate::tracer::accel::isa::Isa;
use crate::tracer::accel::wide8::Bvh8;
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::geometry::triangle::{self, RayFrame, TriangleHit, Triangles8};
use crate::tracer::math::aabb::{Aabb, Bounded};
use crate::tracer::math::lanes::{Lanes8, WithLanes8};
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3};

/// Triangles per leaf of a mesh's tree: one per lane.
const LEAF: usize = triangle::LANES;

/// A triangle mesh.
#[derive(Clone, Debug)]
pub struct Mesh {
    positions: Vec<Vec3>,
    /// One per position, unit length (zero where the file's had none), or empty (then the
    /// flat face normal shades).
    normals: Vec<Vec3>,
    /// One `(u, v)` per position, or empty (then a triangle's barycentric `(b1, b2)`).
    uvs: Vec<[Real; 2]>,
    /// Vertex indices, in the tree's order.
    triangles: Vec<[u32; 3]>,
    /// Its leaves are numbered: leaf `k`'s corners are `leaves[k]`, for the test (spare lanes
    /// never hit), and its triangles, in lane order, start at `first[k]` (read only on a hit).
    tree: Bvh8,
    leaves: Vec<Triangles8>,
    first: Vec<u32>,
    bounds: Aabb,
    /// Off-surface distance for new rays, from the mesh's magnitude.
    offset: Real,
}

/// A triangle while the tree is built: its indices, box and centre.
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

impl Mesh {
    /// A mesh of `triangles` over `positions`, with optional per-vertex `normals` and `uvs`
    /// (empty, or one per position). Refuses, with a sentence naming the first, an index out
    /// of range, a triangle of zero area, a number that is not finite, or no triangle at all.
    ///
    /// ```
    /// use raypool::tracer::{accel::isa::Isa, world::mesh::Mesh};
    /// use raypool::tracer::math::{ray::Ray, real::Vec3};
    /// let square = Mesh::new(
    ///     vec![Vec3::new(-1.0, -1.0, -3.0), Vec3::new(1.0, -1.0, -3.0), Vec3::new(1.0, 1.0, -3.0), Vec3::new(-1.0, 1.0, -3.0)],
    ///     vec![], vec![], vec![[0, 1, 2], [0, 2, 3]],
    /// ).unwrap();
    /// assert_eq!(square.hit(&Ray::new(Vec3::ZERO, -Vec3::Z), f32::INFINITY, 0, Isa::best()).unwrap().t, 3.0);
    /// assert!(Mesh::new(vec![Vec3::ZERO; 3], vec![], vec![], vec![[0, 1, 2]]).is_err(), "no area");
    /// ```
    pub fn new(
        positions: Vec<Vec3>,
        normals: Vec<Vec3>,
        uvs: Vec<[Real; 2]>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<Mesh, String> {
        if triangles.is_empty() {
            return Err("a mesh needs at least one triangle".to_owned());
        }
        if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
            return Err(format!("vertex {} is not finite numbers", k + 1));
        }
        for (what, len) in [("normals", normals.len()), ("texture coordinates", uvs.len())] {
            if len != 0 && len != positions.len() {
                return Err(format!("{len} {what} for {} vertices", positions.len()));
            }
        }
        let mut building = Vec::with_capacity(triangles.len());
        for (k, &indices) in triangles.iter().enumerate() {
            if let Some(&i) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(format!("triangle {} names vertex {} of {}", k + 1, i + 1, positions.len()));
            }
            let p = indices.map(|i| positions[i as usize]);
            if triangle::degenerate(p) {
                return Err(format!(
                    "triangle {} has zero area (vertices {:?})",
                    k + 1,
                    p.map(|v| v.to_array())
                ));
            }
            let bounds = p.iter().fold(Aabb::EMPTY, |b, &v| b.grow(v));
            building.push(Building { indices, bounds });
        }
        // Unit once here, not at every hit that raises its point (`Mesh::lift`).
        let normals = normals.into_iter().map(Vec3::normalize_or_zero).collect();
        let whole = building.iter().fold(Aabb::EMPTY, |b, t| b.union(t.bounds));
        let offset = 8.0 * Real::EPSILON * whole.magnitude();
        // Boxes padded as the spheres' are: a quarter of the spawn offset.
        building.iter_mut().for_each(|t| t.bounds = t.bounds.padded(0.25 * offset));
        let binary = Bvh::build_with_leaves(&mut building, LEAF);
        let (tree, ranges) = Bvh8::collapse(&binary);
        let leaves = ranges
            .iter()
            .map(|range| {
                let corners: Vec<_> = building[range.clone()]
                    .iter()
                    .map(|t| t.indices.map(|i| positions[i as usize]))
                    .collect();
                Triangles8::new(&corners)
            })
            .collect();
        let first = ranges.iter().map(|range| range.start as u32).collect();
        let triangles = building.iter().map(|t| t.indices).collect();
        let bounds = whole.padded(0.25 * offset);
        Ok(Mesh { positions, normals, uvs, triangles, tree, leaves, first, bounds, offset })
    }

    /// The same mesh with every vertex multiplied by `factor` (> 0): normals and texture
    /// coordinates are kept, since a uniform scale changes neither.
    pub fn scaled(self, factor: Real) -> Mesh {
        let positions = self.positions.iter().map(|&p| p * factor).collect();
        let triangles = self.triangles.clone();
        Mesh::new(positions, self.normals, self.uvs, triangles).expect("a scaled mesh keeps its area")
    }

    /// Whether its hits are shaded by normals from the file (else by each face's own).
    pub fn has_normals(&self) -> bool {
        !self.normals.is_empty()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The positions, shared by the triangles.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// The triangles' vertex indices (in the tree's order).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The three corners of triangle `k`.
    #[inline(always)]
    pub fn corners(&self, k: usize) -> [Vec3; 3] {
        self.triangles[k].map(|i| self.positions[i as usize])
    }

    /// The nearest triangle hit in `(0, t_max)` as `(triangle, hit)`, ties to the lower index,
    /// searched with the vector instructions of `isa` (the same answer at every level).
    #[inline]
    pub fn closest(&self, ray: &Ray, t_max: Real, isa: Isa) -> Option<(usize, TriangleHit)> {
        isa.run_lanes(ClosestSearch { mesh: self, ray, t_max })
    }

    /// Whether any triangle is hit in `(0, t_max)`: the search ends at the first found.
    #[inline]
    pub fn occludes(&self, ray: &Ray, t_max: Real, isa: Isa) -> bool {
        isa.run_lanes(OcclusionSearch { mesh: self, ray, t_max })
    }

    /// The nearest hit in `(0, t_max)`, with `material`.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: Real, material: u32, isa: Isa) -> Option<Hit> {
        let (k, found) = self.closest(ray, t_max, isa)?;
        let [i0, i1, i2] = self.triangles[k].map(|i| i as usize);
        let [b0, b1, b2] = found.barycentric;
        let p = [self.positions[i0], self.positions[i1], self.positions[i2]];
        let geometric = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let front_face = ray.dir.dot(geometric) < 0.0;
        let facing = if front_face { geometric } else { -geometric };
        let point = b0 * p[0] + b1 * p[1] + b2 * p[2];
        // A shading normal, where the file gives them, turned to the side the ray sees.
        let (normal, lift) = if self.normals.is_empty() {
            (facing, 0.0)
        } else {
            let n =
                (b0 * self.normals[i0] + b1 * self.normals[i1] + b2 * self.normals[i2]).normalize_or_zero();
            if n == Vec3::ZERO {
                (facing, 0.0)
            } else {
                let side = if n.dot(facing) > 0.0 { 1.0 } else { -1.0 };
                let normal = side * n;
                (normal, self.lift(point, [i0, i1, i2], found.barycentric, side, normal))
            }
        };
        let (u, v) = if self.uvs.is_empty() {
            (b1, b2)
        } else {
            let uv = |c: usize| b0 * self.uvs[i0][c] + b1 * self.uvs[i1][c] + b2 * self.uvs[i2][c];
            (uv(0), uv(1))
        };
        Some(Hit { t: found.t, point, normal, front_face, material, offset: self.offset, lift, u, v })
    }

    /// How far above the flat triangle, along `normal`, rises the curved surface that its
    /// vertex normals describe, at `point` (barycentric `b` of the triangle whose vertices are
    /// `corners`; `side` turns the normals to the side the ray came from): Hanika's "Hacking
    /// the shadow terminator" (2021), as Cycles offsets rays. Where the surface bulges (the
    /// point lies below a vertex's tangent plane), the point is raised towards each such
    /// plane, weighted by `b`. Paths leave on the normal's side from that much higher
    /// ([`Hit::departure`]): interpolated normals lean away from the flat facets, and a
    /// bounce drawn about one may point below the facet it leaves, into its own mesh. On a
    /// coarse mesh the smooth surface strays from the curve the mesh stands for by about as
    /// much as the facets do, outside it where they sag inside (measured on two spheres:
    /// `results/history/comment-figures.md`).
    fn lift(&self, point: Vec3, corners: [usize; 3], b: [Real; 3], side: Real, normal: Vec3) -> Real {
        let raised: Vec3 = (0..3)
            .map(|k| {
                let n = side * self.normals[corners[k]];
                let below = (point - self.positions[corners[k]]).dot(n).min(0.0);
                -b[k] * below * n
            })
            .sum();
        raised.dot(normal).max(0.0)
    }

    /// The mesh's box.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}

/// [`Mesh::closest`]'s search, run with the lanes of the scene's vector level.
struct ClosestSearch<'a> {
    mesh: &'a Mesh,
    ray: &'a Ray,
    t_max: Real,
}

impl WithLanes8 for ClosestSearch<'_> {
    type Output = Option<(usize, TriangleHit)>;

    #[inline(always)]
    fn run<L: Lanes8>(self, lanes: L) -> Self::Output {
        let mut closest = Closest::none(self.t_max);
        // The closest hit's distance and barycentric coordinates, worked out when a lane wins
        // (about once a ray): copying the leaf test's whole findings instead moved 160 bytes,
        // which at the avx512 level the compiler does in 512-bit registers (slower on Intel).
        let mut best = None;
        let frame = RayFrame::new(self.ray);
        self.mesh.tree.traverse(
            lanes,
            self.ray,
            &mut closest,
            // Inlined, or the leaf test runs in a copy compiled for the baseline at every level.
            #[inline(always)]
            |leaf: usize, closest: &mut Closest| {
                let hits = self.mesh.leaves[leaf].intersect(lanes, &frame, closest.bound());
                for lane in hits.lanes() {
                    let k = self.mesh.first[leaf] + lane as u32;
                    closest.offer(hits.t(lane), k);
                    if closest.index == k {
                        best = Some(hits.hit(lane));
                    }
                }
            },
        );
        let (k, _) = closest.found()?;
        Some((k, best.expect("a found triangle was found by a leaf")))
    }
}

/// [`Mesh::occludes`]'s search, run with the lanes of the scene's vector level.
struct OcclusionSearch<'a> {
    mesh: &'a Mesh,
    ray: &'a Ray,
    t_max: Real,
}

impl WithLanes8 for OcclusionSearch<'_> {
    type Output = bool;

    #[inline(always)]
    fn run<L: Lanes8>(self, lanes: L) -> bool {
        let mut closest = Closest::none(self.t_max);
        let mut found = false;
        let frame = RayFrame::new(self.ray);
        self.mesh.tree.traverse(
            lanes,
            self.ray,
            &mut closest,
            #[inline(always)]
            |leaf: usize, closest: &mut Closest| {
                if self.mesh.leaves[leaf].intersect(lanes, &frame, self.t_max).any() {
                    found = true;
                    closest.rule_out_rest();
                }
            },
        );
        found
    }
}
