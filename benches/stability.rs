//! `cargo bench --bench stability`: the numerical stress cases of `raypool::measure::stress`, rendered
//! with the book's method (textbook quadratic, fixed t_min = 0.001, rays spawned at the raw
//! hit point) and with raypool's robust one. Writes `results/stability-f32.csv` (or `-f64`
//! with `--features f64`) and `results/stability.md` from whichever of the two exist.

use std::fmt::Write as _;

use raypool::measure::machine::{Machine, results_dir};
use raypool::measure::stress::cases;
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
    std::fs::write(dir.join("stability.md"), &md).expect("results/ is writable");
    println!("{md}");
}

/// A CSV line's fields; only the first (the case's name, quoted) may contain commas.
fn fields(line: &str) -> Vec<String> {
    let mut fields: Vec<String> = line.rsplitn(8, ',').map(|f| f.trim_matches('"').to_owned()).collect();
    fields.reverse();
    fields
}
