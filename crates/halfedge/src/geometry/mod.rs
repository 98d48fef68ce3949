//! Geometry helpers over a positions slice (`&[DVec3]`, f64).
