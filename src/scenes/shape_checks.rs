//! The checks of a scene's shapes ([`Shapes::check`]): what TOML accepts but a renderer
//! cannot use (numbers that are not finite, a zero radius, a degenerate quad, disc, triangle or
//! box), each refused with a message naming the shape. Apart from `world.rs`,
//! which holds the shapes and what they become, to keep each file one sitting's reading.

use crate::scenes::checks::{REAL, check, colour, finite3, representable};
use crate::scenes::looks::Looks;
use crate::scenes::placement::TransformSpec;
use crate::scenes::world::{BoundarySpec, Shapes};
use crate::tracer::geometry::disc::Disc;
use crate::tracer::geometry::quad::Quad;
use crate::tracer::geometry::triangle;
use crate::tracer::math::real::{Real, vec3};

impl Shapes {
    /// Checks every shape; `at` names where they are (`""` or `"group #2 "`).
    pub fn check(&self, looks: &Looks, at: &str) -> Result<(), String> {
        let Shapes { spheres, quads, discs, boxes, triangles, meshes, media } = self;
        for (i, s) in spheres.iter().enumerate() {
            let name = format!("{at}sphere #{} (center {:?})", i + 1, s.center);
            check(finite3(s.center), || format!("{at}sphere #{}: center must be finite numbers", i + 1))?;
            check(representable(s.radius) && s.radius != 0.0, || {
                format!("{name}: radius must be finite (as {REAL}) and non-zero, got {}", s.radius)
            })?;
            check(s.center1.is_none_or(finite3), || format!("{name}: center1 must be finite numbers"))?;
            looks.check_material(&s.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, q) in quads.iter().enumerate() {
            let name = format!("{at}quad #{}", i + 1);
            check(finite3(q.q) && finite3(q.u) && finite3(q.v), || {
                format!("{name}: q, u, v must be finite numbers")
            })?;
            check(Quad::new(vec3(q.q), vec3(q.u), vec3(q.v), 0).is_some(), || {
                format!("{name}: degenerate (u = {:?} and v = {:?} span no area)", q.u, q.v)
            })?;
            looks.check_material(&q.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, d) in discs.iter().enumerate() {
            let name = format!("{at}disc #{}", i + 1);
            check(finite3(d.center) && finite3(d.normal), || {
                format!("{name}: center, normal must be finite numbers")
            })?;
            check(Disc::new(vec3(d.center), vec3(d.normal), d.radius as Real, 0).is_some(), || {
                format!(
                    "{name}: degenerate (normal {:?}, radius {}: needs a normal and a radius > 0)",
                    d.normal, d.radius
                )
            })?;
            looks.check_material(&d.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, b) in boxes.iter().enumerate() {
            let name = format!("{at}box #{}", i + 1);
            check_box(b.min, b.max).map_err(|e| format!("{name}: {e}"))?;
            b.transform.as_ref().map_or(Ok(()), TransformSpec::check).map_err(|e| format!("{name}: {e}"))?;
            looks.check_material(&b.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, t) in triangles.iter().enumerate() {
            let name = format!("{at}triangle #{}", i + 1);
            check(t.vertices.iter().all(|&v| finite3(v)), || {
                format!("{name}: vertices must be finite numbers")
            })?;
            check(!triangle::degenerate(t.vertices.map(vec3)), || {
                format!("{name}: degenerate (its vertices {:?} span no area)", t.vertices)
            })?;
            looks.check_material(&t.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, m) in meshes.iter().enumerate() {
            let name = format!("{at}mesh #{}", i + 1);
            check(m.obj.is_some() != m.generate.is_some(), || {
                format!("{name}: needs exactly one of obj and generate")
            })?;
            if let Some(g) = &m.generate {
                g.check().map_err(|e| format!("{name}: {e}"))?;
            }
            check(m.scale.is_none_or(|s| representable(s) && s > 0.0), || {
                format!("{name}: scale must be finite (as {REAL}) and > 0")
            })?;
            m.transform.as_ref().map_or(Ok(()), TransformSpec::check).map_err(|e| format!("{name}: {e}"))?;
            looks.check_material(&m.material).map_err(|e| format!("{name}: {e}"))?;
        }
        for (i, m) in media.iter().enumerate() {
            let name = format!("{at}medium #{}", i + 1);
            check(representable(m.density) && m.density >= 0.0, || {
                format!("{name}: density must be finite (as {REAL}) and ≥ 0, got {}", m.density)
            })?;
            colour(m.albedo).map_err(|e| format!("{name}: albedo {e}"))?;
            match m.boundary {
                BoundarySpec::Sphere { center, radius } => {
                    check(finite3(center) && representable(radius) && radius > 0.0, || {
                        format!("{name}: a boundary sphere needs a finite centre and a radius > 0")
                    })?
                }
                BoundarySpec::Box { min, max } => {
                    check_box(min, max).map_err(|e| format!("{name}: boundary {e}"))?
                }
            }
            m.transform.as_ref().map_or(Ok(()), TransformSpec::check).map_err(|e| format!("{name}: {e}"))?;
        }
        Ok(())
    }
}

fn check_box(min: [f64; 3], max: [f64; 3]) -> Result<(), String> {
    check(finite3(min) && finite3(max), || "min and max must be finite numbers".to_owned())?;
    check((0..3).all(|k| min[k] != max[k]), || {
        format!("degenerate: min {min:?} and max {max:?} span no volume")
    })
}
