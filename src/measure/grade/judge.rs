//! Whether a time can be judged: the machine must be quiet, and the rounds must agree.
//!
//! A grade compares the submission's time with the reference's, both measured in the same
//! run. That cancels a machine that is slow, but not one whose load comes and goes, nor one so
//! busy that threads cannot run in parallel at all (then a static split and a dynamic
//! scheduler both take one thread's time, and the static split earns full marks). So before
//! and after the rows of each thread count `T ≥ 2`, the grader times the reference alone on
//! `balanced` at 1 and at `T` threads: its own speedup must reach [`speedup_floor`], half the
//! gain a quiet machine gives. Where the system says (Linux's `/proc`), the grader also
//! measures the CPU time *other* processes used while it timed a thread count's rows: on
//! average at most [`OTHERS_LIMIT`] CPUs ([`Usage`]). And a row's rounds must agree: the
//! largest of its per-round ratios at most [`SPREAD_LIMIT`] times the smallest (the most
//! extreme round at each end set aside, from 4 rounds on). A row that
//! fails any of these, after [`ATTEMPTS`] tries, earns no points, and the report says why.

use std::time::Instant;

use crate::error::Error;
use crate::measure::grade::workloads::Workload;
use crate::measure::machine::cpus;
use crate::measure::speedup::median;
use crate::schedule::modes::Scheduler;

/// Tries per thread count before a busy machine's rows are left unjudged.
pub const ATTEMPTS: usize = 3;

/// The largest spread (largest ÷ smallest per-round ratio) a row's rounds may have.
pub const SPREAD_LIMIT: f64 = 1.5;

/// The most CPUs other processes may keep busy, on average, while rows are timed.
pub const OTHERS_LIMIT: f64 = 0.5;

/// Clock ticks per second of `/proc/stat` and `/proc/self/stat` (`USER_HZ`: 100 on every
/// mainstream Linux build).
const TICKS_PER_SECOND: f64 = 100.0;

/// CPU time used so far by the whole machine and by this process, to measure what other
/// processes used in between (Linux only: `None` where `/proc` does not say).
pub struct Usage {
    all: f64,
    mine: f64,
    at: Instant,
}

impl Usage {
    /// The counters now.
    ///
    /// ```
    /// use raypool::measure::grade::judge::Usage;
    /// if let Some(start) = Usage::now() {
    ///     std::thread::sleep(std::time::Duration::from_millis(50));
    ///     assert!(start.others_since().unwrap() >= 0.0);
    /// }
    /// ```
    pub fn now() -> Option<Usage> {
        let stat = std::fs::read_to_string("/proc/stat").ok()?;
        // "cpu  user nice system idle iowait irq softirq steal …": busy = all but idle and iowait.
        let ticks: Vec<f64> =
            stat.lines().next()?.split_whitespace().skip(1).filter_map(|t| t.parse().ok()).collect();
        let busy = ticks.iter().sum::<f64>() - ticks.get(3)? - ticks.get(4).unwrap_or(&0.0);
        let me = std::fs::read_to_string("/proc/self/stat").ok()?;
        // Fields after the command's closing parenthesis: utime and stime are the 12th and 13th.
        let fields: Vec<&str> = me.rsplit_once(')')?.1.split_whitespace().collect();
        let mine = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
        Some(Usage { all: busy / TICKS_PER_SECOND, mine: mine / TICKS_PER_SECOND, at: Instant::now() })
    }

    /// The CPUs other processes kept busy since `self`, on average (≥ 0).
    pub fn others_since(&self) -> Option<f64> {
        let now = Usage::now()?;
        let seconds = now.at.duration_since(self.at).as_secs_f64().max(1e-3);
        Some((((now.all - self.all) - (now.mine - self.mine)) / seconds).max(0.0))
    }
}

/// Why the rows cannot be judged, if other processes used more than [`OTHERS_LIMIT`] CPUs.
pub fn competing(others: Option<f64>, threads: usize) -> Option<String> {
    let others = others?;
    (others > OTHERS_LIMIT).then(|| {
        format!(
            "the machine was too busy to judge at {threads} threads: other processes kept {others:.2} CPUs \
             busy on average while the rows were timed (at most {OTHERS_LIMIT} allowed)"
        )
    })
}

/// Rounds of the machine check (each times the reference at 1 and at `T` threads).
const CHECK_ROUNDS: usize = 3;

/// The reference's speedup at `threads` threads below which the machine is too busy to
/// judge: half the ideal gain, `1 + (min(threads, cpus) − 1) / 2` (1.5 at 2 threads on 2
/// CPUs; a quiet machine gives 1.8–2.0 there).
///
/// ```
/// use raypool::measure::grade::judge::speedup_floor;
/// assert_eq!(speedup_floor(1), 1.0);
/// assert!(speedup_floor(2) <= 1.5);
/// ```
pub fn speedup_floor(threads: usize) -> f64 {
    1.0 + (threads.min(cpus()).max(1) - 1) as f64 / 2.0
}

/// The machine check at `threads`: the reference's own speedup on `workload` over 1 thread,
/// median of alternating rounds.
pub fn reference_speedup(
    reference: &dyn Scheduler,
    workload: &Workload,
    threads: usize,
) -> Result<f64, Error> {
    let (one, many) = (workload.frame(1)?, workload.frame(threads)?);
    let time = |frame| {
        let start = Instant::now();
        for _ in 0..workload.frames {
            reference.render(frame);
        }
        start.elapsed().as_secs_f64()
    };
    let mut speedups: Vec<f64> = (0..CHECK_ROUNDS).map(|_| time(&one) / time(&many)).collect();
    Ok(median(&mut speedups))
}

/// Why a machine check failed, in the report's words; `None` when it passed.
pub fn too_busy(speedup: f64, threads: usize) -> Option<String> {
    let floor = speedup_floor(threads);
    (threads > 1 && speedup < floor).then(|| {
        format!(
            "the machine was too busy to judge at {threads} threads: the reference's own speedup on \
             `balanced` was {speedup:.2}, below the floor of {floor:.2}"
        )
    })
}

/// Why a row's rounds cannot be judged, if they disagree beyond [`SPREAD_LIMIT`]: the
/// largest ratio over the smallest, once the most extreme round at each end is set aside
/// (from 4 rounds on: one round caught by a passing hiccup does not void a row).
///
/// ```
/// use raypool::measure::grade::judge::disagreement;
/// assert!(disagreement(&[1.0, 1.1, 1.05]).is_none());
/// assert!(disagreement(&[0.8, 1.1, 1.6]).unwrap().contains("0.80–1.60"));
/// assert!(disagreement(&[1.06, 1.30, 1.32, 1.80, 1.80]).is_none(), "1.30–1.80 once the ends are set aside");
/// ```
pub fn disagreement(ratios: &[f64]) -> Option<String> {
    let mut sorted = ratios.to_vec();
    sorted.sort_by(f64::total_cmp);
    let kept = if sorted.len() >= 4 { &sorted[1..sorted.len() - 1] } else { &sorted[..] };
    let (low, high) = (*kept.first()?, *kept.last()?);
    (high > SPREAD_LIMIT * low).then(|| {
        let all = if kept.len() < sorted.len() { " (the smallest and largest round set aside)" } else { "" };
        format!("the rounds disagree: ratios {low:.2}–{high:.2}{all}, more than {SPREAD_LIMIT}× apart")
    })
}
