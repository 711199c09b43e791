//! Frames and JSON progress: `--frames A..B` writes one image per frame
//! through the `{frame:W}` pattern, the scene's motion follows the frame, and
//! `--progress json` prints parseable lines ending with the finished pass.

mod dist_support;

use dist_support::{folder, pixels, render, rtlang, s, SCENE};

#[test]
fn frames_render_to_padded_names_and_motion_follows_the_frame() {
    let dir = folder("frames");
    let pattern = dir.join("f{frame:03}.exr");
    render(&pattern, &["--frames", "0..2"]);
    let f: Vec<_> = (0..3)
        .map(|i| pixels(&dir.join(format!("f{i:03}.exr"))))
        .collect();
    assert_ne!(f[0], f[1]);
    assert_ne!(f[1], f[2]);
    // The same frame renders the same picture alone.
    let single = dir.join("one.exr");
    render(&single, &["--frame", "1"]);
    assert_eq!(pixels(&single), f[1]);
    // Several frames to one name are refused.
    let o = rtlang(&["render", SCENE, "-o", s(&single), "--frames", "0..1"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("{frame}"));
}

#[test]
fn json_progress_lines_count_up_to_the_whole_image() {
    let dir = folder("progress");
    let out = dir.join("p.exr");
    let o = rtlang(&[
        "render",
        SCENE,
        "-o",
        s(&out),
        "--progress",
        "json",
        "--tile",
        "1/2",
    ]);
    assert!(o.status.success());
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    assert!(lines.len() > 2);
    let last = lines.last().expect("a line");
    assert_eq!(last["event"], "pass");
    assert_eq!(last["pixels_done"], 32 * 12);
    assert_eq!(last["pixels_total"], 32 * 12);
    assert_eq!(last["eta_s"], 0.0);
    let done: Vec<u64> = lines
        .iter()
        .map(|l| l["samples_done"].as_u64().expect("count"))
        .collect();
    assert!(done.windows(2).all(|w| w[0] <= w[1]), "{done:?}");
}
