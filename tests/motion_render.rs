//! Motion blur with known answers: a glowing sphere moving linearly during
//! the shutter leaves a streak whose centre of mass is the mid-shutter
//! position and whose length is its travel, and no time outside the shutter
//! is ever sampled.

mod support;

const WIDTH: u32 = 200;
const HEIGHT: u32 = 100;

/// Renders `source` and returns the summed brightness of each pixel column.
fn column_sums(source: &str) -> Vec<f64> {
    let file = support::scratch::file("motion.rt", source.as_bytes());
    let loaded = rtlang::lang::load_scene(&file, &[]).unwrap_or_else(|errors| {
        panic!("scene does not load: {errors:?}");
    });
    let out = support::render::as_set(&loaded.scene);
    let mut sums = vec![0.0; WIDTH as usize];
    for (i, p) in out.pixels.iter().enumerate() {
        sums[i % WIDTH as usize] += f64::from(p.x + p.y + p.z) / 3.0;
    }
    sums
}

/// Camera at z = 10 looking at the origin, vfov 20, 2:1: the plane z = 0
/// maps x to column 100 + x · PX_PER_UNIT.
fn px_per_unit() -> f64 {
    let half_width = 10.0 * (10f64).to_radians().tan() * 2.0;
    f64::from(WIDTH) / 2.0 / half_width
}

fn scene(shutter: &str, motion: &str) -> String {
    format!(
        "render {{ size {WIDTH} x {HEIGHT}  samples 32  depth 2  seed 3  background rgb(0, 0, 0) }}
         camera {{ from (0, 0, 10)  at (0, 0, 0)  fov 20  shutter {shutter} }}
         sphere {{ center (0, 0, 0)  radius 0.2  material light(rgb(1, 1, 1))
                   motion {{ {motion} }} }}"
    )
}

fn centroid(sums: &[f64]) -> f64 {
    let total: f64 = sums.iter().sum();
    sums.iter()
        .enumerate()
        .map(|(i, s)| (i as f64 + 0.5) * s)
        .sum::<f64>()
        / total
}

fn lit_columns(sums: &[f64]) -> (usize, usize) {
    let peak = sums.iter().cloned().fold(0.0, f64::max);
    let lit: Vec<usize> = (0..sums.len()).filter(|&i| sums[i] > 0.02 * peak).collect();
    (lit[0], *lit.last().expect("something is lit"))
}

#[test]
fn linear_motion_streak_is_centred_at_mid_shutter_with_the_travel_length() {
    // x(t) = 4t − 1.5 over the shutter [0.25, 0.75]: from −0.5 to 1.5,
    // mid-shutter at x = 0.5.
    let sums = column_sums(&scene("0.25 0.75", "translate (4 * t - 1.5, 0, 0)"));
    let k = px_per_unit();
    let expected_centre = 100.0 + 0.5 * k;
    let c = centroid(&sums);
    assert!(
        (c - expected_centre).abs() < 0.5,
        "streak centre at column {c:.2}, expected {expected_centre:.2}"
    );
    let (first, last) = lit_columns(&sums);
    // A column is lit when its sum passes 2 % of the peak column's. At the
    // streak's ends that is where the sphere's disc (radius 0.2) has swept
    // 2 % of its area, 0.895 of a radius beyond its centre's first and last
    // positions ((acos u − u√(1 − u²)) / π = 0.02 at u = 0.895). A column
    // is judged by its mean, about its centre's value, so the first lit
    // column (index i spans [i, i + 1)) starts near the left point and the
    // last one ends near the right point.
    let reach = 0.895 * 0.2;
    let (lo, hi) = (100.0 + (-0.5 - reach) * k, 100.0 + (1.5 + reach) * k - 1.0);
    assert!(
        (first as f64 - lo).abs() <= 2.0 && (last as f64 - hi).abs() <= 2.0,
        "streak spans columns {first}..{last}, expected about {lo:.1}..{hi:.1}"
    );
}

#[test]
fn a_static_sphere_is_not_streaked() {
    let sums = column_sums(&scene("0.25 0.75", "translate (0.5, 0, 0)"));
    let k = px_per_unit();
    let (first, last) = lit_columns(&sums);
    let width = (last - first) as f64;
    assert!(
        width <= 0.4 * k + 3.0,
        "a sphere of diameter 0.4 covers {width} columns"
    );
}

#[test]
fn no_time_outside_the_shutter_is_sampled() {
    // Outside [0.4, 0.6] the sphere jumps far to the side (x = ±3); if any
    // ray had a time outside the shutter, those columns would light up.
    let sums = column_sums(&scene(
        "0.4 0.6",
        "translate (keyframes(t, [(0.39, -3), (0.4, 0), (0.6, 0), (0.61, 3)]), 0, 0)",
    ));
    let k = px_per_unit();
    let (first, last) = lit_columns(&sums);
    assert!(
        first as f64 >= 100.0 - 0.3 * k && last as f64 <= 100.0 + 0.3 * k,
        "lit columns {first}..{last} reach outside the sphere's shutter-time position"
    );
}
