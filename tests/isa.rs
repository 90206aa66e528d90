//! The vector instructions a search runs with change its time, never its answer: the mesh's
//! search finds the same triangle, distance and barycentric coordinates, bit for bit, at
//! every level this CPU offers (`tests/golden.rs` checks whole images at every level), and
//! `RAYPOOL_ISA` names a level or is refused in one line.

mod deadline;

use std::process::Command;

use deadline::{output_within, within};
use raypool::scenes::builtin::{DEFAULT_SCENE_SEED, builtin_scene};
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::math::ray::Ray;
use raypool::tracer::math::real::{Real, Vec3};
use raypool::tracer::world::mesh::Mesh;
use raypool::tracer::world::object::Object;

/// splitmix64's numbers in [0, 1).
fn uniform(state: &mut u64) -> Real {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 40) as Real / (1u64 << 24) as Real
}

fn the_mesh() -> Mesh {
    let scene = builtin_scene("mesh", DEFAULT_SCENE_SEED).unwrap().to_scene();
    let mesh = scene.objects().iter().find_map(|o| match o {
        Object::Mesh(mesh, _) => Some(mesh.clone()),
        _ => None,
    });
    Mesh::clone(&mesh.expect("the mesh scene has a mesh"))
}

/// Rays from points around and on the mesh (its vertices: rays that start on a corner shared
/// by six triangles) in every direction, and rays along the axes (a zero direction component
/// in the slab test and the shear).
fn rays(mesh: &Mesh) -> Vec<Ray> {
    let mut state = 7;
    let positions = mesh.positions();
    let (lo, hi) = positions
        .iter()
        .fold((Vec3::splat(Real::MAX), Vec3::splat(Real::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let mut rays = Vec::new();
    for k in 0..60_000 {
        let mut point = || Vec3::new(uniform(&mut state), uniform(&mut state), uniform(&mut state));
        let origin = if k % 3 == 0 {
            positions[k % positions.len()]
        } else {
            lo + (hi - lo) * (point() * 1.4 - Vec3::splat(0.2))
        };
        let dir = if k % 10 == 0 {
            [Vec3::X, -Vec3::Y, Vec3::Z][k % 3]
        } else {
            (point() - Vec3::splat(0.5)).normalize_or(Vec3::X)
        };
        rays.push(Ray::new(origin, dir));
    }
    rays
}

#[test]
fn every_isa_level_finds_the_same_triangle_hits() {
    within("the mesh's searches at every level to finish", || {
        let mesh = the_mesh();
        let rays = rays(&mesh);
        let answers = |isa: Isa| -> Vec<_> {
            rays.iter()
                .map(|ray| {
                    let found = mesh.closest(ray, Real::INFINITY, isa);
                    let found =
                        found.map(|(k, hit)| (k, hit.t.to_bits(), hit.barycentric.map(Real::to_bits)));
                    (found, mesh.occludes(ray, 10.0, isa))
                })
                .collect()
        };
        let baseline = answers(Isa::BASELINE);
        let hits = baseline.iter().filter(|(found, _)| found.is_some()).count();
        assert!(hits > rays.len() / 10, "only {hits} of {} rays hit: the test tests little", rays.len());
        for isa in Isa::available() {
            let differ = answers(isa).iter().zip(&baseline).filter(|(a, b)| a != b).count();
            assert_eq!(
                differ,
                0,
                "{differ} of {} rays found another hit at {isa:?} than at sse2",
                rays.len()
            );
        }
        eprintln!("levels checked: {:?}", Isa::available());
    })
}

fn render(isa: &str) -> std::process::Output {
    let out = tempfile::tempdir().unwrap();
    let image = out.path().join("mesh.ppm");
    let mut command = Command::new(env!("CARGO_BIN_EXE_raypool"));
    command.env("RAYPOOL_ISA", isa).args(["render", "--scene", "mesh", "--width", "40", "--spp", "2"]);
    let mut output = output_within(command.arg("--out").arg(&image), format!("`raypool render` at {isa}"));
    output.stdout = std::fs::read(&image).unwrap_or_default();
    output
}

#[test]
fn raypool_isa_chooses_a_level_and_refuses_what_it_cannot_run() {
    let sse2 = render("sse2");
    assert!(sse2.status.success(), "{}", String::from_utf8_lossy(&sse2.stderr));
    for isa in Isa::available() {
        assert_eq!(render(isa.name()).stdout, sse2.stdout, "the image at {isa:?}");
    }
    for (name, why) in [("avx9", "unknown ISA `avx9`: it is sse2, avx2 or avx512"), ("", "unknown ISA ``")] {
        let refused = render(name);
        let stderr = String::from_utf8_lossy(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
        assert!(stderr.contains(why), "{stderr}");
        assert!(refused.stdout.is_empty(), "no image is written");
    }
}

/// A code-generation guard, not a timing: no function of the built `raypool` uses a 512-bit
/// register (`zmm`). The avx512 level keeps eight lanes, in 256-bit registers; a lone 512-bit
/// instruction (once, the compiler's one masked load of a quad hit's two coordinates, a ray)
/// slowed every later instruction on an Intel Xeon (`results/simd.md`, fifth pass). Third-party code that uses them on purpose, outside the
/// render loop, is listed with where it runs. Needs binutils' `objdump`; without it, skipped.
/// Not in the `f64` build: made to compare numerics, not speed, it moves its eight f64 lanes
/// (64 bytes) in whatever registers the compiler picks.
#[cfg(not(feature = "f64"))]
#[test]
fn no_function_of_ours_uses_512_bit_registers() {
    // crc32fast: the checksums of a PNG being written, once per image.
    const THEIRS: [&str; 1] = ["<crc32fast::"];
    let mut command = Command::new("objdump");
    command.args(["-d", "--no-show-raw-insn", "-C", env!("CARGO_BIN_EXE_raypool")]);
    let listing = match command.output() {
        Ok(output) if output.status.success() => output.stdout,
        _ => return eprintln!("skipped: no objdump (Debian's binutils) to read the binary with"),
    };
    let listing = String::from_utf8_lossy(&listing);
    let mut function = "";
    let mut offenders = std::collections::BTreeSet::new();
    for line in listing.lines() {
        if line.ends_with(">:") {
            function = line;
        } else if line.contains("zmm") && !THEIRS.iter().any(|theirs| function.contains(theirs)) {
            offenders.insert(function);
        }
    }
    assert!(offenders.is_empty(), "512-bit registers used in {offenders:#?}");
}
