//! `cargo bench --bench stability`: the numerical stress cases of `raypool::measure::stress`, rendered
//! with the book's method (textbook quadratic, fixed t_min = 0.001, rays spawned at the raw
//! hit point) and with raypool's robust one; then the ray-by-ray cases of
//! `raypool::measure::stress_shapes` (leaks through the seams of closed meshes and boxes, acne
//! on quads and triangles far from the origin, thin boxes met by grazing rays, each also through
//! an instance) and of `raypool::measure::stress_smooth` (bounces off a mesh shaded by its
//! vertex normals that meet it again) at `RAYPOOL_SHAPE_RAYS` rays a case (10⁶ unless set), at
//! every vector level the CPU has (`RAYPOOL_ISA`'s sse2, avx2, avx512). Writes
//! `results/stability-f32.csv` and `results/stability-shapes-f32.csv` (or `-f64` with
//! `--features f64`) and `results/stability.md` from whichever of them exist.

use std::fmt::Write as _;

use raypool::measure::machine::{Machine, results_dir};
use raypool::measure::stress::cases;
use raypool::measure::stress_shapes::Row;
use raypool::measure::{stress_shapes, stress_smooth};
use raypool::tracer::accel::isa::Isa;
use raypool::tracer::geometry::sphere::Intersection;

const PRECISION: &str = if cfg!(feature = "f64") { "f64" } else { "f32" };
const METHODS: [(&str, Intersection); 2] =
    [("textbook", Intersection::Textbook), ("robust", Intersection::Robust)];

fn main() {
    let mut csv = String::from("case,precision,method,pixels,non_finite,dark,bright,worst\n");
    for case in cases() {
        for (method, intersection) in METHODS {
            let o = case.run(intersection);
            let pixels = case.size * case.size;
            let _ = writeln!(
                csv,
                "\"{}\",{PRECISION},{method},{pixels},{},{},{},{:.3e}",
                case.name, o.non_finite, o.dark, o.bright, o.worst
            );
            eprintln!("{} {PRECISION} {method}: {o:?}", case.name);
        }
    }
    let dir = &results_dir();
    std::fs::write(dir.join(format!("stability-{PRECISION}.csv")), &csv).expect("results/ is writable");
    let rays = std::env::var("RAYPOOL_SHAPE_RAYS").ok().and_then(|n| n.parse().ok()).unwrap_or(1_000_000);
    let mut shapes = String::from("case,precision,rays,failures,detail\n");
    // Every case at every vector level the CPU has (`RAYPOOL_ISA`): one row, its failures the
    // most of any level, its detail the levels' own where they differ.
    let levels = Isa::available();
    let per_level: Vec<Vec<Row>> = levels
        .iter()
        .map(|&isa| {
            stress_shapes::table(rays, isa).into_iter().chain(stress_smooth::rows(rays, isa)).collect()
        })
        .collect();
    let names: Vec<&str> = levels.iter().map(|isa| isa.name()).collect();
    for (k, row) in per_level[0].iter().enumerate() {
        let details: Vec<&str> = per_level.iter().map(|rows| rows[k].detail.as_str()).collect();
        let detail = if details.iter().all(|d| *d == row.detail) {
            format!("{} (the same at {})", row.detail, names.join(", "))
        } else {
            names.iter().zip(&details).map(|(isa, d)| format!("{isa}: {d}")).collect::<Vec<_>>().join("; ")
        };
        let failures = per_level.iter().map(|rows| rows[k].failures).max().unwrap_or(0);
        eprintln!("{} {PRECISION}: {detail}", row.case);
        let _ = writeln!(shapes, "\"{}\",{PRECISION},{},{failures},\"{detail}\"", row.case, row.rays);
    }
    std::fs::write(dir.join(format!("stability-shapes-{PRECISION}.csv")), &shapes)
        .expect("results/ is writable");

    let rows: Vec<Vec<String>> = ["f32", "f64"]
        .iter()
        .filter_map(|p| std::fs::read_to_string(dir.join(format!("stability-{p}.csv"))).ok())
        .flat_map(|text| text.lines().skip(1).map(fields).collect::<Vec<_>>())
        .collect();
    let mut md = format!(
        "# Numerical stability: the book's method against raypool's\n\n\
         `cargo bench --bench stability [--features f64]`; {}.\n\n\
         Every scene is lit by a uniform white sky, so every correct pixel lies between a known floor (the albedo; 1 \
         for clear glass) and 1 (`src/measure/stress.rs`). **dark**: pixels below the floor, i.e. energy lost to a ray \
         re-hitting the surface it left (acne); **NaN**: pixels with a NaN or infinite channel; **worst**: the largest \
         distance of a value outside the correct range. Textbook = the book's quadratic `h² − c`, hits nearer than \
         t_min = 0.001 ignored, new rays from the raw hit point. Robust = the stable quadratic, hit points re-projected \
         on the surface, new rays pushed off by a scale-aware offset.\n\n\
         | case | pixels | precision | textbook: dark | textbook: NaN | textbook: worst | robust: dark | robust: NaN | robust: worst |\n\
         |---|---:|---|---:|---:|---:|---:|---:|---:|\n",
        Machine::current().describe()
    );
    for textbook in rows.iter().filter(|r| r[2] == "textbook") {
        let Some(robust) =
            rows.iter().find(|r| r[2] == "robust" && r[0] == textbook[0] && r[1] == textbook[1])
        else {
            continue;
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            textbook[0],
            textbook[3],
            textbook[1],
            textbook[5],
            textbook[4],
            textbook[7],
            robust[5],
            robust[4],
            robust[7]
        );
    }
    md.push_str(&shapes_section(dir));
    std::fs::write(dir.join("stability.md"), &md).expect("results/ is writable");
    println!("{md}");
}

/// A CSV line's fields; only the first (the case's name, quoted) may contain commas.
fn fields(line: &str) -> Vec<String> {
    let mut fields: Vec<String> = line.rsplitn(8, ',').map(|f| f.trim_matches('"').to_owned()).collect();
    fields.reverse();
    fields
}

/// The second section of `stability.md`: the shapes' cases, from whichever precisions' CSVs exist.
fn shapes_section(dir: &std::path::Path) -> String {
    let mut md = format!(
        "\n## Quads, triangles and instances, ray by ray\n\n\
         `cargo bench --bench stability [--features f64]`; {}.\n\n\
         Counted ray by ray (`src/measure/stress_shapes.rs`), each case from a fixed seed, at every vector level \
         this CPU has (the detail says whether the levels' counts are the same). **leaks**: rays from \
         outside aimed exactly at a random point of a shared edge, or at a shared vertex, of a closed solid (never \
         grazing a face it lies on) that miss it entirely. **acne**: a tilted quad or triangle (unit-sized) far from \
         the origin, hit from either side; from each hit one ray is spawned (`Hit::spawn`) back to the hit's side \
         (acne if it meets the shape again) and one through it (blocked if it does); a quarter of them within \
         6° of grazing. **thin box**: a 1 × h × 1 box and rays aimed at and around it, half within a slope of \
         10⁻⁷..10⁻¹ of its large faces, judged against an exact f64 slab test of the same box and ray; rays within \
         16 ε (32 ε through the instance) of an edge are counted but not judged. **through an instance**: the \
         same shape turned 30° about y and 20° about x, then moved by (1, 0.5, −1) (acne: moved to the distance). \
         **self-hits** (`src/measure/stress_smooth.rs`): a convex icosphere shaded by its vertex normals, hit from \
         outside; from each hit one Lambertian bounce about the shading normal, spawned as the renderer spawns it \
         (from the smooth surface the normals describe); it fails if it meets the mesh again. The detail also counts \
         the same bounces started from the flat facet instead.\n\n\
         | case | rays | precision | failures | detail |\n|---|---:|---|---:|---|\n",
        Machine::current().describe()
    );
    for p in ["f32", "f64"] {
        let Ok(text) = std::fs::read_to_string(dir.join(format!("stability-shapes-{p}.csv"))) else {
            continue;
        };
        for line in text.lines().skip(1) {
            let quoted: Vec<&str> = line.split('"').collect();
            let numbers: Vec<&str> = quoted[2].trim_matches(',').split(',').collect();
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} |",
                quoted[1], numbers[1], numbers[0], numbers[2], quoted[3]
            );
        }
    }
    md
}
