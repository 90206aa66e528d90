//! The TOML scene format: round trips, named materials, and precise error messages.

use raypool::scenes::builtin::{BUILTINS, builtin_scene};
use raypool::scenes::format::SceneFile;
use raypool::scenes::world::Shapes;
use raypool::tracer::render::{RenderJob, RenderSettings, render_tile};
use raypool::tracer::sampling::sobol::SobolStreams;
use raypool::tracer::shading::material::Material;
use raypool::tracer::tile::Tile;

const MINIMAL: &str = r#"
[camera]
lookfrom = [0.0, 0.0, 5.0]
lookat = [0.0, 0.0, 0.0]
vup = [0.0, 1.0, 0.0]
vfov = 40.0
focus_dist = 5.0

[materials]
gold = { kind = "metal", albedo = [0.8, 0.6, 0.2], fuzz = 0.1 }

[[sphere]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "gold"

[[sphere]]
center = [0.0, -101.0, 0.0]
radius = 100.0
material = { kind = "lambertian", albedo = [0.5, 0.5, 0.5] }
"#;

#[test]
fn every_builtin_round_trips_through_toml() {
    for b in BUILTINS {
        let scene = builtin_scene(b.name, 77).unwrap();
        let text = scene.to_toml();
        let again =
            SceneFile::parse(&text, "round-trip").unwrap_or_else(|e| panic!("{}: {e}\n{text}", b.name));
        assert_eq!(again, scene, "{} changed in the round trip", b.name);
    }
}

#[test]
fn without_focus_dist_the_lookat_distance_is_in_focus() {
    // MINIMAL looks from 5 units away; through a wide lens, leaving focus_dist out must give
    // the image of focus_dist = 5, bit for bit, and not that of another distance.
    let lens = |focus: &str| MINIMAL.replace("focus_dist = 5.0", &format!("aperture = 0.5\n{focus}"));
    let image = |text: String| {
        let settings = RenderSettings { width: 16, height: 12, spp: 4, ..Default::default() };
        let scene = SceneFile::parse(&text, "lens.toml").unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.to_toml().contains("focus_dist") == text.contains("focus_dist"), "printed as read");
        let job = RenderJob::new(scene.to_scene(), settings);
        render_tile(&job, &SobolStreams::new(1), Tile { x: 0, y: 0, width: 16, height: 12 }).pixels
    };
    let absent = image(lens(""));
    assert_eq!(absent, image(lens("focus_dist = 5.0")), "the distance to lookat, 5");
    assert_ne!(absent, image(lens("focus_dist = 2.0")), "a lens makes the focus show");
    let far = MINIMAL.replace("focus_dist = 5.0", "");
    let far = far.replace("lookat = [0.0, 0.0, 0.0]", "lookat = [0.0, 0.0, 0.0]\nfocus_dist = 0.0");
    let error = SceneFile::parse(&far, "zero.toml").unwrap_err().to_string();
    assert!(error.contains("camera.focus_dist must be > 0"), "{error}");
    // Left out where the eye is the look-at point: the message names the real mistake.
    let blind = lens("").replace("lookfrom = [0.0, 0.0, 5.0]", "lookfrom = [0.0, 0.0, 0.0]");
    let error = SceneFile::parse(&blind, "blind.toml").unwrap_err().to_string();
    assert!(error.contains("camera.lookfrom and camera.lookat are the same point"), "{error}");
}

#[test]
fn final_scene_is_the_books_and_depends_on_its_seed() {
    let a = builtin_scene("final", 1).unwrap();
    let b = builtin_scene("final", 2).unwrap();
    assert_ne!(a, b);
    // 1 ground + up to 22 × 22 small + 3 big spheres; a few are skipped near the metal one.
    assert!((450..=488).contains(&a.shapes.spheres.len()), "{} spheres", a.shapes.spheres.len());
    assert_eq!(builtin_scene("final", 1).unwrap(), a, "same seed, same scene");
}

#[test]
fn named_and_inline_materials_resolve() {
    let scene = SceneFile::parse(MINIMAL, "minimal.toml").unwrap().to_scene();
    let (spheres, materials) = (scene.spheres(), scene.materials());
    assert_eq!(spheres.len(), 2);
    assert!(matches!(materials[spheres[0].material as usize], Material::Metal { .. }));
    assert!(matches!(materials[spheres[1].material as usize], Material::Lambertian { .. }));
    assert_eq!(scene.camera.aperture, 0.0, "aperture defaults to a pinhole");
    assert_eq!(scene.camera.aspect, 1.5, "aspect defaults to 3:2");
}

fn error_of(text: &str) -> String {
    SceneFile::parse(text, "bad.toml").unwrap_err().to_string()
}

#[test]
fn syntax_errors_name_file_line_and_column() {
    let text = MINIMAL.replace("radius = 1.0", "radius = 1.0.0");
    let e = error_of(&text);
    assert!(e.starts_with("bad.toml:14:13:"), "{e}");
    assert!(!e.contains('\n'), "one line: {e}");
}

#[test]
fn unknown_material_kind_is_named() {
    let e = error_of(&MINIMAL.replace("\"lambertian\"", "\"plastic\""));
    assert!(e.starts_with("bad.toml:20:") && e.contains("plastic") && e.contains("lambertian"), "{e}");
}

#[test]
fn missing_and_unknown_fields_are_reported() {
    let e = error_of(&MINIMAL.replace("vfov = 40.0\n", ""));
    assert!(e.contains("vfov"), "{e}");
    let e = error_of(&MINIMAL.replace("vfov = 40.0", "vfov = 40.0\nzoom = 2.0"));
    assert!(e.contains("zoom") && e.starts_with("bad.toml:7:"), "{e}");
    // A camera missing several fields is told all of them at once, at its table's line.
    let e = error_of(&MINIMAL.replace("vup = [0.0, 1.0, 0.0]\nvfov = 40.0\n", ""));
    assert_eq!(
        e,
        "bad.toml:2:1: [camera] is missing fields `vup`, `vfov` (it needs lookfrom, lookat, vup, vfov)"
    );
    let e = error_of(&format!("[materials]{}", MINIMAL.split_once("[materials]").unwrap().1));
    assert!(e.starts_with("bad.toml:1:1: no [camera] table"), "{e}");
    // What the message calls required is what the format requires: a camera of those fields
    // alone parses, and without any one of them it is refused naming that one.
    let smallest = "[camera]\nlookfrom = [0.0, 0.0, 0.0]\nlookat = [0.0, 0.0, -1.0]\nvup = [0.0, 1.0, 0.0]\nvfov = 40.0\n";
    SceneFile::parse(smallest, "smallest.toml").unwrap_or_else(|e| panic!("{e}"));
    for field in raypool::scenes::format::CAMERA_REQUIRED {
        let line = smallest.lines().find(|l| l.starts_with(&format!("{field} ="))).unwrap();
        let e = error_of(&smallest.replace(&format!("{line}\n"), ""));
        assert!(e.starts_with(&format!("bad.toml:1:1: [camera] is missing field `{field}` (")), "{e}");
    }
}

#[test]
fn every_shape_table_is_read_and_unknown_tables_are_refused_where_they_stand() {
    // A scene file and a group are read by hand (`Shapes::read`), so each name the key check
    // accepts must be one that is read: an empty list of each parses, at both levels.
    let no_shapes = MINIMAL.split("[[sphere]]").next().unwrap();
    for table in Shapes::TABLES {
        let top = format!("{table} = []\n{no_shapes}");
        SceneFile::parse(&top, "top.toml").unwrap_or_else(|e| panic!("{table}: {e}"));
        let group = format!("{no_shapes}\n[[group]]\n{table} = []\n");
        SceneFile::parse(&group, "group.toml").unwrap_or_else(|e| panic!("group.{table}: {e}"));
    }
    let line_of = |text: &str, needle: &str| text.lines().position(|l| l.contains(needle)).unwrap() + 1;
    let text = format!("{MINIMAL}\n[[sphre]]\n");
    let e = error_of(&text);
    let at =
        format!("bad.toml:{}:3: unknown field `sphre`, expected one of `camera`,", line_of(&text, "sphre"));
    assert!(e.starts_with(&at) && e.contains("`disc`") && e.contains("`group`"), "{e}");
    let text = format!("{MINIMAL}\n[[group]]\n[[group.sphre]]\n");
    let e = error_of(&text);
    let at = format!(
        "bad.toml:{}:9: unknown field `sphre`, expected one of `transform`, `sphere`",
        line_of(&text, "sphre")
    );
    assert!(e.starts_with(&at), "{e}");
    // An error inside a shape's table keeps its place.
    let text = MINIMAL.replace("radius = 1.0", "radius = \"one\"");
    let e = error_of(&text);
    assert!(e.starts_with(&format!("bad.toml:{}:10: invalid type: string", line_of(&text, "one"))), "{e}");
}

#[test]
fn semantic_errors_name_the_item() {
    let cases = [
        (MINIMAL.replace("radius = 1.0", "radius = 0.0"), "sphere #1"),
        (MINIMAL.replace("radius = 1.0", "radius = nan"), "radius"),
        (MINIMAL.replace("vfov = 40.0", "vfov = 180.0"), "vfov"),
        (MINIMAL.replace("focus_dist = 5.0", "focus_dist = -1.0"), "focus_dist"),
        (MINIMAL.replace("lookat = [0.0, 0.0, 0.0]", "lookat = [0.0, 0.0, 5.0]"), "same point"),
        (MINIMAL.replace("vup = [0.0, 1.0, 0.0]", "vup = [0.0, 0.0, 1.0]"), "vup"),
        (MINIMAL.replace("material = \"gold\"", "material = \"silver\""), "silver"),
        (MINIMAL.replace("fuzz = 0.1", "fuzz = inf"), "fuzz"),
        (MINIMAL.replace("[0.8, 0.6, 0.2]", "[0.8, nan, 0.2]"), "materials.gold"),
        (MINIMAL.replace("center = [0.0, 0.0, 0.0]", "center = [0.0, -inf, 0.0]"), "center"),
    ];
    for (text, needle) in cases {
        let e = error_of(&text);
        assert!(e.contains(needle) && e.starts_with("bad.toml: "), "expected '{needle}' in: {e}");
    }
}
