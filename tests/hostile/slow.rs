//! The slow and statistical tests of this binary (over about two CPU-seconds a module, or
//! a statistical test at a stated confidence), kept as they are and grouped here so that
//! `cargo test -- --skip slow::` runs the fast set (docs/testing.md). The files stay beside
//! `main.rs`.

#[path = "hostile_mutation.rs"]
mod hostile_mutation;
#[path = "output_plan.rs"]
mod output_plan;
