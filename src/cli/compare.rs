//! `raypool compare`: two PFM images' error metrics on one line, and optionally a map of
//! each pixel's error.

use crate::cli::args::CompareArgs;
use crate::cli::output;
use crate::error::Error;
use crate::measure::compare::compare_files;

/// Runs `raypool compare`.
pub fn run(args: &CompareArgs) -> Result<(), Error> {
    let m = compare_files(&args.image, &args.reference, args.diff.as_deref())?;
    output(&format!(
        "rmse {:.6}  rel_mse {:.6}  mae {:.6}  max {:.6}  psnr {:.2} dB\n",
        m.rmse, m.rel_mse, m.mae, m.max_error, m.psnr
    ))
}
