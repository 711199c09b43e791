//! `--tile`, `--pass` and `rtlang merge`: tiles join bit-identically into the
//! single-process image, passes average to the summed-spp image, and pieces
//! that do not belong together are refused with a clear message.

mod dist_support;

use dist_support::{folder, pixels, render, rtlang, s};

#[test]
fn four_tiles_merge_bit_identically_to_one_render() {
    let dir = folder("tiles");
    let full = dir.join("full.exr");
    render(&full, &[]);
    let mut args = vec!["merge".to_string()];
    for i in 1..=4 {
        let tile = dir.join(format!("t{i}.exr"));
        render(&tile, &["--tile", &format!("{i}/4")]);
        args.push(s(&tile).into());
    }
    let merged = dir.join("merged.exr");
    args.extend(["-o".into(), s(&merged).into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = rtlang(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(pixels(&merged), pixels(&full));
    assert_eq!(std::fs::read(&merged).ok(), std::fs::read(&full).ok());
    // PNG from the merge equals the PNG a single render writes.
    let (mp, fp) = (dir.join("m.png"), dir.join("f.png"));
    render(&fp, &[]);
    let o = rtlang(&["merge", args[1], args[2], args[3], args[4], "-o", s(&mp)]);
    assert!(o.status.success());
    assert_eq!(std::fs::read(&mp).ok(), std::fs::read(&fp).ok());
}

/// The merge rule: pass K of S spp takes sample indices K·S .. (K+1)·S, so
/// passes 0 and 1 averaged are the 16-spp render (up to the order of the
/// floating-point sums), under either sampler.
#[test]
fn two_passes_average_to_the_summed_spp_render() {
    for sampler in ["sobol", "independent"] {
        two_passes_average_to_the_summed_spp_render_with(sampler);
    }
}

fn two_passes_average_to_the_summed_spp_render_with(sampler: &str) {
    let dir = folder(&format!("passes-{sampler}"));
    let (p0, p1, direct) = (dir.join("p0.exr"), dir.join("p1.exr"), dir.join("d.exr"));
    let with = |extra: &[&'static str]| [extra, &["--sampler", sampler]].concat();
    render(&p0, &with(&["--spp", "8", "--pass", "0"]));
    render(&p1, &with(&["--spp", "8", "--pass", "1"]));
    render(&direct, &with(&["--spp", "16"]));
    let merged = dir.join("m.exr");
    let o = rtlang(&["merge", "--average", s(&p0), s(&p1), "-o", s(&merged)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (m, d, a) = (pixels(&merged), pixels(&direct), pixels(&p0));
    let mut worst = 0f32;
    for (x, y) in m.iter().zip(&d) {
        for c in 0..3 {
            worst = worst.max((x[c] - y[c]).abs() / y[c].abs().max(1e-3));
        }
    }
    assert!(worst < 1e-5, "{sampler}: relative difference {worst}");
    // The passes are independent: one pass alone differs from the average.
    assert_ne!(a, m);
    let info = std::fs::read_to_string(dir.join("m.exr.json")).expect("sidecar");
    assert!(info.contains("\"spp\": 16"), "{info}");
}

#[test]
fn pieces_that_do_not_belong_together_are_refused() {
    let dir = folder("refuse");
    let t = |name: &str, extra: &[&str]| {
        let p = dir.join(name);
        render(&p, extra);
        p
    };
    let t1 = t("t1.exr", &["--tile", "1/2"]);
    let t2 = t("t2.exr", &["--tile", "2/2"]);
    let t2_seed = t("t2s.exr", &["--tile", "2/2", "--seed", "9"]);
    let t2_size = t("t2w.exr", &["--tile", "2/2", "--width", "40"]);
    let t2_frame = t("t2f.exr", &["--tile", "2/2", "--frame", "3"]);
    let t2_pass = t("t2p.exr", &["--tile", "2/2", "--pass", "1"]);
    let t2_sampler = t("t2i.exr", &["--tile", "2/2", "--sampler", "independent"]);
    let t2_power = t("t2l.exr", &["--tile", "2/2", "--light-selection", "power"]);
    let t2_path = t("t2n.exr", &["--tile", "2/2", "--integrator", "path"]);
    let p1_power = t("p1l.exr", &["--pass", "1", "--light-selection", "power"]);
    let p0 = t("p0.exr", &["--pass", "0"]);
    let t3 = t("t3.exr", &["--tile", "2/3"]);
    let fails = |pieces: &[&std::path::Path], extra: &[&str], needle: &str| {
        let out = dir.join("out.exr");
        let mut args = vec!["merge", "-o", s(&out)];
        args.extend(pieces.iter().map(|p| s(p)));
        args.extend_from_slice(extra);
        let o = rtlang(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "merged {pieces:?}");
        assert!(err.contains(needle), "`{needle}` not in: {err}");
        assert!(!out.exists());
    };
    fails(&[&t1], &[], "missing");
    fails(&[&t1, &t2, &t3], &[], "overlap");
    fails(&[&t1, &t2_seed], &[], "seed");
    fails(&[&t1, &t2_size], &[], "image size");
    fails(&[&t1, &t2_sampler], &[], "sampler");
    // Tiles or passes that chose their lights otherwise (by the tree, by
    // power, or none at all) do not make one render.
    fails(
        &[&t1, &t2_power],
        &[],
        "light selection: tree against power",
    );
    fails(&[&t1, &t2_path], &[], "light selection: tree against none");
    fails(&[&p0, &p1_power], &["--average"], "light selection");
    fails(&[&t1, &t2_frame], &[], "scene");
    fails(&[&t1, &t2_pass], &[], "--average");
    fails(&[&t1, &t2_pass], &["--average"], "missing");
    std::fs::remove_file(dir.join("t2.exr.json")).expect("removes");
    fails(&[&t1, &t2], &[], "sidecar");
}

#[test]
fn only_pieces_and_requested_renders_get_a_sidecar() {
    let dir = folder("sidecars");
    let sidecar = |name: &str| dir.join(format!("{name}.json")).exists();
    render(&dir.join("plain.png"), &["--spp", "1"]);
    assert!(
        !sidecar("plain.png"),
        "a whole single render leaves only its image"
    );
    render(&dir.join("asked.exr"), &["--spp", "1", "--sidecar"]);
    render(&dir.join("tile.exr"), &["--spp", "1", "--tile", "1/2"]);
    render(&dir.join("crop.exr"), &["--spp", "1", "--crop", "0,4,0,4"]);
    render(&dir.join("pass.exr"), &["--spp", "1", "--pass", "0"]);
    let ck = dir.join("ck.bin");
    render(&dir.join("ck.exr"), &["--spp", "1", "--checkpoint", s(&ck)]);
    for name in ["asked.exr", "tile.exr", "crop.exr", "pass.exr", "ck.exr"] {
        assert!(sidecar(name), "{name} has no sidecar");
    }
}
