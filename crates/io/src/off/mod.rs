//! Geomview OFF (ascii), written by hand.
//!
//! The format most shape and denoising data sets ship (Princeton Shape Benchmark,
//! ModelNet, …): a keyword line, the counts, one vertex per line, one face per line.

mod read;
mod write;

pub(crate) use read::{declared_counts, read_off};
pub(crate) use write::write_off_to;

/// Whether `word` is an OFF header keyword, `[ST][C][N][4][n]OFF`.
pub(crate) fn is_off_keyword(word: &[u8]) -> bool {
    read::Keyword::parse(word).is_some_and(|(_, rest)| rest.is_empty())
}
