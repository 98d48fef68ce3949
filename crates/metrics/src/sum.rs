//! Compensated summation, so that statistics over millions of values do not depend on
//! rounding drift.

pub(crate) use beltrami_halfedge::geometry::CompensatedSum as Sum;
