//! Evaluation (work in progress).
