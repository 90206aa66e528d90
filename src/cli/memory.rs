//! Will this render fit in memory? Asked before a render starts, so that one too big for the
//! machine ends at once with a one-line error (exit code 2) instead of aborting minutes later
//! on a failed allocation, with a backtrace and a temporary file left behind (an allocation
//! failure aborts a Rust process: nothing can clean up after it).
//!
//! The estimate is measured, not guessed: peak resident memory of `raypool render` at 1024²
//! and 3072² (`/usr/bin/time -f %M`, spp 1), the difference divided by the pixels added, on
//! this project's machine (AMD EPYC, 2026-12-01), f32 build: 34.8 bytes per pixel for a PNG,
//! a part file (written streaming), PFM or EXR; 22.1 per image pixel for a quarter shard
//! (`--shard 1/4`); 106.5 with `--target-error`. In terms of `V` = the size of a pixel value
//! (16 bytes: glam's `Vec3A`; 24 with the `f64` feature), they fit
//! - the whole image, even in a shard (the frame is assembled full size): `V + 2` (the pixels
//!   and two bitmaps that check every pixel is rendered once);
//! - each rendered pixel: `V + 1` (the tiles' pixels before assembly);
//! - with adaptive sampling, each rendered pixel also keeps running sums in `f64` and its
//!   pass's tile: `52 + V + 4`
//!
//! (34, 22.25 and 106 bytes), and a tenth more is added for what one machine's measurement
//! cannot see (another allocator, another layout).
//!
//! What the process may use is the least of: the kernel's `MemAvailable`, the cgroup's
//! `memory.max` less what it already uses, and `ulimit -v` (address space) less what the
//! process already maps and the 64 MiB of address space glibc reserves per thread's arena.
//! Where none of these can be read (not Linux), every render is allowed.

use crate::error::Error;
use crate::tracer::math::real::Vec3;

/// The memory a render needs, bytes: `image_pixels` (the frame's full size), of which
/// `rendered_pixels` are rendered (all, or a shard's), with or without adaptive sampling.
///
/// ```
/// use raypool::cli::memory::estimate;
/// let plain = estimate(4096 * 4096, 4096 * 4096, false);
/// let per_pixel = plain / (4096 * 4096);
/// assert!((35..=45).contains(&per_pixel), "35 bytes a pixel (f32), a margin: {per_pixel}");
/// let adaptive = estimate(4096 * 4096, 4096 * 4096, true);
/// assert!(adaptive > 5 * plain / 2, "adaptive sampling: about three times");
/// let shard = estimate(4096 * 4096, 4096 * 4096 / 4, false);
/// assert!(shard > plain / 2, "a quarter shard still assembles the whole image");
/// ```
pub fn estimate(image_pixels: u64, rendered_pixels: u64, adaptive: bool) -> u64 {
    let value = size_of::<Vec3>() as u64;
    let per_rendered = value + 1 + if adaptive { 52 + value + 4 } else { 0 };
    let pixels = image_pixels * (value + 2) + rendered_pixels * per_rendered;
    BASELINE + pixels + pixels / 10
}

/// What the process needs besides the pixels: the binary, the scene, the threads' stacks.
const BASELINE: u64 = 32 << 20;

/// Address space glibc reserves for each thread's malloc arena (counted by `ulimit -v`).
const ARENA: u64 = 64 << 20;

/// Refuses a render of `needed` bytes (see [`estimate`]) on `threads` threads that this
/// process cannot have; `what` names the render in the message, `adaptive` picks the advice.
pub fn check(needed: u64, threads: usize, what: &str, adaptive: bool) -> Result<(), Error> {
    let Some((available, limit)) = available(threads) else { return Ok(()) };
    if needed <= available {
        return Ok(());
    }
    let advice = if adaptive {
        "render fewer pixels, or without --target-error (it keeps two running sums per pixel)"
    } else {
        "render fewer pixels (--width, --height)"
    };
    Err(Error::new(format!(
        "{what} needs about {} of memory, more than the {} this process may use ({limit}): {advice}",
        size(needed),
        size(available)
    )))
}

/// The least of the limits that can be read, and which one it is.
fn available(threads: usize) -> Option<(u64, &'static str)> {
    let mut limits: Vec<(u64, &'static str)> = Vec::new();
    if let Some(kib) = field("/proc/meminfo", "MemAvailable:") {
        limits.push((kib << 10, "the machine's available memory"));
    }
    if let (Some(max), Some(current)) =
        (number("/sys/fs/cgroup/memory.max"), number("/sys/fs/cgroup/memory.current"))
    {
        limits.push((max.saturating_sub(current), "the cgroup's memory.max"));
    }
    if let (Some(limit), Some(mapped)) = (address_space_limit(), field("/proc/self/status", "VmSize:")) {
        let reserved = (mapped << 10) + threads as u64 * ARENA;
        limits.push((limit.saturating_sub(reserved), "ulimit -v"));
    }
    limits.into_iter().min_by_key(|&(bytes, _)| bytes)
}

/// The soft `RLIMIT_AS` from `/proc/self/limits`, bytes; `None` when unlimited.
fn address_space_limit() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..].split_whitespace().next()?.parse().ok()
}

/// The number after `key` in a `/proc` file of `key value` lines (kB values).
fn field(path: &str, key: &str) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    text.lines().find(|l| l.starts_with(key))?[key.len()..].split_whitespace().next()?.parse().ok()
}

/// A file holding one number (`max` and other words are `None`).
fn number(path: &str) -> Option<u64> {
    std::fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// `bytes` for a person: "3.1 GB", "820 MB".
fn size(bytes: u64) -> String {
    let gb = bytes as f64 / 1e9;
    if gb >= 1.0 { format!("{gb:.1} GB") } else { format!("{:.0} MB", bytes as f64 / 1e6) }
}
