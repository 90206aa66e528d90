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
//! 1. `queue.rs`: what a job is; the `JobQueue` interface; [`Discipline`].
//! 2. `locked.rs`: the textbook queue, a mutex and a condition variable.
//! 3. `shared.rs`: the same with a channel; shutdown by disconnection.
//! 4. `sleep.rs` then `steal.rs`: per-worker deques, stealing, sleeping without lost wake-ups.
//! 5. `worker.rs`: the worker loop, panics, the thread-local "which worker am I".
//! 6. `latch.rs` then `batch.rs`: waiting for many jobs; why waiting workers must help.
//! 7. `stats.rs`: counting and timing what workers do.
//! 8. `pool.rs`: building, submitting, dropping.
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

mod batch;
mod latch;
mod locked;
mod pool;
mod queue;
mod shared;
mod sleep;
mod stats;
mod steal;
mod worker;

pub use pool::{BuildError, Builder, ThreadPool};
pub use queue::Discipline;
pub use stats::{JobSpan, PoolStats, WorkerStats};
