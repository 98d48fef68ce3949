//! The X3P reader on arbitrary bytes: an error or a valid grid mesh, never a panic.
#![no_main]

use beltrami_fuzz::check_read;
use beltrami_io::MeshFormat;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| check_read(data, MeshFormat::X3p));
