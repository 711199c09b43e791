//! Pieces that do not belong together: tiles rendered
//! with and without `--clamp` are not merged, nor is a checkpoint of
//! another noise target resumed; a PNG renamed `.exr` is refused by its
//! content; sidecars swapped between two tiles are caught by the hash of
//! the pixels; `merge -o` naming one of its pieces is refused and leaves
//! the piece intact; a sidecar of an older format is refused with a word
//! to render again. (A checkpoint's flipped bit: `robust_resume_merge.rs`.)

mod dist_support;

use std::path::{Path, PathBuf};

use dist_support::{folder, render, rtlang, s};

/// Asserts that `args` fail with exit 1 and `needle` in their diagnostic
/// (its line wrapping undone), writing no `unwritten` file.
fn refused(args: &[&str], needle: &str, unwritten: &Path) {
    let o = rtlang(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    let words: Vec<&str> = err.split_whitespace().filter(|w| *w != "│").collect();
    assert!(words.join(" ").contains(needle), "`{needle}` not in: {err}");
    assert!(!unwritten.exists(), "{} was written", unwritten.display());
}

/// The two tiles `dir/NAME1.EXT`, `dir/NAME2.EXT` of a 32×24 render, each
/// with its own extra options.
fn tiles(dir: &Path, name: &str, ext: &str, extra: [&[&str]; 2]) -> [PathBuf; 2] {
    let mut i = 0;
    extra.map(|extra| {
        i += 1;
        let path = dir.join(format!("{name}{i}.{ext}"));
        let tile = format!("{i}/2");
        let mut args = vec!["--tile", tile.as_str(), "--spp", "2"];
        args.extend_from_slice(extra);
        render(&path, &args);
        path
    })
}

fn sidecar(image: &Path) -> PathBuf {
    PathBuf::from(format!("{}.json", image.display()))
}

#[test]
fn tiles_of_another_clamp_are_not_merged() {
    let dir = folder("pieces-clamp");
    let [a, b] = tiles(&dir, "t", "exr", [&["--clamp", "1"], &[]]);
    let out = dir.join("merged.exr");
    refused(
        &["merge", s(&a), s(&b), "-o", s(&out)],
        "differ in clamp: Some(1.0) against None",
        &out,
    );
}

#[test]
fn a_checkpoint_of_another_noise_target_is_not_resumed() {
    let dir = folder("pieces-noise");
    let (ck, out) = (dir.join("c.ckpt"), dir.join("out.exr"));
    render(
        &out,
        &["--spp", "2", "--noise", "0.05", "--checkpoint", s(&ck)],
    );
    std::fs::remove_file(&out).expect("removes");
    let resume = ["--resume", "--checkpoint", s(&ck), "--spp", "4"];
    let args = [&["render", dist_support::SCENE, "-o", s(&out)], &resume[..]].concat();
    refused(&args, "its noise target is Some(0.05)", &out);
}

#[test]
fn a_png_named_exr_is_refused_by_its_content() {
    let dir = folder("pieces-format");
    let [a, b] = tiles(&dir, "t", "png", [&[], &[]]);
    let renamed: Vec<PathBuf> = [a, b]
        .iter()
        .map(|png| {
            let exr = png.with_extension("exr");
            std::fs::rename(sidecar(png), sidecar(&exr)).expect("renames");
            std::fs::rename(png, &exr).expect("renames");
            exr
        })
        .collect();
    let out = dir.join("merged.exr");
    refused(
        &["merge", s(&renamed[0]), s(&renamed[1]), "-o", s(&out)],
        "is a Png image, not an EXR image",
        &out,
    );
}

#[test]
fn swapped_sidecars_are_refused() {
    let dir = folder("pieces-swap");
    let [a, b] = tiles(&dir, "t", "exr", [&[], &[]]);
    let (sa, sb) = (sidecar(&a), sidecar(&b));
    let held = dir.join("held.json");
    std::fs::rename(&sa, &held).expect("renames");
    std::fs::rename(&sb, &sa).expect("renames");
    std::fs::rename(&held, &sb).expect("renames");
    let out = dir.join("merged.exr");
    refused(
        &["merge", s(&a), s(&b), "-o", s(&out)],
        "are not the ones its sidecar describes",
        &out,
    );
}

#[test]
fn merging_over_one_of_the_pieces_is_refused_and_keeps_it() {
    let dir = folder("pieces-over");
    let [a, b] = tiles(&dir, "t", "exr", [&[], &[]]);
    let before = (std::fs::read(&a).ok(), std::fs::read(sidecar(&a)).ok());
    // The output spelled another way than the piece.
    let over = dir.join(".").join("t1.exr");
    let o = rtlang(&["merge", s(&a), s(&b), "-o", s(&over)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("rtlang::merge::output_is_input"), "{err}");
    let after = (std::fs::read(&a).ok(), std::fs::read(sidecar(&a)).ok());
    assert_eq!(before, after, "the piece changed");
}

#[test]
fn a_sidecar_of_an_older_format_is_refused() {
    let dir = folder("pieces-old");
    let [a, b] = tiles(&dir, "t", "exr", [&[], &[]]);
    for t in [&a, &b] {
        let text = std::fs::read_to_string(sidecar(t)).expect("reads");
        let mut v: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        let fields = v.as_object_mut().expect("object");
        for added in ["format", "clamp", "noise", "pixels"] {
            fields.remove(added);
        }
        std::fs::write(sidecar(t), v.to_string()).expect("writes");
    }
    let out = dir.join("merged.exr");
    refused(
        &["merge", s(&a), s(&b), "-o", s(&out)],
        "written by another version of rtlang (sidecar format 0",
        &out,
    );
}
