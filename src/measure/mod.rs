//! **Measurement**: the speedup benchmark, the scaling model that predicts it past this
//! machine's cores, error against a reference and its convergence with samples, whether two
//! estimators agree (block by block, with the comparison's power stated), the numerical
//! stress cases, the plots, the machine a measurement runs on (its CPUs, the thread counts to
//! measure, the label every committed figure carries), and the course's grader (conformance,
//! then workloads timed against the reference). [`speedup`] and [`grade`] are folders: each
//! opens with its idea.
//!
//! It may use every layer below: [`crate::tracer`], [`crate::scenes`], [`crate::files`],
//! [`crate::schedule`] and [`crate::error`]. Only the command line, the viewer (for the CPUs)
//! and the `benches/` use it. The stress cases live here, not in [`crate::scenes`], because
//! they are a check, not just scenes: each renders itself and judges the pixels against a
//! known answer.

pub mod speedup;
pub mod scaling;
pub mod convergence;
pub mod agreement;
pub mod compare;
pub mod stress;
pub mod stress_shapes;
pub mod stress_smooth;
pub mod solids;
pub mod plot;
pub mod machine;
pub mod grade;
