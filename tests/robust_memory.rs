//! The memory budget: for every allocation whose size a
//! scene controls (tessellated revolutions, analytic shells, `repeat`
//! counts, media, meshes placed many times, light lists, texture images and
//! the film), the largest scene that the estimate accepts under
//! `--memory-budget` renders inside an address space of the budget plus a
//! fixed allowance for the program itself (set with `prlimit --as`, so an
//! estimate too low shows as an allocation failure), and one step more is
//! refused before rendering, with the estimate and the budget in the
//! message. Every scene's 8×8 image charges its film too, and every scene
//! file (and OBJ file) its text.

use std::process::{Command, Output};

mod support;
use support::scratch;

const RTLANG: &str = env!("CARGO_BIN_EXE_rtlang");
/// The budget the tests give: 0.25 GiB.
const BUDGET_GIB: &str = "0.25";
const BUDGET: f64 = (1u64 << 28) as f64;
/// Address space for the program beside its budget: code, libraries, the
/// thread's stack, the parsed scene and the allocator's own reserve.
const ALLOWANCE: u64 = 192 << 20;
/// The estimate's figures (src/lang/eval/budget.rs, docs/language.md).
const BYTES_PER_PRIMITIVE: f64 = 1024.0;
const BYTES_PER_TRIANGLE: f64 = 400.0;
const BYTES_PER_LIGHT: f64 = 1024.0;
const BYTES_PER_SHELL: f64 = 1024.0;
const BYTES_PER_IMAGE_PIXEL: f64 = 32.0;
const BYTES_PER_FILM_PIXEL: f64 = 128.0;
const BYTES_PER_SOURCE_BYTE: f64 = 40.0;
const BYTES_PER_OBJ_BYTE: f64 = 32.0;
/// The film of the tests' 8×8 image.
const FILM: f64 = 64.0 * BYTES_PER_FILM_PIXEL;

/// Renders `scene` (an 8×8 image, 1 sample, 1 thread) under the test budget
/// and an address-space limit of budget + allowance.
fn render_capped(name: &str, scene: &str) -> Output {
    render_in(&scratch::folder(&format!("memory-{name}")), scene)
}

/// Renders `scene` as [`render_capped`] does, in `dir`.
fn render_in(dir: &std::path::Path, scene: &str) -> Output {
    let dir = dir.to_path_buf();
    let size = if scene.contains("render {") { "" } else { SIZE };
    let path = scratch::write(&dir, "scene.rt", &format!("{size}{scene}"));
    let limit = BUDGET as u64 + ALLOWANCE;
    Command::new("prlimit")
        .arg(format!("--as={limit}"))
        .arg(RTLANG)
        .args(["render", path.to_str().expect("utf-8 path")])
        .args(["-o", dir.join("out.png").to_str().expect("utf-8 path")])
        .args(["--spp", "1", "--threads", "1"])
        .args(["--quiet", "--memory-budget", BUDGET_GIB])
        .output()
        .expect("runs prlimit (util-linux)")
}

fn assert_rendered(name: &str, out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{name} under its budget: {err}");
}

fn assert_refused(name: &str, out: &Output) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{name} over its budget: {err}");
    assert!(err.contains("rtlang::memory-budget"), "{name}: {err}");
    assert!(err.contains("the scene would need about"), "{name}: {err}");
    assert!(
        err.contains("256.0 MiB"),
        "{name}: the budget is not named: {err}"
    );
}

/// The tests' image size, unless a scene sets its own (the film test).
const SIZE: &str = "render { size 8 x 8 }\n";
const CAMERA: &str = "camera { from (0, 1, 5) at (0, 0.5, 0) }\n";
const GREY: &str = "lambertian(rgb(0.5, 0.5, 0.5))";

/// The charge of a scene file's text as [`render_in`] writes it.
fn text(scene: &str) -> f64 {
    let size = if scene.contains("render {") {
        0
    } else {
        SIZE.len()
    };
    (size + scene.len()) as f64 * BYTES_PER_SOURCE_BYTE
}

/// The largest `n` whose estimate, `charge(n)` beside the text of
/// `scene(n)`, fits the budget (both grow with `n`).
fn largest(charge: impl Fn(u64) -> f64, scene: impl Fn(u64) -> String) -> u64 {
    let fits = |n: u64| charge(n) + text(&scene(n)) <= BUDGET;
    let (mut low, mut high) = (0, 1);
    while fits(high) {
        (low, high) = (high, high * 2);
    }
    while high - low > 1 {
        let mid = (low + high) / 2;
        if fits(mid) {
            low = mid;
        } else {
            high = mid;
        }
    }
    low
}

/// Renders the largest accepted `scene(n)` and refuses `scene(n + 1)`, for
/// a scene whose objects are charged `charge(n)`.
fn largest_renders(name: &str, charge: impl Fn(u64) -> f64, scene: impl Fn(u64) -> String) {
    let largest = largest(charge, &scene);
    assert!(largest > 0, "{name}: nothing fits");
    assert_rendered(name, &render_capped(name, &scene(largest)));
    let over = format!("{name}-over");
    assert_refused(name, &render_capped(&over, &scene(largest + 1)));
}

fn revolve(resolution: u64, mode: &str) -> String {
    format!(
        "revolve bezier [(0.5, 0), (1.5, 0.5), (0.2, 1)] {{\n\
         material {GREY}\n  mode {mode}\n  resolution {resolution}\n}}\n"
    )
}

#[test]
fn the_largest_accepted_tessellated_revolution_renders_under_its_budget() {
    // 2·r² triangles.
    let charge = |r: u64| FILM + 2.0 * (r * r) as f64 * BYTES_PER_TRIANGLE;
    largest_renders("revolve", charge, |r| {
        format!("{CAMERA}{}", revolve(r, "mesh"))
    });
}

#[test]
fn the_most_analytic_shells_accepted_render_under_their_budget() {
    // The language allows 100000 pieces a revolution; copies reach the budget.
    let each = 100_000.0 * BYTES_PER_SHELL + BYTES_PER_PRIMITIVE;
    largest_renders(
        "shells",
        |n| FILM + n as f64 * each,
        |n| {
            format!(
                "{CAMERA}repeat i in 0..{n} {{\n{}}}\n",
                revolve(100_000, "analytic")
                    .replace("resolution", "translate (i * 0.01, 0, 0)\n  resolution")
            )
        },
    );
}

fn spheres(count: u64, material: &str) -> String {
    format!(
        "{CAMERA}repeat i in 0..{count} {{\n\
         sphere {{ center (i * 1e-4, 0, 0) radius 0.5 material {material} }}\n}}\n"
    )
}

#[test]
fn the_largest_accepted_repeat_renders_under_its_budget() {
    let charge = |n: u64| FILM + n as f64 * BYTES_PER_PRIMITIVE;
    largest_renders("repeat", charge, |n| spheres(n, GREY));
}

#[test]
fn the_longest_accepted_light_list_renders_under_its_budget() {
    // Every sphere emits: one light entry each, sampled (the default `nee`).
    let charge = |n: u64| FILM + n as f64 * BYTES_PER_PRIMITIVE;
    largest_renders("lights", charge, |n| spheres(n, "light(rgb(1, 1, 1))"));
}

#[test]
fn the_most_accepted_media_render_under_their_budget() {
    // The medium and its boundary are each charged as a primitive.
    let charge = |n: u64| FILM + n as f64 * 2.0 * BYTES_PER_PRIMITIVE;
    largest_renders("media", charge, |n| {
        format!(
            "{CAMERA}repeat i in 0..{n} {{\n\
             medium {{ boundary sphere {{ center (i * 1e-4, 0, 0) radius 0.5 }} density 0.1 color rgb(1, 1, 1) }}\n}}\n"
        )
    });
}

/// An OBJ strip of `2 · quads` triangles.
fn strip(quads: u64) -> String {
    let mut obj = String::new();
    for i in 0..=quads {
        let x = i as f64 / quads as f64;
        obj += &format!("v {x} 0 0\nv {x} 1 0\n");
    }
    for i in 0..quads {
        let a = 2 * i + 1;
        obj += &format!(
            "f {a} {} {}\nf {} {} {}\n",
            a + 2,
            a + 1,
            a + 1,
            a + 2,
            a + 3
        );
    }
    obj
}

#[test]
fn the_most_accepted_emitting_mesh_copies_render_under_their_budget() {
    // Each placement is charged its triangles and, since the mesh emits,
    // a light entry (with its light-tree share) for each.
    const QUADS: u64 = 1000;
    let dir = scratch::folder("memory-mesh");
    let text = strip(QUADS);
    let obj = scratch::write(&dir, "strip.obj", &text);
    // The file is charged once as it is loaded, its triangles per placement.
    let loading = text.len() as f64 * BYTES_PER_OBJ_BYTE;
    let each = 2.0 * QUADS as f64 * (BYTES_PER_TRIANGLE + BYTES_PER_LIGHT);
    let scene = |n: u64| {
        format!(
            "{CAMERA}repeat i in 0..{n} {{\n\
             mesh \"{}\" {{ material light(rgb(1, 1, 1)) translate (0, 0, -i * 1e-3) }}\n}}\n",
            obj.display()
        )
    };
    let largest = largest(|n| FILM + loading + n as f64 * each, scene);
    assert_rendered("mesh", &render_in(&dir, &scene(largest)));
    assert_refused("mesh", &render_in(&dir, &scene(largest + 1)));
}

#[test]
fn the_largest_accepted_texture_image_renders_under_its_budget() {
    let dir = scratch::folder("memory-image");
    let png = |side: u64| dir.join(format!("{side}.png"));
    let scene = |side: u64| {
        format!(
            "{CAMERA}rect xy {{ from (-1, 0) to (1, 2) at 0 material lambertian(image(\"{}\")) }}\n",
            png(side).display()
        )
    };
    let pixels = |side: u64| (side * side) as f64 * BYTES_PER_IMAGE_PIXEL;
    let side = largest(|s| FILM + BYTES_PER_PRIMITIVE + pixels(s), scene);
    for s in [side, side + 1] {
        image::RgbImage::from_pixel(s as u32, s as u32, image::Rgb([90, 120, 200]))
            .save(png(s))
            .expect("writes the texture");
    }
    assert_rendered("image", &render_in(&dir, &scene(side)));
    assert_refused("image", &render_in(&dir, &scene(side + 1)));
}

#[test]
fn the_largest_accepted_film_renders_under_its_budget() {
    let charge = |w: u64| BYTES_PER_PRIMITIVE + (w * w) as f64 * BYTES_PER_FILM_PIXEL;
    largest_renders("film", charge, |w| {
        format!("render {{ size {w} x {w} }}\n{CAMERA}sphere {{ radius 0.5 material {GREY} }}\n")
    });
}
