//! `rtlang gen`: writes the project's procedural assets (porcelain and
//! planet textures, the bunny stand-in mesh) with the library generators.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};
use rtlang::gen::{self, critter, earth, porcelain, GenError};

/// Arguments of `rtlang gen`.
#[derive(Args)]
pub struct GenArgs {
    #[command(subcommand)]
    asset: Asset,
}

/// Size and seed shared by the texture generators.
#[derive(Args)]
struct TextureArgs {
    /// Output PNG file.
    #[arg(short, long)]
    output: PathBuf,
    /// Width in pixels.
    #[arg(long, default_value_t = 1024)]
    width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 512)]
    height: u32,
    /// Random seed; the same seed always gives the same bytes.
    #[arg(long)]
    seed: Option<u64>,
}

#[derive(Subcommand)]
enum Asset {
    /// Floral porcelain glaze texture, seamless in u (stands in for bottle.jpg).
    Porcelain(TextureArgs),
    /// Earth-like equirectangular planet map (stands in for earthmap.jpg).
    Earth(TextureArgs),
    /// Closed rabbit-like mesh with vertex normals (stands in for the Stanford bunny).
    Bunny {
        /// Output OBJ file.
        #[arg(short, long)]
        output: PathBuf,
        /// Grid spacing of the polygoniser in design units (the figure is ~17 tall).
        #[arg(long, default_value_t = 0.45)]
        cell: f64,
    },
}

/// Runs `rtlang gen`.
pub fn run(args: GenArgs) -> ExitCode {
    match generate(args.asset) {
        Ok(message) => {
            outln!("{message}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            errln!("{:?}", miette::Report::new(e));
            ExitCode::FAILURE
        }
    }
}

fn generate(asset: Asset) -> Result<String, GenError> {
    match asset {
        Asset::Porcelain(t) => {
            gen::check_size(t.width, t.height)?;
            let defaults = porcelain::PorcelainOptions::default();
            let canvas = porcelain::porcelain(porcelain::PorcelainOptions {
                width: t.width,
                height: t.height,
                seed: t.seed.unwrap_or(defaults.seed),
            });
            gen::write_png(&canvas, &t.output)?;
            Ok(format!("wrote {}", t.output.display()))
        }
        Asset::Earth(t) => {
            gen::check_size(t.width, t.height)?;
            let defaults = earth::EarthOptions::default();
            let canvas = earth::earth(earth::EarthOptions {
                width: t.width,
                height: t.height,
                seed: t.seed.unwrap_or(defaults.seed),
            });
            gen::write_png(&canvas, &t.output)?;
            Ok(format!("wrote {}", t.output.display()))
        }
        Asset::Bunny { output, cell } => {
            if !(0.05..=2.0).contains(&cell) {
                return Err(GenError::Cell { cell });
            }
            let mesh = critter::critter(critter::CritterOptions { cell });
            let command = format!("rtlang gen bunny --cell {cell}");
            let header = [
                "rtlang's generated stand-in for the Stanford bunny",
                command.as_str(),
            ];
            gen::write_obj(&mesh, &header, &output)?;
            Ok(format!(
                "wrote {} ({} vertices, {} triangles)",
                output.display(),
                mesh.positions.len(),
                mesh.triangles.len()
            ))
        }
    }
}
