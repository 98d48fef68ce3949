//! Arbitrary polygon soups and positions, built with and without repairs and smoothed
//! with every scheme, boundary mode and weight-update policy: a typed error or finite
//! positions, never a panic.
#![no_main]

use beltrami_fuzz::{SmoothInput, check_build_smooth};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|input: SmoothInput| check_build_smooth(&input));
