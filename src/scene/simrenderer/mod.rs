//! SIMRenderer's scene format (the keyword-block files of the course's Java ray tracer that
//! students complete, as its public lab sources read them): its lexical rules ([`lex`]),
//! and reading a file into a [`crate::scene::Scene`] ([`parse`], `read.rs`). The format
//! and its mapping to lumiere are documented in docs/simrenderer.md.

pub mod lex;
mod read;

pub use read::{
    DEFAULT_SEED, Options, PIXEL_COORDINATES, Parsed, REFLEXION_ALGORITHMS, TOP_BLOCKS, canonical, grey_default, load,
    parse, shading_of,
};

/// Something the reader did or met that the user should know: an error it went past under
/// `lenient` (saying what it did instead), or a surprise SIMRenderer accepts silently.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{column}: {field}: {message}")]
pub struct Warning {
    pub file: String,
    pub line: usize,
    pub column: usize,
    /// `block.keyword`, as the file writes them.
    pub field: String,
    pub message: String,
}
