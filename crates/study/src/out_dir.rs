//! The check of a study's output directory before the study runs: new, empty, or
//! holding only what a study writes (an earlier study, which the new one replaces).

use std::path::{Path, PathBuf};

use beltrami_io::{IoError, check_writable};

/// The entries [`write_study`](crate::write_study) writes into its directory.
pub const STUDY_ENTRIES: [&str; 7] = [
    "report.md",
    "results.csv",
    "results.json",
    "countermeasures.csv",
    "plots",
    "renders",
    "scan",
];

/// The entries [`write_scan`](crate::write_scan) writes into its directory, besides the
/// smoothed meshes `best-<scheme>-<method>.ply` (see [`is_scan_entry`]).
pub const SCAN_ENTRIES: [&str; 4] = ["report.md", "results.csv", "results.json", "timings.csv"];

/// Whether `name` is an entry [`write_study`](crate::write_study) writes.
#[must_use]
pub fn is_study_entry(name: &str) -> bool {
    STUDY_ENTRIES.contains(&name)
}

/// Whether `name` is an entry [`write_scan`](crate::write_scan) writes: one of
/// [`SCAN_ENTRIES`] or a `best-….ply` mesh.
#[must_use]
pub fn is_scan_entry(name: &str) -> bool {
    SCAN_ENTRIES.contains(&name)
        || (name.starts_with("best-")
            && Path::new(name)
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("ply")))
}

/// Whether a study of either kind writes `name`: a directory holding the paper's study
/// may take a study of a given surface and the other way round (it is replaced as a
/// whole), so both callers of [`check_out_dir`] pass this.
#[must_use]
pub fn is_any_study_entry(name: &str) -> bool {
    is_study_entry(name) || is_scan_entry(name)
}

/// Why a directory cannot take a study (see [`check_out_dir`]). The messages start with
/// the directory, so that a caller can put the name of its option in front.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OutDirError {
    /// The directory's parent cannot be written to.
    #[error("{0}")]
    Unwritable(#[source] IoError),
    /// The path exists and is not a directory.
    #[error("{} is not a directory", .dir.display())]
    NotADirectory {
        /// The path.
        dir: PathBuf,
    },
    /// The directory holds an entry a study does not write.
    #[error(
        "{} holds '{name}', which a study does not write; give a new or empty directory, or one holding an earlier study (which is replaced)",
        .dir.display()
    )]
    Foreign {
        /// The directory.
        dir: PathBuf,
        /// The entry's name.
        name: String,
    },
    /// The directory holds only entries a study writes, but no study's `results.json`
    /// (a directory of the user's own `report.md`, say): it is no earlier study.
    #[error(
        "{} holds '{name}' but no results.json of a study, so it is no earlier study (which would be replaced); give a new or empty directory",
        .dir.display()
    )]
    NotAStudy {
        /// The directory.
        dir: PathBuf,
        /// An entry it holds.
        name: String,
    },
}

/// Refuses an output directory that holds anything but an earlier study (which the new
/// one replaces), before the study runs: `is_entry` names what a study writes there
/// ([`is_study_entry`] for the paper's study, [`is_scan_entry`] for the study of a given
/// surface; either kind may replace the other, so a caller may accept both), and a
/// directory that is not empty must hold a study's `results.json`. A directory that
/// does not exist yet passes when its parent can be written.
///
/// # Examples
/// ```
/// use beltrami_study::{OutDirError, check_out_dir, is_study_entry};
/// let dir = tempfile::tempdir()?;
/// check_out_dir(&dir.path().join("new"), is_study_entry)?;
/// std::fs::write(dir.path().join("notes.txt"), "mine")?;
/// let err = check_out_dir(dir.path(), is_study_entry).unwrap_err();
/// assert!(matches!(err, OutDirError::Foreign { ref name, .. } if name == "notes.txt"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`OutDirError::Unwritable`] when the parent cannot be written to,
/// [`OutDirError::NotADirectory`] when `dir` is a file, [`OutDirError::Foreign`]
/// for the first entry `is_entry` does not name, and [`OutDirError::NotAStudy`] for a
/// directory of such entries without a study's `results.json`.
pub fn check_out_dir(dir: &Path, is_entry: impl Fn(&str) -> bool) -> Result<(), OutDirError> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    check_writable(parent.join("report.md")).map_err(OutDirError::Unwritable)?;
    let Ok(entries) = std::fs::read_dir(dir) else {
        if dir.exists() {
            return Err(OutDirError::NotADirectory {
                dir: dir.to_path_buf(),
            });
        }
        return Ok(());
    };
    let mut first = None;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if !is_entry(&name) {
            return Err(OutDirError::Foreign {
                dir: dir.to_path_buf(),
                name: name.into_owned(),
            });
        }
        first.get_or_insert_with(|| name.into_owned());
    }
    // Replacing a directory is for an earlier study: both kinds write a results.json
    // holding their configuration.
    if let Some(name) = first
        && !holds_study_results(&dir.join("results.json"))
    {
        return Err(OutDirError::NotAStudy {
            dir: dir.to_path_buf(),
            name,
        });
    }
    Ok(())
}

/// Whether `path` is a study's results.json: a regular file (not a pipe or a device,
/// which could block or never end) holding a JSON object with a `config` member. The
/// file is streamed and its values skipped, not held: a long study's is large.
fn holds_study_results(path: &Path) -> bool {
    // An object's members by name, their values skipped (a derived struct would also
    // take an array).
    type Members = std::collections::BTreeMap<String, serde::de::IgnoredAny>;
    std::fs::metadata(path).is_ok_and(|m| m.is_file())
        && std::fs::File::open(path).is_ok_and(|file| {
            serde_json::from_reader::<_, Members>(std::io::BufReader::new(file))
                .is_ok_and(|members| members.contains_key("config"))
        })
}
