//! Object blocks → scene nodes: shapes with their checks, meshes,
//! surfaces of revolution, media, groups, loops and placements of defined
//! objects (as shared prototypes when placed more than once).

use crate::lang::codes::Code;
use glam::{DVec2, DVec3};

use super::props::{Allow, Block};
use super::steps::Site;
use super::value::Value;
use super::{Eval, Evaluator, Fail};
use crate::lang::ast::{Object, ObjectKind, RectPlane, Stmt};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::properties::{self, cuboid, medium, mesh, plane, rect, revolve, sphere, triangle};
use crate::lang::source::Span;
use crate::scene::light::holds_lamp;
use crate::scene::object::{RectPlane as Plane, RevolutionMode};
use crate::scene::{MaterialId, Node, Shape};

/// The most loop iterations one `repeat` may run.
const MAX_ITERATIONS: f64 = 10_000_000.0;

/// A block that takes no property, only transforms and objects.
fn holder(what: &'static str) -> Allow {
    Allow {
        what,
        props: &[],
        transforms: true,
        children: true,
        size: false,
        shutter: false,
    }
}

impl Evaluator {
    /// A top-level statement: the node it adds to the world, if any.
    pub(super) fn top_stmt(&mut self, stmt: &Stmt) -> Eval<Option<Node>> {
        self.step(1, super::statement_span(stmt))?;
        match stmt {
            Stmt::Object(o) => self.object(o).map(Some),
            Stmt::Place {
                name, args, body, ..
            } => self.place(name, args.as_deref(), body).map(Some),
            Stmt::If {
                cond,
                then,
                otherwise,
                ..
            } => self.if_stmt(cond, then, otherwise),
            other => {
                let span = match other {
                    Stmt::Property { span, .. }
                    | Stmt::Size { span, .. }
                    | Stmt::Shutter { span, .. } => *span,
                    Stmt::Motion { span, .. } | Stmt::Flip { span } => *span,
                    Stmt::Transform(t) => t.span,
                    Stmt::Object(_) | Stmt::Place { .. } | Stmt::If { .. } => {
                        unreachable!("handled above")
                    }
                };
                Err(self.report(
                    Diagnostic::error(Code::Misplaced, span, "this belongs inside a block")
                        .label("not allowed at top level")
                        .help("properties and transforms go inside an object, `render` or `camera` block"),
                ))
            }
        }
    }

    /// The node of an object block, transforms applied.
    pub(super) fn object(&mut self, o: &Object) -> Eval<Node> {
        let (node, block) = match &o.kind {
            ObjectKind::Sphere => {
                let b = self.block(&o.body, &Allow::props(&properties::SPHERE, true));
                (self.sphere(&b, o), b)
            }
            ObjectKind::Plane => {
                let b = self.block(&o.body, &Allow::props(&properties::PLANE, true));
                (self.plane(&b, o), b)
            }
            ObjectKind::Rect(plane) => {
                let b = self.block(&o.body, &Allow::props(&properties::RECT, true));
                (self.rect(&b, *plane, o), b)
            }
            ObjectKind::Box => {
                let b = self.block(&o.body, &Allow::props(&properties::BOX, true));
                (self.cuboid(&b, o), b)
            }
            ObjectKind::Triangle => {
                let b = self.block(&o.body, &Allow::props(&properties::TRIANGLE, true));
                (self.triangle(&b, o), b)
            }
            ObjectKind::Mesh(path) => {
                let b = self.block(&o.body, &Allow::props(&properties::MESH, true));
                (self.mesh_node(&b, path), b)
            }
            ObjectKind::Revolve(curve) => {
                let b = self.block(&o.body, &Allow::props(&properties::REVOLVE, true));
                (self.revolve(&b, curve, o), b)
            }
            ObjectKind::Medium => {
                let b = self.block(&o.body, &Allow::props(&properties::MEDIUM, true));
                (self.medium(&b, o), b)
            }
            ObjectKind::Sun => {
                let b = self.block(&o.body, &Allow::props(&properties::SUN, true));
                (self.sun(&b), b)
            }
            ObjectKind::PointLight => {
                let b = self.block(&o.body, &Allow::props(&properties::POINT_LIGHT, true));
                (self.point_light(&b), b)
            }
            ObjectKind::SpotLight => {
                let b = self.block(&o.body, &Allow::props(&properties::SPOT_LIGHT, true));
                (self.spot_light(&b, o), b)
            }
            ObjectKind::Group => {
                let b = self.block(&o.body, &holder("group"));
                (self.children(&b.children).map(Node::Group), b)
            }
            ObjectKind::Repeat { var, from, to } => return self.repeat(var, from, to, o),
        };
        if let Ok(n) = &node {
            self.charge_node(n, o.head)?;
        }
        let transformed = self.apply_transforms(&block.transforms);
        let node = transformed?.wrap(flipped(node?, block.flip));
        if matches!(node, Node::Motion { .. }) && holds_lamp(&self.scene, &node) {
            return Err(self.report(
                Diagnostic::error(
                    Code::Range,
                    o.head,
                    "a light that is not a shape cannot move",
                )
                .label("this moves a sun, point or spot light")
                .help("place the light outside the `motion`, or use a moving emissive shape"),
            ));
        }
        Ok(node)
    }

    /// `if COND { ... } else { ... }`: the objects of the branch taken (the
    /// other branch is not evaluated); nothing when that branch is empty.
    fn if_stmt(
        &mut self,
        cond: &crate::lang::ast::Expr,
        then: &[Stmt],
        otherwise: &[Stmt],
    ) -> Eval<Option<Node>> {
        let v = self.expr(cond)?;
        let branch = if self.condition(&v, cond.span)? {
            then
        } else {
            otherwise
        };
        let allow = holder("if");
        let block = self.block(
            branch,
            &Allow {
                transforms: false,
                ..allow
            },
        );
        self.enter(Site::Branch);
        let nodes = self.children(&block.children);
        self.leave();
        let nodes = nodes?;
        Ok((!nodes.is_empty()).then(|| group_of(nodes)))
    }

    /// The nodes of child statements, all evaluated even when some fail.
    fn children(&mut self, stmts: &[&Stmt]) -> Eval<Vec<Node>> {
        let mut nodes = Vec::with_capacity(stmts.len());
        let mut failed = false;
        for stmt in stmts {
            match self.top_stmt(stmt) {
                Ok(Some(node)) => nodes.push(node),
                Ok(None) => {}
                Err(_) => failed = true,
            }
        }
        if failed {
            Err(Fail)
        } else {
            Ok(nodes)
        }
    }

    /// The material of a shape: required except inside a medium's boundary.
    fn shape_material(&mut self, b: &Block, o: &Object) -> Eval<MaterialId> {
        match self.prop(b, &properties::MATERIAL)? {
            Some((v, s)) => self.material(&v, s),
            None if self.in_boundary > 0 => Ok(self.default_material()),
            None => Err(self.missing(
                o,
                "material",
                "add e.g. `material lambertian(rgb(0.5, 0.5, 0.5))`",
            )),
        }
    }

    fn missing(&mut self, o: &Object, name: &str, help: &str) -> Fail {
        // A misspelt `name`, or a material under another renderer's word
        // (`color`), is already reported as an unknown property.
        let misspelt = o.body.iter().any(|s| {
            matches!(s, Stmt::Property { name: p, .. }
                if crate::lang::names::suggest(&p.name, [name]).is_some()
                    || (name == "material"
                        && properties::MATERIAL_ALIASES.contains(&p.name.as_str())))
        });
        if misspelt {
            return Fail;
        }
        self.report(
            Diagnostic::error(
                Code::MissingProperty,
                o.head,
                format!("this object needs a `{name}`"),
            )
            .label(format!("no `{name}`"))
            .help(help.to_string()),
        )
    }

    fn shape(&mut self, shape: Eval<Shape>, material: Eval<MaterialId>) -> Eval<Node> {
        let (shape, material) = (shape?, material?);
        Ok(Node::Shape { shape, material })
    }

    fn sphere(&mut self, b: &Block, o: &Object) -> Eval<Node> {
        let center = self.prop_vec3(b, &sphere::CENTER, DVec3::ZERO);
        let radius = self.prop_num(b, &sphere::RADIUS, 1.0).and_then(|(r, s)| {
            self.range(
                r > 0.0,
                s,
                format!("the radius must be positive, not {r}"),
                "a sphere's radius is its size in scene units",
            )?;
            let least = crate::scene::object::MIN_RADIUS;
            self.range(
                r as f32 >= least,
                s,
                format!("the radius {r:e} is below the smallest, {least:e}"),
                "rtlang traces rays in f32, where the square of a smaller radius underflows and \
                 the sphere would vanish; scale the whole scene up",
            )?;
            Ok(r)
        });
        let material = self.shape_material(b, o);
        let shape = center.and_then(|(c, _)| {
            Ok(Shape::Sphere {
                center: c.as_vec3(),
                radius: radius? as f32,
            })
        });
        self.shape(shape, material)
    }

    fn plane(&mut self, b: &Block, o: &Object) -> Eval<Node> {
        let normal = self
            .prop_vec3(b, &plane::NORMAL, DVec3::Y)
            .and_then(|(n, s)| self.unit(n, s, "the normal"));
        let point = self.prop(b, &plane::POINT);
        let offset = self.prop(b, &plane::OFFSET);
        let material = self.shape_material(b, o);
        let (normal, point, offset) = (normal?, point?, offset?);
        let point = match (point, offset) {
            (Some(_), Some((_, s))) => {
                return Err(self.report(
                    Diagnostic::error(
                        Code::Conflict,
                        s,
                        "a plane takes `point` or `offset`, not both",
                    )
                    .label("second way to place the plane")
                    .help("keep one: `point (x, y, z)` or `offset d` along the normal"),
                ))
            }
            (Some((v, s)), None) => self.vec3(&v, s)?,
            (None, Some((v, s))) => normal * self.num(&v, s)?,
            (None, None) => DVec3::ZERO,
        };
        let shape = Ok(Shape::Plane {
            point: point.as_vec3(),
            normal: normal.as_vec3(),
        });
        self.shape(shape, material)
    }

    /// `v` normalised; zero-length vectors are errors.
    pub(super) fn unit(&mut self, v: DVec3, span: Span, what: &str) -> Eval<DVec3> {
        let len = v.length();
        self.range(
            len > 1e-12 && len.is_finite(),
            span,
            format!("{what} has zero length"),
            "give a direction, such as (0, 1, 0)",
        )?;
        Ok(v / len)
    }

    fn rect(&mut self, b: &Block, plane: RectPlane, o: &Object) -> Eval<Node> {
        let from = self.prop_vec2(b, &rect::FROM, DVec2::ZERO);
        let to = self.prop_vec2(b, &rect::TO, DVec2::ONE);
        let at = self.prop_num(b, &rect::AT, 0.0);
        let material = self.shape_material(b, o);
        let ((from, _), (to, ts), (at, _)) = (from?, to?, at?);
        let (lo, hi) = (from.min(to), from.max(to));
        self.range(
            (hi - lo).min_element() > 0.0,
            if ts.is_empty() { o.head } else { ts },
            "the rectangle has zero area".to_string(),
            "`from` and `to` are opposite corners and must differ in both coordinates",
        )?;
        let shape = Ok(Shape::Rect {
            plane: match plane {
                RectPlane::Xy => Plane::Xy,
                RectPlane::Xz => Plane::Xz,
                RectPlane::Yz => Plane::Yz,
            },
            a: (lo.x as f32, hi.x as f32),
            b: (lo.y as f32, hi.y as f32),
            k: at as f32,
        });
        self.shape(shape, material)
    }

    fn cuboid(&mut self, b: &Block, o: &Object) -> Eval<Node> {
        let min = self.prop_vec3(b, &cuboid::MIN, DVec3::ZERO);
        let max = self.prop_vec3(b, &cuboid::MAX, DVec3::ONE);
        let material = self.shape_material(b, o);
        let ((min, _), (max, ms)) = (min?, max?);
        self.range(
            (max - min).min_element() > 0.0,
            if ms.is_empty() { o.head } else { ms },
            format!(
                "`max` ({}, {}, {}) must exceed `min` ({}, {}, {}) in every coordinate",
                max.x, max.y, max.z, min.x, min.y, min.z
            ),
            "a box spans from its `min` corner to its `max` corner",
        )?;
        let shape = Ok(Shape::Cuboid {
            min: min.as_vec3(),
            max: max.as_vec3(),
        });
        self.shape(shape, material)
    }

    fn triangle(&mut self, b: &Block, o: &Object) -> Eval<Node> {
        let a = self.prop_vec3(b, &triangle::A, DVec3::ZERO);
        let bb = self.prop_vec3(b, &triangle::B, DVec3::X);
        let c = self.prop_vec3(b, &triangle::C, DVec3::Y);
        let material = self.shape_material(b, o);
        let ((a, sa), (bv, sb), (c, sc)) = (a?, bb?, c?);
        let limit = crate::scene::object::MAX_COORDINATE;
        for (v, span) in [(a, sa), (bv, sb), (c, sc)] {
            self.range(
                v.as_vec3().abs().max_element() <= limit,
                if span.is_empty() { o.span } else { span },
                format!(
                    "the corner ({}, {}, {}) lies beyond the coordinate limit ±{limit:e}",
                    v.x, v.y, v.z
                ),
                "triangle corners must stay within ±1e18 (an f32 area of larger ones \
                 overflows); scale the whole scene down, or use a sphere or rect",
            )?;
        }
        let area2 = (bv - a).cross(c - a).length();
        let scale = (bv - a).length().max((c - a).length()).max(1e-300);
        self.range(
            area2 > 1e-12 * scale * scale,
            o.span,
            "the triangle is degenerate (zero area)".to_string(),
            "its three corners must not lie on one line",
        )?;
        let shape = Ok(Shape::Triangle {
            vertices: [a.as_vec3(), bv.as_vec3(), c.as_vec3()],
        });
        self.shape(shape, material)
    }

    fn mesh_node(&mut self, b: &Block, path: &crate::lang::ast::Expr) -> Eval<Node> {
        let file = self.expr(path).and_then(|v| self.string(&v, path.span));
        let material = match self.prop(b, &mesh::MATERIAL) {
            Ok(Some((v, s))) => self.material(&v, s).map(Some),
            Ok(None) => Ok(None),
            Err(f) => Err(f),
        };
        let (file, material) = (file?, material?);
        let (mesh, slots) = self.mesh(&file, path.span)?;
        let materials = match material {
            Some(m) => vec![m; slots.len().max(1)],
            None => slots,
        };
        Ok(Node::Mesh { mesh, materials })
    }

    fn revolve(&mut self, b: &Block, curve: &crate::lang::ast::Expr, o: &Object) -> Eval<Node> {
        let curve = match self.expr(curve) {
            Ok(Value::Curve(c)) => Ok(c),
            Ok(other) => Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    curve.span,
                    format!("expected a curve, found {}", other.type_name()),
                )
                .label("not a curve")
                .help("define the profile with `bezier [(r, h), ...]`"),
            )),
            Err(f) => Err(f),
        };
        let material = self.shape_material(b, o);
        let analytic = self.mode(b);
        let resolution = self
            .prop_count(b, &revolve::RESOLUTION, 50)
            .and_then(|(r, s)| {
                self.range(
                    (3..=100_000).contains(&r),
                    s,
                    format!("the resolution must be in 3..=100000, not {r}"),
                    "the resolution is the number of segments along the curve and around the axis",
                )?;
                Ok(r)
            });
        let tolerance = self
            .prop_num(b, &revolve::TOLERANCE, 1e-4)
            .and_then(|(t, s)| {
                self.range(
                    t > 0.0 && t <= 0.1,
                    s,
                    format!("the tolerance must be in (0, 0.1], not {t}"),
                    "the Newton tolerance is a fraction of the profile's size, e.g. 1e-4",
                )?;
                Ok(t)
            });
        let (curve, material, analytic, resolution, tolerance) =
            (curve?, material?, analytic?, resolution?, tolerance?);
        let mode = if analytic {
            RevolutionMode::Analytic {
                resolution,
                tolerance: tolerance as f32,
            }
        } else {
            RevolutionMode::Mesh { resolution }
        };
        Ok(Node::Shape {
            shape: Shape::Revolution {
                curve: (*curve).clone(),
                mode,
            },
            material,
        })
    }

    /// `mode mesh | analytic` (or a string with either word); default analytic.
    fn mode(&mut self, b: &Block) -> Eval<bool> {
        let Some(e) = b.get(&revolve::MODE) else {
            return Ok(true);
        };
        let word = match &e.kind {
            crate::lang::ast::ExprKind::Name(n) if n == "mesh" || n == "analytic" => n.clone(),
            _ => {
                let v = self.expr(e)?;
                self.string(&v, e.span)?
            }
        };
        match word.as_str() {
            "mesh" => Ok(false),
            "analytic" => Ok(true),
            _ => Err(self.report(
                Diagnostic::error(Code::UnknownName, e.span, format!("unknown mode `{word}`"))
                    .label("not a mode")
                    .help("the mode is `mesh` or `analytic`"),
            )),
        }
    }

    fn medium(&mut self, b: &Block, o: &Object) -> Eval<Node> {
        self.in_boundary += 1;
        let boundary = match self.prop(b, &medium::BOUNDARY) {
            Ok(Some((Value::Object(node), _))) => Ok((*node).clone()),
            Ok(Some((other, s))) => Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    s,
                    format!("expected an object, found {}", other.type_name()),
                )
                .label("not an object")
                .help("the boundary is a closed object, e.g. `boundary sphere { radius 1 }`"),
            )),
            Ok(None) => Err(self.missing(
                o,
                "boundary",
                "add e.g. `boundary box { min (0, 0, 0) max (1, 1, 1) }`",
            )),
            Err(f) => Err(f),
        };
        self.in_boundary -= 1;
        if let Ok(node) = &boundary {
            if holds_lamp(&self.scene, node) {
                return Err(self.report(
                    Diagnostic::error(
                        Code::Range,
                        o.head,
                        "a medium's boundary cannot hold a light that is not a shape",
                    )
                    .label("a sun, point or spot light in the boundary")
                    .help("place the light beside the medium"),
                ));
            }
        }
        let density = self.prop_num(b, &medium::DENSITY, 1.0).and_then(|(d, s)| {
            self.range(
                d > 0.0,
                s,
                format!("the density must be positive, not {d}"),
                "the density is the chance of scattering per unit length",
            )?;
            Ok(d)
        });
        let color = match self.prop(b, &medium::COLOR) {
            Ok(Some((v, s))) => self.texture(&v, s),
            Ok(None) => self.texture(&Value::Vec3(DVec3::ONE), o.head),
            Err(f) => Err(f),
        };
        let (boundary, density, color) = (boundary?, density?, color?);
        let material = self
            .scene
            .add_material(crate::scene::Material::Isotropic { albedo: color });
        Ok(Node::Medium {
            boundary: Box::new(boundary),
            density: density as f32,
            material,
        })
    }

    /// `repeat VAR in FROM..TO { ... }`: the body once per whole number in
    /// `FROM..TO` (end excluded), all in one group.
    fn repeat(
        &mut self,
        var: &crate::lang::ast::Ident,
        from: &crate::lang::ast::Expr,
        to: &crate::lang::ast::Expr,
        o: &Object,
    ) -> Eval<Node> {
        let ok_name = self.check_new_name(&var.name, var.span);
        let lo = self.expr(from).and_then(|v| self.num(&v, from.span));
        let hi = self.expr(to).and_then(|v| self.num(&v, to.span));
        let (lo, hi) = (lo?, hi?);
        if !ok_name {
            return Err(Fail);
        }
        self.range(
            lo.fract() == 0.0 && hi.fract() == 0.0,
            from.span.to(to.span),
            format!("loop bounds must be whole numbers, not {lo}..{hi}"),
            "write whole numbers, e.g. `0..10`",
        )?;
        self.range(
            hi - lo <= MAX_ITERATIONS,
            from.span.to(to.span),
            format!(
                "the loop would run {} times, more than {MAX_ITERATIONS}",
                hi - lo
            ),
            "use a mesh for very many primitives",
        )?;
        let count = (hi - lo).max(0.0);
        self.check_nest(count, o.head)?;
        let allow = holder("repeat");
        let block = self.block(&o.body, &allow);
        let mut nodes = Vec::new();
        let mut i = lo;
        let mut failed = false;
        self.enter(Site::Loop {
            span: o.head,
            count,
            left: count,
        });
        while i < hi {
            if self.iteration(o.head).is_err() {
                failed = true;
                break;
            }
            self.locals.push((var.name.clone(), Value::Num(i)));
            self.loops.push((var.name.clone(), i, var.span));
            let children = self.children(&block.children);
            let transforms = self.apply_transforms(&block.transforms);
            self.loops.pop();
            self.locals.pop();
            match (children, transforms) {
                (Ok(children), Ok(t)) if t.is_identity() => nodes.extend(children),
                (Ok(children), Ok(t)) => nodes.push(t.wrap(group_of(children))),
                _ => {
                    failed = true;
                    break;
                }
            }
            i += 1.0;
        }
        self.leave();
        if failed {
            return Err(Fail);
        }
        Ok(flipped(Node::Group(nodes), block.flip))
    }

    /// `place NAME { transforms }`: the defined object, shared as a
    /// prototype when placed more than once; `place NAME(args) { ... }`:
    /// the object a function call returns.
    pub(super) fn place(
        &mut self,
        name: &crate::lang::ast::Ident,
        args: Option<&[crate::lang::ast::Arg]>,
        body: &[Stmt],
    ) -> Eval<Node> {
        let allow = Allow::transforms_only("place");
        let block = self.block(body, &allow);
        let transforms = self.apply_transforms(&block.transforms);
        let value = match args {
            Some(args) => self.call(name, args, name.span)?,
            None => self.lookup(&name.name, name.span)?,
        };
        let Value::Object(node) = value else {
            return Err(self.report(
                Diagnostic::error(
                    Code::Type,
                    name.span,
                    format!("`{}` is {}, not an object", name.name, value.type_name()),
                )
                .label("cannot be placed")
                .help("`place` takes a name defined as an object, e.g. `let x = sphere { ... }`"),
            ));
        };
        let index = args
            .is_none()
            .then(|| self.def_index.get(&name.name).copied())
            .flatten();
        let many = self.place_counts.get(&name.name).copied().unwrap_or(0) > 1;
        let placed = match index {
            Some(index) if many => {
                let id = match self.caches.protos.get(&index) {
                    Some(id) => *id,
                    None => {
                        self.charge_tree(&node, name.span)?;
                        let id = self.scene.add_prototype((*node).clone());
                        self.caches.protos.insert(index, id);
                        id
                    }
                };
                Node::Instance(id)
            }
            _ => {
                // Charging the tree walks it, as copying a shared one does.
                self.step_copy(&node, name.span)?;
                std::rc::Rc::unwrap_or_clone(node)
            }
        };
        self.charge_tree(&placed, name.span)?;
        Ok(transforms?.wrap(flipped(placed, block.flip)))
    }
}

/// `node` with its faces swapped when `flip` is set.
fn flipped(node: Node, flip: bool) -> Node {
    if flip {
        Node::Flip(Box::new(node))
    } else {
        node
    }
}

/// One node for several: the node itself when there is one.
fn group_of(mut nodes: Vec<Node>) -> Node {
    if nodes.len() == 1 {
        nodes.pop().unwrap_or(Node::Group(Vec::new()))
    } else {
        Node::Group(nodes)
    }
}
