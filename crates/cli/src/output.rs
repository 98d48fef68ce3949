//! Output files: every command checks all of its outputs before any work, stages them
//! as temporary files beside their targets, and replaces the targets only once every
//! output has been produced.
//!
//! The checks, in order, before anything is read or computed:
//! 1. no two outputs name the same file (by path after resolving `..` and symbolic
//!    links, or by inode, which also catches hard links);
//! 2. no output is an input, unless `--force`;
//! 3. every output's directory exists and a file can be created in it;
//! 4. no output is a write-protected file, unless `--force` (as `cp` refuses);
//! 5. a mesh OUTPUT's extension names a format the command can write
//!    ([`refuse_height_map_output`]).
//!
//! An output that is a symbolic link is written through: the link stays and its
//! target is replaced.

use std::path::{Path, PathBuf};

use beltrami_io::{
    Encoding, IoError, MeshData, StagedFile, WriteOptions, check_writable, resolve_target,
    stage_bytes, stage_mesh,
};

use crate::error::CliError;

/// A usage error (exit 2) when `path` has no extension a mesh can be written in, found
/// before anything is read (for the commands that may write every format, height maps
/// included when the mesh is one).
pub(crate) fn refuse_unknown_output(path: &Path, command: &str) -> Result<(), CliError> {
    match beltrami_io::MeshFormat::from_path(path) {
        Ok(_) => Ok(()),
        Err(_) => Err(unknown_output(
            path,
            command,
            ".ply, .stl, .obj, .off, .x3p or .sdf",
        )),
    }
}

/// The usage error for an output `path` of no known format, naming what `command`
/// writes (`formats`).
fn unknown_output(path: &Path, command: &str, formats: &str) -> CliError {
    CliError::Usage(format!(
        "{}: {} for the output; {command} writes {formats}",
        path.display(),
        path.extension().map_or_else(
            || "no file extension".to_string(),
            |e| format!("unsupported file extension {:?}", e.to_string_lossy())
        ),
    ))
}

/// Refuses, before any work, an OUTPUT whose extension names no format (the error the
/// write would give after the run) and an OUTPUT named `.x3p` or `.sdf` for a command
/// whose result is no height map (its vertices leave the input's grid): `why` says what
/// moves them.
pub(crate) fn refuse_height_map_output(
    path: &Path,
    command: &str,
    why: &str,
) -> Result<(), CliError> {
    match beltrami_io::MeshFormat::from_path(path) {
        Ok(beltrami_io::MeshFormat::X3p | beltrami_io::MeshFormat::Sdf) => {
            Err(CliError::Usage(format!(
                "{command} cannot write {} as a height map: {why}; write .ply, .stl, .obj or .off instead",
                path.display()
            )))
        }
        Ok(_) => Ok(()),
        // A bad OUTPUT name is a usage error (exit 2), as a height-map name is, and the
        // list is of what this command writes.
        Err(_) => Err(unknown_output(path, command, ".ply, .stl, .obj or .off")),
    }
}

/// Writes the result of a mesh algorithm (its connectivity and positions) to `path` as
/// one staged, atomic write: nothing appears unless the whole file is written.
pub(crate) fn write_result(
    path: &Path,
    mesh: &beltrami_halfedge::HalfedgeMesh,
    positions: Vec<beltrami_halfedge::DVec3>,
    ascii: bool,
) -> Result<(), CliError> {
    write_result_and_report(path, mesh, positions, ascii, None)
}

/// [`write_result`], and with `report` the bytes of a report file beside it, staged
/// together: both appear, or neither.
pub(crate) fn write_result_and_report(
    path: &Path,
    mesh: &beltrami_halfedge::HalfedgeMesh,
    positions: Vec<beltrami_halfedge::DVec3>,
    ascii: bool,
    report: Option<(&PathBuf, &[u8])>,
) -> Result<(), CliError> {
    let data = MeshData {
        positions,
        faces: mesh.to_polygons(),
    };
    let mut staged = Staged::new();
    staged.push_mesh(path, &data, ascii)?;
    if let Some((report, bytes)) = report {
        staged.push(report, |report| stage_bytes(report, bytes))?;
    }
    staged.commit()
}

/// The notes a command prints before its sentence and puts in its JSON: the load's
/// `lines` (what `--repair` changed, what `--lenient` ignored), then what OUTPUT's format
/// leaves out of `mesh` (an STL file: the vertices in no face).
pub(crate) fn notes_for_output(
    output: &Path,
    lines: &[String],
    mesh: &beltrami_halfedge::HalfedgeMesh,
) -> Vec<String> {
    let mut notes = lines.to_vec();
    let dropped = beltrami_io::MeshFormat::from_path(output)
        .ok()
        .and_then(|format| format.drops_vertices_in_no_face(mesh.n_isolated_vertices()));
    if let Some(note) = dropped {
        notes.push(format!("note: {note}"));
    }
    // STL holds triangles: a polygon is written as the fan around its first corner.
    if beltrami_io::MeshFormat::from_path(output).ok() == Some(beltrami_io::MeshFormat::Stl)
        && !mesh.is_triangle_mesh()
    {
        let polygons = mesh.faces().filter(|&f| mesh.face_valence(f) != 3).count();
        notes.push(format!(
            "note: STL holds triangles only: {polygons} polygon {} written as triangle fans (PLY, OBJ and OFF keep {})",
            if polygons == 1 { "face is" } else { "faces are" },
            if polygons == 1 { "it" } else { "them" },
        ));
    }
    notes
}

/// Whether `a` and `b` name the same existing file: the same path after resolving
/// symbolic links and `..`, or (on Unix) the same inode on the same device, which also
/// catches hard links. A path that does not exist names no input.
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if ma.dev() == mb.dev() && ma.ino() == mb.ino() {
            return true;
        }
    }
    let _ = (ma, mb);
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(ca), Ok(cb)) => ca == cb,
        _ => false,
    }
}

/// The absolute path a write to `path` creates or replaces, with symbolic links and
/// `..` resolved as far as the file system allows (the file itself may not exist yet).
fn destination(path: &Path) -> PathBuf {
    let target = resolve_target(path).unwrap_or_else(|_| path.to_path_buf());
    if let Ok(full) = std::fs::canonicalize(&target) {
        return full;
    }
    let name = target.file_name().map(ToOwned::to_owned);
    let parent = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    match (std::fs::canonicalize(&parent), name) {
        (Ok(dir), Some(name)) => dir.join(name),
        _ => target,
    }
}

/// Whether a write to `a` and a write to `b` would land in the same file.
fn same_destination(a: &Path, b: &Path) -> bool {
    same_file(a, b) || destination(a) == destination(b)
}

/// Fails when the output `output`, named by `option`, is one of `inputs` (the command's
/// mesh first, then files its options read): [`CliError::OverwritesInput`] for the
/// command's result mesh (`mesh_output`) naming the first input without `force` (an
/// edit in place, which `force` allows); [`CliError::Usage`] for every other output
/// naming an input, with or without `force` (a report, an image or a mesh replacing a
/// file of options or a second mesh is never what was meant). Call it before reading
/// anything, so that a refused run changes nothing.
pub(crate) fn check_not_input(
    output: &Path,
    option: &str,
    mesh_output: bool,
    inputs: &[&PathBuf],
    force: bool,
    has_result_mesh: bool,
) -> Result<(), CliError> {
    for (k, input) in inputs.iter().enumerate() {
        if !same_file(output, input) {
            continue;
        }
        let in_place = k == 0 && mesh_output;
        if in_place && force {
            continue;
        }
        return Err(if in_place {
            CliError::OverwritesInput {
                output: output.to_path_buf(),
                input: (*input).clone(),
            }
        } else {
            CliError::Usage(format!(
                "{}: {option} is the input file {}, which it would replace{}; give {option} a file of its own",
                output.display(),
                input.display(),
                if has_result_mesh {
                    " (--force lets only the result mesh replace the input mesh)"
                } else {
                    ""
                }
            ))
        });
    }
    Ok(())
}

/// Whether `path` (the target of a symbolic link) is an existing file without write
/// permission for anyone.
fn write_protected(path: &Path) -> bool {
    let target = resolve_target(path).unwrap_or_else(|_| path.to_path_buf());
    std::fs::metadata(target).is_ok_and(|m| m.is_file() && m.permissions().readonly())
}

/// The outputs of one command, with the option that names each (`OUTPUT`,
/// `--report`, …) and whether it is the command's result mesh (which `--force` lets
/// replace the input mesh), checked together before any work.
#[derive(Debug, Default)]
pub(crate) struct Outputs {
    entries: Vec<(PathBuf, &'static str, bool)>,
}

impl Outputs {
    /// No outputs yet.
    pub(crate) fn new() -> Self {
        Self::default()
    }

    /// Adds the output `path`, named by `option` in messages.
    pub(crate) fn add(&mut self, path: &Path, option: &'static str) -> &mut Self {
        self.entries.push((path.to_path_buf(), option, false));
        self
    }

    /// Adds the command's result mesh `path`, named by `option` in messages: with
    /// `--force` it may replace the input mesh (an edit in place).
    pub(crate) fn add_mesh(&mut self, path: &Path, option: &'static str) -> &mut Self {
        self.entries.push((path.to_path_buf(), option, true));
        self
    }

    /// Adds `path` when it is given.
    pub(crate) fn add_opt(&mut self, path: Option<&PathBuf>, option: &'static str) -> &mut Self {
        if let Some(path) = path {
            self.add(path, option);
        }
        self
    }

    /// Runs every check of the module documentation against `inputs`.
    ///
    /// # Errors
    /// [`CliError::Usage`] for two outputs naming one file, and for an output naming
    /// an input other than the result mesh naming the input mesh (with or without
    /// `force`, see [`check_not_input`]); [`CliError::OverwritesInput`] for the result
    /// mesh naming the input mesh and [`CliError::WriteProtected`], without `force`;
    /// [`CliError::Io`] for an output that cannot be written.
    pub(crate) fn check(&self, inputs: &[&PathBuf], force: bool) -> Result<(), CliError> {
        for (i, (a, option_a, _)) in self.entries.iter().enumerate() {
            for (b, option_b, _) in &self.entries[..i] {
                if same_destination(a, b) {
                    return Err(CliError::Usage(format!(
                        "{option_b} and {option_a} name the same file {}; each output needs its own file",
                        b.display()
                    )));
                }
            }
        }
        let has_result_mesh = self.entries.iter().any(|(_, _, mesh)| *mesh);
        for (path, option, mesh) in &self.entries {
            check_not_input(path, option, *mesh, inputs, force, has_result_mesh)?;
        }
        for (path, _, _) in &self.entries {
            check_writable(path).map_err(|source| CliError::Io {
                path: path.clone(),
                source,
            })?;
            if !force && write_protected(path) {
                return Err(CliError::WriteProtected { path: path.clone() });
            }
        }
        Ok(())
    }
}

/// Outputs written to temporary files, replacing their targets all at once on
/// [`commit`](Self::commit). Dropped uncommitted, they leave every target untouched.
#[derive(Debug, Default)]
pub(crate) struct Staged {
    files: Vec<(PathBuf, StagedFile)>,
}

impl Staged {
    /// Nothing staged yet.
    pub(crate) fn new() -> Self {
        Self::default()
    }

    /// Stages one output: `stage` writes it to a temporary file (one of
    /// `beltrami_io`'s `stage_*` functions); errors name `path`.
    pub(crate) fn push(
        &mut self,
        path: &Path,
        stage: impl FnOnce(&Path) -> Result<StagedFile, IoError>,
    ) -> Result<(), CliError> {
        let file = stage(path).map_err(|source| CliError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        self.files.push((path.to_path_buf(), file));
        Ok(())
    }

    /// Stages the mesh file `path` (format by extension): binary PLY and STL, or ascii
    /// text with `ascii`.
    pub(crate) fn push_mesh(
        &mut self,
        path: &Path,
        data: &MeshData,
        ascii: bool,
    ) -> Result<(), CliError> {
        let options = WriteOptions::default().encoding(if ascii {
            Encoding::Ascii
        } else {
            Encoding::BinaryLittleEndian
        });
        self.push(path, |path| stage_mesh(path, data, &options))
    }

    /// Replaces every target, in the order staged, flushing each directory once.
    pub(crate) fn commit(self) -> Result<(), CliError> {
        let (paths, files): (Vec<PathBuf>, Vec<StagedFile>) = self.files.into_iter().unzip();
        beltrami_io::commit_staged(files).map_err(|(index, source)| CliError::Io {
            path: paths[index].clone(),
            source,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_and_aliases_are_the_same_file() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.ply");
        std::fs::write(&a, b"x").unwrap();
        let b = dir.path().join("b.ply");
        std::fs::write(&b, b"x").unwrap();
        let alias = dir.path().join(".").join("a.ply");
        assert!(same_file(&a, &alias));
        assert!(!same_file(&a, &b));
        assert!(!same_file(&a, &dir.path().join("missing.ply")));
        let hard = dir.path().join("hard.ply");
        std::fs::hard_link(&a, &hard).unwrap();
        assert!(same_file(&a, &hard));
        #[cfg(unix)]
        {
            let soft = dir.path().join("soft.ply");
            std::os::unix::fs::symlink(&a, &soft).unwrap();
            assert!(same_file(&a, &soft));
        }
        // OUTPUT may replace INPUT with --force (an edit in place), and nothing else
        // may replace an input: not another output, not OUTPUT replacing a second
        // input (a reference mesh, a file of feature edges).
        assert!(matches!(
            check_not_input(&hard, "OUTPUT", true, &[&a, &b], false, true),
            Err(CliError::OverwritesInput { .. })
        ));
        assert!(check_not_input(&hard, "OUTPUT", true, &[&a, &b], true, true).is_ok());
        for force in [false, true] {
            for (option, mesh, inputs) in [
                ("OUTPUT", true, [&b, &a]),
                ("--report", false, [&a, &b]),
                ("--report", false, [&b, &a]),
            ] {
                assert!(
                    matches!(
                        check_not_input(&hard, option, mesh, &inputs, force, true),
                        Err(CliError::Usage(_))
                    ),
                    "{option} {mesh} {force}"
                );
            }
        }
        assert!(check_not_input(&b, "OUTPUT", true, &[&a], false, true).is_ok());
        // The hint about --force only where the command has a result mesh to allow.
        for (has_result_mesh, hint) in [(true, true), (false, false)] {
            let Err(CliError::Usage(message)) =
                check_not_input(&hard, "--scalars", false, &[&a], true, has_result_mesh)
            else {
                panic!("not a usage error");
            };
            assert_eq!(message.contains("--force"), hint, "{message}");
            assert!(
                message.ends_with("give --scalars a file of its own"),
                "{message}"
            );
        }
    }

    #[test]
    fn two_outputs_to_one_new_file_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.ply");
        let alias = dir.path().join("sub").join("..").join("out.ply");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let mut outputs = Outputs::new();
        outputs.add(&out, "OUTPUT").add(&alias, "--report");
        let e = outputs.check(&[], false).unwrap_err().to_string();
        assert!(e.contains("OUTPUT and --report"), "{e}");
        let mut distinct = Outputs::new();
        distinct
            .add(&out, "OUTPUT")
            .add(&dir.path().join("r.json"), "--report");
        distinct.check(&[], false).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_link_to_another_output_is_the_same_file() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out.ply");
        let link = dir.path().join("link.json");
        std::os::unix::fs::symlink(&out, &link).unwrap();
        let mut outputs = Outputs::new();
        outputs.add(&out, "OUTPUT").add(&link, "--report");
        assert!(outputs.check(&[], false).is_err());
    }
}
