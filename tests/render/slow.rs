//! The slow and statistical tests of this binary (over about two CPU-seconds a module, or
//! a statistical test at a stated confidence), kept as they are and grouped here so that
//! `cargo test -- --skip slow::` runs the fast set (docs/testing.md). The files stay beside
//! `main.rs`.

#[path = "annotations.rs"]
mod annotations;
#[path = "cycles_goldens.rs"]
mod cycles_goldens;
#[path = "denoise.rs"]
mod denoise;
#[path = "ground_truth.rs"]
mod ground_truth;
#[path = "image_hashes.rs"]
mod image_hashes;
#[path = "sampling.rs"]
mod sampling;
