//! The log-log plot: written as an SVG of the asked size with lines, labels,
//! tick labels and a legend in the series colours, and bad input rejected.

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
fn plot_is_written_at_the_asked_size_with_lines_labels_and_legend() {
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
    let path = dir.join("loglog.svg");
    p.save(&path).expect("written");
    let svg = std::fs::read_to_string(&path).expect("an SVG");
    assert!(svg.starts_with("<svg") && svg.contains(r#"width="640" height="400""#));
    // The contents of the <text> elements.
    let texts: Vec<&str> = svg
        .split("<text")
        .skip(1)
        .filter_map(|t| Some(t.split_once('>')?.1.split_once("</text>")?.0.trim()))
        .collect();
    for text in [
        "Error against time",
        "time (s)",
        "relative MSE",
        "path tracing",
        "light sampling",
    ] {
        assert!(texts.contains(&text), "`{text}` not drawn");
    }
    // Each series: a polyline in its colour and six markers.
    for colour in ["#1F77B4", "#D62728"] {
        let lines = svg.matches(&format!(r#"stroke="{colour}""#)).count();
        assert!(lines >= 2, "{colour}: {lines} strokes (line and legend)");
    }
    let dots = svg.matches("<circle").count();
    assert!(dots >= 12, "{dots} markers");
    // Tick labels of both logarithmic axes: y spans 0.01 … 1, x 1 … 10.
    assert!(
        texts.contains(&"1") && texts.contains(&"0.01") && texts.contains(&"3"),
        "tick labels missing: {texts:?}"
    );
}

#[test]
fn plot_without_positive_points_or_too_small_is_an_error() {
    let bad = vec![Series {
        name: "zero".into(),
        points: vec![(0.0, 1.0), (1.0, -2.0)],
    }];
    assert!(matches!(
        plot(bad, 300, 200).svg(),
        Err(PictureError::Plot(_))
    ));
    let ok = vec![Series {
        name: "one".into(),
        points: vec![(1.0, 1.0)],
    }];
    assert!(matches!(
        plot(ok.clone(), 10, 200).svg(),
        Err(PictureError::Plot(_))
    ));
    assert!(plot(ok, 200, 200).svg().is_ok());
}
