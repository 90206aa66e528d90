//! The queue conformance check (`pool::conformance`): the built-in disciplines pass it, and a
//! queue that spins while idle fails it with a reason.
#![cfg(not(loom))] // a `--cfg loom` build runs the loom models only (see pool/src/sync.rs)

mod common;

use std::collections::VecDeque;
use std::sync::Mutex;

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

/// Correct in every way but one: an idle worker polls instead of sleeping.
#[derive(Default)]
struct Spinning(Mutex<(VecDeque<Job>, bool)>);

impl JobQueue for Spinning {
    fn push(&self, job: Job, _me: Option<usize>) {
        self.0.lock().unwrap().0.push_back(job);
    }
    fn try_pop(&self, _me: Option<usize>) -> Option<Popped> {
        self.0.lock().unwrap().0.pop_front().map(|job| Popped { job, stolen: false })
    }
    fn wait_pop(&self, _me: usize) -> Option<Popped> {
        loop {
            let mut state = self.0.lock().unwrap();
            if let Some(job) = state.0.pop_front() {
                return Some(Popped { job, stolen: false });
            }
            if state.1 {
                return None;
            }
            drop(state);
            std::hint::spin_loop();
        }
    }
    fn close(&self) {
        self.0.lock().unwrap().1 = true;
    }
}

#[test]
fn a_queue_whose_idle_workers_spin_fails() {
    within("the conformance check of a spinning queue to finish", || {
        let error = pool::conformance::check(|_| Box::new(Spinning::default())).unwrap_err();
        assert!(error.contains("must sleep"), "{error}");
    });
}
