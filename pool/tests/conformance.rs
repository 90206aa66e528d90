//! The queue conformance check (`pool::conformance`): the built-in disciplines pass it, and
//! queues broken in one way each (one type, [`Fault`] picks the way) fail it with a reason
//! naming that way.
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use common::within;
use pool::{Discipline, Job, JobQueue, Popped};

#[test]
fn every_builtin_discipline_conforms() {
    for discipline in Discipline::ALL {
        within(format!("{discipline:?}: the conformance check to finish"), move || {
            pool::conformance::check(discipline.queue()).unwrap_or_else(|e| panic!("{discipline:?}: {e}"))
        });
    }
}

/// One way to break a queue.
#[derive(Clone, Copy, PartialEq)]
enum Fault {
    /// `push_batch` drops the last job of every batch.
    LosesABatchJob,
    /// `push` (a spawned job) drops every 100th job.
    LosesSpawnedJobs,
    /// `try_pop` never hands a waiting worker anything.
    NeverHelps,
    /// `wait_pop` returns `None` as soon as the queue is closed, jobs left or not.
    QuitsOnClose,
    /// An idle worker polls in `wait_pop` instead of sleeping.
    Spins,
}

/// A correct monitor queue, except for its fault.
struct Faulty {
    fault: Fault,
    state: Mutex<(VecDeque<Job>, bool)>,
    ready: Condvar,
    pushes: AtomicUsize,
}

impl Faulty {
    fn boxed(fault: Fault) -> Box<dyn JobQueue> {
        Box::new(Faulty {
            fault,
            state: Mutex::default(),
            ready: Condvar::new(),
            pushes: AtomicUsize::new(0),
        })
    }
}

impl JobQueue for Faulty {
    fn push(&self, job: Job, _me: Option<usize>) {
        let n = self.pushes.fetch_add(1, Relaxed);
        if self.fault == Fault::LosesSpawnedJobs && n % 100 == 99 {
            return;
        }
        self.state.lock().unwrap().0.push_back(job);
        self.ready.notify_one();
    }
    fn push_batch(&self, mut jobs: Vec<Job>, _me: Option<usize>) {
        if self.fault == Fault::LosesABatchJob {
            jobs.pop();
        }
        self.state.lock().unwrap().0.extend(jobs);
        self.ready.notify_all();
    }
    fn try_pop(&self, _me: Option<usize>) -> Option<Popped> {
        if self.fault == Fault::NeverHelps {
            return None;
        }
        self.state.lock().unwrap().0.pop_front().map(|job| Popped { job, stolen: false })
    }
    fn wait_pop(&self, _me: usize) -> Option<Popped> {
        let mut state = self.state.lock().unwrap();
        loop {
            if state.1 && self.fault == Fault::QuitsOnClose {
                return None;
            }
            if let Some(job) = state.0.pop_front() {
                return Some(Popped { job, stolen: false });
            }
            if state.1 {
                return None;
            }
            state = if self.fault == Fault::Spins {
                drop(state);
                std::hint::spin_loop();
                self.state.lock().unwrap()
            } else {
                self.ready.wait(state).unwrap()
            };
        }
    }
    fn close(&self) {
        self.state.lock().unwrap().1 = true;
        self.ready.notify_all();
    }
}

#[test]
fn each_broken_queue_fails_the_part_that_checks_what_it_breaks() {
    let cases: [(pool::MakeQueue, &str); 5] = [
        (|_| Faulty::boxed(Fault::LosesABatchJob), "for a batch of 2,000 jobs on 1 worker to return"),
        (|_| Faulty::boxed(Fault::LosesSpawnedJobs), "of 20,000 spawned jobs ran: is a pushed job lost?"),
        (|_| Faulty::boxed(Fault::NeverHelps), "for batches nested in jobs on 1 worker(s) to return"),
        (|_| Faulty::boxed(Fault::QuitsOnClose), "of 1,000 queued jobs ran before drop returned"),
        (|_| Faulty::boxed(Fault::Spins), "a worker with nothing to do must sleep"),
    ];
    for (make, expected) in cases {
        within(format!("the check of a queue that should fail with '{expected}'"), move || {
            let error = pool::conformance::check_within(make, Duration::from_secs(2))
                .err()
                .unwrap_or_else(|| panic!("the check passed a queue that should fail with '{expected}'"));
            assert!(error.contains(expected), "expected '{expected}' in: {error}");
        });
    }
}

#[test]
fn the_check_with_its_own_deadline_refuses_a_broken_queue_too() {
    // `check` is what a student calls: it must say no as `check_within` does. A spinning
    // queue fails fast (its idle workers' CPU time), so its 30 s deadlines are never reached.
    within("the default check of a spinning queue to finish", || {
        let error = pool::conformance::check(|_| Faulty::boxed(Fault::Spins)).unwrap_err();
        assert!(error.contains("a worker with nothing to do must sleep"), "{error}");
    });
}
