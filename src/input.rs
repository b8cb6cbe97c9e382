//! Bounded reading of a user's input file (meshes, `.gbp` patches, the command line's point lists
//! and grids): the path must be a regular file (not a directory, device or FIFO, which could be
//! read without end), and at most [`MAX_INPUT_BYTES`] are read. The mesh and `.gbp` readers wrap
//! [`InputError`] in their own error types.

use crate::limits::MAX_INPUT_BYTES;
use std::io::Read;
use std::path::Path;

/// Why an input file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// The path is not a regular file.
    #[error("{path} is not a regular file")]
    NotAFile { path: String },
    /// The file is larger than [`MAX_INPUT_BYTES`].
    #[error("{path} is larger than the limit of {limit} bytes")]
    TooLarge { path: String, limit: u64 },
    /// Opening or reading failed.
    #[error("i/o error on {path}: {source}")]
    Io { path: String, source: std::io::Error },
}

/// The bytes of the regular file at `path`, at most [`MAX_INPUT_BYTES`] of them.
pub fn read_input(path: impl AsRef<Path>) -> Result<Vec<u8>, InputError> {
    let path = path.as_ref();
    let name = || path.display().to_string();
    let io = |source| InputError::Io { path: name(), source };
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.is_file() {
        return Err(InputError::NotAFile { path: name() });
    }
    let too_large = || InputError::TooLarge { path: name(), limit: MAX_INPUT_BYTES };
    if meta.len() > MAX_INPUT_BYTES {
        return Err(too_large());
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(meta.len().min(MAX_INPUT_BYTES) as usize);
    file.take(MAX_INPUT_BYTES + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(too_large()); // the file grew while being read
    }
    Ok(bytes)
}
