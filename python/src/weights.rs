//! The weight schemes known to the package: the library's built-ins and the
//! edge-preserving schemes, as the command line knows them.

use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use beltrami_weights::{WeightRegistry, WeightScheme};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// The registry shared by every call.
fn registry() -> PyResult<&'static Mutex<WeightRegistry>> {
    static REGISTRY: OnceLock<Result<Mutex<WeightRegistry>, String>> = OnceLock::new();
    REGISTRY
        .get_or_init(|| {
            let mut registry = WeightRegistry::with_builtins();
            beltrami_schemes::register_all(&mut registry).map_err(|e| e.to_string())?;
            Ok(Mutex::new(registry))
        })
        .as_ref()
        .map_err(|e| PyRuntimeError::new_err(e.clone()))
}

/// The scheme registered under `name`; `ValueError` naming the known ones otherwise.
pub(crate) fn scheme(name: &str) -> PyResult<Arc<dyn WeightScheme>> {
    registry()?
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .get(name)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Every registered scheme, in the registry's order (built-ins, the edge-preserving
/// schemes, then those registered from Python).
pub(crate) fn all_schemes() -> PyResult<Vec<Arc<dyn WeightScheme>>> {
    Ok(registry()?
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .iter()
        .cloned()
        .collect())
}

/// The names of the registered weight schemes, sorted.
#[pyfunction]
pub(crate) fn weight_schemes() -> PyResult<Vec<String>> {
    Ok(registry()?
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .names()
        .into_iter()
        .map(str::to_string)
        .collect())
}

/// Adds `scheme` to the registry; `ValueError` when the name is taken or invalid.
pub(crate) fn register(scheme: impl WeightScheme + 'static) -> PyResult<()> {
    registry()?
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .register(scheme)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Whether a scheme is registered under `name`.
pub(crate) fn is_registered(name: &str) -> PyResult<bool> {
    Ok(registry()?
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .get(name)
        .is_ok())
}

/// Puts `scheme` in the place of the registered scheme of the same name.
pub(crate) fn replace(scheme: impl WeightScheme + 'static) -> PyResult<()> {
    registry()?
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .replace(scheme)
        .map(drop)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}
