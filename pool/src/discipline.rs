//! The built-in queue disciplines by name: [`Discipline`] picks one of `locked.rs`,
//! `shared.rs` and `steal.rs` and builds its queue.
//!
//! A file of its own, read after the queues, so that the arrows between files point one way:
//! `queue.rs` says what a queue is and knows no discipline; each discipline's file imports
//! `queue.rs`; this file imports the disciplines. Nothing imports back (no import circle).
//!
//! Invariant: [`Discipline::ALL`] lists every variant, so that the tests and benchmarks that
//! iterate over it cover a discipline added here with no other list to edit (but for the loom
//! models' `MODELLED` in `pool/tests/loom.rs`, which a discipline built on `sync.rs` joins).

use crate::locked::LockedQueue;
use crate::queue::MakeQueue;
use crate::shared::SharedQueue;
use crate::steal::StealQueue;

/// How a [`ThreadPool`](crate::ThreadPool) queues its jobs, chosen at construction.
///
/// ```
/// use pool::{Discipline, ThreadPool};
/// for discipline in Discipline::ALL {
///     let pool = ThreadPool::new(2, discipline).unwrap();
///     assert_eq!(pool.batch((0..4).map(|i| move || i * i)), vec![0, 1, 4, 9]);
/// }
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Discipline {
    /// One FIFO shared by all workers: a multi-producer multi-consumer channel. The seed
    /// paper's thread pool. Every push and pop touches the same channel.
    #[default]
    Shared,
    /// One `Mutex<VecDeque>` with a `Condvar`: the textbook monitor-based pool, kept to
    /// compare with the channel.
    Locked,
    /// One deque per worker: a worker takes from the front of its own and, when it is empty,
    /// steals from the back of another's. Batches are dealt out in contiguous runs, so
    /// stealing is what balances an uneven load.
    Stealing,
}

impl Discipline {
    /// Every discipline. The pool's tests (`pool/tests/`) and its benchmark (`cargo bench
    /// --bench pool`) iterate over this list, so a discipline added here is tested and
    /// measured with no other list to edit.
    ///
    /// ```
    /// use pool::{Discipline, ThreadPool};
    /// for discipline in Discipline::ALL {
    ///     let pool = ThreadPool::new(2, discipline).unwrap();
    ///     assert_eq!(pool.discipline(), Some(discipline));
    /// }
    /// assert_eq!(Discipline::ALL.len(), 3);
    /// ```
    pub const ALL: [Discipline; 3] = [Discipline::Shared, Discipline::Locked, Discipline::Stealing];

    /// Its name on a command line: `shared`, `locked`, `stealing`.
    ///
    /// ```
    /// use pool::Discipline;
    /// assert_eq!(Discipline::Stealing.name(), "stealing");
    /// assert_eq!(Discipline::named("locked"), Some(Discipline::Locked));
    /// assert_eq!(Discipline::named("lifo"), None);
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Discipline::Shared => "shared",
            Discipline::Locked => "locked",
            Discipline::Stealing => "stealing",
        }
    }

    /// The discipline called `name` (one of [`Discipline::ALL`]'s names), if any.
    pub fn named(name: &str) -> Option<Discipline> {
        Discipline::ALL.into_iter().find(|d| d.name() == name)
    }

    /// How this discipline's queue is made.
    ///
    /// ```
    /// let make = pool::Discipline::Locked.queue();
    /// let queue = make(2);
    /// assert!(queue.try_pop(None).is_none(), "a new queue is empty");
    /// ```
    pub fn queue(self) -> MakeQueue {
        match self {
            Discipline::Shared => |_| Box::new(SharedQueue::new()),
            Discipline::Locked => |_| Box::new(LockedQueue::new()),
            Discipline::Stealing => |workers| Box::new(StealQueue::new(workers)),
        }
    }
}
