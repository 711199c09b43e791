//! The memory budget: every allocation whose size the scene controls is
//! estimated as the scene is evaluated (primitives, so `repeat` counts;
//! tessellated and analytic surfaces of revolution; meshes per placement;
//! media; light entries; texture images, from their headers before they
//! are decoded; the image and its film), and the scene is refused at the
//! object that takes the total past the budget, with both figures in the
//! message, before anything that large is allocated. The per-item figures
//! are upper bounds of the renderer's peak use (`tests/robust_memory.rs`
//! renders the largest accepted scene of each kind under an address-space
//! cap; docs/testing.md gives the measured margins).

use std::path::Path;

use super::{Eval, Evaluator, Fail};
use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::object::RevolutionMode;
use crate::scene::{Material, Node, Scene, Shape};

/// The budget when none is given: 16 GiB, like the image guard.
pub const DEFAULT_BUDGET: u64 = 16 << 30;

/// One placed primitive (sphere, rect, box, triangle, plane, medium, placed
/// prototype): its scene node, its built primitive with bounds, its BVH
/// leaf and inner nodes, its light entry, and the builder's scratch.
pub const BYTES_PER_PRIMITIVE: f64 = 1024.0;
/// One triangle of a mesh (a tessellated revolution or an OBJ file, counted
/// per placement): its indices and share of the vertex arrays, its order
/// entry, BVH nodes, light entry and the builder's scratch, with the growth
/// slack of the arrays the tessellation fills.
pub const BYTES_PER_TRIANGLE: f64 = 400.0;
/// What an emitting triangle adds: its light entry, its light-tree bounds
/// (f64), its share of the tree's nodes and the build's scratch. (An
/// emitting shape's light fits in its `BYTES_PER_PRIMITIVE`.)
pub const BYTES_PER_LIGHT: f64 = 1024.0;
/// One shell piece of an analytic revolution: the piece (its parameter
/// range, end points, box and control points: about 170 bytes for a cubic
/// profile) and its share of the four-wide shell tree (about 55 bytes),
/// with room for profiles of higher degree.
pub const BYTES_PER_SHELL: f64 = 1024.0;

/// One byte of a scene file while it is parsed and evaluated: its text
/// (kept for diagnostics), line table, syntax tree and the values built
/// from it (three 63 MiB includes took 7.1 GB, 36 bytes a byte). Charged
/// for every file of a scene, so includes add up.
pub const BYTES_PER_SOURCE_BYTE: f64 = 40.0;
/// One byte of an OBJ file while it is loaded: the file's bytes, tobj's
/// arrays and vertex map, and the mesh built from them (a 2e7-face file of
/// 8-byte face lines peaked at 2.8 GB, about 18 bytes a byte). Its
/// triangles are charged again, per placement, once it is loaded.
pub const BYTES_PER_OBJ_BYTE: f64 = 32.0;

/// One byte of a glTF file or of its buffers while it is loaded: the
/// bytes, and the mesh arrays copied out of them (vertex data is copied
/// about once, with normals and texture coordinates widened to f32).
pub const BYTES_PER_GLTF_BYTE: f64 = 4.0;

/// One texture image pixel while its file is decoded: the file's bytes,
/// the decoded and 8-bit RGB copies and the linear `Vec3` kept (12 bytes).
pub const BYTES_PER_IMAGE_PIXEL: f64 = 32.0;
/// One pixel of the rendered image: the film's sum and counts (20 bytes),
/// the finished pixels (12), the encoded output and the allocator's growth
/// (64 bytes was too few: a 2047² image failed under the address cap).
pub const BYTES_PER_FILM_PIXEL: f64 = 128.0;

/// A byte count in the largest unit that keeps it above 1.
pub fn human(bytes: f64) -> String {
    const UNITS: [&str; 4] = ["bytes", "KiB", "MiB", "GiB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{value:.0} bytes")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

/// The estimated bytes of one node built from an object (children of groups
/// are charged when they are built themselves).
pub fn node_bytes(node: &Node, scene: &Scene) -> f64 {
    match node {
        Node::Shape {
            shape: Shape::Revolution { mode, .. },
            ..
        } => match *mode {
            RevolutionMode::Mesh { resolution } => {
                let r = resolution.max(3) as f64;
                2.0 * r * r * BYTES_PER_TRIANGLE
            }
            RevolutionMode::Analytic { resolution, .. } => {
                resolution as f64 * BYTES_PER_SHELL + BYTES_PER_PRIMITIVE
            }
        },
        Node::Shape { .. } | Node::Medium { .. } | Node::Instance(_) => BYTES_PER_PRIMITIVE,
        Node::Mesh { mesh, materials } => {
            let triangles = scene
                .meshes
                .get(mesh.0 as usize)
                .map_or(0, |m| m.triangles.len());
            let emits = materials
                .iter()
                .any(|m| matches!(scene.material(*m), Material::Light { .. }));
            let light = if emits { BYTES_PER_LIGHT } else { 0.0 };
            triangles as f64 * (BYTES_PER_TRIANGLE + light)
        }
        Node::Group(_)
        | Node::Transform { .. }
        | Node::Motion { .. }
        | Node::Flip(_)
        | Node::Lamp(_) => 0.0,
    }
}

/// The estimated bytes of a whole tree (a definition placed by copy).
pub fn tree_bytes(node: &Node, scene: &Scene) -> f64 {
    let children = match node {
        Node::Group(nodes) => nodes.iter().collect(),
        Node::Transform { child, .. } | Node::Motion { child, .. } | Node::Flip(child) => {
            vec![child.as_ref()]
        }
        Node::Medium { boundary, .. } => vec![boundary.as_ref()],
        Node::Shape { .. } | Node::Mesh { .. } | Node::Instance(_) | Node::Lamp(_) => Vec::new(),
    };
    node_bytes(node, scene)
        + children
            .into_iter()
            .map(|c| tree_bytes(c, scene))
            .sum::<f64>()
}

impl Evaluator {
    /// Adds `bytes` for `what` at `span` to the scene's estimate; past the
    /// budget, reports it (once) and fails.
    /// Objects inside a definition are charged where it is placed.
    pub(super) fn charge(&mut self, bytes: f64, span: Span, what: &str) -> Eval<()> {
        if self.dry || !self.def_stack.is_empty() {
            return Ok(());
        }
        if self.memory.refused {
            return Err(Fail);
        }
        self.memory.estimate += bytes;
        let budget = self.options.memory_budget as f64;
        if self.memory.estimate <= budget {
            return Ok(());
        }
        self.memory.refused = true;
        Err(self.halt(
            Diagnostic::error(
                Code::MemoryBudget,
                span,
                format!(
                    "the scene would need about {} of memory, more than the budget of {}",
                    human(self.memory.estimate),
                    human(budget)
                ),
            )
            .label(format!("{what}: about {}", human(bytes)))
            .help(
                "lower this object's resolution or count, use a mesh or a placed \
                 definition for many copies, or raise the budget with `--memory-budget GIB`",
            ),
        ))
    }

    /// Charges the film of the scene's image size, at its `size` (or its
    /// `render` block); a default size is counted without a place.
    pub(super) fn charge_film(&mut self) {
        let s = &self.scene.settings;
        let bytes = s.width as f64 * s.height as f64 * BYTES_PER_FILM_PIXEL;
        match self.size_span.or(self.render_seen) {
            Some(span) => {
                let _ = self.charge(bytes, span, "the image and its film");
            }
            None => self.memory.estimate += bytes,
        }
    }

    /// Charges the size of the regular file `path` at `factor` bytes a
    /// byte, before it is read, and gives the size (the most bytes it may
    /// then be read with); a file that is missing or no regular file is
    /// charged nothing (reading it reports why).
    pub(super) fn charge_file(
        &mut self,
        path: &Path,
        factor: f64,
        span: Span,
        what: &str,
    ) -> Eval<u64> {
        let Ok(size) = crate::scene::file::regular_size(path) else {
            return Ok(0);
        };
        self.charge(size as f64 * factor, span, what)?;
        Ok(size)
    }

    /// Charges the node built from an object.
    pub(super) fn charge_node(&mut self, node: &Node, span: Span) -> Eval<()> {
        let bytes = node_bytes(node, &self.scene);
        self.charge(bytes, span, "this object")
    }

    /// Charges a copy of a whole tree (a definition placed once).
    pub(super) fn charge_tree(&mut self, node: &Node, span: Span) -> Eval<()> {
        let bytes = tree_bytes(node, &self.scene);
        self.charge(bytes, span, "this placement")
    }
}

/// The running estimate of one evaluation.
#[derive(Default)]
pub(super) struct Memory {
    pub estimate: f64,
    /// The budget was exceeded and reported; later charges fail quietly.
    pub refused: bool,
}
