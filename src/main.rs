//! The `rtlang` command-line entry point.

fn main() -> miette::Result<()> {
    Ok(())
}
