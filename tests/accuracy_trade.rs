//! The measurement behind docs/accuracy.md (ignored: it renders for
//! minutes). Run it with
//! `cargo test --release --test accuracy_trade -- --ignored --nocapture`;
//! it prints the Markdown table and writes docs/img/accuracy.svg.
//! Its assertions are the claims the document makes.

use std::path::PathBuf;

use rtlang::picture::{LogLogPlot, Series};
use rtlang::render::accuracy::measure;
use rtlang::render::RenderOptions;
use rtlang::scene::object::RevolutionMode;

#[test]
#[ignore = "a measurement of minutes, not a check: see docs/accuracy.md"]
fn vase_mesh_resolutions_against_analytic() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let loaded = rtlang::lang::load_scene(&root.join("scenes/vase.rt"), &[]).expect("loads");
    let scene = loaded.scene;
    let options = RenderOptions {
        width: 250,
        height: 225,
        spp: 32,
        seed: 3,
        ..RenderOptions::from_settings(&scene.settings)
    };
    let analytic = |tolerance| RevolutionMode::Analytic {
        resolution: 50,
        tolerance,
    };
    let mut modes: Vec<RevolutionMode> = [8, 16, 32, 64, 128, 256]
        .iter()
        .map(|&resolution| RevolutionMode::Mesh { resolution })
        .collect();
    modes.extend([analytic(1e-2), analytic(1e-4)]);
    let report = measure(&scene, &options, analytic(1e-7), &modes).expect("measures");
    println!("| setting | render time (s) | max hit error | mean hit error | image RMSE |");
    println!("|---|---:|---:|---:|---:|");
    for r in &report.rows {
        let name = match r.mode {
            RevolutionMode::Mesh { resolution } => format!("mesh {resolution}"),
            RevolutionMode::Analytic { tolerance, .. } => {
                format!("analytic, tolerance {tolerance:e}")
            }
        };
        println!(
            "| {name} | {:.2} | {:.2e} | {:.2e} | {:.2e} |",
            r.seconds, r.max_error, r.mean_error, r.rmse
        );
    }
    println!(
        "noise floor (reference vs itself, other seed): {:.2e}",
        report.noise_floor
    );

    let mesh: Vec<_> = report
        .rows
        .iter()
        .filter(|r| matches!(r.mode, RevolutionMode::Mesh { .. }))
        .collect();
    let analytic_rows: Vec<_> = report
        .rows
        .iter()
        .filter(|r| matches!(r.mode, RevolutionMode::Analytic { .. }))
        .collect();
    let plot = LogLogPlot {
        title: "vase.rt: error against render time".into(),
        x_label: "render time (s)".into(),
        y_label: "error".into(),
        series: vec![
            Series {
                name: "mesh: mean hit error".into(),
                points: mesh.iter().map(|r| (r.seconds, r.mean_error)).collect(),
            },
            Series {
                name: "mesh: image RMSE".into(),
                points: mesh.iter().map(|r| (r.seconds, r.rmse)).collect(),
            },
            Series {
                name: "analytic: mean hit error".into(),
                points: analytic_rows
                    .iter()
                    .map(|r| (r.seconds, r.mean_error))
                    .collect(),
            },
            Series {
                name: "analytic: image RMSE".into(),
                points: analytic_rows.iter().map(|r| (r.seconds, r.rmse)).collect(),
            },
        ],
        width: 640,
        height: 420,
    };
    plot.save(&root.join("docs/img/accuracy.svg"))
        .expect("writes the plot");

    // The claims of docs/accuracy.md: finer meshes are closer to the surface,
    // and the analytic mode at tolerance 1e-4 is closer on average than the
    // finest mesh (its worst hits are not: see the document).
    for pair in mesh.windows(2) {
        assert!(pair[1].mean_error < pair[0].mean_error, "{pair:?}");
    }
    let finest = mesh.last().expect("mesh rows");
    let tight = analytic_rows.last().expect("analytic rows");
    assert!(tight.mean_error < finest.mean_error, "{tight:?} {finest:?}");
}
