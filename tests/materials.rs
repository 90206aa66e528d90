//! Scattering invariants: unit directions, reflection/refraction identities, TIR, Fresnel.

use rand::SeedableRng;
use rand::rngs::SmallRng;
use raypool::scenes::format::SceneFile;
use raypool::tracer::geometry::hit::Hit;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::shading::material::{Fresnel, Material, exact_fresnel, reflect, refract, schlick};
use raypool::tracer::shading::texture::Textures;

fn hit(normal: Vec3, front_face: bool) -> Hit {
    Hit {
        t: 1.0,
        point: Vec3::ZERO,
        normal,
        front_face,
        material: 0,
        offset: 1e-6,
        lift: 0.0,
        u: 0.0,
        v: 0.0,
    }
}

fn unit(v: Vec3) -> bool {
    (v.length() - 1.0).abs() < 1e-5
}

#[test]
fn reflect_keeps_length_and_flips_the_normal_component() {
    let n = Vec3::Y;
    let v = Vec3::new(1.0, -1.0, 0.5).normalize();
    let r = reflect(v, n);
    assert!(unit(r));
    assert!((r.dot(n) + v.dot(n)).abs() < 1e-6);
    assert!(((r - r.dot(n) * n) - (v - v.dot(n) * n)).length() < 1e-6, "tangent part kept");
}

#[test]
fn refract_obeys_snell() {
    let n = Vec3::Y;
    let v = Vec3::new(0.6, -0.8, 0.0); // sin θ = 0.6
    let eta = 1.0 / 1.5;
    let t = refract(v, n, eta).expect("entering glass always refracts");
    assert!(unit(t));
    let sin_t = t.cross(-n).length();
    assert!((sin_t - eta * 0.6).abs() < 1e-5, "sin θ' = {sin_t}");
    assert!(t.dot(n) < 0.0, "continues into the surface");
    // Straight in: no bending.
    let straight = refract(-n, n, eta).unwrap();
    assert!((straight + n).length() < 1e-6);
}

#[test]
fn total_internal_reflection_beyond_the_critical_angle() {
    let n = Vec3::Y;
    // Inside glass (η/η' = 1.5), at sin θ = 0.8 > 1/1.5.
    let v = Vec3::new(0.8, -0.6, 0.0);
    assert_eq!(refract(v, n, 1.5), None);
    // The dielectric then always reflects.
    let glass = Material::glass(1.5);
    let mut rng = SmallRng::seed_from_u64(1);
    for _ in 0..100 {
        let s = glass.scatter(v, &hit(n, false), &Textures::default(), &mut rng).unwrap();
        assert!((s.direction - reflect(v, n)).length() < 1e-6);
        assert_eq!(s.attenuation, Vec3::ONE);
    }
}

/// The exact Fresnel equations against values worked by hand, their reciprocity, and the
/// scene format's `fresnel = "exact"` (Mitsuba's and pbrt's glass, for references).
#[test]
fn exact_fresnel_matches_the_equations_and_scene_files_choose_it() {
    // Glass of 1.5 at 45°: r⊥ = −0.3034, r∥ = 0.0920, R = (0.0920 + 0.0085) / 2 = 0.0503.
    let cos45 = std::f64::consts::FRAC_1_SQRT_2 as Real;
    assert!((exact_fresnel(cos45, 1.0 / 1.5) - 0.050_3).abs() < 2e-4, "{}", exact_fresnel(cos45, 1.0 / 1.5));
    assert!((exact_fresnel(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6 && exact_fresnel(0.0, 1.0 / 1.5) == 1.0);
    for i in 1..100 {
        // The same reflectance from either side of one refraction (Schlick's is not), to f32
        // rounding near grazing.
        let cos_in = i as Real / 100.0;
        let cos_out = (1.0 - (1.0 - cos_in * cos_in) / (1.5 * 1.5)).sqrt();
        let (outside, inside) = (exact_fresnel(cos_in, 1.0 / 1.5), exact_fresnel(cos_out, 1.5));
        assert!(
            (outside - inside).abs() < 1e-4 && (0.0..=1.0).contains(&outside),
            "{cos_in}: {outside} {inside}"
        );
    }
    let glass = |fresnel: &str| {
        let text = format!(
            "[camera]\nlookfrom = [0.0, 0.0, 5.0]\nlookat = [0.0, 0.0, 0.0]\nvup = [0.0, 1.0, 0.0]\nvfov = 40.0\n\
             [[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = {{ kind = \"dielectric\", ior = 1.5{fresnel} }}\n"
        );
        SceneFile::parse(&text, "glass.toml").map(|file| file.to_scene().materials()[0])
    };
    assert_eq!(glass("").unwrap(), Material::Dielectric { ior: 1.5, fresnel: Fresnel::Schlick });
    assert_eq!(
        glass(", fresnel = \"exact\"").unwrap(),
        Material::Dielectric { ior: 1.5, fresnel: Fresnel::Exact }
    );
    let error = glass(", fresnel = \"fancy\"").unwrap_err().to_string();
    assert!(error.starts_with("glass.toml:") && error.contains("fancy") && !error.contains('\n'), "{error}");
}

#[test]
fn schlick_stays_in_unit_interval() {
    for i in 0..=100 {
        let cos = i as Real / 100.0;
        for eta in [1.0 / 2.4, 1.0 / 1.5, 1.0, 1.5, 2.4] {
            let r = schlick(cos, eta);
            assert!((0.0..=1.0).contains(&r), "schlick({cos}, {eta}) = {r}");
        }
    }
    assert!((schlick(0.0, 1.5) - 1.0).abs() < 1e-6, "grazing: all reflected");
    assert!((schlick(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-3, "normal incidence on glass: 4%");
}

#[test]
fn every_material_scatters_to_unit_directions_on_the_right_side() {
    let mut rng = SmallRng::seed_from_u64(42);
    let n = Vec3::new(0.3, 0.9, -0.2).normalize();
    let materials = [
        Material::Lambertian { albedo: Vec3::splat(0.5) },
        Material::Metal { albedo: Vec3::splat(0.8), fuzz: 0.3 },
        Material::Metal { albedo: Vec3::splat(0.8), fuzz: 7.0 }, // fuzz > 1 acts as 1
        Material::glass(1.5),
        Material::glass(1.0), // no bending at all
    ];
    for m in materials {
        for k in 0..2000 {
            let incoming = (-n
                + 0.7 * Vec3::new((k % 7) as Real - 3.0, 1.0, (k % 5) as Real - 2.0).normalize())
            .normalize();
            let Some(s) = m.scatter(incoming, &hit(n, true), &Textures::default(), &mut rng) else {
                assert!(matches!(m, Material::Metal { .. }), "only fuzzy metal absorbs");
                continue;
            };
            assert!(unit(s.direction), "{m:?}: {:?}", s.direction);
            assert!(s.attenuation.is_finite());
            match m {
                Material::Lambertian { .. } | Material::Metal { .. } => assert!(s.direction.dot(n) >= 0.0),
                // ior 1 does not bend light; Schlick still reflects a little at grazing angles.
                Material::Dielectric { ior: 1.0, .. } => assert!(
                    (s.direction - incoming).length() < 1e-4
                        || (s.direction - reflect(incoming, n)).length() < 1e-4
                ),
                Material::Dielectric { .. } => {}
                other => unreachable!("not in the list: {other:?}"),
            }
        }
    }
}

#[test]
fn lambertian_never_returns_a_degenerate_direction() {
    // A random unit vector exactly opposite the normal would cancel it; the guard must
    // return the normal. Exercise it statistically over many draws near the antipode.
    let m = Material::Lambertian { albedo: Vec3::ONE };
    let mut rng = SmallRng::seed_from_u64(3);
    for _ in 0..100_000 {
        let s = m.scatter(-Vec3::Z, &hit(Vec3::Z, true), &Textures::default(), &mut rng).unwrap();
        assert!(s.direction.is_finite() && unit(s.direction));
    }
}
