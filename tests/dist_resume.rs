//! Nothing lost: a render stopped between rounds and resumed from its
//! checkpoint equals an uninterrupted one bit for bit; SIGINT writes the
//! image so far and exits 130; a failed render leaves the old file intact.

mod dist_support;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use dist_support::{folder, pixels, render, rtlang, s, SCENE};
use rtlang::geometry::World;
use rtlang::render::checkpoint::{self, Header};
use rtlang::render::piece::PieceInfo;
use rtlang::render::scenes::cornell_box;
use rtlang::render::{render_film, Film, Hooks, RenderOptions};

#[test]
fn stopped_saved_and_resumed_film_equals_the_uninterrupted_one() {
    let scene = cornell_box(24, 12);
    let world = World::build(&scene).expect("builds");
    let options = RenderOptions::from_settings(&scene.settings);
    let region = options.region().expect("valid");
    let run = |film: &mut Film, stop_after: Option<u32>| {
        let stop = AtomicBool::new(false);
        let tiles = AtomicU32::new(0);
        let tile_done = |_| {
            if Some(tiles.fetch_add(1, Ordering::SeqCst) + 1) == stop_after {
                stop.store(true, Ordering::SeqCst);
            }
        };
        let mut hooks = Hooks {
            stop: &stop,
            tile_done: &tile_done,
            round_done: &mut |_| {},
        };
        render_film(&scene, &world, &options, film, &mut hooks).expect("renders");
    };
    let mut direct = Film::new(region);
    run(&mut direct, None);
    assert_eq!(direct.spp_reached(), 12);

    // Stop after 5 tiles (of 4 per round): mid-way through round two.
    let mut part = Film::new(region);
    run(&mut part, Some(5));
    assert!(part.spp_reached() < 12);
    let dir = folder("film");
    let path = dir.join("c.ckpt");
    let header = Header {
        piece: PieceInfo::new(&scene, &options, region, 0.0, 0),
        first_sample: 0,
    };
    checkpoint::save(&path, &header, &part).expect("saves");
    let mut resumed = checkpoint::load(&path, &header).expect("loads");
    assert_eq!(resumed, part);
    run(&mut resumed, None);
    assert_eq!(resumed, direct);

    let mut other = header.clone();
    other.piece.seed = 1;
    let err = checkpoint::load(&path, &other).expect_err("another seed");
    assert!(err.to_string().contains("seed"), "{err}");
    // A film of lights chosen by the tree does not go on by power.
    let mut power = header.clone();
    power.piece.light_selection = "power".into();
    let err = checkpoint::load(&path, &power).expect_err("another selection");
    assert!(
        err.to_string()
            .contains("its light selection is tree, this render's is power"),
        "{err}"
    );
}

#[test]
fn resume_from_4_to_8_spp_equals_a_direct_8_spp_render() {
    let dir = folder("resume");
    let (ck, a, b) = (dir.join("c.ckpt"), dir.join("a.exr"), dir.join("b.exr"));
    render(&a, &["--spp", "4", "--checkpoint", s(&ck)]);
    render(&a, &["--spp", "8", "--checkpoint", s(&ck), "--resume"]);
    render(&b, &["--spp", "8"]);
    assert_eq!(pixels(&a), pixels(&b));
    // A checkpoint ahead of the request is refused.
    let o = rtlang(&[
        "render",
        SCENE,
        "-o",
        s(&a),
        "--spp",
        "2",
        "--checkpoint",
        s(&ck),
        "--resume",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("more than the 2"));
    // Nor is a checkpoint of another light selection resumed.
    let o = rtlang(&[
        "render",
        SCENE,
        "-o",
        s(&a),
        "--spp",
        "12",
        "--checkpoint",
        s(&ck),
        "--resume",
        "--light-selection",
        "power",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("light selection"), "{err}");
    assert_eq!(pixels(&a), pixels(&b), "the output is left as it was");
}

#[cfg(unix)]
#[test]
fn sigint_writes_the_image_so_far_and_exits_130() {
    let dir = folder("sigint");
    let (out, ck) = (dir.join("i.exr"), dir.join("i.ckpt"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_rtlang"))
        .args([
            "render",
            SCENE,
            "-o",
            s(&out),
            "--width",
            "16",
            "--height",
            "16",
        ])
        .args(["--spp", "10000000", "--threads", "1", "--progress", "json"])
        .args(["--checkpoint", s(&ck)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let first = lines.next().expect("a progress line").expect("reads");
    assert!(first.contains("\"event\":\"tile\""), "{first}");
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    let last = lines.last().expect("more lines").expect("reads");
    assert!(last.contains("\"event\":\"interrupted\""), "{last}");
    let status = child.wait().expect("waits");
    assert_eq!(status.code(), Some(130));
    let info: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("i.exr.json")).expect("sidecar"))
            .expect("json");
    let reached = info["spp_reached"].as_u64().expect("spp_reached");
    assert!((1..10_000_000).contains(&reached), "{info}");
    assert!(pixels(&out).iter().any(|p| p[0] > 0.0));

    // The checkpoint resumes to a little more than was reached, identical
    // to a direct render of that spp.
    let spp = (reached + 3).to_string();
    let small = ["--width", "16", "--height", "16", "--spp", &spp];
    let resumed = dir.join("r.exr");
    let mut args = small.to_vec();
    args.extend(["--checkpoint", s(&ck), "--resume"]);
    render(&resumed, &args);
    let direct = dir.join("d.exr");
    render(&direct, &small);
    assert_eq!(pixels(&resumed), pixels(&direct));
}

#[test]
fn a_failed_render_leaves_the_existing_output_untouched() {
    let dir = folder("atomic");
    let out = dir.join("keep.png");
    std::fs::write(&out, b"previous picture").expect("writes");
    let o = rtlang(&[
        "render",
        SCENE,
        "-o",
        s(&out),
        "--crop",
        "0,99,0,4",
        "--quiet",
    ]);
    assert!(!o.status.success());
    assert_eq!(std::fs::read(&out).expect("reads"), b"previous picture");
}
