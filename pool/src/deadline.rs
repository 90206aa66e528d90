//! Waiting under a deadline: the one helper every test of the workspace waits with.
//!
//! No test may hang. A pool bug that blocks (a lost wake-up, a worker that waits without
//! helping) must be a failure one can read, "waited 15 s for the batch to return: it never
//! happened", not a `cargo test` that stalls until a CI limit kills it with no word of where.
//! So whatever a test waits for, it waits for here: [`run_within`] runs the waiting on a
//! thread of its own and gives up after a limit, saying what never happened ([`Missed`]).
//! [`within`] is the form a test uses; [`conformance`](crate::conformance) uses
//! [`run_within`] and reports a miss as an error. The root crate's tests (`tests/deadline/`)
//! use [`within`] too, and [`limit`] for waiting on child processes.
//!
//! Invariants:
//! - one limit for the whole workspace: [`limit`], 120 s unless `RAYPOOL_TEST_DEADLINE` says
//!   otherwise (`pool/break-it/run.sh` and `pool/mutants.sh` set 15): far above what the
//!   slowest wait needs (a million-job batch in a debug build, a render in a release build,
//!   a few seconds on a loaded 2-core machine), far below a CI time limit;
//! - a body that panics (a failed assertion) is not a miss: its panic reaches the caller
//!   unchanged;
//! - a thread stuck past its deadline cannot be stopped from outside: it is left behind, so a
//!   miss is the end of a test binary ([`within`] exits it).

use std::fmt;
use std::io::Write;
use std::panic::resume_unwind;
use std::sync::mpsc;
use std::time::Duration;

/// The variable that sets [`limit`], in whole seconds.
pub const VARIABLE: &str = "RAYPOOL_TEST_DEADLINE";

/// [`limit`] when [`VARIABLE`] is not set (or not a whole number of seconds).
pub const DEFAULT: Duration = Duration::from_secs(120);

/// How long any one wait of a test may take before the test fails: `RAYPOOL_TEST_DEADLINE`
/// seconds, or [`DEFAULT`].
///
/// ```
/// // Unless the variable says otherwise, two minutes.
/// if std::env::var_os(pool::deadline::VARIABLE).is_none() {
///     assert_eq!(pool::deadline::limit(), std::time::Duration::from_secs(120));
/// }
/// ```
pub fn limit() -> Duration {
    let seconds = std::env::var(VARIABLE).ok().and_then(|s| s.parse().ok());
    seconds.map_or(DEFAULT, Duration::from_secs)
}

/// A deadline that passed: what was waited for, and how long.
///
/// ```
/// use std::time::Duration;
/// let missed = pool::deadline::Missed { what: "the batch to return".into(), limit: Duration::from_secs(15) };
/// assert_eq!(missed.to_string(), "waited 15 s for the batch to return: it never happened");
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Missed {
    /// What never happened, worded to follow "waited N s for": "the batch to return".
    pub what: String,
    /// How long it was waited for.
    pub limit: Duration,
}

impl fmt::Display for Missed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "waited {} s for {}: it never happened", self.limit.as_secs_f64(), self.what)
    }
}

impl std::error::Error for Missed {}

/// Runs `body` on a thread of its own and waits for it at most `limit`: its value, or
/// [`Missed`] naming `what` (so `what` reads "the batch to return"). A panic in `body` is
/// re-raised here unchanged. After a miss the body's thread is left running.
///
/// ```
/// use std::time::Duration;
/// use pool::deadline::run_within;
/// assert_eq!(run_within(Duration::from_secs(60), "two and two to add up", || 2 + 2), Ok(4));
/// let missed = run_within(Duration::from_millis(10), "a nap to end", || {
///     std::thread::sleep(Duration::from_secs(1))
/// });
/// assert_eq!(missed.unwrap_err().what, "a nap to end");
/// ```
pub fn run_within<T: Send + 'static>(
    limit: Duration,
    what: impl AsRef<str>,
    body: impl FnOnce() -> T + Send + 'static,
) -> Result<T, Missed> {
    let (done, finished) = mpsc::channel();
    let thread = std::thread::Builder::new()
        .name("deadline-body".into())
        .spawn(move || {
            let _ = done.send(body());
        })
        .expect("a thread to wait on starts");
    match finished.recv_timeout(limit) {
        Ok(value) => Ok(value),
        Err(mpsc::RecvTimeoutError::Disconnected) => match thread.join() {
            Err(panic) => resume_unwind(panic),
            Ok(()) => unreachable!("the body sends before it returns"),
        },
        Err(mpsc::RecvTimeoutError::Timeout) => Err(Missed { what: what.as_ref().to_string(), limit }),
    }
}

/// A test's wait: runs `body` on a thread of its own and returns its value, waiting at most
/// [`limit`]. If it has not finished by then, the test fails with "waited N s for `what`: it
/// never happened" and the whole test binary stops (exit code 101, as a failed `cargo test`):
/// the stuck thread cannot be stopped, and the binary's other tests would most likely wait
/// out the same bug one by one. A panic in `body` (a failed assertion) is re-raised here
/// unchanged.
///
/// ```
/// let pool = pool::ThreadPool::new(2, pool::Discipline::Locked).unwrap();
/// let sum: u32 = pool::deadline::within("the batch to return", move || pool.batch([|| 1, || 2]).iter().sum());
/// assert_eq!(sum, 3);
/// ```
pub fn within<T: Send + 'static>(what: impl AsRef<str>, body: impl FnOnce() -> T + Send + 'static) -> T {
    within_for(limit(), what, body)
}

/// [`within`] with a limit of the caller's choosing.
///
/// ```
/// use std::time::Duration;
/// assert_eq!(pool::deadline::within_for(Duration::from_secs(60), "a quick sum", || 40 + 2), 42);
/// ```
pub fn within_for<T: Send + 'static>(
    limit: Duration,
    what: impl AsRef<str>,
    body: impl FnOnce() -> T + Send + 'static,
) -> T {
    run_within(limit, what, body).unwrap_or_else(|missed| {
        let test = std::thread::current().name().unwrap_or("a test").to_string();
        // Straight to the process's stderr: the test harness keeps what `eprintln!` writes
        // until the test ends, and this test never will.
        let _ = writeln!(
            std::io::stderr(),
            "\ntest {test} FAILED: {missed}\n\
             (stopping this test binary: its other tests would wait out the same bug)"
        );
        std::process::exit(101)
    })
}
