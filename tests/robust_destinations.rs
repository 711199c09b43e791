//! Where renders write: the temporary file is created
//! under a random name without following a symlink; a `--checkpoint` that
//! names the scene, an included file or the output is refused before
//! anything is rendered; an output in a folder that is missing (or is no
//! folder) fails at once, not after the render; the same for `merge -o`.

mod dist_support;

use std::path::Path;
use std::time::{Duration, Instant};

use dist_support::{folder, rtlang, s, SCENE};
use glam::Vec3;
use rtlang::render::output::write_image;

#[test]
fn a_symlink_at_the_old_temporary_name_is_not_followed() {
    let dir = folder("dest-symlink");
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "keep me").expect("writes");
    // A name predictable from the PID, where an attacker would plant a link.
    let planted = dir.join(format!(".out.png.{}.tmp", std::process::id()));
    std::os::unix::fs::symlink(&victim, &planted).expect("symlink");
    let out = dir.join("out.png");
    write_image(&out, 2, 2, &[Vec3::splat(0.5); 4]).expect("writes");
    assert_eq!(std::fs::read_to_string(&victim).expect("reads"), "keep me");
    assert!(image::open(&out).is_ok(), "the output is no PNG");
    assert!(std::fs::symlink_metadata(&out)
        .expect("exists")
        .file_type()
        .is_file());
    // Nothing else is left beside them but the planted link.
    let names: Vec<String> = std::fs::read_dir(&*dir)
        .expect("lists")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");
}

#[test]
fn an_output_is_as_readable_as_a_created_file() {
    use std::os::unix::fs::PermissionsExt;
    let dir = folder("dest-mode");
    let out = dir.join("out.png");
    write_image(&out, 1, 1, &[Vec3::ONE]).expect("writes");
    let plain = dir.join("plain");
    std::fs::File::create(&plain).expect("creates");
    let mode = |p: &Path| std::fs::metadata(p).expect("exists").permissions().mode() & 0o777;
    assert_eq!(mode(&out), mode(&plain));
}

/// `rtlang render SCENE -o OUT --checkpoint CKPT`: refused, with `wanted`
/// in the message, and the checkpoint's file unchanged.
fn checkpoint_refused(scene: &Path, out: &Path, checkpoint: &Path, wanted: &str) {
    let before = std::fs::read(checkpoint).ok();
    let o = rtlang(&[
        "render",
        s(scene),
        "-o",
        s(out),
        "--quiet",
        "--spp",
        "1",
        "--checkpoint",
        s(checkpoint),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("rtlang::checkpoint::clobbers"), "{err}");
    assert!(err.contains(wanted), "{err}");
    assert_eq!(std::fs::read(checkpoint).ok(), before, "the file changed");
    assert!(!err.contains("rendered"), "{err}");
}

#[test]
fn a_checkpoint_over_the_scene_an_include_or_the_output_is_refused() {
    let dir = folder("dest-checkpoint");
    let part = dir.join("part.rt");
    std::fs::write(&part, "let grey = lambertian(rgb(0.5, 0.5, 0.5))\n").expect("writes");
    let scene = dir.join("scene.rt");
    std::fs::write(
        &scene,
        "include \"part.rt\"\nrender { size 8 x 8 }\nsphere { center (0, 0, -3) radius 1 material grey }\n",
    )
    .expect("writes");
    let out = dir.join("out.exr");
    checkpoint_refused(&scene, &out, &scene, "the file the scene reads");
    // Spelled another way, through `..`.
    let roundabout = dir
        .join("..")
        .join(dir.file_name().expect("name"))
        .join("part.rt");
    checkpoint_refused(&scene, &out, &roundabout, "the file the scene reads");
    std::fs::write(&out, "an older render").expect("writes");
    checkpoint_refused(&scene, &out, &out, "the output");
}

/// Asserts that `args` fail within a few seconds (the render they ask for
/// would take 20 s) naming the unwritable `out`.
fn fails_at_once(args: &[&str], out: &Path) {
    let start = Instant::now();
    let o = rtlang(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "failed only after {:?}: {err}",
        start.elapsed()
    );
    assert!(
        err.contains(&format!("cannot write `{}`", out.display())),
        "{err}"
    );
}

#[test]
fn an_output_in_a_missing_folder_fails_before_the_render() {
    let dir = folder("dest-folder");
    let not_a_folder = dir.join("file");
    std::fs::write(&not_a_folder, "").expect("writes");
    for out in [dir.join("missing/out.png"), not_a_folder.join("out.png")] {
        let args = [
            "render",
            "--time",
            "20s",
            SCENE,
            "-o",
            s(&out),
            "--quiet",
            "--width",
            "16",
            "--height",
            "16",
        ];
        fails_at_once(&args, &out);
        assert!(!out.exists());
    }
}

#[test]
fn merge_into_a_missing_folder_fails_before_reading_the_pieces() {
    let dir = folder("dest-merge");
    // The piece is never rendered: the output's folder is the first error.
    let tile = dir.join("t.exr");
    let out = dir.join("missing/merged.exr");
    fails_at_once(&["merge", s(&tile), "-o", s(&out)], &out);
}
