//! The shared queue: one multi-producer, multi-consumer channel for all workers.
//!
//! This is the pool of the seed paper's "remaining tasks" and of most tutorials: submitters
//! send jobs into one FIFO channel, idle workers block until one arrives. crossbeam's channel
//! does the sleeping and waking (no lost wake-ups, no spinning while idle).
//!
//! Shutdown uses a second channel that never carries a message: `close` drops its only
//! sender, and a disconnected channel wakes *every* receiver blocked on it: a broadcast.
//! A sleeping worker waits on both channels at once (`select!`); once woken by the shutdown
//! it takes what is left in the job channel and exits when that is empty. The job channel
//! itself is never closed, because a job still running after `close` may submit more work.

use crossbeam_channel::{Receiver, Sender, select, unbounded};

use crate::queue::{Job, JobQueue, Popped};
use crate::sync::Mutex;

pub(crate) struct SharedQueue {
    jobs_in: Sender<Job>,
    jobs_out: Receiver<Job>,
    /// Dropped by `close`; never sends.
    shutdown_in: Mutex<Option<Sender<()>>>,
    shutdown_out: Receiver<()>,
}

impl SharedQueue {
    pub(crate) fn new() -> SharedQueue {
        let (jobs_in, jobs_out) = unbounded();
        let (shutdown_in, shutdown_out) = unbounded();
        SharedQueue { jobs_in, jobs_out, shutdown_in: Mutex::new(Some(shutdown_in)), shutdown_out }
    }
}

impl JobQueue for SharedQueue {
    fn push(&self, job: Job, _me: Option<usize>) {
        self.jobs_in.send(job).expect("the queue holds a receiver as long as a sender");
    }

    fn try_pop(&self, _me: Option<usize>) -> Option<Popped> {
        self.jobs_out.try_recv().ok().map(|job| Popped { job, stolen: false })
    }

    fn wait_pop(&self, me: usize) -> Option<Popped> {
        if let Some(popped) = self.try_pop(Some(me)) {
            return Some(popped);
        }
        select! {
            recv(self.jobs_out) -> job => job.ok().map(|job| Popped { job, stolen: false }),
            // Only ever ready by disconnection, i.e. after `close`: drain, then stop.
            recv(self.shutdown_out) -> _ => self.try_pop(Some(me)),
        }
    }

    fn close(&self) {
        self.shutdown_in.lock().take();
    }
}
