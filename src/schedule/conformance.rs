//! The conformance check for schedulers: what a course assignment's tests call.
//!
//! A scheduler conforms, for a thread count `T`, when on a small image whose size divides
//! evenly into nothing (61 × 37 pixels, tiles of 7):
//! 1. every pixel goes through `Frame::render` exactly once, and the tiles it returns are
//!    those, each pixel once;
//! 2. it renders on at most `T` distinct threads (a pool of `T` workers, or `T` scoped
//!    threads; not a thread per tile);
//! 3. asked for `T ≥ 2`, it really renders in parallel: `min(T, 37)` threads are rendering
//!    a tile *at the same time* at least once;
//! 4. its image equals the `serial` schedule's, byte for byte.
//!
//! Rules 1 and 2 are judged from what the frame itself saw (an
//! [`Observer`] in its hooks), never from what the
//! scheduler returns: a `timing` it cleared, a copy it rendered twice and returned once, or a
//! tile it rendered by calling the tracer directly are all seen for what they are.
//!
//! Rule 3 is checked without a clock, so it cannot be flaky: the check's frame holds every
//! tile at its start (a `Rendezvous`, below) until `min(T, 37)` tiles are in flight on as many
//! threads, then lets them all go. A scheduler with that many threads rendering always gets
//! there; one that renders on the calling thread, or lets each thread finish before the next
//! starts, never does, and the check gives up after [`PATIENCE`] with a message that says so.
//!
//! A scheduler that never returns (a deadlock) cannot be stopped from outside; rather than
//! hang a student's test run, the check then ends the process after [`DEADLINE`] with a
//! message naming the thread count (exit code 101, as a failed test).

use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

use parking_lot::{Condvar, Mutex};

use crate::scenes::builtin::builtin_scene;
use crate::schedule::frame::{Frame, StartHook, TileHook};
use crate::schedule::modes::{Schedule, Scheduler};
use crate::schedule::observe::Observer;
use crate::schedule::random::RngSource;
use crate::tracer::render::{RenderJob, RenderSettings};
use crate::tracer::sampling::independent::PerSample;

/// How long the first tiles wait for the other threads to start theirs before the check
/// decides the scheduler is not parallel. A correct scheduler needs microseconds; ten
/// seconds leaves room for a machine that is busy with something else.
pub const PATIENCE: Duration = Duration::from_secs(10);

/// How long a scheduler may take to return from the check's render before the check ends
/// the process (it takes milliseconds).
pub const DEADLINE: Duration = Duration::from_secs(60);

/// Checks `scheduler` on `threads` threads; the error says what went wrong, in words meant
/// for the student who wrote it.
///
/// ```
/// use raypool::schedule::modes::Schedule;
/// raypool::schedule::conformance::check(&Schedule::Stealing, 3).unwrap();
/// ```
pub fn check(scheduler: &dyn Scheduler, threads: usize) -> Result<(), String> {
    let threads = threads.max(1);
    let frame = test_frame(threads);
    let gate = Arc::new(Rendezvous::new(threads.min(frame.height() as usize)));
    let gated = Arc::new((*frame).clone().with_start_hook(gate.on_start()).with_tile_hook(gate.on_end()));
    let (observer, watched) = Observer::watch(&gated);
    let watchdog = watchdog(threads);
    let tiles = scheduler.render(&watched);
    drop(watchdog);
    observer.verify(&frame, &tiles, threads)?;
    let image = frame.assemble(&tiles)?;
    if threads > 1 {
        gate.check_parallel(threads)?;
    }
    let reference = test_frame(1);
    let expected = reference.assemble(&Schedule::Serial.render(&reference)).expect("serial conforms");
    match image.pixels.iter().zip(&expected.pixels).position(|(a, b)| a != b) {
        Some(k) => Err(format!(
            "pixel ({}, {}) differs from the serial render: {:?} instead of {:?}",
            k % image.width as usize,
            k / image.width as usize,
            image.pixels[k],
            expected.pixels[k]
        )),
        None => Ok(()),
    }
}

/// Ends the process unless the returned sender is dropped within [`DEADLINE`].
fn watchdog(threads: usize) -> mpsc::Sender<()> {
    let (armed, disarmed) = mpsc::channel::<()>();
    std::thread::spawn(move || {
        if let Err(mpsc::RecvTimeoutError::Timeout) = disarmed.recv_timeout(DEADLINE) {
            eprintln!(
                "conformance check FAILED: waited {} s for the scheduler to return from a render on \
                 {threads} threads: it never happened (a deadlock?)",
                DEADLINE.as_secs()
            );
            std::process::exit(101);
        }
    });
    armed
}

/// The small frame the check renders: the book's final scene, 61 × 37, 2 spp, depth 8.
pub fn test_frame(threads: usize) -> Arc<Frame> {
    let settings =
        RenderSettings { width: 61, height: 37, spp: 2, max_depth: 8, seed: 42, ..Default::default() };
    let scene = builtin_scene("final", 7).expect("the final scene builds").to_scene();
    let rng = RngSource::PerSample(PerSample { seed: settings.seed });
    Arc::new(Frame::new(RenderJob::new(scene, settings), rng, threads, 7, Arc::new(|_| {})))
}

/// Holds tiles at their start until `want` of them are in flight at once (or [`PATIENCE`]
/// runs out), then lets every tile through. Invariant: `in_flight` counts the tiles between
/// their start and end hooks; a thread renders one tile at a time, so it also counts the
/// threads rendering right now.
struct Rendezvous {
    want: usize,
    state: Mutex<Gate>,
    opened: Condvar,
}

/// What the rendezvous's lock protects.
#[derive(Default)]
struct Gate {
    in_flight: usize,
    most_in_flight: usize,
    open: bool,
    gave_up: bool,
}

impl Rendezvous {
    fn new(want: usize) -> Rendezvous {
        Rendezvous { want, state: Mutex::new(Gate::default()), opened: Condvar::new() }
    }

    /// The start hook: count the tile in, then wait for the gate to open.
    fn on_start(self: &Arc<Self>) -> StartHook {
        let gate = Arc::clone(self);
        Arc::new(move |_| gate.arrive())
    }

    /// The end hook: count the tile out.
    fn on_end(self: &Arc<Self>) -> TileHook {
        let gate = Arc::clone(self);
        Arc::new(move |_| gate.state.lock().in_flight -= 1)
    }

    fn arrive(&self) {
        let mut gate = self.state.lock();
        gate.in_flight += 1;
        gate.most_in_flight = gate.most_in_flight.max(gate.in_flight);
        if gate.in_flight >= self.want {
            gate.open = true;
            self.opened.notify_all();
        }
        let deadline = Instant::now() + PATIENCE;
        while !gate.open {
            if self.opened.wait_until(&mut gate, deadline).timed_out() {
                // Give up once, for everyone: the remaining tiles render without waiting.
                (gate.open, gate.gave_up) = (true, true);
                self.opened.notify_all();
            }
        }
    }

    /// Rule 3, once the render is over.
    fn check_parallel(&self, threads: usize) -> Result<(), String> {
        let gate = self.state.lock();
        if !gate.gave_up {
            return Ok(());
        }
        Err(format!(
            "asked for {threads} threads, the scheduler never had {} tiles rendering at the same \
             time (at most {}): the first tile waited {} s for the others to start. Are the tiles \
             rendered on the calling thread, or does each thread finish before the next one \
             starts?",
            self.want,
            gate.most_in_flight,
            PATIENCE.as_secs()
        ))
    }
}
