//! Scene files: a world written in TOML (docs/scene-files.md is the schema), loaded into the
//! engine's own types so that the command line, Python and a Rust game share one loader, and
//! a world written back out ([`export`]) so that loading it gives bitwise the same trajectory.
//!
//! Every error is an [`Error::SceneFile`] naming the file, the line (from the TOML parser's
//! spans), the field as a path (`particles[2].mass`) and what was expected.

mod doc;
mod read;
mod solids;
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
/// Only a regular file is read (a symbolic link is followed to one): a device (`/dev/zero`),
/// a FIFO or a directory is refused before it is opened, so that neither an endless read nor
/// a blocking open can happen, and no more than [`MAX_FILE_BYTES`] + 1 bytes are ever read
/// (a file that grows after the check is still cut off).
///
/// # Errors
/// [`Error::SceneFile`] naming the file (line 0) when it cannot be read, is not a regular
/// file, is larger than [`MAX_FILE_BYTES`] or is not UTF-8; otherwise as [`parse`].
pub fn load(path: &std::path::Path) -> Result<SceneFile> {
    use std::io::Read;
    let file = path.display().to_string();
    let fail =
        |reason: String| Error::SceneFile { file: file.clone(), line: 0, field: String::new(), reason };
    let cannot = |e: std::io::Error| fail(format!("cannot be read: {e}"));
    let regular = |meta: &std::fs::Metadata| {
        if meta.is_file() {
            return Ok(());
        }
        let kind = if meta.is_dir() { "a directory" } else { "a device, a FIFO or a socket" };
        Err(fail(format!("is {kind}, not a regular file")))
    };
    let too_large = |size: String| fail(format!("is {size} bytes: must be at most {MAX_FILE_BYTES}"));
    // metadata() follows symbolic links: the check is on what open() would reach.
    let meta = std::fs::metadata(path).map_err(cannot)?;
    regular(&meta)?;
    if meta.len() > MAX_FILE_BYTES {
        return Err(too_large(meta.len().to_string()));
    }
    let handle = std::fs::File::open(path).map_err(cannot)?;
    // The file opened may not be the one checked (replaced in between): checked again.
    let opened = handle.metadata().map_err(cannot)?;
    regular(&opened)?;
    let mut bytes = Vec::with_capacity(usize::try_from(opened.len().min(MAX_FILE_BYTES)).unwrap_or(0));
    handle.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes).map_err(cannot)?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(too_large(format!("more than {MAX_FILE_BYTES}")));
    }
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
    read::scene(&doc::Doc { file, text, restoring: false }, None)
}

/// [`parse`] with the game loop's variant `mode` in place of the text's own: a world rebuilt
/// from its [`structure`] under another loop (its snapshot then restored).
///
/// # Errors
/// As [`parse`].
pub fn parse_with_loop(text: &str, file: &str, mode: crate::clock::LoopMode) -> Result<SceneFile> {
    read::scene(&doc::Doc { file, text, restoring: false }, Some(mode))
}

/// [`parse_with_loop`] of a world's own [`structure`], to restore its snapshot onto (a pickle,
/// a copy under another loop): the balls are taken where the run left them. A run leaves
/// touching balls a rounding closer than their radii (a settled pile: about 1e-7 of a radius),
/// a ball that has just landed deeper for a step, and a ball on a wall a rounding past it,
/// which a scene file's balls may not be ([`World::add_ball`] refuses them): here neither
/// the overlap nor the walls are checked; every other check is as [`parse`]'s.
///
/// # Errors
/// As [`parse`], but for the balls' overlap and walls.
pub fn parse_structure(text: &str, file: &str, mode: crate::clock::LoopMode) -> Result<SceneFile> {
    read::scene(&doc::Doc { file, text, restoring: true }, Some(mode))
}
