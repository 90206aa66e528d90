//! The book's thin-lens camera, with pixel squares that tile the viewport exactly.
//!
//! Sample `(ox, oy)` of pixel `(i, j)` aims at `pixel00 + (i + ox)·Δu + (j + oy)·Δv` with
//! `ox, oy` uniform in `[−½, ½]` (the book's current edition): pixel `i` covers exactly its
//! `1/W` of the viewport, unlike the older `(i + rand)/(W − 1)`, which stretches the image.

use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::ray::Ray;
use crate::tracer::math::real::{Real, Vec3, vec3};
use crate::tracer::sampling::warp::{random_in_unit_disk, uniform};

/// The camera as a scene file states it (the book's parameters, in f64 as written).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSettings {
    /// Eye position.
    pub lookfrom: [f64; 3],
    /// Point the camera looks at (projects to the image centre).
    pub lookat: [f64; 3],
    /// "Up" direction; must not be parallel to the view direction.
    pub vup: [f64; 3],
    /// Vertical field of view, degrees, in (0, 180).
    pub vfov: f64,
    /// Lens diameter; 0 = pinhole (no defocus blur).
    #[serde(default)]
    pub aperture: f64,
    /// Distance from `lookfrom` to the plane in perfect focus; absent: the distance to
    /// `lookat` (so what the camera looks at is sharp), as [`CameraSettings::focus`] says.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus_dist: Option<f64>,
    /// Image width ÷ height used when the height is not given.
    #[serde(default = "default_aspect")]
    pub aspect: f64,
}

impl CameraSettings {
    /// The focus distance: `focus_dist` where given, else the distance from `lookfrom` to
    /// `lookat`. (For a pinhole it only scales the viewport, and the rays stay the same.)
    ///
    /// ```
    /// use raypool::tracer::camera::CameraSettings;
    /// let toml = "lookfrom = [0, 0, 3]\nlookat = [0, 4, 0]\nvup = [0, 1, 0]\nvfov = 40";
    /// let camera: CameraSettings = toml::from_str(toml).unwrap();
    /// assert_eq!(camera.focus(), 5.0);
    /// ```
    pub fn focus(&self) -> f64 {
        let (a, b) = (self.lookfrom, self.lookat);
        self.focus_dist.unwrap_or_else(|| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt())
    }
}

fn default_aspect() -> f64 {
    1.5
}

/// A camera ready to generate rays for one image size.
#[derive(Clone, Copy, Debug)]
pub struct Camera {
    center: Vec3,
    pixel00: Vec3,
    delta_u: Vec3,
    delta_v: Vec3,
    /// Lens basis vectors scaled by the lens radius (zero for a pinhole).
    lens_u: Vec3,
    lens_v: Vec3,
    has_lens: bool,
    /// The angle one pixel spans at the image's centre, radians.
    pixel_angle: Real,
    /// Unit view direction (the lens's axis).
    forward: Vec3,
    /// Distance from the lens to the plane in focus.
    focus: Real,
    /// The whole image's area on the plane in focus.
    film_area: Real,
    /// Image size, pixels.
    width: u32,
    height: u32,
}

impl Camera {
    /// Sets the camera up for a `width × height` image (the image's own aspect ratio rules;
    /// `settings.aspect` only serves to choose a default height).
    pub fn new(settings: &CameraSettings, width: u32, height: u32) -> Camera {
        let center = vec3(settings.lookfrom);
        let focus = settings.focus() as Real;
        let h = (settings.vfov as Real).to_radians() * 0.5;
        let viewport_height = 2.0 * h.tan() * focus;
        let viewport_width = viewport_height * width as Real / height as Real;
        // Orthonormal basis: w points backwards, u right, v up.
        let w = (center - vec3(settings.lookat)).normalize();
        let u = vec3(settings.vup).cross(w).normalize();
        let v = w.cross(u);
        let viewport_u = viewport_width * u;
        let viewport_v = -viewport_height * v; // image rows go down
        let delta_u = viewport_u / width as Real;
        let delta_v = viewport_v / height as Real;
        let upper_left = center - focus * w - 0.5 * (viewport_u + viewport_v);
        let lens_radius = settings.aperture as Real * 0.5;
        Camera {
            center,
            pixel00: upper_left + 0.5 * (delta_u + delta_v),
            delta_u,
            delta_v,
            lens_u: lens_radius * u,
            lens_v: lens_radius * v,
            has_lens: lens_radius > 0.0,
            pixel_angle: 2.0 * h.tan() / height as Real,
            forward: -w,
            focus,
            film_area: viewport_width * viewport_height,
            width,
            height,
        }
    }

    /// A camera ray through a uniformly random point of pixel `(i, j)` (column, row from the
    /// top), from a random point on the lens. A pinhole camera draws no lens numbers. Forced
    /// inline into the render loop: with a Sobol stream the compiler kept it a call, and its
    /// draws and the stream's state went through memory (`results/perf.md`).
    #[inline(always)]
    pub fn ray<R: Rng + ?Sized>(&self, i: u32, j: u32, rng: &mut R) -> Ray {
        let spot = [uniform(rng), uniform(rng)];
        let origin = self.lens_point(rng);
        self.ray_from(origin, i, j, spot)
    }

    /// The ray from the lens point `origin` through the point `spot` (two numbers in
    /// `[0, 1)`, across and down) of pixel `(i, j)`.
    #[inline(always)]
    pub fn ray_from(&self, origin: Vec3, i: u32, j: u32, spot: [Real; 2]) -> Ray {
        let (ox, oy) = (spot[0] - 0.5, spot[1] - 0.5);
        let target = self.pixel00 + (i as Real + ox) * self.delta_u + (j as Real + oy) * self.delta_v;
        Ray::new(origin, target - origin)
    }

    /// The pixels some camera ray through which may meet `bounds` (columns, then rows), or
    /// every pixel if part of the box lies behind the lens: each corner projected from the
    /// lens's centre, spread by how far the lens moves its image, and a pixel more for
    /// rounding. Never leaves out a pixel whose rays can meet the box.
    pub fn pixels_seeing(&self, bounds: &Aabb) -> [std::ops::Range<u32>; 2] {
        let every = [0..self.width, 0..self.height];
        if bounds.min.cmpgt(bounds.max).any() {
            return [0..0, 0..0];
        }
        let corner00 = self.pixel00 - 0.5 * (self.delta_u + self.delta_v);
        let pixel = self.delta_u.length();
        let lens = self.lens_u.length();
        let (mut low, mut high) = ([Real::INFINITY; 2], [Real::NEG_INFINITY; 2]);
        for corner in bounds.corners() {
            let to = corner - self.center;
            let along = to.dot(self.forward);
            // Behind the lens, beside it, or not a number: no projection to trust.
            if along.partial_cmp(&(1e-3 * to.length())) != Some(std::cmp::Ordering::Greater) {
                return every;
            }
            let on_film = self.center + to * (self.focus / along) - corner00;
            let at =
                [on_film.dot(self.delta_u) / (pixel * pixel), on_film.dot(self.delta_v) / (pixel * pixel)];
            let spread = lens * (1.0 - self.focus / along).abs() / pixel;
            for d in 0..2 {
                low[d] = low[d].min(at[d] - spread);
                high[d] = high[d].max(at[d] + spread);
            }
        }
        let size = [self.width, self.height];
        std::array::from_fn(|d| {
            let from = (low[d] - 1.0).floor().clamp(0.0, size[d] as Real) as u32;
            let to = (high[d] + 2.0).floor().clamp(0.0, size[d] as Real) as u32;
            if low[d].is_finite() && high[d].is_finite() { from..to.max(from) } else { every[d].clone() }
        })
    }

    /// The angle one pixel spans at the image's centre, radians (`2·tan(vfov/2) / height`):
    /// how far apart neighbouring pixels' rays are, for the denoiser's sense of scale.
    pub fn pixel_angle(&self) -> Real {
        self.pixel_angle
    }

    /// A point on the lens, drawn uniformly (two numbers), or the pinhole itself (none): where
    /// a light path is joined to the camera (`bidir/`).
    pub fn lens_point<R: Rng + ?Sized>(&self, rng: &mut R) -> Vec3 {
        if !self.has_lens {
            return self.center;
        }
        let (x, y) = random_in_unit_disk(rng);
        self.center + x * self.lens_u + y * self.lens_v
    }

    /// The pixel `(i, j)` whose camera rays include the one from the lens point `lens` through
    /// `point`, if that ray crosses the image: [`Camera::ray`] read backwards, through the
    /// point where the ray meets the plane in focus.
    pub fn pixel_of(&self, lens: Vec3, point: Vec3) -> Option<(u32, u32)> {
        let to = point - lens;
        let along = to.dot(self.forward);
        if along <= 0.0 {
            return None;
        }
        let on_film = lens + to * (self.focus / along) - (self.pixel00 - 0.5 * (self.delta_u + self.delta_v));
        let x = on_film.dot(self.delta_u) / self.delta_u.length_squared();
        let y = on_film.dot(self.delta_v) / self.delta_v.length_squared();
        let inside = x >= 0.0 && y >= 0.0 && x < self.width as Real && y < self.height as Real;
        inside.then(|| ((x as u32).min(self.width - 1), (y as u32).min(self.height - 1)))
    }

    /// The density per unit solid angle with which camera rays leave a lens point in the unit
    /// direction `dir`, over the whole image (a pixel chosen uniformly, then a point in it):
    /// `focus² / (cos³θ · film area)`, θ from the lens's axis; 0 behind the lens. It is also
    /// the camera's importance per unit lens area (pbrt's `We`) times `cos θ`, which is why a
    /// light path joined to the camera is weighed by it.
    pub fn direction_pdf(&self, dir: Vec3) -> Real {
        let cos = dir.dot(self.forward);
        if cos <= 0.0 {
            return 0.0;
        }
        self.focus * self.focus / (cos * cos * cos * self.film_area)
    }

    /// The ray through the exact centre of pixel-space point `(x, y)` (in pixels, from the
    /// top-left corner) from the lens centre: for tests and for aiming.
    pub fn center_ray(&self, x: Real, y: Real) -> Ray {
        let target = self.pixel00 + (x - 0.5) * self.delta_u + (y - 0.5) * self.delta_v;
        Ray::new(self.center, target - self.center)
    }
}
