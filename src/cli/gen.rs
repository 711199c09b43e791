//! `rtlang gen`: writes the project's procedural assets (porcelain and
//! planet textures, the bunny stand-in mesh) with the library generators.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};
use rtlang::gen::{self, critter, earth, porcelain, sky, GenError};

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
    /// Clear sky (Preetham model) as a latitude–longitude OpenEXR for
    /// `background environment(...)`; the sun's disk is left to a `sun` light.
    Sky {
        /// Output EXR file.
        #[arg(short, long)]
        output: PathBuf,
        /// Width in pixels.
        #[arg(long, default_value_t = 1024)]
        width: u32,
        /// Height in pixels.
        #[arg(long, default_value_t = 512)]
        height: u32,
        /// The sun's elevation above the horizon, degrees (0 to 90).
        #[arg(long, default_value_t = 30.0)]
        elevation: f64,
        /// The sun's azimuth, degrees from −z towards +x.
        #[arg(long, default_value_t = 0.0)]
        azimuth: f64,
        /// Haze, 2 (very clear) to 10.
        #[arg(long, default_value_t = 3.0)]
        turbidity: f64,
    },
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
        Asset::Sky {
            output,
            width,
            height,
            elevation,
            azimuth,
            turbidity,
        } => {
            gen::check_size(width, height)?;
            let range = |what, value: f64, ok: bool| {
                if ok {
                    Ok(())
                } else {
                    Err(GenError::Sky { what, value })
                }
            };
            range("elevation", elevation, (0.0..=90.0).contains(&elevation))?;
            range("azimuth", azimuth, azimuth.is_finite())?;
            range("turbidity", turbidity, (2.0..=10.0).contains(&turbidity))?;
            let options = sky::SkyOptions {
                width,
                height,
                elevation,
                azimuth,
                turbidity,
            };
            gen::write_exr(&sky::preetham(&options), width, height, &output)?;
            let d = sky::sun_direction(&options);
            Ok(format!(
                "wrote {}; its sun is in direction ({:.4}, {:.4}, {:.4})",
                output.display(),
                d.x,
                d.y,
                d.z
            ))
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
