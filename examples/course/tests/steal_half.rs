//! Part 2's test: the pool's contract on your queue (results in order, every job once,
//! spawned jobs, nested batches, drop, idle workers asleep), then a render through a pool
//! built on it, plain and with nested batches, checked like a scheduler. One test, in that
//! order: a queue that breaks the contract (say, one whose workers never wake on close) could
//! hang a later pool's drop, so it never gets that far; each part of the contract runs under
//! a deadline.

use raypool::measure::grade::on_queue::OnQueue;
use raypool::schedule::conformance::check;
use raypool_course::discipline::make;

#[test]
fn keeps_the_pools_contract_then_renders_a_frame_through_the_pool() {
    pool::conformance::check(make).unwrap_or_else(|e| panic!("the pool's contract: {e}"));
    for nested in [false, true] {
        for threads in [1, 2, 4] {
            check(&OnQueue::new(make, nested), threads)
                .unwrap_or_else(|e| panic!("{threads} workers, nested batches {nested}: {e}"));
        }
    }
}
