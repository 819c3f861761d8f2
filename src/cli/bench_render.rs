//! Kernel-specialisation benchmark (wired into `glint bench` by the lead).
