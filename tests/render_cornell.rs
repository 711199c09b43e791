//! The Cornell box built in code renders the seed's picture: green wall on
//! the left, red on the right, a bright ceiling light, no dropped samples.
//! Set RTLANG_RENDER_OUT to a .png path to keep the picture for a look.

mod support;

use glam::Vec3;
use rtlang::render::output::write_image;
use rtlang::render::scenes::cornell_box;

#[test]
fn cornell_box_has_its_walls_on_the_seed_sides() {
    let size = std::env::var("RTLANG_RENDER_SIZE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(64);
    let spp = std::env::var("RTLANG_RENDER_SPP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(32);
    let out = support::render::as_set(&cornell_box(size, spp));
    if let Ok(path) = std::env::var("RTLANG_RENDER_OUT") {
        write_image(path.as_ref(), out.width, out.height, &out.pixels).expect("writes");
    }
    eprintln!("{:?}", out.stats);
    assert_eq!(out.stats.dropped, 0);
    let region = |x0: u32, x1: u32, y0: u32, y1: u32| {
        let mut sum = Vec3::ZERO;
        for y in y0..y1 {
            for x in x0..x1 {
                sum += out.pixels[(y * size + x) as usize];
            }
        }
        sum / ((x1 - x0) * (y1 - y0)) as f32
    };
    let left = region(3, 8, 20, 44);
    let right = region(56, 61, 20, 44);
    assert!(left.y > 2.0 * left.x, "left wall should be green: {left}");
    assert!(right.x > 2.0 * right.y, "right wall should be red: {right}");
    let light = region(29, 35, 9, 10);
    assert!(light.min_element() > 5.0, "ceiling light: {light}");
}
