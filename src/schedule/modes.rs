//! Schedulers: who renders which tile. Each is a few lines around [`Frame::render`]; none
//! has a render loop of its own, and all produce the same image, bit for bit.
//!
//! | mode | work split | balance |
//! |---|---|---|
//! | `serial` | one thread, rows in order | – |
//! | `static` | `T` contiguous blocks of rows, one scoped thread each (the paper's naive split) | poor: a block of sky finishes early and its thread idles |
//! | `interleaved` | row `r` to thread `r mod T` | good by construction, still static |
//! | `pool-rows` | one job per row on the Shared pool (the paper's thread pool) | dynamic |
//! | `pool` | square tiles on the Shared pool | dynamic, better cache use than rows |
//! | `steal` | square tiles on the Stealing pool, dealt in contiguous runs | stealing rebalances |
//!
//! Write your own by implementing [`Scheduler`]; check it with
//! [`conformance::check`](crate::schedule::conformance::check).

use std::sync::Arc;

use pool::{Discipline, ThreadPool};

use crate::files::image::Image;
use crate::schedule::adaptive::render_adaptive;
use crate::schedule::frame::Frame;
use crate::schedule::guided::render_guided;
use crate::tracer::render::{TileOutput, TileTiming};
use crate::tracer::splats::Splats;
use crate::tracer::tile::{Shard, Tile};

/// A way of distributing a frame's tiles over threads.
///
/// The contract: call [`Frame::render`] exactly once for every pixel of the frame (through
/// [`Frame::rows`], [`Frame::tiles`] or tiles of your own), computing on at most
/// `frame.threads` threads, and return every [`TileOutput`] in any order.
///
/// ```
/// use std::sync::Arc;
/// use raypool::schedule::frame::Frame;
/// use raypool::tracer::render::TileOutput;
/// use raypool::schedule::modes::Scheduler;
///
/// /// Bottom row first, on the calling thread.
/// struct Upside;
/// impl Scheduler for Upside {
///     fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
///         frame.rows().into_iter().rev().map(|row| frame.render(row)).collect()
///     }
/// }
/// raypool::schedule::conformance::check(&Upside, 1).unwrap();
/// ```
pub trait Scheduler: Sync {
    /// Renders every pixel of `frame` once; returns the rendered tiles.
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput>;
}

/// The built-in schedulers (`--mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Schedule {
    /// One thread, rows in order: the baseline.
    Serial,
    /// `T` contiguous blocks of rows, one `std::thread::scope` thread each.
    #[value(name = "static")]
    StaticBlocks,
    /// Row `r` to thread `r mod T`, scoped threads.
    Interleaved,
    /// One job per row on a Shared-queue pool.
    #[value(name = "pool-rows")]
    PoolRows,
    /// Square tiles on a Shared-queue pool.
    #[value(name = "pool")]
    PoolTiles,
    /// Square tiles on a work-stealing pool.
    #[value(name = "steal")]
    Stealing,
}

impl Schedule {
    /// Every built-in mode, in the table's order.
    pub const ALL: [Schedule; 6] = [
        Schedule::Serial,
        Schedule::StaticBlocks,
        Schedule::Interleaved,
        Schedule::PoolRows,
        Schedule::PoolTiles,
        Schedule::Stealing,
    ];

    /// The mode's `--mode` name.
    pub fn name(self) -> &'static str {
        match self {
            Schedule::Serial => "serial",
            Schedule::StaticBlocks => "static",
            Schedule::Interleaved => "interleaved",
            Schedule::PoolRows => "pool-rows",
            Schedule::PoolTiles => "pool",
            Schedule::Stealing => "steal",
        }
    }
}

impl Scheduler for Schedule {
    fn render(&self, frame: &Arc<Frame>) -> Vec<TileOutput> {
        let t = frame.threads;
        match self {
            Schedule::Serial => frame.rows().into_iter().map(|row| frame.render(row)).collect(),
            Schedule::StaticBlocks => {
                // Block k holds rows [k·h/t, (k+1)·h/t): sizes differ by at most one row.
                let (rows, parts) = (frame.rows(), t.min(frame.height() as usize));
                let blocks =
                    (0..parts).map(|k| rows[k * rows.len() / parts..(k + 1) * rows.len() / parts].to_vec());
                on_scoped_threads(frame, blocks.collect())
            }
            Schedule::Interleaved => {
                let rows = frame.rows();
                on_scoped_threads(
                    frame,
                    (0..t).map(|k| rows.iter().skip(k).step_by(t).copied().collect()).collect(),
                )
            }
            Schedule::PoolRows | Schedule::PoolTiles | Schedule::Stealing => {
                let (discipline, jobs) = self.pool_jobs(frame).expect("a pool mode");
                on_pool(frame, discipline, jobs)
            }
        }
    }
}

impl Schedule {
    /// For a mode that renders on a pool: the pool's discipline and the jobs (rows or tiles)
    /// of `frame`; `None` for the modes on scoped threads.
    pub fn pool_jobs(self, frame: &Frame) -> Option<(Discipline, Vec<Tile>)> {
        match self {
            Schedule::PoolRows => Some((Discipline::Shared, frame.rows())),
            Schedule::PoolTiles => Some((Discipline::Shared, frame.tiles())),
            Schedule::Stealing => Some((Discipline::Stealing, frame.tiles())),
            Schedule::Serial | Schedule::StaticBlocks | Schedule::Interleaved => None,
        }
    }
}

/// Static scheduling: scoped thread `k` renders the tiles of `assignment[k]`, in order.
fn on_scoped_threads(frame: &Frame, assignment: Vec<Vec<Tile>>) -> Vec<TileOutput> {
    std::thread::scope(|scope| {
        let threads: Vec<_> = assignment
            .into_iter()
            .map(|tiles| {
                scope.spawn(move || tiles.into_iter().map(|tile| frame.render(tile)).collect::<Vec<_>>())
            })
            .collect();
        threads.into_iter().flat_map(|thread| thread.join().expect("a render thread panicked")).collect()
    })
}

/// Dynamic scheduling: one job per tile on a pool of `frame.threads` workers.
fn on_pool(frame: &Arc<Frame>, discipline: Discipline, tiles: Vec<Tile>) -> Vec<TileOutput> {
    let pool = ThreadPool::new(frame.threads, discipline).expect("a pool of at least one worker starts");
    tiles_on(&pool, frame, tiles)
}

/// Renders `tiles` of `frame` as one batch on `pool`, a job per tile (also from inside a job
/// of `pool`: a nested batch).
///
/// ```
/// use raypool::schedule::{conformance::test_frame, modes::tiles_on};
/// let pool = pool::ThreadPool::new(2, pool::Discipline::Locked).unwrap();
/// let frame = test_frame(2);
/// let rendered = tiles_on(&pool, &frame, frame.tiles());
/// assert_eq!(rendered.len(), frame.tiles().len());
/// ```
pub fn tiles_on(pool: &ThreadPool, frame: &Arc<Frame>, tiles: Vec<Tile>) -> Vec<TileOutput> {
    pool.batch(tiles.into_iter().map(|tile| {
        let frame = Arc::clone(frame);
        move || frame.render(tile)
    }))
}

/// A finished render: the image, the rays cast, and when each tile was rendered where.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The image.
    pub image: Image,
    /// Light its light paths carried to pixels that is not in `image`: a shard's, which lands
    /// in every shard's pixels and goes into its part file (empty for a whole image, which
    /// holds it).
    pub splats: Splats,
    /// Every ray cast, camera rays and bounces.
    pub rays: u64,
    /// Camera samples taken, all pixels together.
    pub samples: u64,
    /// Each tile with its timing, in the order the scheduler returned them.
    pub timeline: Vec<(Tile, TileTiming)>,
}

impl Rendered {
    /// Number of distinct threads that rendered tiles.
    pub fn threads_used(&self) -> usize {
        self.busy_per_thread().len()
    }

    /// Load imbalance: the busiest thread's rendering time over the mean across threads
    /// (1.0 = perfect balance; a scheduler's idle threads do not count as threads), by the
    /// pool's formula, [`pool::imbalance`].
    pub fn imbalance(&self) -> f64 {
        pool::imbalance(&self.busy_per_thread())
    }

    /// Seconds spent rendering tiles, per thread, in order of each thread's first tile.
    pub fn busy_per_thread(&self) -> Vec<f64> {
        let mut threads: Vec<(std::thread::ThreadId, f64)> = Vec::new();
        for (_, t) in &self.timeline {
            let seconds = (t.end - t.start).as_secs_f64();
            match threads.iter_mut().find(|(id, _)| *id == t.thread) {
                Some((_, busy)) => *busy += seconds,
                None => threads.push((t.thread, seconds)),
            }
        }
        threads.into_iter().map(|(_, busy)| busy).collect()
    }
}

/// Renders `frame` with `scheduler` (adaptively, or guided, in passes, when its settings ask
/// for it).
/// Once the frame is cancelled ([`Frame::with_cancel`]) the image is left empty (0 × 0).
///
/// # Panics
/// If the scheduler breaks its contract (a pixel rendered twice or never).
pub fn render(frame: &Arc<Frame>, scheduler: &dyn Scheduler) -> Rendered {
    let settings = frame.job().settings;
    let (image, tiles) = match (settings.adaptive, settings.guiding) {
        (Some(adaptive), _) => render_adaptive(frame, adaptive, |pass| scheduler.render(pass)),
        (None, Some(guiding)) => render_guided(frame, guiding, |pass| scheduler.render(pass)),
        (None, None) => {
            let tiles = scheduler.render(frame);
            if frame.is_cancelled() {
                // A cancelled render's image is never used: not assembling it keeps a
                // cancel to one job's time, not the whole image's.
                Ok((Image { width: 0, height: 0, pixels: Vec::new() }, tiles))
            } else {
                frame.assemble(&tiles).map(|image| (image, tiles))
            }
        }
    }
    .unwrap_or_else(|e| panic!("scheduler broke its contract: {e}"));
    let splats = if frame.shard() == Shard::WHOLE { Splats::default() } else { Frame::splats(&tiles) };
    Rendered {
        image,
        splats,
        rays: tiles.iter().map(|t| t.rays).sum(),
        samples: tiles.iter().map(|t| t.samples).sum(),
        timeline: tiles.iter().filter_map(|t| Some((t.tile, t.timing?))).collect(),
    }
}
