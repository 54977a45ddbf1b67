//! The order of TNNMG's nonlinear block Gauss–Seidel sweeps ([`SmootherOrder`]): a choice of
//! this crate's solvers, over the colouring of `rsf-ranks` ([`Colouring`](rsf_ranks::Colouring)).

use crate::error::{Error, Result};
use rsf_nonsmooth::ProblemError;

/// The order in which a nonlinear block Gauss–Seidel sweep visits the nodes.
///
/// With the `serde` feature it reads and writes as its [`Display`](std::fmt::Display)
/// names (`"lexicographic"`, `"multicolour"`, `"red-black-chunks"`; `"multicolor"` is read
/// too), as in scene files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum SmootherOrder {
    /// Node by node in increasing index order (decreasing for a backward sweep): the
    /// classical sweep and the default; sequential, and its iterates are those of every
    /// trajectory computed before this option existed.
    #[default]
    Lexicographic,
    /// Colour by colour ([`Colouring`](rsf_ranks::Colouring), greedy, computed once at set-up from the pattern);
    /// within a colour the nodes are independent and are updated in parallel with the
    /// solver's [`Parallelism`](crate::Parallelism). Each node's update is the same
    /// arithmetic whatever the thread count, so the iterates are bit-identical for 1, 2, …
    /// threads; they differ from [`Lexicographic`](Self::Lexicographic) ones (another
    /// Gauss–Seidel order, the same minimiser). The linear multigrid's smoothers stay
    /// lexicographic and sequential.
    #[cfg_attr(feature = "serde", serde(rename = "multicolour", alias = "multicolor"))]
    MultiColour,
    /// Red–black chunks: the fine node graph's breadth-first levels (from a
    /// pseudo-peripheral node, a function of the pattern alone) grouped into 2, 4, 8 or
    /// 16 chunks of consecutive levels and nearly equal node counts, each coupled only to
    /// the chunk before and after it; a forward sweep visits the even chunks, then the odd
    /// ones, each chunk in increasing node order, and a backward sweep the reverse. The
    /// chunks of one colour are
    /// independent and run in parallel on the solver's
    /// [`Parallelism`](crate::Parallelism); inside a chunk the sweep reads the couplings
    /// once, as the lexicographic sweep does (half the matrix traffic of a node colouring,
    /// which reads every row in full). Used by the nonlinear sweeps and by the linear
    /// multigrid's fine-level smoother (the coarse levels stay lexicographic), and for the
    /// residuals after them. One fixed Gauss–Seidel order: bit-identical for every thread
    /// count; other iterates than [`Lexicographic`](Self::Lexicographic) ones (the same
    /// minimiser).
    RedBlackChunks,
}

impl std::fmt::Display for SmootherOrder {
    /// `lexicographic`, `multicolour` or `red-black-chunks`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Lexicographic => "lexicographic",
            Self::MultiColour => "multicolour",
            Self::RedBlackChunks => "red-black-chunks",
        })
    }
}

impl std::str::FromStr for SmootherOrder {
    type Err = Error;

    /// `lexicographic`, `multicolour` (also `multicolor`) or `red-black-chunks`.
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "lexicographic" => Ok(Self::Lexicographic),
            "multicolour" | "multicolor" => Ok(Self::MultiColour),
            "red-black-chunks" => Ok(Self::RedBlackChunks),
            _ => Err(ProblemError::InvalidOption(format!(
                "smoother order `{s}`: expected lexicographic, multicolour or red-black-chunks"
            ))
            .into()),
        }
    }
}
