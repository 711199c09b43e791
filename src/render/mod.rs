//! From geometry to pixels: sampling, camera rays, materials, the path
//! tracing integrator, the film, tiles over threads, and image output.
