//! `gltf("scene.glb")`: a glTF 2.0 file's default scene as one object
//! (its meshes with their materials, its punctual lights as lamps), and
//! the camera block's `gltf` property (the file's first perspective
//! camera). The file is parsed by [`crate::scene::gltf`], once per path;
//! here its data becomes scene nodes, with the photometric units of glTF
//! lights converted to rtlang's radiometric ones.

use std::rc::Rc;

use glam::{Mat4, Vec3};

use super::{budget, Eval, Evaluator};
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::gltf::{load_gltf, GltfCamera, GltfError, GltfFile, GltfLight, Placed};
use crate::scene::{Lamp, Node};

/// Luminous efficacy in lm/W by which glTF's candela and lux become W/sr
/// and W/m²: 683, the figure Blender's exporter multiplies by in its
/// default ("standard") lighting mode, so a Blender light arrives with the
/// radiometric value Blender renders with.
pub const LUMENS_PER_WATT: f32 = 683.0;

/// What one glTF file became: the scene's node and its cameras.
#[derive(Clone)]
pub(super) struct LoadedGltf {
    node: Rc<Node>,
    cameras: Vec<(Mat4, GltfCamera)>,
}

impl Evaluator {
    /// `gltf(path)`.
    pub(crate) fn gltf_call(&mut self, a: &mut super::Args, _: Span) -> Eval<super::Value> {
        let (v, s) = a.positional[0].clone();
        let path = self.string(&v, s)?;
        let loaded = self.gltf_file(&path, s)?;
        Ok(super::Value::Object(loaded.node))
    }

    /// The glTF file `path` loaded and made into nodes (once per path).
    pub(super) fn gltf_file(&mut self, path: &str, span: Span) -> Eval<LoadedGltf> {
        let full = self.resolve(path, span);
        self.check_type(&full, span, &["gltf", "glb"], "glTF")?;
        if self.dry {
            return Ok(LoadedGltf {
                node: Rc::new(Node::Group(Vec::new())),
                cameras: Vec::new(),
            });
        }
        if let Some(hit) = self.caches.gltf.get(&full) {
            return Ok(hit.clone());
        }
        let size = self.charge_file(
            &full,
            budget::BYTES_PER_GLTF_BYTE,
            span,
            "this glTF file while it is loaded",
        )?;
        let left = (self.options.memory_budget as f64 - self.memory.estimate).max(0.0);
        let limit = ((left / budget::BYTES_PER_GLTF_BYTE) as u64 + size)
            .min(crate::scene::gltf::MAX_GLTF_BYTES);
        let file = match load_gltf(&full, limit) {
            Ok(file) => file,
            Err(e) => return Err(self.report(gltf_error(&e, span))),
        };
        let buffers = file.bytes.saturating_sub(size) as f64;
        self.charge(
            buffers * budget::BYTES_PER_GLTF_BYTE,
            span,
            "this glTF file's buffers while they are loaded",
        )?;
        for w in &file.warnings {
            self.warn_gltf(span, w.clone());
        }
        let loaded = self.gltf_nodes(&file, span);
        self.caches.gltf.insert(full, loaded.clone());
        Ok(loaded)
    }

    /// A warning about a glTF file at `span`.
    pub(super) fn warn_gltf(&mut self, span: Span, message: String) {
        self.diagnostics.push(
            Diagnostic::warning(Code::MeshWarning, span, message)
                .label("in this glTF file")
                .help("the file loads without what the warning names"),
        );
    }

    /// The nodes of a loaded file.
    fn gltf_nodes(&mut self, file: &GltfFile, span: Span) -> LoadedGltf {
        let materials = self.gltf_materials(file, span);
        let mut meshes = Vec::with_capacity(file.meshes.len());
        for (mesh, material) in &file.meshes {
            let id = self.scene.add_mesh(std::sync::Arc::new(mesh.clone()));
            let m = match material {
                Some(k) => materials[*k],
                None => materials[file.materials.len()],
            };
            meshes.push((id, m));
        }
        let mut children = Vec::new();
        let mut cameras = Vec::new();
        for (matrix, placed) in &file.placed {
            let child = match placed {
                Placed::Mesh(k) => {
                    let (mesh, material) = meshes[*k];
                    Node::Mesh {
                        mesh,
                        materials: vec![material],
                    }
                }
                Placed::Light(light) => Node::Lamp(lamp(light)),
                Placed::Camera(camera) => {
                    cameras.push((*matrix, camera.clone()));
                    continue;
                }
            };
            if matrix.determinant().abs() < 1e-12 {
                self.warn_gltf(
                    span,
                    "a node has a transform that flattens it (scale 0); it is skipped".into(),
                );
                continue;
            }
            children.push(if *matrix == Mat4::IDENTITY {
                child
            } else {
                Node::Transform {
                    matrix: *matrix,
                    child: Box::new(child),
                }
            });
        }
        if children.is_empty() {
            self.warn_gltf(span, "the file's scene places no mesh and no light".into());
        }
        LoadedGltf {
            node: Rc::new(Node::Group(children)),
            cameras,
        }
    }

    /// The camera block's `gltf "file"`: the file's first perspective
    /// camera as (from, at, up, vertical field of view in degrees).
    pub(super) fn gltf_camera(&mut self, path: &str, span: Span) -> Eval<(Vec3, Vec3, Vec3, f32)> {
        let loaded = self.gltf_file(path, span)?;
        if self.dry {
            return Ok((Vec3::Z, Vec3::ZERO, Vec3::Y, 40.0));
        }
        let first = loaded
            .cameras
            .iter()
            .find_map(|(m, c)| c.perspective.map(|p| (m, p)));
        let Some((m, p)) = first else {
            let (message, help) = match loaded.cameras.first() {
                Some((_, c)) => (
                    format!("the glTF camera `{}` is orthographic", c.name),
                    "rtlang's camera is perspective: give the file a perspective camera, \
                     or set `from`, `at` and `fov` instead",
                ),
                None => (
                    "the glTF file's scene has no camera".to_string(),
                    "add a camera to the file, or set `from`, `at` and `fov` instead",
                ),
            };
            return Err(self.report(
                Diagnostic::error(Code::Mesh, span, message)
                    .label("camera taken from here")
                    .help(help),
            ));
        };
        let from = m.transform_point3(Vec3::ZERO);
        let at = m.transform_point3(-Vec3::Z);
        let up = m.transform_vector3(Vec3::Y);
        let fov = p.yfov.to_degrees();
        let ok = (at - from).length() > 1e-6 && up.cross(at - from).length() > 1e-9;
        if !(ok && fov > 0.0 && fov < 180.0) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Mesh,
                    span,
                    "the glTF camera's transform or field of view is degenerate",
                )
                .label("camera taken from here")
                .help("the camera's node must not scale it to zero, and yfov must be in (0, π)"),
            ));
        }
        Ok((from, at, up, fov))
    }
}

/// A glTF light as a lamp in its node's space: glTF lights shine along
/// −z; candela and lux over [`LUMENS_PER_WATT`] become W/sr and W/m².
fn lamp(light: &GltfLight) -> Lamp {
    let watts =
        |color: Vec3, intensity: f32| color.max(Vec3::ZERO) * intensity.max(0.0) / LUMENS_PER_WATT;
    match *light {
        GltfLight::Point { color, intensity } => Lamp::Point {
            at: Vec3::ZERO,
            intensity: watts(color, intensity),
        },
        GltfLight::Spot {
            color,
            intensity,
            inner,
            outer,
        } => Lamp::Spot {
            at: Vec3::ZERO,
            to: -Vec3::Z,
            intensity: watts(color, intensity),
            cutoff: outer.clamp(1e-4, std::f32::consts::FRAC_PI_2),
            beam: inner.clamp(0.0, outer.clamp(1e-4, std::f32::consts::FRAC_PI_2)),
        },
        GltfLight::Directional { color, intensity } => Lamp::Sun {
            direction: Vec3::Z,
            irradiance: watts(color, intensity),
            diameter: 0.0,
        },
    }
}

/// The diagnostic of a file that did not load.
fn gltf_error(e: &GltfError, span: Span) -> Diagnostic {
    let help = match e {
        GltfError::Io { .. } => "relative paths resolve against the directory of the scene file",
        GltfError::Extension { .. } => {
            "export the file again without that extension (e.g. without Draco compression)"
        }
        GltfError::Parse { .. } | GltfError::Invalid { .. } => {
            "check the file with the Khronos glTF validator, or export it again"
        }
    };
    Diagnostic::error(Code::Mesh, span, e.to_string())
        .label("glTF file used here")
        .help(help)
}
