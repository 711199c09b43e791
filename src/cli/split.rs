//! Parsing how `rtlang render` splits work: `--tile I/N` (horizontal bands
//! of rows), `--frames A..B` (inclusive) and `{frame}` / `{frame:W}`
//! patterns in output names.

use std::path::{Path, PathBuf};

use rtlang::render::Crop;

/// Tile `index` (1-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub index: u32,
    pub count: u32,
}

/// Parses `I/N` with 1 ≤ I ≤ N.
pub fn parse_tile(s: &str) -> Result<Tile, String> {
    let (i, n) = s
        .split_once('/')
        .ok_or("expected I/N, e.g. 3/8 for the third of eight tiles")?;
    let num = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("`{v}`: {e}"));
    let (index, count) = (num(i)?, num(n)?);
    if index == 0 || index > count {
        return Err(format!("tile {index}/{count}: I must be between 1 and N"));
    }
    Ok(Tile { index, count })
}

impl Tile {
    /// The rows of this tile: the image cut into `count` bands of
    /// `height·(I−1)/N .. height·I/N` rows (full width), or `None` when the
    /// band is empty (more tiles than rows).
    pub fn crop(&self, width: u32, height: u32) -> Option<Crop> {
        let row = |k: u32| (height as u64 * k as u64 / self.count as u64) as u32;
        let (y0, y1) = (row(self.index - 1), row(self.index));
        (y0 < y1).then_some(Crop {
            x0: 0,
            x1: width,
            y0,
            y1,
        })
    }
}

/// Parses `A..B` (both included) or a single frame `A`.
pub fn parse_frames(s: &str) -> Result<(i64, i64), String> {
    let num = |v: &str| v.trim().parse::<i64>().map_err(|e| format!("`{v}`: {e}"));
    let (a, b) = match s.split_once("..") {
        Some((a, b)) => (num(a)?, num(b.trim_start_matches('='))?),
        None => (num(s)?, num(s)?),
    };
    if a > b {
        return Err(format!("frames {a}..{b}: the first is after the last"));
    }
    Ok((a, b))
}

/// Whether `path` contains a `{frame}` pattern.
pub fn has_frame_pattern(path: &Path) -> bool {
    path.to_string_lossy().contains("{frame")
}

/// The widest zero-padding `{frame:W}` may ask for (an i64 has 19 digits).
const MAX_FRAME_DIGITS: usize = 20;

/// `path` with every `{frame}` replaced by the frame number and every
/// `{frame:W}` by the number zero-padded to W digits.
pub fn expand_frame(path: &Path, frame: i64) -> Result<PathBuf, String> {
    let text = path.to_string_lossy();
    let mut out = String::new();
    let mut rest: &str = &text;
    while let Some(at) = rest.find("{frame") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "{frame".len()..];
        let end = after
            .find('}')
            .ok_or_else(|| format!("`{text}`: unclosed `{{frame`"))?;
        let spec = &after[..end];
        match spec.strip_prefix(':') {
            None if spec.is_empty() => out.push_str(&frame.to_string()),
            Some(w) => {
                let width: usize = w
                    .parse()
                    .ok()
                    .filter(|&width| width <= MAX_FRAME_DIGITS)
                    .ok_or_else(|| {
                        format!(
                            "`{text}`: `{{frame:{w}}}` needs a digit count of at most {MAX_FRAME_DIGITS}"
                        )
                    })?;
                out.push_str(&format!("{frame:0width$}"));
            }
            None => return Err(format!("`{text}`: write `{{frame}}` or `{{frame:4}}`")),
        }
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    Ok(PathBuf::from(out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_every_row_once() {
        for (h, n) in [(10, 3), (7, 7), (100, 8), (5, 2)] {
            let mut next = 0;
            for i in 1..=n {
                let c = Tile { index: i, count: n }.crop(4, h).expect("non-empty");
                assert_eq!((c.x0, c.x1, c.y0), (0, 4, next));
                next = c.y1;
            }
            assert_eq!(next, h);
        }
        assert_eq!(Tile { index: 1, count: 3 }.crop(4, 2), None);
    }

    #[test]
    fn tile_syntax() {
        assert_eq!(parse_tile("2/4"), Ok(Tile { index: 2, count: 4 }));
        assert!(parse_tile("0/4").is_err());
        assert!(parse_tile("5/4").is_err());
        assert!(parse_tile("2").is_err());
    }

    #[test]
    fn frames_and_patterns() {
        assert_eq!(parse_frames("3..5"), Ok((3, 5)));
        assert_eq!(parse_frames("7"), Ok((7, 7)));
        assert!(parse_frames("5..3").is_err());
        let p = |s: &str, f| expand_frame(Path::new(s), f).map(|p| p.display().to_string());
        assert_eq!(p("out/f{frame:04}.png", 12), Ok("out/f0012.png".into()));
        assert_eq!(p("f{frame}-{frame:2}.exr", 3), Ok("f3-03.exr".into()));
        assert!(p("f{frame:x}.png", 1).is_err());
        assert_eq!(p("{frame:20}", -1).map(|s| s.len()), Ok(20));
        assert!(p("f{frame:21}.png", 1).is_err());
        assert!(p("f{frame:999999999999}.png", 1).is_err());
        assert!(p("f{frame.png", 1).is_err());
        assert!(has_frame_pattern(Path::new("a{frame}.png")));
    }
}
