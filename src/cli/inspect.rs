//! `rtlang inspect MESH.obj`: what the OBJ loader makes of a mesh file —
//! counts, bounds, material slots and warnings — as text or JSON.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use rtlang::scene::mesh::MeshMaterialKind;
use rtlang::scene::obj::load_obj;

use super::compare::Format;

/// Load a mesh file and summarise it.
#[derive(Args)]
pub struct InspectArgs {
    /// The OBJ file.
    pub mesh: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Text)]
    pub format: Format,
}

/// Runs the command; a file that does not load is a diagnostic and exit 1.
pub fn run(args: InspectArgs) -> ExitCode {
    let loaded = match load_obj(&args.mesh) {
        Ok(loaded) => loaded,
        Err(e) => {
            let report = miette::miette!(
                code = "rtlang::mesh",
                help = "rtlang reads Wavefront OBJ files with an optional MTL beside them",
                "{e}"
            );
            errln!("{report:?}");
            return ExitCode::FAILURE;
        }
    };
    let mesh = &loaded.mesh;
    let (lo, hi) = mesh.bounds().unwrap_or_default();
    let materials: Vec<String> = mesh
        .materials
        .iter()
        .map(|m| format!("{} ({})", m.name, kind_name(&m.kind)))
        .collect();
    match args.format {
        Format::Json => {
            let value = serde_json::json!({
                "file": args.mesh.display().to_string(),
                "triangles": mesh.triangles.len(),
                "vertices": mesh.positions.len(),
                "normals": !mesh.normals.is_empty(),
                "uvs": !mesh.uvs.is_empty(),
                "min": [lo.x, lo.y, lo.z],
                "max": [hi.x, hi.y, hi.z],
                "materials": materials,
                "warnings": loaded.warnings,
            });
            outln!("{value}");
        }
        Format::Text => {
            outln!("{}", args.mesh.display());
            outln!(
                "  {} triangles, {} vertices, normals: {}, uvs: {}",
                mesh.triangles.len(),
                mesh.positions.len(),
                yes_no(!mesh.normals.is_empty()),
                yes_no(!mesh.uvs.is_empty())
            );
            outln!(
                "  bounds ({}, {}, {}) .. ({}, {}, {})",
                lo.x,
                lo.y,
                lo.z,
                hi.x,
                hi.y,
                hi.z
            );
            for m in &materials {
                outln!("  material {m}");
            }
            for w in &loaded.warnings {
                outln!("  warning: {w}");
            }
        }
    }
    ExitCode::SUCCESS
}

fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

fn kind_name(kind: &MeshMaterialKind) -> &'static str {
    match kind {
        MeshMaterialKind::Diffuse { .. } => "diffuse",
        MeshMaterialKind::Plastic { .. } => "plastic",
        MeshMaterialKind::Metal { .. } => "metal",
        MeshMaterialKind::Dielectric { .. } => "dielectric",
        MeshMaterialKind::Light { .. } => "light",
    }
}
