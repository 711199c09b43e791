//! The log-log plot: written as a PNG of the asked size with lines, labels
//! and series colours on it, and bad input rejected.

use rtlang::picture::{LogLogPlot, PictureError, Series};

fn plot(series: Vec<Series>, width: u32, height: u32) -> LogLogPlot {
    LogLogPlot {
        title: "Error against time".into(),
        x_label: "time (s)".into(),
        y_label: "relative MSE".into(),
        series,
        width,
        height,
    }
}

#[test]
fn plot_is_written_at_the_asked_size_and_not_blank() {
    let falling = |k: f64| (1..=6).map(|i| (i as f64, k / i as f64)).collect();
    let p = plot(
        vec![
            Series {
                name: "path tracing".into(),
                points: falling(1.0),
            },
            Series {
                name: "light sampling".into(),
                points: falling(0.05),
            },
        ],
        640,
        400,
    );
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("loglog.png");
    p.save(&path).expect("written");
    let img = image::open(&path).expect("a PNG").to_rgb8();
    assert_eq!(img.dimensions(), (640, 400));
    let count = |c: [u8; 3]| img.pixels().filter(|p| p.0 == c).count();
    let white = count([255, 255, 255]);
    assert!(
        white < 640 * 400 * 98 / 100,
        "mostly blank: {white} white pixels"
    );
    assert!(count([31, 119, 180]) > 200, "first series colour missing");
    assert!(count([214, 39, 40]) > 200, "second series colour missing");
    assert!(count([0, 0, 0]) > 500, "axes and labels missing");
}

#[test]
fn plot_without_positive_points_or_too_small_is_an_error() {
    let bad = vec![Series {
        name: "zero".into(),
        points: vec![(0.0, 1.0), (1.0, -2.0)],
    }];
    assert!(matches!(
        plot(bad, 300, 200).draw(),
        Err(PictureError::Plot(_))
    ));
    let ok = vec![Series {
        name: "one".into(),
        points: vec![(1.0, 1.0)],
    }];
    assert!(matches!(
        plot(ok.clone(), 10, 200).draw(),
        Err(PictureError::Plot(_))
    ));
    assert!(plot(ok, 200, 200).draw().is_ok());
}
