//! Errors of `beltrami-schemes`.

use beltrami_weights::WeightError;

/// Why a scheme could not be built or registered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SchemesError {
    /// A parameter outside its valid range.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// The parameter, e.g. `"sigma"`.
        name: &'static str,
        /// Why it is invalid, with the value given.
        reason: String,
    },
    /// A scheme could not be registered.
    #[error(transparent)]
    Weights(#[from] WeightError),
}
