//! Choosing schemes by name.

use std::sync::Arc;

use crate::cotangent::Cotangent;
use crate::error::WeightError;
use crate::inverse_distance::InverseDistance;
use crate::scheme::WeightScheme;
use crate::uniform::Uniform;

/// Weight schemes by name, in registration order. The CLI and the study choose schemes
/// from a registry, so a scheme registered here (built-in or from a user's own crate)
/// can be used everywhere by name.
///
/// # Examples
/// ```
/// use beltrami_weights::{WeightRegistry, Uniform};
/// let registry = WeightRegistry::with_builtins();
/// assert_eq!(registry.names(), ["uniform", "distance", "cotangent"]);
/// assert_eq!(registry.get("distance").unwrap().name(), "distance");
/// assert!(registry.get("nope").is_err());
/// ```
#[derive(Clone, Default)]
pub struct WeightRegistry {
    schemes: Vec<Arc<dyn WeightScheme>>,
}

impl WeightRegistry {
    /// An empty registry.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The built-in schemes: `uniform`, `distance`, `cotangent`.
    #[must_use]
    pub fn with_builtins() -> Self {
        let mut registry = Self::new();
        registry.schemes.push(Arc::new(Uniform));
        registry.schemes.push(Arc::new(InverseDistance));
        registry.schemes.push(Arc::new(Cotangent));
        registry
    }

    /// Adds a scheme under its [`name`](WeightScheme::name).
    ///
    /// # Errors
    /// [`WeightError::DuplicateScheme`] when the name is taken, and
    /// [`WeightError::InvalidSchemeName`] when it is empty or contains anything but
    /// lowercase ASCII letters, digits, `-` and `_`.
    pub fn register(&mut self, scheme: impl WeightScheme + 'static) -> Result<(), WeightError> {
        let name = scheme.name();
        check_name(name)?;
        if self.schemes.iter().any(|s| s.name() == name) {
            return Err(WeightError::DuplicateScheme {
                name: name.to_string(),
            });
        }
        self.schemes.push(Arc::new(scheme));
        Ok(())
    }

    /// Puts `scheme` in the place of the registered scheme of the same name (a new
    /// version of one's own scheme, as a notebook cell run again registers it), keeping
    /// its place in the order; returns the scheme replaced.
    ///
    /// # Errors
    /// [`WeightError::UnknownScheme`] when no scheme has the name, listing the known
    /// ones, and [`WeightError::InvalidSchemeName`] as [`register`](Self::register).
    ///
    /// # Examples
    /// ```
    /// use beltrami_weights::{Cotangent, Uniform, WeightRegistry};
    /// let mut registry = WeightRegistry::new();
    /// registry.register(Uniform)?;
    /// let old = registry.replace(Uniform)?;
    /// assert_eq!(old.name(), "uniform");
    /// assert_eq!(registry.names(), ["uniform"]);
    /// assert!(registry.replace(Cotangent).is_err());
    /// # Ok::<(), beltrami_weights::WeightError>(())
    /// ```
    pub fn replace(
        &mut self,
        scheme: impl WeightScheme + 'static,
    ) -> Result<Arc<dyn WeightScheme>, WeightError> {
        let name = scheme.name();
        check_name(name)?;
        let known = self.names().join(", ");
        let slot = self
            .schemes
            .iter_mut()
            .find(|s| s.name() == name)
            .ok_or_else(|| WeightError::UnknownScheme {
                name: name.to_string(),
                known,
            })?;
        Ok(std::mem::replace(slot, Arc::new(scheme)))
    }

    /// The scheme called `name`.
    ///
    /// # Errors
    /// [`WeightError::UnknownScheme`], listing the known names.
    pub fn get(&self, name: &str) -> Result<Arc<dyn WeightScheme>, WeightError> {
        self.schemes
            .iter()
            .find(|s| s.name() == name)
            .cloned()
            .ok_or_else(|| WeightError::UnknownScheme {
                name: name.to_string(),
                known: self.names().join(", "),
            })
    }

    /// The registered names, in registration order.
    #[must_use]
    pub fn names(&self) -> Vec<&str> {
        self.schemes.iter().map(|s| s.name()).collect()
    }

    /// The registered schemes, in registration order.
    pub fn iter(&self) -> impl Iterator<Item = &Arc<dyn WeightScheme>> {
        self.schemes.iter()
    }
}

/// [`WeightError::InvalidSchemeName`] unless `name` is non-empty lowercase ASCII letters,
/// digits, `-` and `_`.
fn check_name(name: &str) -> Result<(), WeightError> {
    let valid = !name.is_empty()
        && name
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-' || b == b'_');
    if valid {
        Ok(())
    } else {
        Err(WeightError::InvalidSchemeName {
            name: name.to_string(),
        })
    }
}

impl std::fmt::Debug for WeightRegistry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}
