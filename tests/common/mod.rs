//! Helpers shared by the viewer's tests (and `benches/view.rs`, `benches/view_hostile.rs`): a
//! running `raypool view` server, headless Chromium driven over the DevTools protocol, and
//! hostile traffic.

pub mod browser;
pub mod hostile;
pub mod viewer;
