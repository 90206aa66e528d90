//! **Denoising: a few-sample image made presentable while the camera moves**, as a production
//! viewport does (Blender's Cycles denoises its navigation frames).
//!
//! A 1-sample image is noise around the right mean. Its edges, though, are known exactly from
//! the first hit of each pixel's camera ray: which surface, facing where, of what colour.
//! [`guide`] records those first hits; [`atrous`] averages each pixel with neighbours that
//! share its surface (the edge-avoiding à-trous wavelet filter of Dammertz et al. 2010, the
//! spatial filter of SVGF), so the noise is averaged away within a surface and no colour
//! leaks across an edge. Dividing the image by the guide's colour before filtering (and
//! multiplying after) keeps textures sharp: only the light is blurred.
//!
//! A denoised image is biased (a blurred shadow is not the true one), so it is never what a
//! measurement reads: `raypool render --denoise` and the viewer's moving preview only.
//! Everything here depends only on the job and the image, never on the threads that ran it.

pub mod atrous;
pub mod guide;

use crate::files::image::Image;
use crate::tracer::render::RenderJob;

/// `image` (rendered from `job`) denoised with the default [`atrous::Filter`], on `threads`
/// threads: the same bits however many.
///
/// ```
/// use raypool::denoise::{denoise, guide::Guides};
/// use raypool::scenes::builtin::builtin_scene;
/// use raypool::{Image, RenderJob, RenderSettings};
/// let scene = builtin_scene("final", 0).unwrap().to_scene();
/// let job = RenderJob::new(scene, RenderSettings { width: 30, height: 20, ..RenderSettings::default() });
/// // An image with no noise: every pixel its first hit's colour under one light level.
/// let lit: Vec<_> = Guides::of(&job, 1).pixels.iter().map(|g| g.albedo * 0.5).collect();
/// let image = Image { width: 30, height: 20, pixels: lit.clone() };
/// let out = denoise(&job, &image, 2);
/// for (after, before) in out.pixels.iter().zip(&lit) {
///     assert!((*after - *before).abs().max_element() <= 0.01 * before.max_element(), "{after:?} {before:?}");
/// }
/// ```
pub fn denoise(job: &RenderJob, image: &Image, threads: usize) -> Image {
    let guides = guide::Guides::of(job, threads);
    let pixels = atrous::Filter::default().apply(&image.pixels, &guides, threads);
    Image { width: image.width, height: image.height, pixels }
}

/// Calls `work(first_row, band)` for bands of a few whole rows of `out` (rows of `width`), on
/// up to `threads` scoped threads (no more than the machine's CPUs: a render may ask for
/// 4,096), each thread taking every `threads`-th band: interleaved, because an image's cost is
/// not even (a sky's rows cost nearly nothing; with one band per thread, the thread given the
/// ground did all the work). Each pixel is written by exactly one call, so the result does not
/// depend on how many threads.
fn in_row_bands<T: Send>(out: &mut [T], width: usize, threads: usize, work: impl Fn(usize, &mut [T]) + Sync) {
    let rows = out.len() / width.max(1);
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = threads.min(cpus).clamp(1, rows.max(1));
    let rows_per_band = rows.div_ceil(BANDS_PER_THREAD * threads).max(1);
    let mut shares: Vec<Vec<(usize, &mut [T])>> = (0..threads).map(|_| Vec::new()).collect();
    for (k, band) in out.chunks_mut(rows_per_band * width.max(1)).enumerate() {
        shares[k % threads].push((k * rows_per_band, band));
    }
    let run =
        |share: Vec<(usize, &mut [T])>| share.into_iter().for_each(|(first_row, band)| work(first_row, band));
    std::thread::scope(|scope| {
        let mut shares = shares.into_iter();
        let own = shares.next();
        for share in shares {
            scope.spawn(|| run(share));
        }
        if let Some(share) = own {
            run(share);
        }
    });
}

/// Bands of rows per thread: enough that uneven rows even out, few enough that each band is
/// a long run of pixels.
const BANDS_PER_THREAD: usize = 8;
