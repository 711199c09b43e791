//! Code shared by the robustness tests and the fuzz targets.
#![allow(dead_code)]

pub mod blocks;
pub mod defines;
pub mod gen;
pub mod lsp;
pub mod pipeline;
pub mod render;
pub mod scratch;
