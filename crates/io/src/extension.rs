//! Formats from file names: [`MeshFormat::from_path`]. Apart from `format.rs` because
//! it reports through [`IoError`], whose variants in turn name formats.

use std::path::Path;

use crate::error::IoError;
use crate::format::MeshFormat;

impl MeshFormat {
    /// The format named by the extension of `path` (`.ply`, `.stl`, `.obj`, `.off`,
    /// `.x3p`, `.sdf`, in any letter case).
    ///
    /// # Examples
    /// ```
    /// use std::path::Path;
    /// use beltrami_io::MeshFormat;
    /// assert_eq!(MeshFormat::from_path(Path::new("scan.PLY"))?, MeshFormat::Ply);
    /// assert!(MeshFormat::from_path(Path::new("scan.xyz")).is_err());
    /// # Ok::<(), beltrami_io::IoError>(())
    /// ```
    ///
    /// # Errors
    /// [`IoError::MissingExtension`] without an extension,
    /// [`IoError::UnsupportedExtension`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Self, IoError> {
        let extension = path.extension().ok_or(IoError::MissingExtension)?;
        let extension = extension.to_string_lossy();
        match extension.to_ascii_lowercase().as_str() {
            "ply" => Ok(Self::Ply),
            "stl" => Ok(Self::Stl),
            "obj" => Ok(Self::Obj),
            "off" => Ok(Self::Off),
            "x3p" => Ok(Self::X3p),
            "sdf" => Ok(Self::Sdf),
            _ => Err(IoError::UnsupportedExtension {
                extension: extension.into_owned(),
            }),
        }
    }
}
