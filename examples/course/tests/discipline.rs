//! Part 2's tests: the pool's contract on your queue (results in order, every job once,
//! spawned jobs, nested batches, drop, idle workers asleep), then a render through a pool
//! built on it, plain and with nested batches, checked like a scheduler.

use raypool::measure::grade::OnQueue;
use raypool::schedule::conformance::check;
use raypool_course::discipline::make;

#[test]
fn keeps_the_pools_contract() {
    pool::conformance::check(make).unwrap();
}

#[test]
fn renders_a_frame_through_the_pool() {
    for nested in [false, true] {
        for threads in [1, 2, 4] {
            check(&OnQueue::new(make, nested), threads)
                .unwrap_or_else(|e| panic!("{threads} workers, nested batches {nested}: {e}"));
        }
    }
}
