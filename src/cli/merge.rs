//! `raypool merge`: the part files of a sharded render read, checked to be one image, and
//! written as it; prints the parts' hosts and times.

use crate::cli::args::MergeArgs;
use crate::error::{Error, io_reason};
use crate::files::output::{Format, PendingOutput};
use crate::files::part::{Part, merge};

/// Runs `raypool merge`.
pub fn run(args: &MergeArgs) -> Result<(), Error> {
    let out = &args.out;
    let output = PendingOutput::create(out)?;
    if output.format() == Format::Part {
        return Err(Error::new(format!(
            "merge writes an image: name it .png, .ppm, .pfm or .exr (not '{}')",
            out.display()
        )));
    }
    let mut parts = Vec::with_capacity(args.parts.len());
    for path in &args.parts {
        let name = path.display().to_string();
        let bytes =
            std::fs::read(path).map_err(|e| Error::new(format!("{name}: cannot read: {}", io_reason(&e))))?;
        let part = Part::from_bytes(&bytes).map_err(|e| Error::new(format!("{name}: {e}")))?;
        parts.push((name, part));
    }
    let image = merge(&parts)?;
    output.write(&image)?;
    let headers: Vec<_> = parts.iter().map(|(_, p)| &p.header).collect();
    let slowest = headers.iter().map(|h| h.seconds).fold(0.0, f64::max);
    let mut hosts: Vec<&str> = headers.iter().map(|h| h.host.as_str()).collect();
    hosts.sort_unstable();
    hosts.dedup();
    eprintln!(
        "merged {} parts from {} host(s): {}x{}, {} rays; slowest part {slowest:.3} s, all parts {:.3} s -> {}",
        parts.len(),
        hosts.len(),
        image.width,
        image.height,
        headers.iter().map(|h| h.rays).sum::<u64>(),
        headers.iter().map(|h| h.seconds).sum::<f64>(),
        out.display()
    );
    Ok(())
}
