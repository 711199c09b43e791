//! The procedural textures: deterministic from their seed, seamless in u,
//! plausible in content, and identical to the committed files in textures/.

use rtlang::gen::canvas::Canvas;
use rtlang::gen::earth::{earth, EarthOptions};
use rtlang::gen::png_bytes;
use rtlang::gen::porcelain::{porcelain, PorcelainOptions};

/// Mean absolute difference (0–255 scale) between columns `a` and `b`.
fn column_difference(c: &Canvas, a: u32, b: u32) -> f64 {
    let sum: f64 = (0..c.height)
        .map(|y| {
            let row = (y * c.width) as usize;
            let d = c.pixels[row + a as usize] - c.pixels[row + b as usize];
            d.abs().element_sum() / 3.0
        })
        .sum();
    sum / c.height as f64 * 255.0
}

/// Mean difference between neighbouring columns over the whole image.
fn mean_neighbour_difference(c: &Canvas) -> f64 {
    (0..c.width - 1)
        .map(|x| column_difference(c, x, x + 1))
        .sum::<f64>()
        / (c.width - 1) as f64
}

fn small_porcelain(seed: u64) -> Canvas {
    porcelain(PorcelainOptions {
        width: 256,
        height: 128,
        seed,
    })
}

fn small_earth(seed: u64) -> Canvas {
    earth(EarthOptions {
        width: 256,
        height: 128,
        seed,
    })
}

#[test]
fn porcelain_is_deterministic_and_seed_dependent() {
    let a = png_bytes(&small_porcelain(5)).expect("encodes");
    let b = png_bytes(&small_porcelain(5)).expect("encodes");
    let c = png_bytes(&small_porcelain(6)).expect("encodes");
    assert_eq!(a, b, "same seed must give identical PNG bytes");
    assert_ne!(a, c, "a different seed must give a different texture");
}

#[test]
fn earth_is_deterministic_and_seed_dependent() {
    let a = small_earth(5);
    let b = small_earth(5);
    let c = small_earth(6);
    assert_eq!(a.to_rgb8(), b.to_rgb8());
    assert_ne!(a.to_rgb8(), c.to_rgb8());
}

#[test]
fn textures_are_seamless_in_u() {
    for (name, canvas) in [
        ("porcelain", porcelain(PorcelainOptions::default())),
        ("earth", earth(EarthOptions::default())),
    ] {
        let seam = column_difference(&canvas, 0, canvas.width - 1);
        let typical = mean_neighbour_difference(&canvas);
        assert!(
            seam < 3.0 * typical + 1.0,
            "{name}: seam difference {seam:.2} vs typical neighbour difference {typical:.2}"
        );
        // The check can fail: two far-apart columns differ much more.
        let far = column_difference(&canvas, 0, canvas.width / 3);
        assert!(far > seam, "{name}: far columns {far:.2} vs seam {seam:.2}");
    }
}

#[test]
fn porcelain_is_mostly_ivory_glaze_with_coloured_motifs() {
    let c = porcelain(PorcelainOptions::default());
    let n = c.pixels.len() as f64;
    let glaze = c.pixels.iter().filter(|p| p.min_element() > 0.85).count() as f64;
    let pink = c
        .pixels
        .iter()
        .filter(|p| p.x > p.y + 0.15 && p.x > p.z)
        .count() as f64;
    let green = c
        .pixels
        .iter()
        .filter(|p| p.y > p.x + 0.08 && p.y > p.z)
        .count() as f64;
    let blue = c
        .pixels
        .iter()
        .filter(|p| p.z > p.x + 0.15 && p.z > p.y)
        .count() as f64;
    assert!(glaze / n > 0.6, "glaze fraction {}", glaze / n);
    for (name, count) in [("pink", pink), ("green", green), ("blue", blue)] {
        assert!(count / n > 0.005, "{name} fraction {}", count / n);
    }
}

#[test]
fn earth_has_oceans_land_and_polar_ice() {
    let c = earth(EarthOptions::default());
    let n = c.pixels.len() as f64;
    let ocean = c
        .pixels
        .iter()
        .filter(|p| p.z > p.x + 0.2 && p.z > p.y)
        .count() as f64;
    let land = c.pixels.iter().filter(|p| p.z < p.y && p.z < 0.5).count() as f64;
    assert!(
        (0.45..0.8).contains(&(ocean / n)),
        "ocean fraction {}",
        ocean / n
    );
    assert!(
        (0.15..0.45).contains(&(land / n)),
        "land fraction {}",
        land / n
    );
    let top_row_ice = c.pixels[..c.width as usize]
        .iter()
        .all(|p| p.min_element() > 0.85);
    let bottom_row = &c.pixels[c.pixels.len() - c.width as usize..];
    assert!(top_row_ice && bottom_row.iter().all(|p| p.min_element() > 0.85));
}

#[test]
fn committed_textures_are_what_the_documented_commands_write() {
    let root = env!("CARGO_MANIFEST_DIR");
    for (file, canvas) in [
        (
            "textures/porcelain.png",
            porcelain(PorcelainOptions::default()),
        ),
        ("textures/planet.png", earth(EarthOptions::default())),
    ] {
        let stored = std::fs::read(format!("{root}/{file}")).expect("committed texture");
        assert!(stored.len() < 1 << 20, "{file} is {} bytes", stored.len());
        let fresh = png_bytes(&canvas).expect("encodes");
        assert!(
            stored == fresh,
            "{file} differs from `rtlang gen`'s output: regenerate it (docs/assets.md)"
        );
    }
}
