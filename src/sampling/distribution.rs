//! Discrete and piecewise-constant distributions (filled in by the light-sampling work).
