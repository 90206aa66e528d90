//! Measuring error: how far an image is from a reference, over linear (PFM) values.
//!
//! `raypool compare A.pfm REF.pfm` prints the usual figures of the rendering literature:
//! RMSE, relative MSE (squared error ÷ (reference² + 0.01), which weighs dark regions fairly),
//! mean absolute error, the largest pixel error and PSNR (peak 1.0, i.e. white). `--diff`
//! writes a false-colour map of each pixel's error (viridis: dark = none, yellow = the largest).

use std::path::Path;

use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};

use crate::error::{Error, io_reason};
use crate::files::output::{PendingOutput, read_pfm};

/// Error figures of an image against a reference, over every channel of every pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metrics {
    /// Root mean squared error.
    pub rmse: f64,
    /// Mean of (a − ref)² ÷ (ref² + 0.01).
    pub rel_mse: f64,
    /// Mean absolute error.
    pub mae: f64,
    /// Largest absolute error of any channel of any pixel.
    pub max_error: f64,
    /// Peak signal-to-noise ratio in dB, for a peak of 1.0 (infinite for identical images).
    pub psnr: f64,
}

/// The weight of a squared error in the relative MSE, where the reference's value is
/// `reference`: 1 ÷ (reference² + 0.01), so dark pixels count as much as bright ones.
pub fn relative_weight(reference: f64) -> f64 {
    1.0 / (reference * reference + 0.01)
}

/// Compares `image` with `reference`, both linear RGB of the same size.
///
/// ```
/// let a = [[0.5f32, 0.5, 0.5]];
/// let m = raypool::measure::compare::metrics(&a, &[[0.25, 0.5, 0.5]]);
/// assert!((m.max_error - 0.25).abs() < 1e-12 && (m.mae - 0.25 / 3.0).abs() < 1e-12);
/// ```
pub fn metrics(image: &[[f32; 3]], reference: &[[f32; 3]]) -> Metrics {
    let n = (image.len() * 3).max(1) as f64;
    let pairs =
        || image.iter().flatten().zip(reference.iter().flatten()).map(|(&a, &r)| (a as f64, r as f64));
    let mse = pairs().map(|(a, r)| (a - r).powi(2)).sum::<f64>() / n;
    Metrics {
        rmse: mse.sqrt(),
        rel_mse: pairs().map(|(a, r)| (a - r).powi(2) * relative_weight(r)).sum::<f64>() / n,
        mae: pairs().map(|(a, r)| (a - r).abs()).sum::<f64>() / n,
        max_error: pairs().map(|(a, r)| (a - r).abs()).fold(0.0, f64::max),
        psnr: -10.0 * mse.log10(),
    }
}

/// Reads two PFM files, compares them, and optionally writes the false-colour difference.
pub fn compare_files(image: &Path, reference: &Path, diff: Option<&Path>) -> Result<Metrics, Error> {
    let pending = diff.map(PendingOutput::create).transpose()?; // fail fast on a bad path
    let read = |path: &Path| {
        let bytes = std::fs::read(path)
            .map_err(|e| Error::new(format!("cannot read '{}': {}", path.display(), io_reason(&e))))?;
        read_pfm(&bytes).map_err(|e| Error::new(format!("'{}' is not a PFM image: {e}", path.display())))
    };
    let (w, h, a) = read(image)?;
    let (rw, rh, r) = read(reference)?;
    if (w, h) != (rw, rh) {
        return Err(Error::new(format!("image sizes differ: {w}x{h} against {rw}x{rh}")));
    }
    let m = metrics(&a, &r);
    if let Some(pending) = pending {
        let errors: Vec<f64> = a
            .iter()
            .zip(&r)
            .map(|(p, q)| (0..3).map(|c| (p[c] as f64 - q[c] as f64).abs()).fold(0.0, f64::max))
            .collect();
        let scale = if m.max_error > 0.0 { 1.0 / m.max_error } else { 0.0 };
        let rgb: Vec<u8> = errors
            .iter()
            .flat_map(|e| {
                let c = ViridisRGB.get_color_normalized(e * scale, 0.0, 1.0);
                [c.0, c.1, c.2]
            })
            .collect();
        pending.write_rgb8(w, h, &rgb)?;
    }
    Ok(m)
}
