//! Glass balls that cast caustics: the solid dielectric spheres of a scene with lights, through
//! which manifold next-event estimation (`lighting/manifold.rs`) aims at the lights. A ball is
//! the one specular shape whose passage has a closed form: a ray that enters it refracts once,
//! crosses a chord and refracts once more on the way out ([`Ball::pass`]), and by symmetry
//! the two refractions are at the same angle inside, so light that entered always leaves.
//!
//! Only balls the scene holds directly and that stand still are casters: a sphere inside an
//! instance or a moving one is glass like any other, found by bounces alone. A hollow shell
//! (negative radius) is not one either; a ball with a shell inside is, and the shell blocks
//! its passages (the shadow rays through the ball see it), as it blocks a bounce's.
//!
//! Invariant: [`Casters::holding`] names the caster whose surface holds a point, so a bounce
//! that entered and left a ball is recognised as the passage [`Ball::pass`] follows.

use glam::DVec3;

use crate::tracer::geometry::Shape;
use crate::tracer::geometry::sphere::Sphere;
use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::real::consts::PI;
use crate::tracer::math::real::{Real, Vec3, from_dvec3, to_dvec3, to_f64};
use crate::tracer::shading::material::{Fresnel, Material};
use crate::tracer::world::object::Object;

/// A solid glass ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// The sphere (positive radius), with its material's index.
    pub sphere: Sphere,
    /// The glass's refractive index relative to the air around it.
    pub ior: Real,
    /// How its glass computes the share it reflects.
    pub fresnel: Fresnel,
}

/// A ray's way through a [`Ball`]: along `dir` in at `entry`, out at `exit` along `out`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passage {
    /// Its unit direction from the start. Not `entry − start` rounded: from a start near the
    /// glass, an `f32` entry point is a turn of the ray off that misses a lamp by units
    /// (`tests/sampling_paths.rs`); a unit vector holds the direction.
    pub dir: Vec3,
    /// Where it enters (on the side it came from).
    pub entry: Vec3,
    /// Its unit direction inside.
    pub inside: Vec3,
    /// Where it leaves.
    pub exit: Vec3,
    /// Its unit direction after leaving.
    pub out: Vec3,
    /// The chance that glass refracts at both points (Schlick's `(1 − R)` twice): the share
    /// of the light that takes this way, and the chance a bounce takes it.
    pub transmitted: Real,
}

/// A [`Passage`] in double precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Its unit direction from the start.
    pub dir: DVec3,
    /// Where it enters (on the side it came from).
    pub entry: DVec3,
    /// Its unit direction inside.
    pub inside: DVec3,
    /// Where it leaves.
    pub exit: DVec3,
    /// Its unit direction after leaving.
    pub out: DVec3,
    /// As [`Passage::transmitted`].
    pub transmitted: Real,
}

impl Crossing {
    /// The passage, rounded to the renderer's precision.
    pub fn rounded(self) -> Passage {
        let Crossing { dir, entry, inside, exit, out, transmitted } = self;
        let round = from_dvec3;
        Passage {
            dir: round(dir),
            entry: round(entry),
            inside: round(inside),
            exit: round(exit),
            out: round(out),
            transmitted,
        }
    }
}

/// The unit direction of `v` refracted at a surface of unit normal `n` facing it, from a side
/// whose index over the other's is `eta` (`shading::material::refract` in double precision).
fn refract(v: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos = (-v).dot(n).min(1.0);
    let perp = eta * (v + cos * n);
    let k = 1.0 - perp.length_squared();
    (k >= 0.0).then(|| (perp - k.sqrt() * n).normalize())
}

impl Ball {
    /// The ball of `sphere` (a positive radius) in glass of index `ior`, Schlick's Fresnel.
    pub fn new(sphere: Sphere, ior: Real) -> Ball {
        Ball { sphere, ior, fresnel: Fresnel::Schlick }
    }

    /// The angle (radians) by which the ball turns a ray that passes it at `impact` radii
    /// from its centre: `2|asin s − asin(s/n)|` for `s = impact` and index `n`, twice the
    /// bend of one refraction. It grows with the impact, up to 96° at grazing entry for glass
    /// of 1.5; a ball of index below 1 lets through only impacts up to `n`, and past them
    /// this is the most it turns.
    ///
    /// ```
    /// use raypool::tracer::geometry::sphere::Sphere;
    /// use raypool::tracer::lights::casters::Ball;
    /// let ball = Ball::new(Sphere { center: Default::default(), radius: 2.0, material: 0 }, 1.5);
    /// assert_eq!(ball.turn(0.0), 0.0);
    /// assert!((ball.turn(1.0).to_degrees() - 96.38).abs() < 0.01);
    /// ```
    pub fn turn(&self, impact: Real) -> Real {
        let s = impact.clamp(0.0, 1.0).min(self.ior);
        2.0 * (s.asin() - (s / self.ior).asin()).abs()
    }

    /// The passage of the ray from `from` (outside) along the unit `dir`, if it meets the
    /// ball at an angle it can refract at ([`Ball::crossing`], rounded).
    ///
    /// ```
    /// use raypool::tracer::geometry::sphere::Sphere;
    /// use raypool::tracer::math::real::Vec3;
    /// use raypool::tracer::lights::casters::Ball;
    /// let ball = Ball::new(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }, 1.5);
    /// // Straight through the centre: in at z = 2 − 1, out at z = −1, undeflected.
    /// let passage = ball.pass(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, -1.0)).unwrap();
    /// assert!((passage.exit - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5);
    /// assert!((passage.transmitted - 0.96 * 0.96).abs() < 1e-5);
    /// ```
    pub fn pass(&self, from: Vec3, dir: Vec3) -> Option<Passage> {
        self.crossing(to_dvec3(from), to_dvec3(dir)).map(Crossing::rounded)
    }

    /// [`Ball::pass`] in double precision.
    pub fn crossing(&self, from: DVec3, dir: DVec3) -> Option<Crossing> {
        let (center, radius) = (to_dvec3(self.sphere.center), to_f64(self.sphere.radius));
        let f = from - center;
        let b = f.dot(dir);
        // The robust form (as `Sphere::intersect`): the centre's distance from the line.
        let perp = f - b * dir;
        let r2 = radius * radius;
        let discriminant = r2 - perp.length_squared();
        if f.length_squared() <= r2 || discriminant <= 0.0 || b >= 0.0 {
            return None;
        }
        let t = -b - discriminant.sqrt();
        self.cross(from, from + t * dir)
    }

    /// The passage of the ray from `from` that enters at `entry`, a point of the ball's
    /// surface that `from` sees (the way [`Ball::crossing`] ends, and how a solver tries
    /// points). In double precision: from a start near the glass, where rays enter it all
    /// but edge-on, `f32` turns them wrongly enough to miss a lamp by units
    /// (`tests/sampling_paths.rs`).
    pub fn cross(&self, from: DVec3, entry: DVec3) -> Option<Crossing> {
        let (center, radius, ior) =
            (to_dvec3(self.sphere.center), to_f64(self.sphere.radius), to_f64(self.ior));
        let dir = (entry - from).try_normalize()?;
        let normal = (entry - center) / radius;
        let cos_in = -dir.dot(normal);
        if cos_in <= 0.0 {
            return None;
        }
        let inside = refract(dir, normal, 1.0 / ior)?;
        // The chord: the second root of |entry + t·inside − centre| = radius.
        let chord = -2.0 * (entry - center).dot(inside);
        let exit = entry + chord * inside;
        let exit_normal = (exit - center) / radius;
        let cos_out = inside.dot(exit_normal);
        let out = refract(inside, -exit_normal, ior)?;
        let reflected = |cos: f64, ratio| self.fresnel.reflectance(cos as Real, ratio);
        let transmitted = (1.0 - reflected(cos_in, 1.0 / self.ior)) * (1.0 - reflected(cos_out, self.ior));
        Some(Crossing { dir, entry, inside, exit, out, transmitted })
    }

    /// The widest angle, seen from the centre, between the way in from a start outside and the
    /// way out to a point of the sphere `lamps`, at which a passage can
    /// join them: a ray arrives at most 90° off the way to the centre, the ball turns it by at
    /// most [`Ball::turn`]`(1)` back across it, so it leaves at most the larger of the two off;
    /// it leaves on a line at most `r` from the centre, so a point `f` away is at most
    /// `asin(r / f)` off that line, and the lamps' points are at most `asin(ρ / a)` off their
    /// centre, `a` away with radius `ρ`. π where the lamps come within the ball's radius.
    ///
    /// ```
    /// use raypool::tracer::geometry::sphere::Sphere;
    /// use raypool::tracer::math::real::Vec3;
    /// use raypool::tracer::lights::casters::{Ball, Lamps};
    /// let ball = Ball::new(Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }, 1.5);
    /// // A point lamp far away: the turn at the rim alone, 96°.
    /// let far = Lamps { center: Vec3::new(0.0, 1e4, 0.0), radius: 0.0 };
    /// assert!((ball.widest(far).to_degrees() - 96.4).abs() < 0.1);
    /// ```
    pub fn widest(&self, lamps: Lamps) -> Real {
        let Lamps { center: lamp, radius: spread } = lamps;
        let away = (lamp - self.sphere.center).length();
        let nearest = away - spread;
        if nearest <= self.sphere.radius {
            return PI;
        }
        let off =
            self.turn(1.0).max(PI / 2.0) + (self.sphere.radius / nearest).asin() + (spread / away).asin();
        off.min(PI)
    }

    /// How far from its centre the ball focuses light that arrives parallel: `n r / 2(n − 1)`
    /// (paraxial; 1.5 radii for glass of 1.5), 0 for an index of 1 or below, which focuses
    /// nothing. Within it lies the bright core of the ball's caustic.
    ///
    /// ```
    /// use raypool::tracer::geometry::sphere::Sphere;
    /// use raypool::tracer::lights::casters::Ball;
    /// let ball = Ball::new(Sphere { center: Default::default(), radius: 2.0, material: 0 }, 1.5);
    /// assert_eq!(ball.focus(), 3.0);
    /// ```
    pub fn focus(&self) -> Real {
        if self.ior > 1.0 { self.ior * self.sphere.radius / (2.0 * (self.ior - 1.0)) } else { 0.0 }
    }

    /// Whether `point` lies on the ball's surface (to a thousandth of its radius).
    pub fn holds(&self, point: Vec3) -> bool {
        ((point - self.sphere.center).length() - self.sphere.radius).abs() <= 1e-3 * self.sphere.radius
    }
}

/// A sphere around every point of a scene's lights, which a caster's bounds are drawn against.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Lamps {
    /// Its centre.
    pub center: Vec3,
    /// Its radius.
    pub radius: Real,
}

/// The scene's casters, in the scene's order, and a sphere around its lights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Casters {
    balls: Vec<Ball>,
    lamps: Lamps,
    /// Per ball, the cosine of the widest angle that light from the lamps can pass ([`Casters::may_light`]).
    widest: Vec<Real>,
}

impl Casters {
    /// The solid, still glass spheres among `objects` (not inside instances), their materials
    /// in `materials`, casting the light of lights inside the box `lamps` (not empty).
    ///
    /// ```
    /// use raypool::tracer::geometry::sphere::Sphere;
    /// use raypool::tracer::math::{aabb::Aabb, real::Vec3};
    /// use raypool::tracer::shading::material::Material;
    /// use raypool::tracer::lights::casters::Casters;
    /// use raypool::tracer::world::object::Object;
    /// let ball = |radius| Object::shape(Sphere { center: Vec3::ZERO, radius, material: 0 });
    /// let lamps = Aabb::EMPTY.grow(Vec3::new(-1.0, 5.0, -1.0)).grow(Vec3::new(1.0, 5.0, 1.0));
    /// let casters = Casters::new(&[ball(1.0), ball(-0.9)], &[Material::glass(1.5)], lamps);
    /// assert_eq!(casters.len(), 1); // the bubble inside is not a caster
    /// ```
    pub fn new(objects: &[Object], materials: &[Material], lamps: Aabb) -> Casters {
        let balls = objects.iter().filter_map(|object| match object {
            Object::Shape(Shape::Sphere(ball)) if ball.radius > 0.0 => {
                match materials[ball.material as usize] {
                    Material::Dielectric { ior, fresnel } => Some(Ball { fresnel, ..Ball::new(*ball, ior) }),
                    _ => None,
                }
            }
            // Only a still glass ball is aimed through: anything else, a new shape too, casts
            // no caustic a path aims at (a bounce still finds it).
            _ => None,
        });
        let middle = 0.5 * (lamps.min + lamps.max);
        let lamps = Lamps { center: middle, radius: (lamps.max - middle).length() };
        let balls: Vec<Ball> = balls.collect();
        let widest = balls.iter().map(|ball| ball.widest(lamps).cos()).collect();
        Casters { balls, lamps, widest }
    }

    /// Whether light from the lamps may pass through ball `k` to `from` at all, by a test of
    /// one product against [`Ball::widest`]: the loose first of two (`lighting/passage.rs`'s
    /// `may_pass` is the tight one), which on `cornell` rules out the ceiling and high walls.
    pub fn may_light(&self, k: usize, from: Vec3) -> bool {
        let (center, lamp) = (self.balls[k].sphere.center, self.lamps.center);
        let (inward, outward) = (center - from, lamp - center);
        inward.dot(outward) >= self.widest[k] * (inward.length_squared() * outward.length_squared()).sqrt()
    }

    /// Whether `from` lies within some ball's [`Ball::focus`] of its centre, where its caustic
    /// is brightest.
    pub fn near_focus(&self, from: Vec3) -> bool {
        self.balls
            .iter()
            .any(|ball| (from - ball.sphere.center).length_squared() < ball.focus() * ball.focus())
    }

    /// A sphere around every point of the scene's lights.
    pub fn lamps(&self) -> Lamps {
        self.lamps
    }

    /// How many.
    pub fn len(&self) -> usize {
        self.balls.len()
    }

    /// Whether there are none (then no path pays for anything of this).
    pub fn is_empty(&self) -> bool {
        self.balls.is_empty()
    }

    /// Caster `k`.
    pub fn ball(&self, k: usize) -> &Ball {
        &self.balls[k]
    }

    /// The first caster of `material` whose surface holds `point`.
    pub fn holding(&self, point: Vec3, material: u32) -> Option<usize> {
        self.balls.iter().position(|ball| ball.sphere.material == material && ball.holds(point))
    }
}
