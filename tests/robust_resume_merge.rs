//! Files read back by `--resume` and `rtlang merge` that were damaged or
//! edited: each is refused with a diagnostic and exit 1, never a panic or
//! an abort, and no image is written. A checkpoint with a NaN sum, more
//! samples kept than taken, trailing bytes, missing bytes, a wrong magic
//! line, the magic line of the format before checksums, a header of the
//! wrong shape or one flipped bit; sidecars claiming a 4·10⁹ × 4·10⁹
//! image, zero samples, wrongly typed or missing fields, a region outside
//! the image, or passes whose spp overflow a u32 when added.

mod dist_support;

use std::path::Path;

use dist_support::{folder, render, rtlang, s, SCENE};

/// Asserts that `args` fails with exit 1, no panic, and `needle` in stderr
/// (read with the diagnostic's line wrapping undone).
fn assert_refused(args: &[&str], needle: &str) {
    let o = rtlang(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    let flat = err.replace('│', " ");
    let flat: Vec<&str> = flat.split_whitespace().collect();
    assert!(flat.join(" ").contains(needle), "`{needle}` not in: {err}");
}

/// The byte offset where a checkpoint's pixel data starts (after two lines).
fn pixel_data_start(bytes: &[u8]) -> usize {
    let mut lines = bytes
        .iter()
        .enumerate()
        .filter(|(_, &b)| b == b'\n')
        .map(|(i, _)| i + 1);
    lines.nth(1).expect("two header lines")
}

#[test]
fn damaged_checkpoints_are_refused() {
    let dir = folder("bad-checkpoints");
    let (ck, out) = (dir.join("c.ckpt"), dir.join("out.png"));
    render(&out, &["--spp", "2", "--checkpoint", s(&ck)]);
    let good = std::fs::read(&ck).expect("checkpoint written");
    let start = pixel_data_start(&good);
    let header = String::from_utf8_lossy(&good[..start]).to_string();
    let data = &good[start..good.len() - 4];
    assert_eq!(data.len(), 32 * 24 * 20, "3 f32 + 2 u32 per pixel");
    // Each damage below but the flipped bit comes with a checksum made for
    // it, so that the check behind the checksum is the one that refuses it.
    let sealed = |mut body: Vec<u8>| {
        let sum = crc32fast::hash(&body);
        body.extend_from_slice(&sum.to_le_bytes());
        body
    };
    let body = good[..good.len() - 4].to_vec();

    let mut nan_sum = body.clone();
    nan_sum[start + 4..start + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    let mut kept_more = body.clone();
    kept_more[start + 12..start + 16].copy_from_slice(&99u32.to_le_bytes());
    let mut trailing = body.clone();
    trailing.extend_from_slice(b"more");
    let truncated = body[..body.len() - 7].to_vec();
    let wrong_magic = [b"rtlang-checkpoint 9".as_slice(), &good[19..]].concat();
    let older = [b"rtlang-checkpoint 1".as_slice(), &good[19..]].concat();
    let misshapen = [
        header.lines().next().expect("magic").as_bytes(),
        b"\n{\"piece\": {\"scene\": 7}, \"first_sample\": \"x\"}\n",
        &body[start..],
    ]
    .concat();
    let mut flipped = good.clone();
    flipped[start + 100] ^= 0x08;
    let cases: [(&str, &[u8], &str); 8] = [
        ("NaN sum", &sealed(nan_sum), "corrupt pixel data at pixel 0"),
        ("kept > taken", &sealed(kept_more), "99 kept of 2 taken"),
        (
            "trailing bytes",
            &sealed(trailing),
            "longer than its region",
        ),
        ("truncated", &sealed(truncated), "truncated pixel data"),
        ("wrong magic", &wrong_magic, "not an rtlang checkpoint"),
        ("older", &older, "written by an older rtlang"),
        ("misshapen header", &sealed(misshapen), "invalid type"),
        ("flipped bit", &flipped, "its checksum does not match"),
    ];
    for (what, bytes, needle) in cases {
        std::fs::write(&ck, bytes).expect("write damaged checkpoint");
        let _ = std::fs::remove_file(&out);
        let args = [
            "render",
            SCENE,
            "-o",
            s(&out),
            "--quiet",
            "--spp",
            "4",
            "--checkpoint",
            s(&ck),
            "--resume",
        ];
        assert_refused(&args, needle);
        assert!(!out.exists(), "{what}: an image was written");
    }
    // The undamaged file resumes.
    std::fs::write(&ck, &good).expect("restore checkpoint");
    render(&out, &["--spp", "4", "--checkpoint", s(&ck), "--resume"]);
}

/// Renders the two tiles of one pass; returns their paths.
fn two_tiles(dir: &Path, extra: &[&str], tag: &str) -> [std::path::PathBuf; 2] {
    [1, 2].map(|i| {
        let p = dir.join(format!("{tag}{i}.exr"));
        let mut args = vec!["--tile".to_string(), format!("{i}/2")];
        args.extend(extra.iter().map(|a| a.to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        render(&p, &args);
        p
    })
}

/// Rewrites the sidecar of `image` by `edit`.
fn edit_sidecar(image: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let path = format!("{}.json", image.display());
    let text = std::fs::read_to_string(&path).expect("sidecar");
    let mut v: serde_json::Value = serde_json::from_str(&text).expect("sidecar is JSON");
    edit(&mut v);
    std::fs::write(&path, v.to_string()).expect("write sidecar");
}

#[test]
fn sidecars_that_describe_no_render_are_refused_by_merge() {
    let dir = folder("bad-sidecars");
    let out = dir.join("merged.exr");
    let merge = |pieces: &[std::path::PathBuf], extra: &[&str], needle: &str| {
        let mut args = vec!["merge", "-o", s(&out)];
        args.extend(pieces.iter().map(|p| s(p)));
        args.extend_from_slice(extra);
        assert_refused(&args, needle);
        assert!(!out.exists(), "an image was written for `{needle}`");
    };
    type Edit = fn(&mut serde_json::Value);
    let cases: [(&str, Edit, &str); 5] = [
        (
            "huge",
            |v| {
                v["width"] = 4_000_000_000u32.into();
                v["height"] = 4_000_000_000u32.into();
            },
            "GiB for its film",
        ),
        (
            "no samples",
            |v| {
                v["spp"] = 0.into();
                v["spp_reached"] = 0.into();
            },
            "samples per pixel must be at least 1",
        ),
        ("typed", |v| v["width"] = "ten".into(), "invalid type"),
        (
            "missing",
            |v| {
                v.as_object_mut().expect("object").remove("seed");
            },
            "missing field `seed`",
        ),
        (
            "outside",
            |v| v["region"] = serde_json::json!([0, 32, 20, 30]),
            "but its sidecar gives",
        ),
    ];
    for (tag, edit, needle) in cases {
        let tiles = two_tiles(&dir, &[], tag);
        for t in &tiles {
            edit_sidecar(t, edit);
        }
        merge(&tiles, &[], needle);
    }
    // Two passes, each a valid 32×24 render (4·10⁹ spp in pass 0, 2³¹ − 1
    // in pass 1, whose sample indices then end at 2³² − 2), whose spp add
    // up to more than a u32 holds.
    let mut passes = Vec::new();
    for (pass, spp) in [("0", 4_000_000_000u32), ("1", 2_147_483_647)] {
        for t in two_tiles(&dir, &["--pass", pass], &format!("pass{pass}-")) {
            edit_sidecar(&t, |v| {
                v["spp"] = spp.into();
                v["spp_reached"] = spp.into();
            });
            passes.push(t);
        }
    }
    merge(&passes, &["--average"], "more than 4294967295");
}
