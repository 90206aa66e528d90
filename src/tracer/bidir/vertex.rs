//! A path's vertex, as bidirectional path tracing keeps it: where it is, how it scatters, the
//! light (or importance) that reached it, and the two densities with which it can be drawn.
//!
//! Densities are per unit *area* (per unit volume in a medium), so that the densities of one
//! vertex drawn by the camera's walk and by the light's compare directly (Veach 1997, §10.2):
//! `pdf_fwd` is the density with which its own walk drew it, `pdf_rev` the density with which
//! the other walk would have, from the nearest vertex on that side that scatters into every
//! direction. A mirror or glass vertex scatters into one direction: no connection can end on
//! it, and its own densities are 0 ("delta"), which the weights read as "cancels"
//! (`weight.rs`); the vertices on either side of such a chain carry the density through it
//! (`chain.rs`). A fuzzy mirror is treated as a mirror there: its density, unknown in closed
//! form, is the same both ways (the fuzz is symmetric about the mirror direction), and the
//! chain is followed along the mirror direction, so its weights are approximate but still a
//! function of the path alone (the image stays unbiased).

use crate::tracer::camera::Camera;
use crate::tracer::geometry::hit::Hit;
use crate::tracer::lighting::lobe_pdf;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3};
use crate::tracer::shading::material::{Lobe, Material};
use crate::tracer::shading::texture::Textures;

/// What a vertex is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// The lens point a camera path leaves from.
    Camera,
    /// The point on a light a light path leaves from.
    Light,
    /// A surface hit.
    Surface,
    /// A scattering event in a medium (no surface, no cosine).
    Medium,
}

/// One vertex of a camera or light path.
#[derive(Clone, Copy, Debug)]
pub struct Vertex {
    /// What it is.
    pub kind: Kind,
    /// Where connections start and end (a surface's departure point).
    pub point: Vec3,
    /// Unit normal on the side the path is on (a light's emitting side).
    pub normal: Vec3,
    /// How it scatters; `None` for mirrors, glass, a light that absorbs, the camera.
    pub lobe: Option<Lobe>,
    /// What it scatters, per channel (its reflectance, or the medium's albedo).
    pub albedo: Vec3,
    /// What it emits towards the previous vertex of its camera path.
    pub emitted: Vec3,
    /// The walk's throughput on arrival (a light vertex: its emission over its density).
    pub beta: Vec3,
    /// Density with which its own walk drew it (per unit area), 0 after a delta vertex.
    pub pdf_fwd: Real,
    /// Density with which the other walk would draw it from its next vertex, 0 next to a
    /// delta vertex.
    pub pdf_rev: Real,
    /// The surface hit, to leave it (`None` for the camera and light vertices).
    pub hit: Option<Hit>,
}

impl Vertex {
    /// The camera's vertex at lens point `point`.
    pub fn camera(point: Vec3) -> Vertex {
        let base = Vertex::base(Kind::Camera, point, Vec3::ZERO, Vec3::ONE);
        Vertex { pdf_fwd: 1.0, ..base }
    }

    /// A light's vertex: `point` with `normal` on the emitting side, drawn with density `pdf`.
    pub fn light(point: Vec3, normal: Vec3, emitted: Vec3, pdf: Real) -> Vertex {
        Vertex { emitted, pdf_fwd: pdf, ..Vertex::base(Kind::Light, point, normal, emitted / pdf) }
    }

    /// The vertex at `hit` on `material`, reached along `incoming` with throughput `beta`.
    pub fn at(hit: Hit, material: &Material, textures: &Textures, beta: Vec3) -> Vertex {
        let medium = matches!(material, Material::Isotropic { .. });
        let kind = if medium { Kind::Medium } else { Kind::Surface };
        let lobe = material.lobe();
        let albedo = if lobe.is_some() { material.albedo(&hit, textures) } else { Vec3::ZERO };
        // A light's `albedo` is its emission seen from the front: its reflectance is a grey.
        let albedo = match *material {
            Material::DiffuseLight { albedo, .. } => Vec3::splat(albedo),
            _ => albedo,
        };
        Vertex {
            lobe,
            albedo,
            emitted: material.emitted(&hit),
            hit: Some(hit),
            ..Vertex::base(kind, hit.departure(), hit.normal, beta)
        }
    }

    fn base(kind: Kind, point: Vec3, normal: Vec3, beta: Vec3) -> Vertex {
        Vertex {
            kind,
            point,
            normal,
            lobe: None,
            albedo: Vec3::ZERO,
            emitted: Vec3::ZERO,
            beta,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
            hit: None,
        }
    }

    /// Whether a connection may end here: the camera, a light's point, or a vertex that
    /// scatters into every direction.
    #[inline]
    pub fn connectable(&self) -> bool {
        matches!(self.kind, Kind::Camera | Kind::Light) || self.lobe.is_some()
    }

    /// What this vertex scatters towards the unit direction `dir`, per unit of arriving light,
    /// its cosine included (`f · cos`): albedo × the lobe's density.
    #[inline]
    pub fn scattered(&self, dir: Vec3) -> Vec3 {
        self.lobe.map_or(Vec3::ZERO, |lobe| self.albedo * lobe_pdf(lobe, dir, self.normal))
    }

    /// The density per unit solid angle with which a walk here draws the unit direction `dir`
    /// (0 for a delta vertex): the lobe's, a light's cosine law from its front, or the
    /// camera's rays.
    #[inline]
    pub fn direction_pdf(&self, dir: Vec3, camera: &Camera) -> Real {
        match self.kind {
            Kind::Camera => camera.direction_pdf(dir),
            Kind::Light => dir.dot(self.normal).max(0.0) / PI,
            Kind::Surface | Kind::Medium => self.lobe.map_or(0.0, |lobe| lobe_pdf(lobe, dir, self.normal)),
        }
    }

    /// The density per unit area (volume, in a medium) with which a walk at `self` draws
    /// `next`: its direction density times the Jacobian `|cos| / d²` at `next` (no cosine in
    /// a medium); 0 for a delta `next`.
    #[inline]
    pub fn density_to(&self, next: &Vertex, camera: &Camera) -> Real {
        if !next.connectable() {
            return 0.0; // a delta vertex: its density is the chain's, on the vertex after it
        }
        let to = next.point - self.point;
        let d2 = to.length_squared();
        let dir = to / d2.sqrt();
        next.area_density(self.direction_pdf(dir, camera), dir, d2)
    }

    /// `pdf` per unit solid angle, along the unit `dir` from a point `d2` away squared,
    /// turned into a density per unit area here.
    #[inline]
    pub fn area_density(&self, pdf: Real, dir: Vec3, d2: Real) -> Real {
        let cos = if self.kind == Kind::Medium { 1.0 } else { dir.dot(self.normal).abs() };
        let density = pdf * cos / d2;
        if density.is_finite() { density } else { 0.0 }
    }
}
