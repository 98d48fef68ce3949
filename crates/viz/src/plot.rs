//! Line plots (in progress).
