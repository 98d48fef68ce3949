//! Errors of `beltrami-algorithms`, and the input checks the algorithms share.

use beltrami_halfedge::{DVec3, HalfedgeMesh, TopologyError};

/// A problem with an algorithm's input, found by the checks every algorithm of this crate
/// makes first ([`check_mesh`], [`check_finite`]). Each algorithm's error has a variant
/// of the same name and fields for it (see [`algorithm_error!`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum InputProblem {
    /// The positions slice does not have one position per vertex.
    PositionCount { positions: usize, vertices: usize },
    /// A face is not a triangle (the first one, by index).
    NotTriangle { face: usize, len: usize },
    /// A position is NaN or infinite (the first one, by index).
    NonFinite { vertex: usize },
}

/// Checks that `positions` has one position per vertex of `mesh` and that every face of
/// `mesh` is a triangle, in this order.
pub(crate) fn check_mesh(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<(), InputProblem> {
    if positions.len() != mesh.n_vertices() {
        return Err(InputProblem::PositionCount {
            positions: positions.len(),
            vertices: mesh.n_vertices(),
        });
    }
    if let Some(f) = mesh.faces().find(|&f| mesh.face_valence(f) != 3) {
        return Err(InputProblem::NotTriangle {
            face: f.index(),
            len: mesh.face_valence(f),
        });
    }
    Ok(())
}

/// Checks that every position is finite.
pub(crate) fn check_finite(positions: &[DVec3]) -> Result<(), InputProblem> {
    match positions.iter().position(|p| !p.is_finite()) {
        Some(vertex) => Err(InputProblem::NonFinite { vertex }),
        None => Ok(()),
    }
}

/// Declares the error enum of an algorithm that takes a triangle mesh, its positions and
/// options: the variants every such algorithm shares (`NotTriangle`, `PositionCount`,
/// `NonFinite`, `Options`), then the algorithm's own, and the conversion from an
/// [`InputProblem`]. `for "…"` names the algorithm in the `NotTriangle` message
/// ("face 3 has 4 vertices; remeshing needs a triangle mesh"). With `mesh only`, the
/// enum gets the mesh's variants (`NotTriangle`, `PositionCount`) and no conversion: for
/// an algorithm without options that reads no position value (subdivision).
macro_rules! algorithm_error {
    (
        $(#[$meta:meta])*
        pub enum $name:ident for $what:literal {
            $($own:tt)*
        }
    ) => {
        $crate::error::algorithm_error! {
            mesh only
            $(#[$meta])*
            pub enum $name for $what {
                /// A position is NaN or infinite.
                #[error("vertex {vertex} has a non-finite position")]
                NonFinite {
                    /// The vertex index.
                    vertex: usize,
                },
                /// An option is out of its range.
                #[error("invalid option: {reason}")]
                Options {
                    /// The problem in words.
                    reason: String,
                },
                $($own)*
            }
        }

        impl From<$crate::error::InputProblem> for $name {
            fn from(problem: $crate::error::InputProblem) -> Self {
                use $crate::error::InputProblem as P;
                match problem {
                    P::PositionCount { positions, vertices } => {
                        Self::PositionCount { positions, vertices }
                    }
                    P::NotTriangle { face, len } => Self::NotTriangle { face, len },
                    P::NonFinite { vertex } => Self::NonFinite { vertex },
                }
            }
        }
    };
    (
        mesh only
        $(#[$meta:meta])*
        pub enum $name:ident for $what:literal {
            $($own:tt)*
        }
    ) => {
        $(#[$meta])*
        pub enum $name {
            /// A face is not a triangle; the algorithm needs a triangle mesh.
            #[error("face {face} has {len} vertices; {what} needs a triangle mesh", what = $what)]
            NotTriangle {
                /// The face index (0-based, in mesh order).
                face: usize,
                /// The number of vertices it has.
                len: usize,
            },
            /// The positions slice does not have one position per vertex.
            #[error("{positions} positions were given for a mesh of {vertices} vertices")]
            PositionCount {
                /// The length of the positions slice.
                positions: usize,
                /// The number of vertices of the mesh.
                vertices: usize,
            },
            $($own)*
        }
    };
}
pub(crate) use algorithm_error;

/// A count for a message: the number, or "more than 18446744073709551614" where it was
/// saturated at `u64::MAX`.
fn count_text(count: u64) -> String {
    if count == u64::MAX {
        format!("more than {}", u64::MAX - 1)
    } else {
        count.to_string()
    }
}

algorithm_error! {
    mesh only
    /// Why a mesh could not be subdivided. Every variant names the offending element or
    /// count.
    #[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
    #[non_exhaustive]
    pub enum SubdivisionError for "subdivision" {
        /// The result would have more elements than a mesh can hold.
        #[error(
            "{steps} steps of {scheme} subdivision would make {} {kind}; a mesh holds at most {max}",
            count_text(*count)
        )]
        TooLarge {
            /// The scheme's name (`"loop"` or `"sqrt3"`).
            scheme: &'static str,
            /// The number of steps asked for.
            steps: usize,
            /// `"vertices"`, `"halfedges"` or `"faces"`.
            kind: &'static str,
            /// How many there would be (saturated at `u64::MAX`).
            count: u64,
            /// The largest supported count.
            max: usize,
        },
        /// The subdivided faces did not build into a mesh. Subdividing a valid mesh always
        /// gives a valid one, so this is a defect of this crate, reported rather than
        /// panicking.
        #[error("the subdivided mesh did not build: {0}")]
        Topology(#[from] TopologyError),
    }
}

algorithm_error! {
    /// Why [`delaunay_flip`](crate::delaunay_flip) could not run. Every variant names the
    /// offending element or value.
    #[derive(Debug, Clone, PartialEq, thiserror::Error)]
    #[non_exhaustive]
    pub enum DelaunayError for "Delaunay flipping" {
        /// A flip the checks allowed was refused, or the result did not convert back to a
        /// mesh: a defect of this crate, reported rather than panicking.
        #[error("the flipped mesh is not valid: {0}")]
        Edit(#[from] beltrami_halfedge::EditError),
        /// The input or the result did not convert between the frozen and the editable
        /// mesh.
        #[error("{0}")]
        Topology(#[from] TopologyError),
        /// Measuring the change of the surface failed (a defect: the positions are finite).
        #[error("measuring the deviation: {0}")]
        Metrics(#[from] beltrami_metrics::MetricsError),
    }
}

/// `x` with six significant digits, for messages (see
/// [`short_number`](beltrami_halfedge::short_number)).
pub(crate) fn short(x: f64) -> String {
    beltrami_halfedge::short_number(x)
}

/// "about N triangles" for an estimated count of triangles, in scientific notation, or
/// "more triangles than can be counted" when the estimate overflowed.
pub(crate) fn about_count(predicted: f64) -> String {
    if predicted.is_finite() {
        format!("about {predicted:.2e} triangles")
    } else {
        "more triangles than can be counted".to_string()
    }
}

#[cfg(test)]
mod short_tests {
    use super::*;

    #[test]
    fn triangle_counts_in_messages() {
        assert_eq!(
            about_count(f64::INFINITY),
            "more triangles than can be counted"
        );
        assert_eq!(about_count(1.5e9), "about 1.50e9 triangles");
    }
}
