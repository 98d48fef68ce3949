//! `beltrami render`: a shaded picture of a mesh (PNG), optionally coloured by a
//! per-vertex scalar of a PLY file or by the signed distance to a reference surface,
//! with a colour bar.
//!
//! [`render_png`] is the part other commands reuse: a loaded mesh (and its scalars)
//! in, PNG bytes out.

use std::fmt;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_io::{IoError, MeshFormat, stage_bytes};
use beltrami_metrics::distance::SurfaceIndex;
use beltrami_viz::render::{
    ColorBar, ColorBarTicks, ColorMap, MAX_RENDER_SIZE, MAX_SAMPLES, MIN_COLORBAR_RENDER_SIZE,
    RenderOptions, View, render_mesh_with, render_with_colorbar,
};

use crate::compare::metrics_error;
use crate::error::CliError;
use crate::load::{LoadedMesh, ReadArgs, load};
use crate::output::{Outputs, Staged};
use crate::text::number;

/// Arguments of `beltrami render`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  beltrami render smoothed.ply smoothed.png
  beltrami render smoothed.ply distance.png --distance-to clean.ply --view top
  beltrami compare smoothed.ply clean.ply --scalars distance.ply
  beltrami render distance.ply distance.png --scalar signed_distance --size 800x600")]
pub(crate) struct RenderArgs {
    /// The mesh to draw (.ply, .stl, .obj, .off, or an .x3p or .sdf height map).
    mesh: PathBuf,
    /// The image to write (.png); it is replaced atomically.
    #[arg(value_name = "OUT.png")]
    out: PathBuf,
    /// Colour by this per-vertex property of a PLY mesh, e.g. signed_distance (written
    /// by `compare --scalars`) or residual (by `residual --out`). When 0 is within the
    /// values' range, the colours are symmetric about 0 (white = 0); values all above or
    /// all below 0 span blue (minimum) to red (maximum).
    #[arg(long, value_name = "NAME", conflicts_with = "distance_to")]
    scalar: Option<String>,
    /// Colour by the signed distance of each vertex to this reference surface (.ply,
    /// .stl, .obj or .off), as `compare` measures it: blue inside, white on, red outside,
    /// symmetric about 0.
    #[arg(long, value_name = "REF")]
    distance_to: Option<PathBuf>,
    /// The camera (orthographic; the whole mesh is framed).
    #[arg(long, value_enum, default_value_t = ViewKind::Iso)]
    view: ViewKind,
    /// The image's width and height in pixels, each 1 to 8192 (at least 160x120 with a
    /// colour bar), at most 33 554 432 pixels in all.
    #[arg(long, value_name = "WxH", default_value = "1200x900", value_parser = parse_size)]
    size: ImageSize,
    /// Replace OUT.png even when it is write-protected. It never replaces MESH or REF.
    #[arg(long)]
    force: bool,
    #[command(flatten)]
    read: ReadArgs,
}

/// Where the camera looks from. The fixed views take +z as up.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum ViewKind {
    /// Three-quarter view from the front right and above, with the mesh's thinnest
    /// axis up (+z for a height field over the xy-plane and for round shapes).
    Iso,
    /// From above: looking down −z, +x to the right, +y up.
    Top,
    /// From the front: looking along +y, +x to the right, +z up.
    Front,
    /// From the right: looking along −x, +y to the right, +z up.
    Side,
}

impl ViewKind {
    /// The camera for a mesh at `positions`.
    pub(crate) fn view(self, positions: &[DVec3]) -> View {
        match self {
            Self::Iso => View::default_for(positions),
            Self::Top => View::from_above(),
            Self::Front => View::from_side(),
            Self::Side => View::new(DVec3::NEG_X, DVec3::Z),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::Iso => "iso",
            Self::Top => "top",
            Self::Front => "front",
            Self::Side => "side",
        }
    }
}

/// The size of an image in pixels: each side 1 to [`MAX_RENDER_SIZE`], at most
/// [`MAX_SAMPLES`] pixels (as `--size` checks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct ImageSize {
    pub(crate) width: u32,
    pub(crate) height: u32,
}

/// The default `--size` (and the size of `compare --png`).
pub(crate) const DEFAULT_SIZE: ImageSize = ImageSize {
    width: 1200,
    height: 900,
};

impl fmt::Display for ImageSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// Parses `--size`: `WIDTHxHEIGHT`, e.g. `1200x900`.
pub(crate) fn parse_size(text: &str) -> Result<ImageSize, String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or("expected WIDTHxHEIGHT in pixels, e.g. 1200x900")?;
    let side = |name: &str, value: &str| match value.trim().parse::<u32>() {
        Ok(v) if (1..=MAX_RENDER_SIZE).contains(&v) => Ok(v),
        _ => Err(format!(
            "the {name} must be a whole number of pixels from 1 to {MAX_RENDER_SIZE}, got '{value}'"
        )),
    };
    let size = ImageSize {
        width: side("width", w)?,
        height: side("height", h)?,
    };
    let pixels = u64::from(size.width) * u64::from(size.height);
    if pixels > MAX_SAMPLES {
        return Err(format!(
            "{size} is {pixels} pixels, more than the limit of {MAX_SAMPLES}"
        ));
    }
    Ok(size)
}

/// How per-vertex values are turned into colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ColorRange {
    /// From −m (blue) through 0 (white) to m (red), m the largest absolute value: for
    /// signed quantities such as distances and residuals.
    Symmetric,
    /// From the smallest value (blue) to the largest (red).
    MinToMax,
}

/// Per-vertex values to colour a render by.
#[derive(Clone, Copy, Debug)]
pub(crate) struct VertexScalars<'a> {
    /// What the values are, with their unit: the colour bar's label, e.g.
    /// `"signed distance to clean.ply (mesh units)"`.
    pub(crate) label: &'a str,
    /// One value per vertex of the mesh. Non-finite values are drawn grey.
    pub(crate) values: &'a [f64],
    /// How values map to colours.
    pub(crate) range: ColorRange,
}

/// A rendered image as PNG bytes, and how its colours read.
#[derive(Debug)]
pub(crate) struct RenderedPng {
    /// The PNG file's bytes.
    pub(crate) bytes: Vec<u8>,
    /// With scalars: the smallest and largest finite value on the drawn surface (at
    /// vertices with a face), or `None` when there is none.
    pub(crate) range: Option<(f64, f64)>,
    /// With scalars: the colour map, from full blue (`min`) to full red (`max`).
    pub(crate) colors: Option<ColorMap>,
}

/// Renders `mesh` at `positions` as PNG bytes of `size`: shaded light grey, or coloured
/// by `scalars` with a colour bar under the mesh (tick labels at both ends of the colour
/// range and at round values between, and the scalars' label). The camera is
/// orthographic from `view` and frames the whole mesh. 2×2 supersampling while the
/// samples stay within the renderer's limit, none beyond. The same input gives the same
/// bytes.
///
/// This is what `beltrami render` draws; a command that wants a picture of its result
/// (`compare --png`) calls it with its loaded mesh. `out` is the file the bytes are
/// meant for, named in errors.
///
/// # Errors
/// [`CliError::Usage`] when `size` is below [`MIN_COLORBAR_RENDER_SIZE`] with scalars;
/// [`CliError::Io`] on `out` when drawing fails (mismatched lengths, a size beyond the
/// renderer's limits: what callers validate first).
pub(crate) fn render_png(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scalars: Option<VertexScalars<'_>>,
    view: ViewKind,
    size: ImageSize,
    out: &Path,
) -> Result<RenderedPng, CliError> {
    let ImageSize { width, height } = size;
    let drawing = |e: beltrami_viz::VizError| CliError::Io {
        path: out.to_path_buf(),
        source: IoError::Io {
            operation: "draw the image",
            source: std::io::Error::other(e.to_string()),
        },
    };
    let samples = u64::from(width) * u64::from(height) * 4;
    let options = RenderOptions::default().supersample(if samples <= MAX_SAMPLES { 2 } else { 1 });
    let camera = view.view(positions);
    let Some(scalars) = scalars else {
        let image = render_mesh_with(
            mesh,
            positions,
            None,
            &ColorMap::default(),
            &camera,
            None,
            width,
            height,
            &options,
        )
        .map_err(drawing)?;
        return Ok(RenderedPng {
            bytes: image.encode_png().map_err(drawing)?,
            range: None,
            colors: None,
        });
    };
    let (min_w, min_h) = MIN_COLORBAR_RENDER_SIZE;
    if width < min_w || height < min_h {
        return Err(CliError::Usage(format!(
            "--size {size} is too small for an image with a colour bar (at least {min_w}x{min_h})"
        )));
    }
    // The range of what is drawn: vertices with a face.
    let drawn = mesh
        .vertices()
        .filter(|&v| !mesh.is_isolated(v))
        .filter_map(|v| scalars.values.get(v.index()).copied())
        .filter(|s| s.is_finite());
    let range = drawn.fold(None, |r: Option<(f64, f64)>, s| {
        Some(r.map_or((s, s), |(lo, hi)| (lo.min(s), hi.max(s))))
    });
    let colors = match (scalars.range, range) {
        (ColorRange::Symmetric, Some((lo, hi))) if lo != 0.0 || hi != 0.0 => {
            ColorMap::symmetric(lo.abs().max(hi.abs()))
        }
        (ColorRange::MinToMax, Some((lo, hi))) => ColorMap::new(lo, hi),
        _ => ColorMap::default(),
    };
    let bar = ColorBar::new(colors, scalars.label).with_ticks(ColorBarTicks::Ends);
    let image = render_with_colorbar(
        mesh,
        positions,
        scalars.values,
        &bar,
        &camera,
        width,
        height,
        &options,
    )
    .map_err(drawing)?;
    Ok(RenderedPng {
        bytes: image.encode_png().map_err(drawing)?,
        range,
        colors: Some(colors),
    })
}

/// Runs `beltrami render`.
pub(crate) fn run(args: &RenderArgs, out: &mut impl Write) -> Result<(), CliError> {
    let mut inputs = vec![&args.mesh];
    inputs.extend(&args.distance_to);
    let mut outputs = Outputs::new();
    outputs.add(&args.out, "OUT");
    outputs.check(&inputs, args.force)?;
    check_render_args(args)?;

    let loaded = load_surface(&args.mesh, &args.read)?;
    let mut notes = loaded.read_notes(&args.mesh, args.distance_to.is_some());
    let (values, label, range) = colour_values(args, &loaded, &mut notes)?;
    let scalars = values.as_deref().map(|values| VertexScalars {
        label: &label,
        values,
        range,
    });
    let rendered = render_png(
        &loaded.mesh,
        &loaded.positions,
        scalars,
        args.view,
        args.size,
        &args.out,
    )?;
    let mut staged = Staged::new();
    staged.push(&args.out, |path| stage_bytes(path, &rendered.bytes))?;
    staged.commit()?;

    let colouring = colouring_text(values.as_deref(), &label, &rendered);
    writeln!(
        out,
        "rendered {} ({} vertices, {} faces) from the {} view, {colouring} -> {} ({})",
        args.mesh.display(),
        loaded.mesh.n_vertices(),
        loaded.mesh.n_faces(),
        args.view.name(),
        args.out.display(),
        args.size,
    )?;
    for line in &notes {
        writeln!(out, "{line}")?;
    }
    Ok(())
}

/// The usage errors of `render`'s options: OUT must be a PNG, large enough for a colour
/// bar when there is one; `--scalar` reads a PLY file.
fn check_render_args(args: &RenderArgs) -> Result<(), CliError> {
    let is_png = args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        return Err(CliError::Usage(format!(
            "render writes a PNG image: OUT must end in .png, got '{}'",
            args.out.display()
        )));
    }
    if args.scalar.is_some() || args.distance_to.is_some() {
        let (min_w, min_h) = MIN_COLORBAR_RENDER_SIZE;
        if args.size.width < min_w || args.size.height < min_h {
            return Err(CliError::Usage(format!(
                "--size {} is too small for an image with a colour bar (at least {min_w}x{min_h})",
                args.size
            )));
        }
    }
    if args.scalar.is_some() && MeshFormat::from_path(&args.mesh).ok() != Some(MeshFormat::Ply) {
        return Err(CliError::Usage(format!(
            "--scalar reads a vertex property of a PLY file, but '{}' is not .ply",
            args.mesh.display()
        )));
    }
    Ok(())
}

/// The values to colour the vertices by (from `--scalar` or `--distance-to`; none for
/// shading alone), their label and their colour range.
fn colour_values(
    args: &RenderArgs,
    loaded: &LoadedMesh,
    notes: &mut Vec<String>,
) -> Result<(Option<Vec<f64>>, String, ColorRange), CliError> {
    Ok(match (&args.scalar, &args.distance_to) {
        (Some(name), _) => {
            let values = vertex_property(&args.mesh, loaded, name)?;
            // 0 inside the range (or at an end): a signed quantity, white at 0.
            let reaches_zero = values.iter().any(|&s| s <= 0.0) && values.iter().any(|&s| s >= 0.0);
            let range = if reaches_zero {
                ColorRange::Symmetric
            } else {
                ColorRange::MinToMax
            };
            (Some(values), name.clone(), range)
        }
        (None, Some(reference)) => {
            let values = signed_distances(loaded, &args.mesh, reference, &args.read, notes)?;
            let name = reference.file_name().map_or_else(
                || reference.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            let label = format!("signed distance to {name} (mesh units)");
            (Some(values), label, ColorRange::Symmetric)
        }
        (None, None) => (None, String::new(), ColorRange::Symmetric),
    })
}

/// How the image is coloured, for the summary line.
fn colouring_text(values: Option<&[f64]>, label: &str, rendered: &RenderedPng) -> String {
    match (values, rendered.range, rendered.colors.as_ref()) {
        (None, ..) => "shaded grey".to_owned(),
        (Some(values), range, Some(colors)) => {
            let values_text = match range {
                Some((lo, hi)) => format!("in [{}, {}]", number(lo), number(hi)),
                None => "with no finite value".to_owned(),
            };
            let map = if colors.min == -colors.max {
                format!("±{}", number(colors.max))
            } else {
                format!("{} to {}", number(colors.min), number(colors.max))
            };
            let grey = values.iter().filter(|s| !s.is_finite()).count();
            let grey = match grey {
                0 => String::new(),
                1 => ", 1 non-finite value in grey".to_owned(),
                n => format!(", {n} non-finite values in grey"),
            };
            format!("coloured by {label} {values_text} (colour bar {map}{grey})")
        }
        (Some(_), _, None) => format!("coloured by {label}"),
    }
}

/// Reads a mesh to draw: it must have vertices and faces.
fn load_surface(path: &Path, read: &ReadArgs) -> Result<LoadedMesh, CliError> {
    let loaded = load(path, read)?;
    loaded.require_faces(path, "render")?;
    Ok(loaded)
}

/// The signed distance of every vertex of `loaded` (read from `path`) to the surface
/// in the file `reference`, as `compare` measures it; what reading `reference` did
/// besides reading it goes into `notes`.
fn signed_distances(
    loaded: &LoadedMesh,
    path: &Path,
    reference: &Path,
    read: &ReadArgs,
    notes: &mut Vec<String>,
) -> Result<Vec<f64>, CliError> {
    let surface = load(reference, read)?;
    notes.extend(surface.read_notes(reference, true));
    surface.require_faces(reference, "render --distance-to")?;
    let index =
        SurfaceIndex::new(&surface.mesh, &surface.positions).map_err(metrics_error(reference))?;
    index.prepare_signed();
    index
        .signed_distances(&loaded.positions)
        .map_err(metrics_error(path))
}

/// The vertex property `name` of the PLY file `path` (already read into `loaded`), one
/// value per vertex of the built mesh: vertices added by `--repair` copy the value of
/// the vertex they split from.
fn vertex_property(path: &Path, loaded: &LoadedMesh, name: &str) -> Result<Vec<f64>, CliError> {
    let io = |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(|e| {
        io(IoError::Io {
            operation: "open the file",
            source: e,
        })
    })?;
    let mut reader = BufReader::new(file);
    let header = ply::Header::read(&mut reader).map_err(io)?;
    let Some(column) = header.vertex_scalar(name) else {
        let available = header.vertex_scalar_names();
        let available = if available.is_empty() {
            "none".to_owned()
        } else {
            available.join(", ")
        };
        return Err(CliError::Usage(format!(
            "{}: no scalar vertex property '{name}' (the file has: {available})",
            path.display()
        )));
    };
    let values = header.read_vertex_column(reader, column).map_err(io)?;
    let read = loaded.input_counts.0;
    if values.len() != read {
        return Err(io(IoError::PlyData {
            line: None,
            element: "vertex".to_owned(),
            index: values.len().min(read),
            reason: format!("{} values of '{name}' for {read} vertices", values.len()),
        }));
    }
    let Some(report) = &loaded.repair else {
        return Ok(values);
    };
    // After --repair: each output vertex takes the value of the input vertex it comes
    // from (a merged group the value of its lowest vertex, a split copy its original's).
    let mut repaired = vec![f64::NAN; loaded.positions.len()];
    let mut set = vec![false; repaired.len()];
    for (input, output) in report.vertex_map.iter().enumerate() {
        if let Some(o) = output
            && !set[*o as usize]
        {
            repaired[*o as usize] = values[input];
            set[*o as usize] = true;
        }
    }
    for &(input, copy) in &report.split_vertices {
        repaired[copy as usize] = values[input as usize];
    }
    Ok(repaired)
}

/// Just enough PLY to read one scalar vertex property, which `beltrami_io` skips: the
/// header, then the elements up to and including `vertex`, ascii or binary. The file
/// has been read (and checked) by `beltrami_io` first.
mod ply {
    use super::{BufRead, IoError};

    /// The longest header accepted, in lines.
    const MAX_HEADER_LINES: usize = 10_000;

    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    enum Encoding {
        Ascii,
        Little,
        Big,
    }

    #[derive(Clone, Copy, Debug)]
    enum Scalar {
        I8,
        U8,
        I16,
        U16,
        I32,
        U32,
        F32,
        F64,
    }

    impl Scalar {
        fn parse(name: &str) -> Option<Self> {
            Some(match name {
                "char" | "int8" => Self::I8,
                "uchar" | "uint8" => Self::U8,
                "short" | "int16" => Self::I16,
                "ushort" | "uint16" => Self::U16,
                "int" | "int32" => Self::I32,
                "uint" | "uint32" => Self::U32,
                "float" | "float32" => Self::F32,
                "double" | "float64" => Self::F64,
                _ => return None,
            })
        }

        fn size(self) -> usize {
            match self {
                Self::I8 | Self::U8 => 1,
                Self::I16 | Self::U16 => 2,
                Self::I32 | Self::U32 | Self::F32 => 4,
                Self::F64 => 8,
            }
        }

        /// The value of `bytes` (`size()` of them) in byte order `encoding`.
        fn decode(self, bytes: &[u8], encoding: Encoding) -> f64 {
            let mut b = [0u8; 8];
            let n = self.size();
            b[..n].copy_from_slice(&bytes[..n]);
            if encoding == Encoding::Big {
                b[..n].reverse();
            }
            match self {
                Self::I8 => f64::from(b[0] as i8),
                Self::U8 => f64::from(b[0]),
                Self::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
                Self::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
                Self::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                Self::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                Self::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
                Self::F64 => f64::from_le_bytes(b),
            }
        }
    }

    #[derive(Debug)]
    enum Kind {
        Scalar(Scalar),
        List { count: Scalar, item: Scalar },
    }

    #[derive(Debug)]
    struct Property {
        name: String,
        kind: Kind,
    }

    #[derive(Debug)]
    struct Element {
        name: String,
        count: usize,
        properties: Vec<Property>,
    }

    /// A parsed PLY header.
    #[derive(Debug)]
    pub(super) struct Header {
        encoding: Encoding,
        elements: Vec<Element>,
        /// Lines up to and including `end_header`.
        lines: usize,
    }

    /// The `vertex` element's property at position `.0` in each record.
    #[derive(Clone, Copy, Debug)]
    pub(super) struct Column(usize);

    fn header_error(line: usize, reason: impl Into<String>) -> IoError {
        IoError::PlyHeader {
            line: Some(line),
            reason: reason.into(),
        }
    }

    fn read_error(source: std::io::Error) -> IoError {
        IoError::Io {
            operation: "read the file",
            source,
        }
    }

    impl Header {
        /// Reads the header from the start of `reader`, leaving it at the first element.
        pub(super) fn read(reader: &mut impl BufRead) -> Result<Self, IoError> {
            let mut encoding = None;
            let mut elements: Vec<Element> = Vec::new();
            let mut line = Vec::new();
            for number in 1..=MAX_HEADER_LINES {
                line.clear();
                if reader.read_until(b'\n', &mut line).map_err(read_error)? == 0 {
                    return Err(header_error(number, "the header has no end_header line"));
                }
                let text = String::from_utf8_lossy(&line);
                let words: Vec<&str> = text.split_ascii_whitespace().collect();
                match words.as_slice() {
                    ["ply"] if number == 1 => {}
                    _ if number == 1 => return Err(header_error(1, "not a ply file")),
                    ["end_header"] => {
                        let encoding =
                            encoding.ok_or_else(|| header_error(number, "no format line"))?;
                        return Ok(Self {
                            encoding,
                            elements,
                            lines: number,
                        });
                    }
                    ["format", format, _] => {
                        encoding = Some(match *format {
                            "ascii" => Encoding::Ascii,
                            "binary_little_endian" => Encoding::Little,
                            "binary_big_endian" => Encoding::Big,
                            _ => return Err(header_error(number, "unknown format")),
                        });
                    }
                    ["comment" | "obj_info", ..] | [] => {}
                    ["element", name, count] => elements.push(Element {
                        name: (*name).to_owned(),
                        count: count
                            .parse()
                            .map_err(|_| header_error(number, "invalid element count"))?,
                        properties: Vec::new(),
                    }),
                    ["property", "list", count, item, name] => {
                        let scalar = |t: &str| {
                            Scalar::parse(t)
                                .ok_or_else(|| header_error(number, "unknown property type"))
                        };
                        let kind = Kind::List {
                            count: scalar(count)?,
                            item: scalar(item)?,
                        };
                        push_property(&mut elements, number, name, kind)?;
                    }
                    ["property", kind, name] => {
                        let kind = Scalar::parse(kind)
                            .ok_or_else(|| header_error(number, "unknown property type"))?;
                        push_property(&mut elements, number, name, Kind::Scalar(kind))?;
                    }
                    _ => return Err(header_error(number, "unexpected line")),
                }
            }
            Err(header_error(
                MAX_HEADER_LINES,
                "the header has no end_header line",
            ))
        }

        fn vertex(&self) -> Option<&Element> {
            self.elements.iter().find(|e| e.name == "vertex")
        }

        /// The scalar property `name` of the `vertex` element.
        pub(super) fn vertex_scalar(&self, name: &str) -> Option<Column> {
            let vertex = self.vertex()?;
            vertex
                .properties
                .iter()
                .position(|p| p.name == name && matches!(p.kind, Kind::Scalar(_)))
                .map(Column)
        }

        /// The names of the scalar properties of the `vertex` element, in file order.
        pub(super) fn vertex_scalar_names(&self) -> Vec<&str> {
            self.vertex().map_or_else(Vec::new, |v| {
                v.properties
                    .iter()
                    .filter(|p| matches!(p.kind, Kind::Scalar(_)))
                    .map(|p| p.name.as_str())
                    .collect()
            })
        }

        /// Reads the elements from where [`Header::read`] left `reader` up to the end
        /// of the `vertex` element, and returns the values of `column`, one per vertex.
        pub(super) fn read_vertex_column(
            &self,
            reader: impl BufRead,
            column: Column,
        ) -> Result<Vec<f64>, IoError> {
            let mut values = Vec::new();
            match self.encoding {
                Encoding::Ascii => {
                    let mut tokens = Tokens {
                        reader,
                        line: String::new(),
                        position: 0,
                        number: self.lines,
                    };
                    for element in &self.elements {
                        let is_vertex = element.name == "vertex";
                        for index in 0..element.count {
                            for (k, property) in element.properties.iter().enumerate() {
                                let mut next = || {
                                    tokens.next(&element.name, index).and_then(|(t, line)| {
                                        t.parse::<f64>().map_err(|_| IoError::PlyData {
                                            line: Some(line),
                                            element: element.name.clone(),
                                            index,
                                            reason: format!("invalid number {t:?}"),
                                        })
                                    })
                                };
                                match property.kind {
                                    Kind::Scalar(_) => {
                                        let value = next()?;
                                        if is_vertex && k == column.0 {
                                            values.push(value);
                                        }
                                    }
                                    Kind::List { .. } => {
                                        let n = next()?;
                                        for _ in 0..n.max(0.0) as usize {
                                            next()?;
                                        }
                                    }
                                }
                            }
                        }
                        if is_vertex {
                            return Ok(values);
                        }
                    }
                }
                Encoding::Little | Encoding::Big => {
                    let mut reader = reader;
                    let mut buffer = [0u8; 8];
                    let truncated = |element: &str, index| IoError::Truncated {
                        element: element.to_owned(),
                        index,
                    };
                    for element in &self.elements {
                        let is_vertex = element.name == "vertex";
                        for index in 0..element.count {
                            for (k, property) in element.properties.iter().enumerate() {
                                let mut next = |t: Scalar| {
                                    let bytes = &mut buffer[..t.size()];
                                    reader
                                        .read_exact(bytes)
                                        .map(|()| t.decode(bytes, self.encoding))
                                        .map_err(|_| truncated(&element.name, index))
                                };
                                match property.kind {
                                    Kind::Scalar(t) => {
                                        let value = next(t)?;
                                        if is_vertex && k == column.0 {
                                            values.push(value);
                                        }
                                    }
                                    Kind::List { count, item } => {
                                        let n = next(count)?;
                                        for _ in 0..n.max(0.0) as usize {
                                            next(item)?;
                                        }
                                    }
                                }
                            }
                        }
                        if is_vertex {
                            return Ok(values);
                        }
                    }
                }
            }
            Err(IoError::MissingElement { element: "vertex" })
        }
    }

    fn push_property(
        elements: &mut [Element],
        line: usize,
        name: &str,
        kind: Kind,
    ) -> Result<(), IoError> {
        let element = elements
            .last_mut()
            .ok_or_else(|| header_error(line, "a property before any element"))?;
        element.properties.push(Property {
            name: name.to_owned(),
            kind,
        });
        Ok(())
    }

    /// The whitespace-separated words of an ascii body, with their line numbers.
    struct Tokens<R> {
        reader: R,
        line: String,
        position: usize,
        number: usize,
    }

    impl<R: BufRead> Tokens<R> {
        /// The next word and its line; running out is a truncated `element` `index`.
        fn next(&mut self, element: &str, index: usize) -> Result<(&str, usize), IoError> {
            loop {
                let rest = &self.line[self.position..];
                if let Some(start) = rest.find(|c: char| !c.is_ascii_whitespace()) {
                    let start = self.position + start;
                    let end = self.line[start..]
                        .find(|c: char| c.is_ascii_whitespace())
                        .map_or(self.line.len(), |e| start + e);
                    self.position = end;
                    return Ok((&self.line[start..end], self.number));
                }
                self.line.clear();
                self.position = 0;
                if self.reader.read_line(&mut self.line).map_err(read_error)? == 0 {
                    return Err(IoError::Truncated {
                        element: element.to_owned(),
                        index,
                    });
                }
                self.number += 1;
            }
        }
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        fn column(file: &[u8], name: &str) -> Result<Vec<f64>, IoError> {
            let mut reader = file;
            let header = Header::read(&mut reader)?;
            let column = header.vertex_scalar(name).expect("the property");
            header.read_vertex_column(reader, column)
        }

        #[test]
        fn ascii_and_binary_give_the_same_values() {
            let ascii = b"ply\nformat ascii 1.0\ncomment x\nelement camera 1\n\
                property list uchar int ids\nelement vertex 2\nproperty float x\n\
                property double q\nproperty uchar red\nelement face 0\n\
                property list uchar int vertex_indices\nend_header\n\
                3 7 8 9\n0.5 -1.25 200\n1 3e-4\n 7\n";
            assert_eq!(column(ascii, "q").unwrap(), [-1.25, 3e-4]);
            assert_eq!(column(ascii, "red").unwrap(), [200.0, 7.0]);
            let header = |format: &str| {
                format!(
                    "ply\nformat {format} 1.0\nelement vertex 2\nproperty short s\n\
                     property double q\nend_header\n"
                )
                .into_bytes()
            };
            let (mut little, mut big) =
                (header("binary_little_endian"), header("binary_big_endian"));
            for (s, q) in [(-3i16, -1.25f64), (4, 3e-4)] {
                little.extend(s.to_le_bytes());
                little.extend(q.to_le_bytes());
                big.extend(s.to_be_bytes());
                big.extend(q.to_be_bytes());
            }
            assert_eq!(column(&little, "q").unwrap(), [-1.25, 3e-4]);
            assert_eq!(column(&big, "q").unwrap(), [-1.25, 3e-4]);
            assert_eq!(column(&big, "s").unwrap(), [-3.0, 4.0]);
            // Cut inside the second vertex.
            let cut = &little[..little.len() - 3];
            assert!(matches!(
                column(cut, "q"),
                Err(IoError::Truncated { index: 1, .. })
            ));
        }

        #[test]
        fn names_list_the_scalar_vertex_properties() {
            let file = b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n\
                property list uchar int l\nproperty float r\nend_header\n";
            let header = Header::read(&mut &file[..]).unwrap();
            assert_eq!(header.vertex_scalar_names(), ["x", "r"]);
            assert!(header.vertex_scalar("l").is_none());
        }
    }
}
