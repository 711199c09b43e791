//! The page, embedded in the binary: plain HTML, CSS and JavaScript with no
//! build step, no framework and nothing fetched from elsewhere.

pub const INDEX: &str = include_str!("page/index.html");
pub const SCRIPT: &str = include_str!("page/app.js");
pub const STYLE: &str = include_str!("page/style.css");
