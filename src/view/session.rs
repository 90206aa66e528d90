//! The render session: one progressive render at a time, on our own pool (one pool for the
//! whole session, kept from pass to pass and render to render), its events fanned out to
//! every page that listens.
//!
//! [`Session::restart`] cancels the running render (its jobs see the cancel flag before their
//! next tile, so it stops within one tile's time), waits for its thread, and starts the new
//! one. The render thread runs passes of 1, 1, 2, 4, 8, 16, 16, … samples per pixel (so 1, 2,
//! 4, 8, 16, 32, 48, … accumulated; fewer per pass for big tiles or wide rows, see
//! `passes.rs`'s `MAX_JOB_SAMPLES`) up to `--spp`, each pass one batch of tiles on the chosen scheduler; every
//! finished tile becomes an event for the pages, and every finished pass becomes the image that
//! `/image.pfm` serves, which is the image `raypool render` makes at that many samples.
//! Guided (`--guiding on`), the passes follow `render`'s plan ([`crate::schedule::guided`]):
//! none spans two of its passes, and each draws from its pass's guide and learns into its
//! statistics, so the last pass's image is `render`'s (an earlier one holds the same samples,
//! but `render --spp` of that many plans passes of its own); a new render (a camera move, any
//! setting) learns its guides from the start.
//! A render asked for while the camera moves starts with a navigation frame instead
//! ([`crate::view::preview`]): a small 1-spp frame first, the passes once the camera rests.
//!
//! Invariants: at most one render thread runs; events of an old render carry its generation
//! number, so a page ignores stragglers; a page that cannot keep up (its queue full) or has
//! gone is dropped, never waited for.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread::{JoinHandle, ThreadId};
use std::time::Instant;

use crossbeam_channel::{Receiver, Sender};
use parking_lot::Mutex;
use serde_json::json;

use crate::files::image::Image;
use crate::files::output::{Format, encode};
use crate::schedule::frame::Frame;
use crate::schedule::guided::Plan;
use crate::schedule::kept::KeptPool;
use crate::schedule::modes::render;
use crate::schedule::progressive::{Cancel, Pass};
use crate::tracer::render::{RenderJob, TileOutput};
use crate::view::events::{frame_event, preview_event, start_event, tile_event};
use crate::view::passes::Passes;
use crate::view::preview::{Preview, StartResolution, camera_rested, render_preview};
use crate::view::request::Config;

/// Events a page may fall behind by before it is dropped.
const QUEUE: usize = 8192;

/// The latest finished pass.
#[derive(Clone, Debug)]
pub struct Snapshot {
    /// Which render it belongs to.
    pub generation: u64,
    /// Samples per pixel accumulated.
    pub spp: u32,
    /// The image after them.
    pub image: Image,
}

struct Current {
    generation: u64,
    config: Arc<Config>,
    cancel: Cancel,
    thread: Option<JoinHandle<()>>,
}

/// The viewer's one render at a time and the pages listening to it.
pub struct Session {
    current: Mutex<Current>,
    /// The pool every render of the session runs on (in a pool mode): one for the session,
    /// not one per pass; replaced only when a request asks for other threads or discipline.
    pool: KeptPool,
    /// Serialises restarts, so two requests cannot both start a render.
    restarting: Mutex<()>,
    latest: Mutex<Option<Arc<Snapshot>>>,
    /// The latest pass encoded, once per format however many pages ask for it.
    encoded: Mutex<Vec<Encoded>>,
    /// The latest pass as a `frame` event for pages that join late, built once, outside the
    /// pages' lock (a 2048 × 2048 frame is 16 MB of base64).
    frame: Mutex<Option<(u64, u32, Arc<str>)>>,
    /// The latest navigation frame, and the size the next one starts at.
    preview: Mutex<Option<Arc<Preview>>>,
    start_resolution: Mutex<StartResolution>,
    /// Image answers being written now (see [`Session::image_slot`]).
    image_readers: AtomicUsize,
    pages: Mutex<Pages>,
}

/// One pass's image, encoded.
#[derive(Clone)]
pub struct Encoded {
    /// The render it belongs to.
    pub generation: u64,
    /// Samples per pixel accumulated.
    pub spp: u32,
    /// Its file format.
    pub format: Format,
    /// The file's bytes, shared.
    pub bytes: Arc<[u8]>,
}

/// The most image answers written at once; more get 503. Each shares the one encoded image,
/// so the cap bounds the connections slow readers hold, not memory.
pub const MAX_IMAGE_READERS: usize = 32;

/// A place among the [`MAX_IMAGE_READERS`] image answers, given back when dropped.
pub struct ImageSlot<'a>(&'a AtomicUsize);

impl Drop for ImageSlot<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// The pages listening, and what a page that joins late is told first.
#[derive(Default)]
struct Pages {
    senders: Vec<Sender<Arc<str>>>,
    /// The running render's `start`, its latest `pass` and its `done`, as sent.
    start: Option<Arc<str>>,
    last_pass: Option<Arc<str>>,
    done: Option<Arc<str>>,
    /// The `tile` events of the latest pass that has any (the running one, or the last one
    /// once the render is done), and that pass's number: a late page draws their outlines and
    /// the timeline's bars from them.
    tiles: Vec<Arc<str>>,
    tiles_pass: u32,
    /// The `frame` sent when those tiles' pass ended, if it was sent (bdpt: its light paths
    /// lit pixels the tiles do not show), to draw over them.
    frame_over_tiles: Option<Arc<str>>,
}

/// What an event is, for what a late page must be told.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Start,
    Tile { pass: u32 },
    Preview,
    Frame,
    Pass,
    Done,
}

impl Session {
    /// A session that starts rendering `config` at once.
    pub fn start(config: Config) -> Arc<Session> {
        let session = Arc::new(Session {
            current: Mutex::new(Current {
                generation: 0,
                config: Arc::new(config.clone()),
                cancel: Cancel::default(),
                thread: None,
            }),
            pool: KeptPool::new(config.mode),
            restarting: Mutex::new(()),
            latest: Mutex::new(None),
            encoded: Mutex::new(Vec::new()),
            frame: Mutex::new(None),
            preview: Mutex::new(None),
            start_resolution: Mutex::default(),
            image_readers: AtomicUsize::new(0),
            pages: Mutex::new(Pages::default()),
        });
        session.restart(config);
        session
    }

    /// Cancels the running render and starts `config`; returns the new generation number.
    pub fn restart(self: &Arc<Session>, config: Config) -> u64 {
        let _one_at_a_time = self.restarting.lock();
        self.cancel_running();
        let mut current = self.current.lock();
        let (generation, config, cancel) = (current.generation + 1, Arc::new(config), Cancel::default());
        let thread = {
            let (session, config, cancel) = (Arc::clone(self), Arc::clone(&config), cancel.clone());
            std::thread::Builder::new()
                .name("raypool-view-render".into())
                .spawn(move || session.render_passes(generation, &config, &cancel))
                .expect("a thread starts")
        };
        *current = Current { generation, config, cancel, thread: Some(thread) };
        generation
    }

    /// Cancels the running render and waits for it (Ctrl-C); pages' streams end.
    pub fn stop(&self) {
        let _one_at_a_time = self.restarting.lock();
        self.cancel_running();
        self.pages.lock().senders.clear();
    }

    /// Cancels the running render and waits for its thread, outside the `current` lock (the
    /// render thread takes locks of its own until its jobs have seen the flag).
    fn cancel_running(&self) {
        let thread = {
            let mut current = self.current.lock();
            current.cancel.cancel();
            current.thread.take()
        };
        if let Some(thread) = thread {
            let _ = thread.join();
        }
    }

    /// The running render's settings and generation.
    pub fn current(&self) -> (u64, Arc<Config>) {
        let current = self.current.lock();
        (current.generation, Arc::clone(&current.config))
    }

    /// The latest finished pass of the running render, if one has finished (shared, not
    /// copied: a 2048 × 2048 image is 100 MB of sums).
    pub fn latest(&self) -> Option<Arc<Snapshot>> {
        let generation = self.current.lock().generation;
        self.latest.lock().clone().filter(|s| s.generation == generation)
    }

    /// The latest finished pass encoded as `format`: encoded once
    /// per pass and format, the bytes shared by every request. `Ok(None)` before a first pass.
    pub fn encoded(&self, format: Format) -> Result<Option<Encoded>, String> {
        let Some(snapshot) = self.latest() else { return Ok(None) };
        // Held while encoding: a second request for the same pass waits and shares the bytes.
        let mut encoded = self.encoded.lock();
        encoded.retain(|e| e.generation == snapshot.generation && e.spp == snapshot.spp);
        if let Some(e) = encoded.iter().find(|e| e.format == format) {
            return Ok(Some(e.clone()));
        }
        let mut bytes = Vec::new();
        encode(&snapshot.image, format, &mut bytes)?;
        let image =
            Encoded { generation: snapshot.generation, spp: snapshot.spp, format, bytes: bytes.into() };
        encoded.push(image.clone());
        Ok(Some(image))
    }

    /// A place to write an image answer, or `None` when [`MAX_IMAGE_READERS`] are being
    /// written.
    pub fn image_slot(&self) -> Option<ImageSlot<'_>> {
        if self.image_readers.fetch_add(1, Ordering::SeqCst) >= MAX_IMAGE_READERS {
            self.image_readers.fetch_sub(1, Ordering::SeqCst);
            return None;
        }
        Some(ImageSlot(&self.image_readers))
    }

    /// The `frame` event of `snapshot`, built once per pass.
    fn frame_event_of(&self, snapshot: &Snapshot) -> Arc<str> {
        let mut frame = self.frame.lock();
        match &*frame {
            Some((generation, spp, event)) if (*generation, *spp) == (snapshot.generation, snapshot.spp) => {
                Arc::clone(event)
            }
            _ => {
                let event: Arc<str> = frame_event(snapshot.generation, snapshot.spp, &snapshot.image).into();
                *frame = Some((snapshot.generation, snapshot.spp, Arc::clone(&event)));
                event
            }
        }
    }

    /// A new page's event stream. It starts with what the page missed of the running render:
    /// its `start`, a `frame` with the image of its latest pass, the `tile`s of the latest pass
    /// that has any (outlines, timeline bars and their pixels), the `frame` sent when that pass
    /// ended if one was (bdpt), that `pass`, and `done`; so a
    /// page opened late shows what a page open from the start shows. The frame is built
    /// before the pages' lock is taken (a render's tile hook takes that lock too); a pass that
    /// ends meanwhile only means its tiles are drawn over a frame one pass older.
    pub fn subscribe(&self) -> Receiver<Arc<str>> {
        let (tx, rx) = crossbeam_channel::bounded(QUEUE);
        let frame = self.latest().map(|s| self.frame_event_of(&s));
        let mut pages = self.pages.lock(); // no event goes out between the replay and the joining
        let frame = frame.filter(|_| pages.last_pass.is_some());
        let replay =
            [pages.start.clone(), frame].into_iter().flatten().chain(pages.tiles.iter().cloned()).chain(
                [pages.frame_over_tiles.clone(), pages.last_pass.clone(), pages.done.clone()]
                    .into_iter()
                    .flatten(),
            );
        for event in replay {
            let _ = tx.try_send(event);
        }
        pages.senders.push(tx);
        rx
    }

    /// Sends `event` (of type `kind`) to every page; drops pages that are gone or too far
    /// behind, and remembers what a late page must be told.
    fn broadcast(&self, kind: Kind, event: String) {
        let event: Arc<str> = event.into();
        let mut pages = self.pages.lock();
        match kind {
            Kind::Start => {
                (pages.start, pages.last_pass, pages.done) = (Some(Arc::clone(&event)), None, None);
                pages.tiles.clear();
                pages.frame_over_tiles = None;
            }
            Kind::Tile { pass } => {
                if pass != pages.tiles_pass {
                    (pages.tiles_pass, pages.tiles, pages.frame_over_tiles) = (pass, Vec::new(), None);
                }
                pages.tiles.push(Arc::clone(&event));
            }
            Kind::Preview => {} // a late page is shown the latest pass instead
            Kind::Frame => pages.frame_over_tiles = Some(Arc::clone(&event)),
            Kind::Pass => pages.last_pass = Some(Arc::clone(&event)),
            Kind::Done => pages.done = Some(Arc::clone(&event)),
        }
        pages.senders.retain(|page| page.try_send(Arc::clone(&event)).is_ok());
    }

    /// The latest navigation frame, if a render has made one: kept after the next render
    /// starts, so the page can fetch it while the server renders the next move's.
    pub fn preview(&self) -> Option<Arc<Preview>> {
        self.preview.lock().clone()
    }

    /// Renders and announces a navigation frame at the learnt start resolution; `false` if
    /// the render was cancelled meanwhile.
    fn navigate(&self, generation: u64, config: &Config, cancel: &Cancel) -> bool {
        let divisor = self.start_resolution.lock().divisor();
        let Some(preview) = render_preview(generation, config, divisor, &self.pool, cancel) else {
            return false;
        };
        self.start_resolution.lock().record(divisor, preview.took);
        let event = preview_event(&preview);
        *self.preview.lock() = Some(Arc::new(preview));
        self.broadcast(Kind::Preview, event);
        true
    }

    /// The render thread: passes until `spp` samples or a cancel.
    fn render_passes(self: &Arc<Session>, generation: u64, config: &Config, cancel: &Cancel) {
        self.broadcast(Kind::Start, start_event(generation, config));
        if config.preview && !(self.navigate(generation, config, cancel) && camera_rested(cancel)) {
            return;
        }
        let mut passes = Passes::new(generation, config, cancel);
        // `render`'s passes (one of every sample unless guided), each cut into ours.
        let settings = &config.job.settings;
        let mut plan = Plan::new(&config.job.scene, settings.spp, settings.guiding);
        while let Some(guided) = plan.next_pass() {
            let job = Arc::new(guided.job(&config.job, true));
            while passes.done < guided.samples.end {
                if !self.render_pass(&mut passes, &job, guided.samples.end) {
                    return;
                }
            }
        }
        if !cancel.is_cancelled() {
            let done = passes.done;
            self.broadcast(Kind::Done, json!({ "type": "done", "gen": generation, "spp": done }).to_string());
        }
    }

    /// Renders the next of `passes` (of `job`, up to sample `end`) and announces its tiles,
    /// its image and its figures; `false` if the render was cancelled meanwhile.
    fn render_pass(self: &Arc<Session>, passes: &mut Passes, job: &Arc<RenderJob>, end: u32) -> bool {
        if passes.cancel.is_cancelled() {
            return false;
        }
        let (generation, done) = (passes.generation, passes.done);
        let more = if done == 0 { 1 } else { done.min(passes.most).min(end - done) };
        passes.pass += 1;
        let pass = passes.pass;
        let lanes: Arc<Mutex<Vec<ThreadId>>> = Arc::default();
        let hook = {
            let (session, lanes) = (Arc::clone(self), Arc::clone(&lanes));
            Arc::new(move |out: &TileOutput| {
                if let Some(event) = tile_event(generation, pass, done + more, out, &lanes) {
                    session.broadcast(Kind::Tile { pass }, event);
                }
            })
        };
        let config = passes.config;
        let frame =
            Frame::new(Arc::clone(job), passes.rng.clone(), config.threads, config.tile, Arc::new(|_| {}))
                .with_pass(Pass { samples: done..done + more, sums: Arc::clone(&passes.sums), counts: None })
                .with_cancel(passes.cancel.clone())
                .with_tile_hook(hook);
        let pass_start = Instant::now();
        let rendered = render(&Arc::new(frame), &self.pool.with_mode(config.mode));
        if passes.cancel.is_cancelled() {
            return false;
        }
        passes.done += more;
        let seconds = pass_start.elapsed().as_secs_f64();
        let (rays, imbalance) = (rendered.rays, rendered.imbalance());
        let snapshot = Arc::new(Snapshot { generation, spp: passes.done, image: rendered.image });
        *self.latest.lock() = Some(Arc::clone(&snapshot));
        if passes.splatted {
            // bdpt's light paths lit pixels of other tiles than their own, which the tiles'
            // events do not show: the whole image, once per pass, does.
            self.broadcast(Kind::Frame, self.frame_event_of(&snapshot).to_string());
        }
        self.broadcast(
            Kind::Pass,
            json!({
                "type": "pass", "gen": generation, "pass": pass, "spp": passes.done, "seconds": seconds,
                "elapsed": passes.started.elapsed().as_secs_f64(), "rays": rays,
                "mrays": rays as f64 / seconds.max(1e-9) / 1e6, "imbalance": imbalance,
            })
            .to_string(),
        );
        true
    }
}
