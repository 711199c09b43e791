//! Loading Wavefront OBJ meshes (and their MTL materials) into [`MeshData`].

use std::path::Path;

use super::MeshData;

/// A loaded mesh with the non-fatal problems found while loading it
/// (missing MTL, missing texture files: each replaced by a fallback).
pub struct LoadedObj {
    pub mesh: MeshData,
    pub warnings: Vec<String>,
}

/// Why an OBJ file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    #[error("cannot read `{path}`: {message}")]
    Io { path: String, message: String },
    #[error("cannot parse `{path}`: {message}")]
    Parse { path: String, message: String },
    #[error("`{path}` has no faces")]
    Empty { path: String },
    #[error("`{path}` has a vertex that is not a finite number")]
    NonFinite { path: String },
}

/// Loads the OBJ file at `path`, triangulating polygons.
pub fn load_obj(path: &Path) -> Result<LoadedObj, ObjError> {
    Err(ObjError::Io {
        path: path.display().to_string(),
        message: "OBJ loading is not implemented yet".into(),
    })
}
