//! Pictures as measurements: loading rendered or reference images into one
//! linear RGB type, metrics between two of them, a false-colour difference
//! image and log-log plots of error curves (SVG, by plotters). Used by `rtlang compare`, the
//! image tests and the benchmarks.

pub mod diff;
pub mod linear;
pub mod metrics;
pub mod plot;

pub use diff::difference_image;
pub use linear::{LinearImage, PictureError};
pub use metrics::{compare, Metrics};
pub use plot::{LogLogPlot, Series};
