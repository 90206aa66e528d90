//! A fixed-size thread pool, written to be read.
//!
//! This crate is the lesson of the raypool project: how a thread pool works, built from
//! `std::thread`, one channel crate and one lock crate, in safe Rust. It knows nothing about
//! rendering. Three queue disciplines can be compared side by side:
//!
//! ```text
//!        submitter (any thread)                       workers (fixed, named pool-worker-N)
//!   ─────────────────────────────                     ─────────────────────────────────────
//!   Shared:    spawn/batch ──▶ [ one MPMC channel  ] ──▶ w0  w1  w2  w3   (all pop one FIFO)
//!   Locked:    spawn/batch ──▶ [ Mutex<VecDeque>   ] ──▶ w0  w1  w2  w3   (+ Condvar to sleep)
//!   Stealing:  batch ──deal──▶ [d0] [d1] [d2] [d3]       each wᵢ pops the front of dᵢ;
//!                               ▲              │         an idle one steals the back of dⱼ
//!                               └─── steal ────┘
//!
//!   batch([f0 … fn]) ─▶ results [r0 … rn] in submission order, once a count-down latch
//!                       reaches zero; a worker that waits runs other jobs meanwhile.
//! ```
//!
//! # Reading order
//!
//! The modules are declared below in this order: the order of the ideas, not of the imports.
//! Almost every file imports `sync.rs` (it only re-exports std's and parking_lot's types, or
//! loom's under `--cfg loom`: read it first if you like), `queue.rs` names the latch a job
//! carries (`latch.rs`, below) and `worker.rs` the statistics (`stats.rs`). No file imports one that imports
//! it back, directly or through others: the `use` arrows between files form no circle
//! (`pool.rs` is the only file that uses `batch.rs`, `discipline.rs` and `worker.rs` together).
//!
//! 1. `queue.rs`: what a job is; the [`JobQueue`] interface. It knows no discipline.
//! 2. `locked.rs`: the textbook queue, a mutex and a condition variable.
//! 3. `shared.rs`: the same with a channel; shutdown by disconnection.
//! 4. `sleep.rs` then `steal.rs`: per-worker deques, `pop` and `steal`, sleeping without lost
//!    wake-ups.
//! 5. `discipline.rs`: [`Discipline`], the three queues above by name.
//! 6. `worker.rs`: the worker loop, panics, the thread-local "which worker am I".
//! 7. `latch.rs` then `batch.rs`: waiting for many jobs; why waiting workers must help.
//! 8. `stats.rs`: counting and timing what workers do; [`imbalance`].
//! 9. `pool.rs`: [`ThreadPool`], every method of it: building, submitting, dropping.
//! 10. `sync.rs`: where the locks, atomics and threads come from, and how the loom model
//!     checker swaps them; the models sit at the end of each protocol's file.
//! 11. [`deadline`]: waiting without hanging, the helper every test of the workspace uses.
//! 12. [`conformance`]: the contract checked on any queue, including one written outside
//!     this crate on the public [`JobQueue`] trait and given to [`Builder::queue`].
//!
//! # Checked, not hoped
//!
//! Each protocol has a loom model beside it (`sleep.rs`, `steal.rs`, `locked.rs`, `latch.rs`,
//! with helpers they share in `queue.rs`'s; the whole pool in `tests/loom.rs`): loom runs the model once for every interleaving of its
//! threads (up to `LOOM_MAX_PREEMPTIONS` forced switches) and fails with the one that breaks
//! it. Stress tests (`tests/races.rs`) aim real threads at the same race windows many
//! thousand times, and every test that waits runs under a deadline, so a bug that blocks
//! fails with a message naming what never happened instead of hanging. `cargo mutants`
//! (results/pool-mutants.md) shows that the tests notice when a line changes.
//!
//! ```text
//! cargo test -p pool --release                                        contract + stress
//! RUSTFLAGS="--cfg loom" LOOM_MAX_PREEMPTIONS=3 CARGO_TARGET_DIR=target/loom \
//!     cargo test -p pool --release --lib --test loom                  loom models
//! ```
//!
//! # Break it
//!
//! Three plausible bugs live in `pool/break-it/` as patches; `pool/break-it/run.sh NAME`
//! plants one in a copy of this crate and runs both kinds of check on it (about a minute).
//! Each patch names the test that must catch it; `pool/break-it/run.sh --check` plants every
//! one and fails unless that test fails, and CI (`.ci/run`) runs it. What each caught, run on
//! the code as it is now (2026-12-03, 2-core Intel Xeon under load from other builds):
//!
//! | bug | the test CI requires to fail, and what it says | the invariant it breaks |
//! |---|---|---|
//! | `lost-wakeup`: a sleeper counts itself in `sleepers` only once it has decided to sleep | loom, `sleep::model::model_a_pusher_wakes_one_sleeper`: `deadlock`, the pusher blocked joining (`sleep.rs` line 158), the worker in `sleep_unless`'s `wait` (line 85; lines of the planted file). The stress tests cannot see it: the window is nanoseconds wide | a sleeper registers *before* it looks for work (`sleep.rs`) |
//! | `early-latch`: a worker counts the batch's latch down before recording the job | loom, `tests/loom.rs` `model_batch_returns_after_every_job_and_its_bookkeeping`: `the caller saw unrecorded jobs` (`left: 1`, `right: 2`, at `tests/loom.rs:34`). The stress test `random_job_lengths_keep_order_and_count` sees it only when a worker is preempted in the window (it passed once with the bug planted) | the latch opens only after the job's bookkeeping (`worker.rs`) |
//! | `waiter-does-not-help`: a worker waiting on a batch just sleeps | stress, `a_waiting_worker_returns_as_soon_as_its_batch_is_done`: `waited 15 s for Shared: the nested batch to return: it never happened` | the waiting rule (`batch.rs`) |
//!
//! # Example
//!
//! ```
//! use pool::{Discipline, ThreadPool};
//!
//! let pool = ThreadPool::builder().workers(4).discipline(Discipline::Stealing).build().unwrap();
//! let lengths = pool.batch(["a", "bb", "ccc"].map(|s| move || s.len()));
//! assert_eq!(lengths, vec![1, 2, 3]);
//! ```
//!
//! Jobs must be `Send + 'static`: they outlive the call that submits them. Share read-only
//! data with `Arc`. This is what the compiler refuses, and why (an `Rc` cannot cross threads):
//!
//! ```compile_fail
//! use std::rc::Rc;
//! let pool = pool::ThreadPool::new(2, pool::Discipline::Shared).unwrap();
//! let shared = Rc::new(5);
//! pool.spawn(move || println!("{shared}")); // error: `Rc<i32>` cannot be sent between threads
//! ```
//!
//! Nor can a job borrow from the caller's stack, because nothing stops the caller from
//! returning while the job still runs:
//!
//! ```compile_fail
//! let pool = pool::ThreadPool::new(2, pool::Discipline::Shared).unwrap();
//! let local = vec![1, 2, 3];
//! pool.batch([|| local.len()]); // error: closure may outlive `local`
//! ```

#![forbid(unsafe_code)]
#![deny(missing_docs)]

mod queue;
mod locked;
mod shared;
mod sleep;
mod steal;
mod discipline;
mod worker;
mod latch;
mod batch;
mod stats;
mod pool;
mod sync;
pub mod deadline;
pub mod conformance;

pub use discipline::Discipline;
pub use pool::{BuildError, Builder, ThreadPool};
pub use queue::{Job, JobQueue, MakeQueue, Popped};
pub use stats::{JobSpan, PoolStats, WorkerStats, imbalance};
