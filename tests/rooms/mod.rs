//! Small test scenes shared by the tests of the world (`world.rs`) and of bidirectional path
//! tracing (`bidir.rs`).
#![allow(dead_code)]

/// A camera at the origin looking down −z with a 60° view, its focus 1 away.
pub const CAMERA: &str = r#"
[camera]
lookfrom = [0.0, 0.0, 0.0]
lookat = [0.0, 0.0, -1.0]
vup = [0.0, 1.0, 0.0]
vfov = 60.0
focus_dist = 1.0
aspect = 1.0
"#;

/// Six quads facing into the cube `[-1, 1]³`, all of `material`.
pub fn inward_cube(material: &str) -> String {
    let faces = [
        ([-1.0, -1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]), // back wall, facing +z
        ([-1.0, -1.0, 1.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]),  // front wall, facing −z
        ([-1.0, -1.0, -1.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]), // left, facing +x
        ([1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [0.0, 2.0, 0.0]),  // right, facing −x
        ([-1.0, -1.0, -1.0], [0.0, 0.0, 2.0], [2.0, 0.0, 0.0]), // floor, facing +y
        ([-1.0, 1.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]),  // ceiling, facing −y
    ];
    faces
        .iter()
        .map(|(q, u, v)| format!("[[quad]]\nq = {q:?}\nu = {u:?}\nv = {v:?}\nmaterial = {material}\n"))
        .collect()
}

/// A white room lit by a quad and a triangle inside a turned, moved group, a triangle at the
/// top level and a sphere that moves during the shutter.
pub fn lit_room() -> String {
    let lamp = "{ kind = \"diffuse_light\", emit = [3.0, 3.0, 3.0] }";
    format!(
        "{CAMERA}[background]\nkind = \"black\"\n{room}\
         [[triangle]]\nvertices = [[-0.8, -0.8, -0.95], [-0.4, -0.8, -0.95], [-0.6, -0.4, -0.95]]\nmaterial = {lamp}\n\
         [[sphere]]\ncenter = [0.5, -0.6, -0.5]\ncenter1 = [0.7, -0.6, -0.3]\nradius = 0.15\nmaterial = {lamp}\n\
         [[group]]\n[group.transform]\nrotate_y = 30.0\ntranslate = [0.0, 0.9, -0.3]\n\
         [[group.quad]]\nq = [-0.3, 0.0, -0.3]\nu = [0.6, 0.0, 0.0]\nv = [0.0, 0.0, 0.6]\nmaterial = {lamp}\n\
         [[group.triangle]]\nvertices = [[0.5, -0.5, -0.2], [0.5, -0.5, 0.2], [0.5, -0.1, 0.0]]\nmaterial = {lamp}\n",
        room = inward_cube("{ kind = \"lambertian\", albedo = [0.7, 0.7, 0.7] }"),
    )
}
