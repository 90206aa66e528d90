//! The edge rays' search (`lighting/edges.rs`) looks no farther than the lights reach
//! ([`Lights::reach`]): ray by ray it must see exactly the light the whole search sees.

mod rooms;

use rand::{RngExt, SeedableRng};
use raypool::scenes::format::SceneFile;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::math::transform::Transform;
use raypool::tracer::scene::Scene;
use raypool::tracer::world::object::Probe;

/// The lit room (lamps in a turned, moved group, a moving sphere lamp, triangles) with, in the
/// group, a grey quad on the group's lamp (exact ties), a glass ball below it, and fog filling
/// the room.
fn room() -> Scene {
    let grey = "{ kind = \"lambertian\", albedo = [0.5, 0.5, 0.5] }";
    let text = format!(
        "{}[[group.quad]]\nq = [-0.3, 0.0, -0.3]\nu = [0.6, 0.0, 0.0]\nv = [0.0, 0.0, 0.6]\nmaterial = {grey}\n\
         [[sphere]]\ncenter = [0.0, 0.55, -0.3]\nradius = 0.2\nmaterial = {{ kind = \"dielectric\", ior = 1.5 }}\n\
         [[medium]]\ndensity = 0.7\nalbedo = [1.0, 1.0, 1.0]\n\
         boundary = {{ kind = \"box\", min = [-0.99, -0.99, -0.99], max = [0.99, 0.99, 0.99] }}\n",
        rooms::lit_room()
    );
    SceneFile::parse(&text, "edge_reach").unwrap().to_scene()
}

#[test]
fn the_search_up_to_the_lights_reach_sees_the_light_the_whole_search_sees() {
    let scene = room();
    // The group's lamp in the world: the edges and plane where grazing rays and ties are.
    let place = Transform::rotate_y(30.0).then_translate(Vec3::new(0.0, 0.9, -0.3));
    let mut rng = rand::rngs::SmallRng::seed_from_u64(58);
    let (mut lit, mut unreached, mut scattered) = (0, 0, 0);
    for k in 0..60_000 {
        let mut point =
            |scale: Real| Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 * scale - scale;
        let origin = point(0.95);
        let ray = match k % 3 {
            // Anywhere, any way.
            0 => Ray::new(origin, point(1.0)),
            // At the group lamp's edges.
            1 => {
                let s: Real = rng.random();
                let edge = [[s, 0.0], [s, 1.0], [0.0, s], [1.0, s]][k / 3 % 4];
                let local = Vec3::new(-0.3 + 0.6 * edge[0], 0.0, -0.3 + 0.6 * edge[1]);
                Ray::new(origin, place.point(local) - origin)
            }
            // Along the lamp's plane.
            _ => {
                let local = Vec3::new(point(0.5).x, 0.0, point(0.5).z);
                let way = Vec3::new(point(1.0).x, 0.0, point(1.0).z);
                Ray::new(place.point(local), place.vector(way))
            }
        };
        let probe = Probe { time: rng.random(), medium_seed: rng.random(), ..Probe::default() };
        let emitted =
            |hit: Option<_>| hit.map_or(Vec3::ZERO, |hit| scene.material(&hit).emitted(&hit)).to_array();
        let whole = scene.hit_world(&ray, &probe);
        let reach = scene.lights().reach(&ray);
        let near = reach.and_then(|reach| scene.hit_world_before(&ray, reach, &probe));
        assert_eq!(
            emitted(whole),
            emitted(near),
            "ray {k}: {ray:?}, reach {reach:?}, {whole:?} against {near:?}"
        );
        lit += usize::from(emitted(whole) != [0.0; 3]);
        unreached += usize::from(reach.is_none());
        scattered += usize::from(whole.is_some_and(|hit| hit.offset == 0.0));
    }
    // The rays must cover every case: lamps seen, lamps out of reach, scattering in the fog.
    assert!(
        lit > 3000 && unreached > 3000 && scattered > 3000,
        "lit {lit}, unreached {unreached}, fog {scattered}"
    );
}
