//! Part 1's tests: the conformance check (every pixel once, on at most `frame.threads`
//! threads, really in parallel, the same image as `serial`) at several thread counts.

use raypool::schedule::conformance::check;
use raypool_course::scheduler::TileQueue;

#[test]
fn renders_every_pixel_once_in_parallel_and_matches_serial() {
    for threads in [1, 2, 3, 8] {
        check(&TileQueue, threads).unwrap_or_else(|e| panic!("with frame.threads = {threads}: {e}"));
    }
}
