//! Scene files: a world written in TOML (docs/scene-files.md is the schema), loaded into the
//! engine's own types so that the command line, Python and a Rust game share one loader, and
//! a world written back out ([`export`]) so that loading it gives bitwise the same trajectory.
//!
//! Every error is an [`Error::SceneFile`] naming the file, the line (from the TOML parser's
//! spans), the field as a path (`particles[2].mass`) and what was expected.

mod doc;
mod read;
mod read_parts;
mod write;

use crate::error::{Error, Result};
use crate::world::World;

pub use write::{export, structure};

/// The largest scene file read, bytes (a file is read whole before it is parsed).
pub const MAX_FILE_BYTES: u64 = 64 << 20;

/// A loaded scene file: its world at t = 0 and the run length it asks for.
#[derive(Debug, Clone)]
pub struct SceneFile {
    /// The world, as the file describes it.
    pub world: World,
    /// `until`, s, when the file gives one.
    pub until: Option<f64>,
}

/// Loads the scene file at `path`.
///
/// # Errors
/// [`Error::SceneFile`] naming the file (line 0) when it cannot be read, is larger than
/// [`MAX_FILE_BYTES`] or is not UTF-8; otherwise as [`parse`].
pub fn load(path: &std::path::Path) -> Result<SceneFile> {
    let file = path.display().to_string();
    let fail =
        |reason: String| Error::SceneFile { file: file.clone(), line: 0, field: String::new(), reason };
    let meta = std::fs::metadata(path).map_err(|e| fail(format!("cannot be read: {e}")))?;
    if meta.len() > MAX_FILE_BYTES {
        return Err(fail(format!("is {} bytes: must be at most {MAX_FILE_BYTES}", meta.len())));
    }
    let bytes = std::fs::read(path).map_err(|e| fail(format!("cannot be read: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|_| fail("is not UTF-8 text".into()))?;
    parse(&text, &file)
}

/// Parses scene-file `text`; `file` names it in errors.
///
/// # Errors
/// [`Error::SceneFile`] with the line and field of the first problem: not TOML, an
/// unknown key, a value of the wrong type or out of range (as the engine's checks say), a
/// particle index that does not exist, a mesh that is not closed.
pub fn parse(text: &str, file: &str) -> Result<SceneFile> {
    read::scene(&doc::Doc { file, text }, None)
}

/// [`parse`] with the game loop's variant `mode` in place of the text's own: a world rebuilt
/// from its [`structure`] under another loop (its snapshot then restored).
///
/// # Errors
/// As [`parse`].
pub fn parse_with_loop(text: &str, file: &str, mode: crate::clock::LoopMode) -> Result<SceneFile> {
    read::scene(&doc::Doc { file, text }, Some(mode))
}
