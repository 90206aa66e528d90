//! Closed solids for the stress cases of [`crate::measure::stress_shapes`], as f64 vertex lists
//! with shared, indexed vertices: a subdivided icosahedron and a box of twelve triangles, and
//! the list of the edges their triangles share.

use glam::DVec3;

/// The unit icosahedron subdivided `levels` times, its vertices shared and on the unit sphere.
pub fn icosphere(levels: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<DVec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .map(|v| DVec3::from(v).normalize())
    .to_vec();
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut middle = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, p: &mut Vec<DVec3>| {
            *middle.entry((a.min(b), a.max(b))).or_insert_with(|| {
                p.push((p[a as usize] + p[b as usize]).normalize());
                p.len() as u32 - 1
            })
        };
        t = t
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b, &mut p), mid(b, c, &mut p), mid(c, a, &mut p));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    (p, t)
}

/// The box `[lo, hi]` as 12 triangles on its 8 corners (corner `i` takes `hi` on axis `k`
/// where bit `k` of `i` is set).
pub fn cube(lo: DVec3, hi: DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let corner = |i: u32| {
        DVec3::new(
            [lo.x, hi.x][i as usize & 1],
            [lo.y, hi.y][i as usize >> 1 & 1],
            [lo.z, hi.z][i as usize >> 2],
        )
    };
    let faces = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
    let triangles = faces.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    ((0..8).map(corner).collect(), triangles)
}

/// The shared edges of a triangle list, each once.
pub fn edges(triangles: &[[u32; 3]]) -> Vec<[usize; 2]> {
    let mut e: Vec<[usize; 2]> = triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[a, b]| [a.min(b) as usize, a.max(b) as usize])
        .collect();
    e.sort_unstable();
    e.dedup();
    e
}
