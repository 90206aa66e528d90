//! Your two parts of the assignment:
//!
//! 1. [`scheduler::TileQueue`]: hand a frame's tiles to `frame.threads` threads through a
//!    shared queue, so that a thread that finishes early takes more work.
//! 2. [`discipline::StealHalf`]: a queue for raypool's thread pool where each worker has its
//!    own deque and an idle worker steals *half* of another's.
//!
//! `cargo test --release --test scheduler` (or `--test steal_half`) checks one part (the
//! same conformance checks the grader runs); `cargo run --release --bin grade` times them
//! against raypool's own. README.md says how, and how to read the grade.

pub mod discipline;
pub mod scheduler;
