//! Helpers shared by the viewer's tests (and `benches/view.rs`): a running `raypool view`
//! server, and headless Chromium driven over the DevTools protocol.

pub mod browser;
pub mod viewer;
