//! A scene ready to render: flat arrays of spheres and materials, a background, a camera; and,
//! for the second book's scenes, a world of objects and textures.
//!
//! Built from a [`SceneFile`](crate::scenes::format::SceneFile), which is what users write;
//! this is what the tracer reads. Everything is plain data (`Sync` for free), shared by
//! reference between render threads.
//!
//! **Skip what a scene doesn't need.** A scene of the first book's kinds (static spheres;
//! diffuse, metal and glass) keeps the sphere search of `accel/` and the render loop that
//! never asks for emission, textures, time or media ([`Scene::is_first_book`], decided once
//! per render, not per ray). Any other scene puts every object, spheres too, in one
//! [`Group`], searched with a [`Probe`] that carries the ray's time and media seed, and each
//! of those is drawn only if the scene has something that moves ([`Scene::has_motion`]) or a
//! medium ([`Scene::has_media`]).

use crate::tracer::accel::bvh::{Bvh, half_area_around};
use crate::tracer::accel::isa::Isa;
use crate::tracer::accel::wide::WideBvh;
use crate::tracer::camera::CameraSettings;
use crate::tracer::geometry::hit::{Closest, Hit};
use crate::tracer::geometry::sphere::{Intersection, Sphere};
use crate::tracer::lights::casters::Casters;
use crate::tracer::lights::power::Lights;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::Real;
use crate::tracer::shading::background::Background;
use crate::tracer::shading::material::Material;
use crate::tracer::shading::texture::Textures;
use crate::tracer::world::object::{Group, TREE_MIN_OBJECTS};
use crate::tracer::world::object::{Object, Probe};

/// Scenes with fewer spheres than this test every sphere: a hierarchy costs more than it
/// saves there (`results/perf.md`).
pub const BVH_MIN_SPHERES: usize = 6;

/// Scenes with fewer spheres than this (but at least [`BVH_MIN_SPHERES`]) use the binary
/// tree: measured with `--accel`, the four-wide one was slower on paper2 (7 spheres),
/// inconclusive on paper3 (21) and faster on `final` (486) (`results/perf.md`).
pub const WIDE_MIN_SPHERES: usize = 64;

/// A sphere whose box has at least this fraction of the half-area of the box around every
/// sphere is "huge" (the ground of `final`, radius 1000): nearly every ray enters its box,
/// so it is tested directly, before the hierarchy, instead of from inside it.
const HUGE_FRACTION: Real = 0.5;
/// At most this many spheres are kept apart as huge.
const MAX_HUGE: usize = 4;

/// Spheres per leaf of the four-wide tree (measured: `results/perf.md`).
const WIDE_LEAF: usize = 4;

/// How a scene finds the closest hit: what the ablation table switches. Every choice finds
/// exactly the same hits (`tests/bvh.rs`); only the time differs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accel {
    /// Test every sphere, one by one.
    Flat,
    /// The binary SAH tree of `accel/bvh.rs`: the default from [`BVH_MIN_SPHERES`] to
    /// [`WIDE_MIN_SPHERES`] spheres.
    Binary,
    /// The four-wide tree of `accel/wide.rs`, leaves of up to four spheres tested one by one: the
    /// default for scenes of [`WIDE_MIN_SPHERES`] or more.
    Wide,
    /// The four-wide tree, each leaf's spheres tested together in the lanes of one SIMD
    /// register (`accel/packet.rs`).
    WidePackets,
    /// The four-wide tree with the huge spheres (the ground) kept out of it and tested
    /// directly for every ray.
    WideHugeApart,
}

/// The hierarchy over the spheres that are not tested directly.
#[derive(Clone, Debug)]
enum Tree {
    None,
    Binary(Bvh),
    Wide(WideBvh),
}

/// Geometry, materials, background and camera of one scene.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Spheres tested directly first, then the spheres the tree holds.
    spheres: Vec<Sphere>,
    materials: Vec<Material>,
    /// Over `spheres[direct_count..]`.
    tree: Tree,
    /// `spheres[..direct_count]` are tested for every ray, one by one.
    direct_count: usize,
    accel: Accel,
    /// How rays meet spheres: robust unless a comparison asks for the book's method.
    intersection: Intersection,
    /// Light for rays that escape.
    pub background: Background,
    /// Camera parameters (the image size is chosen at render time).
    pub camera: CameraSettings,
    /// Every object of a second-book scene (empty in a first-book one).
    objects: Group,
    /// The textures its materials use.
    pub textures: Textures,
    /// Whether the sphere search and the first book's render loop serve.
    first_book: bool,
    /// Whether anything moves during the shutter interval.
    motion: bool,
    /// Whether any object is a participating medium.
    media: bool,
    /// The emitters paths can aim at (none in a first-book scene).
    lights: Lights,
    /// The glass balls paths aim at the lights through (none without lights).
    casters: Casters,
    /// The widest vector instructions its searches use: the CPU's best unless
    /// [`Scene::with_isa`] chose another (the same hits at every level).
    isa: Isa,
}

impl Scene {
    /// A scene of these spheres (each `material` indexing `materials`). Scenes of
    /// [`BVH_MIN_SPHERES`] or more get a hierarchy (binary, then four-wide from
    /// [`WIDE_MIN_SPHERES`]), which reorders the spheres.
    ///
    /// # Panics
    /// If a sphere's material index is out of range.
    pub fn new(
        spheres: Vec<Sphere>,
        materials: Vec<Material>,
        background: Background,
        camera: CameraSettings,
    ) -> Scene {
        Scene::with_world(spheres, Vec::new(), materials, Textures::default(), background, camera)
    }

    /// A scene of these spheres and other `objects`, with `textures` for its materials. If it
    /// has only static spheres and the first book's materials, it is exactly
    /// [`Scene::new`]'s; otherwise every sphere joins the objects in one [`Group`].
    ///
    /// # Panics
    /// If a material index is out of range.
    pub fn with_world(
        spheres: Vec<Sphere>,
        objects: Vec<Object>,
        materials: Vec<Material>,
        textures: Textures,
        background: Background,
        camera: CameraSettings,
    ) -> Scene {
        let mut used: Vec<u32> = spheres.iter().map(|s| s.material).collect();
        objects.iter().for_each(|o| o.materials(&mut used));
        assert!(used.iter().all(|&m| (m as usize) < materials.len()), "material index out of range");
        let first_book = objects.is_empty() && materials.iter().all(Material::is_first_book);
        if !first_book {
            let objects: Vec<Object> = spheres.into_iter().map(Object::shape).chain(objects).collect();
            let lights = Lights::new(&objects, &materials);
            let casters = if lights.is_empty() {
                Casters::default()
            } else {
                Casters::new(&objects, &materials, lights.bounds)
            };
            let mut objects = Group::new(objects);
            objects.keep_uv_for(&|m| materials[m as usize].reads_uv(&textures));
            let (motion, media) = objects.needs();
            let accel = if objects.has_tree() { Accel::Wide } else { Accel::Flat };
            return Scene {
                spheres: Vec::new(),
                materials,
                tree: Tree::None,
                direct_count: 0,
                accel,
                intersection: Intersection::Robust,
                background,
                camera,
                objects,
                textures,
                first_book,
                motion,
                media,
                lights,
                casters,
                isa: Isa::best(),
            };
        }
        let accel = match spheres.len() {
            n if n < BVH_MIN_SPHERES => Accel::Flat,
            n if n < WIDE_MIN_SPHERES => Accel::Binary,
            _ => Accel::Wide,
        };
        let scene = Scene {
            spheres,
            materials,
            tree: Tree::None,
            direct_count: 0,
            accel: Accel::Flat,
            intersection: Intersection::Robust,
            background,
            camera,
            objects: Group::new(Vec::new()),
            textures,
            first_book,
            motion: false,
            media: false,
            lights: Lights::default(),
            casters: Casters::default(),
            isa: Isa::best(),
        };
        scene.with_accel(accel)
    }

    /// The same scene with another way of finding hits (for comparisons). Rebuilding may
    /// reorder the spheres; [`Accel::Flat`] keeps their order, so it finds exactly what the
    /// scene's hierarchy finds, ties included.
    ///
    /// A second-book scene has one choice only: its group searched one object at a time
    /// ([`Accel::Flat`]) or through its tree (every other choice).
    pub fn with_accel(mut self, accel: Accel) -> Scene {
        if !self.first_book {
            let tree = accel != Accel::Flat && self.objects.objects().len() >= TREE_MIN_OBJECTS;
            self.objects = self.objects.rebuilt(tree);
            self.accel = if tree { accel } else { Accel::Flat };
            return self;
        }
        let mut direct = match accel {
            Accel::Flat => self.spheres.len(),
            Accel::WideHugeApart => move_huge_first(&mut self.spheres),
            Accel::Binary | Accel::Wide | Accel::WidePackets => 0,
        };
        let rest = &mut self.spheres[direct..];
        self.tree = match accel {
            _ if rest.is_empty() => Tree::None,
            Accel::Flat => Tree::None,
            Accel::Binary => Tree::Binary(Bvh::build(rest)),
            Accel::Wide | Accel::WidePackets | Accel::WideHugeApart => {
                let binary = Bvh::build_with_leaves(rest, WIDE_LEAF);
                Tree::Wide(WideBvh::collapse(&binary, rest, direct))
            }
        };
        if matches!(self.tree, Tree::None) {
            direct = self.spheres.len();
        }
        self.direct_count = direct;
        self.accel = accel;
        self
    }

    /// The same scene searched with the vector instructions of `isa` (for tests and
    /// benchmarks: every level finds the same hits, only the time differs).
    pub fn with_isa(mut self, isa: Isa) -> Scene {
        self.isa = isa;
        self
    }

    /// The vector instructions its searches use.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// The same scene traced by testing every sphere (for the ablation table and the
    /// exactness tests: the same hits, only slower for large scenes).
    pub fn without_bvh(self) -> Scene {
        self.with_accel(Accel::Flat)
    }

    /// The same scene traced with another intersection method (for comparisons).
    pub fn with_intersection(mut self, intersection: Intersection) -> Scene {
        self.intersection = intersection;
        self
    }

    /// The spheres, in the order the hierarchy (if any) stored them.
    pub fn spheres(&self) -> &[Sphere] {
        &self.spheres
    }

    /// The material table.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Whether intersection goes through a bounding volume hierarchy.
    pub fn has_bvh(&self) -> bool {
        !matches!(self.tree, Tree::None) || self.objects.has_tree()
    }

    /// Whether this is a scene of the first book's kinds only (static spheres; diffuse, metal,
    /// glass), rendered by the sphere search and the render loop without emission, textures,
    /// time or media.
    pub fn is_first_book(&self) -> bool {
        self.first_book
    }

    /// Whether anything moves (camera rays then draw a time).
    pub fn has_motion(&self) -> bool {
        self.motion
    }

    /// Whether any object is a medium (rays then draw a seed for media).
    pub fn has_media(&self) -> bool {
        self.media
    }

    /// A second-book scene's objects, in their search order (empty for a first-book scene).
    pub fn objects(&self) -> &[Object] {
        self.objects.objects()
    }

    /// The closest hit along `ray` in a second-book scene.
    #[inline]
    pub fn hit_world(&self, ray: &Ray, probe: &Probe) -> Option<Hit> {
        self.objects.hit(ray, Real::INFINITY, probe)
    }

    /// Whether anything in a second-book scene is hit along `ray` in `(0, t_max)`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: Real, probe: &Probe) -> bool {
        self.objects.occludes(ray, t_max, probe)
    }

    /// Whether a mesh is shaded by normals from its file: the light paths of
    /// `--light-sampling bdpt` would then carry light as the camera's paths do not (a shading
    /// normal makes scattering asymmetric), so that setting refuses such scenes.
    pub fn has_shading_normals(&self) -> bool {
        self.objects.objects().iter().any(Object::has_shading_normals)
    }

    /// The emitters paths can aim at.
    pub fn lights(&self) -> &Lights {
        &self.lights
    }

    /// The glass balls paths aim at the lights through (`--light-sampling mis`).
    pub fn casters(&self) -> &Casters {
        &self.casters
    }

    /// How hits are found.
    pub fn accel(&self) -> Accel {
        self.accel
    }

    /// How many spheres are tested directly, outside any hierarchy (all of them for a flat
    /// scene; the huge ones for the default hierarchy).
    pub fn direct_count(&self) -> usize {
        self.direct_count
    }

    /// The closest hit along `ray` closer than `t_max`.
    ///
    /// One branch per ray picks the method: the robust test (the renderer's) or the book's
    /// (for comparisons only), each one sphere at a time unless [`Accel::WidePackets`] asks
    /// for four at once (robust test only).
    #[inline(always)]
    pub fn hit(&self, ray: &Ray, t_max: Real) -> Option<Hit> {
        match self.intersection {
            Intersection::Robust => {
                let (index, t) = self.closest(ray, t_max, Sphere::intersect)?;
                Some(self.spheres[index].hit_at(ray, t))
            }
            Intersection::Textbook => {
                let (index, t) = self.closest(ray, t_max, Sphere::intersect_textbook)?;
                Some(self.spheres[index].hit_at_textbook(ray, t))
            }
        }
    }

    /// The closest sphere `test` finds, as `(index, t)`: first the spheres tested directly
    /// (all of a flat scene's, the huge ones with [`Accel::WideHugeApart`]), then the tree.
    #[inline]
    fn closest(
        &self,
        ray: &Ray,
        t_max: Real,
        test: impl Fn(&Sphere, &Ray, Real) -> Option<Real>,
    ) -> Option<(usize, Real)> {
        // In index order with a strict bound the first sphere at a distance keeps it: ties
        // already go to the lower index, with no tie test (this is the loop of small scenes).
        let (mut nearest, mut found) = (t_max, None);
        for (i, sphere) in self.spheres[..self.direct_count].iter().enumerate() {
            if let Some(t) = test(sphere, ray, nearest) {
                (nearest, found) = (t, Some(i));
            }
        }
        match &self.tree {
            Tree::None => found.map(|i| (i, nearest)),
            // A binary tree holds every sphere (only `WideHugeApart` keeps some apart), so it
            // answers alone.
            Tree::Binary(bvh) => {
                debug_assert_eq!(self.direct_count, 0, "the binary tree holds every sphere");
                bvh.hit(&self.spheres, ray, t_max, test)
            }
            Tree::Wide(wide) => self.closest_wide(wide, ray, t_max, found.map(|i| (i, nearest)), test),
        }
    }

    /// The four-wide tree's search, after the spheres tested directly found `direct`. Kept out
    /// of line: with the wide traversal inlined, [`Scene::hit`] was a call that saved and
    /// restored six registers per ray for every scene; now only the wide tree costs a call
    /// (`results/history/comment-figures.md`).
    #[inline(never)]
    fn closest_wide(
        &self,
        wide: &WideBvh,
        ray: &Ray,
        t_max: Real,
        direct: Option<(usize, Real)>,
        test: impl Fn(&Sphere, &Ray, Real) -> Option<Real>,
    ) -> Option<(usize, Real)> {
        // The tree's visiting order is not the index order: ties are decided by `Closest`.
        let mut closest = Closest::none(t_max);
        if let Some((i, t)) = direct {
            closest.offer(t, i as u32);
        }
        if self.accel == Accel::WidePackets && self.intersection == Intersection::Robust {
            wide.intersect(ray, &mut closest);
        } else {
            self.isa.run(
                #[inline(always)]
                || wide.intersect_each(&self.spheres, ray, &mut closest, test),
            );
        }
        closest.found()
    }

    /// The material of a hit.
    #[inline]
    pub fn material(&self, hit: &Hit) -> &Material {
        &self.materials[hit.material as usize]
    }
}

/// Moves the huge spheres (at most [`MAX_HUGE`], the largest first) to the front of
/// `spheres`, each group keeping its order; returns how many there are.
fn move_huge_first(spheres: &mut [Sphere]) -> usize {
    let whole = half_area_around(spheres);
    let mut by_size: Vec<usize> = (0..spheres.len()).collect();
    by_size.sort_by(|&a, &b| spheres[b].radius.abs().total_cmp(&spheres[a].radius.abs()));
    let count = by_size
        .iter()
        .take(MAX_HUGE)
        .take_while(|&&i| half_area_around(&spheres[i..=i]) >= HUGE_FRACTION * whole)
        .count();
    let mut huge = vec![false; spheres.len()];
    for &i in &by_size[..count] {
        huge[i] = true;
    }
    // A stable sort on "not huge" puts the huge first and keeps both groups' order.
    let mut tagged: Vec<(bool, Sphere)> = spheres.iter().zip(huge).map(|(s, h)| (!h, *s)).collect();
    tagged.sort_by_key(|&(not_huge, _)| not_huge);
    for (slot, (_, sphere)) in spheres.iter_mut().zip(tagged) {
        *slot = sphere;
    }
    count
}
