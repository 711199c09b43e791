//! A grammar-aware generator of rtlang scenes: structurally valid text whose
//! meaning is wild — huge, tiny, infinite and NaN numbers, deep nesting,
//! empty groups, self-referencing names, zero-size images, degenerate
//! triangles and curves. Its choices come from a byte string (a fuzzer's
//! input) followed by a fixed pseudo-random stream, so any seed or input
//! gives a reproducible scene.

/// The source of every choice the generator makes.
pub struct Gen {
    bytes: Vec<u8>,
    pos: usize,
    state: u64,
    depth: u32,
    in_group: bool,
}

/// Finite numbers at the extremes, which the language accepts.
const EXTREME: &[&str] = &[
    "0",
    "-0",
    "1e-4",
    "1e5",
    "1e-12",
    "1e20",
    "1e308",
    "-1e308",
    "1e-320",
    "4294967296",
    "1e9",
    "0.0001",
    "100000",
    "180",
    "360",
    "-180",
    "90",
    "random(1e300)",
    "(-8) ^ (1/3)",
    "1e-999",
];

/// Numbers the language must refuse (infinite or NaN) or that overflow.
const INVALID: &[&str] = &[
    "1e999",
    "-1e999",
    "(0/0)",
    "(1/0)",
    "sqrt(-1)",
    "ln(0)",
    "pow(0, -1)",
    "(1e308 * 10)",
    "exp(1000)",
    "(2 ^ 1024)",
    "18446744073709551616",
    "tan(pi / 2)",
];

impl Gen {
    /// Choices from `bytes`, then from a pseudo-random stream.
    pub fn from_bytes(bytes: &[u8]) -> Gen {
        Gen {
            bytes: bytes.to_vec(),
            pos: 0,
            state: 0x9e37_79b9_7f4a_7c15,
            depth: 0,
            in_group: false,
        }
    }

    /// Choices from a pseudo-random stream seeded with `seed`.
    pub fn from_seed(seed: u64) -> Gen {
        let mut g = Gen::from_bytes(&[]);
        g.state ^= seed.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        g
    }

    fn next(&mut self) -> u32 {
        if let Some(&b) = self.bytes.get(self.pos) {
            self.pos += 1;
            return u32::from(b);
        }
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) & 0xff_ffff) as u32
    }

    /// A choice in `0..n`.
    fn pick(&mut self, n: u32) -> u32 {
        self.next() % n.max(1)
    }

    fn chance(&mut self, percent: u32) -> bool {
        self.pick(100) < percent
    }

    /// A whole scene file.
    pub fn scene(&mut self) -> String {
        let mut out = String::new();
        if self.chance(70) {
            out += &self.settings();
        }
        if self.chance(70) {
            out += &self.camera();
        }
        out += &format!("let x = {}\nlet m = ", self.number());
        out += &self.material();
        out += "\nlet c = ";
        out += &self.curve();
        out += "\nlet o = ";
        out += &self.object();
        out += "\n";
        let count = 1 + self.pick(6);
        for _ in 0..count {
            out += &self.statement();
            out += "\n";
        }
        out
    }

    fn settings(&mut self) -> String {
        let mut s = String::from("render {\n");
        if self.chance(60) {
            let (w, h) = (self.size(), self.size());
            s += &format!("  size {w} x {h}\n");
        }
        if self.chance(50) {
            s += &format!("  samples {}\n", self.size());
        }
        if self.chance(50) {
            s += &format!("  depth {}\n", self.size());
        }
        if self.chance(30) {
            s += &format!("  seed {}\n", self.number());
        }
        if self.chance(50) {
            let bg = if self.chance(50) {
                self.color()
            } else {
                format!("gradient({}, {})", self.color(), self.color())
            };
            s += &format!("  background {bg}\n");
        }
        s + "}\n"
    }

    fn size(&mut self) -> String {
        match self.pick(40) {
            0 => "0".into(),
            1 => "-3".into(),
            2 => "100000".into(),
            3 => self.number(),
            _ => format!("{}", 1 + self.pick(8)),
        }
    }

    fn camera(&mut self) -> String {
        let mut s = String::from("camera {\n");
        for field in ["from", "at", "up"] {
            if self.chance(70) {
                s += &format!("  {field} {}\n", self.vector());
            }
        }
        for field in ["fov", "aperture", "focus"] {
            if self.chance(50) {
                s += &format!("  {field} {}\n", self.expr());
            }
        }
        if self.chance(5) {
            s += &format!("  shutter {} {}\n", self.number(), self.number());
        }
        s + "}\n"
    }

    /// A number literal: usually tame, often extreme, rarely invalid.
    fn number(&mut self) -> String {
        match self.pick(100) {
            0..=39 => format!("{}", 1 + self.pick(9)),
            40..=69 => format!("{}.{}", self.pick(10), self.pick(100)),
            70..=96 => EXTREME[self.pick(EXTREME.len() as u32) as usize].to_string(),
            _ => INVALID[self.pick(INVALID.len() as u32) as usize].to_string(),
        }
    }

    fn expr(&mut self) -> String {
        if self.depth > 6 || self.chance(75) {
            return self.number();
        }
        self.depth += 1;
        let e = match self.pick(9) {
            0 => format!("({} + {})", self.expr(), self.expr()),
            1 => format!("({} * {})", self.expr(), self.expr()),
            2 => format!("({} / {})", self.expr(), self.expr()),
            3 => format!("{} ^ {}", self.number(), self.number()),
            4 => format!("-{}", self.expr()),
            5 => {
                let f = [
                    "sin", "cos", "tan", "sqrt", "abs", "exp", "ln", "floor", "radians",
                ];
                let f = f[self.pick(f.len() as u32) as usize];
                format!("{f}({})", self.expr())
            }
            6 => format!("clamp({}, {}, {})", self.expr(), self.expr(), self.expr()),
            7 => format!(
                "smoothstep({}, {}, {})",
                self.expr(),
                self.expr(),
                self.expr()
            ),
            _ => self.name(),
        };
        self.depth -= 1;
        e
    }

    fn name(&mut self) -> String {
        let names = ["frame", "fps", "pi", "x", "x", "x"];
        if self.chance(2) {
            return "undefined_name".into();
        }
        names[self.pick(names.len() as u32) as usize].into()
    }

    fn vector(&mut self) -> String {
        if self.chance(1) {
            return "(1, 2)".into();
        }
        format!("({}, {}, {})", self.expr(), self.expr(), self.expr())
    }

    fn color(&mut self) -> String {
        match self.pick(50) {
            0 => "hex(\"#zz\")".into(),
            1..=9 => "#ffcc00".into(),
            10..=19 => self.vector(),
            20..=24 => format!("rgb({}, {}, {})", self.expr(), self.expr(), self.expr()),
            _ => format!(
                "rgb({}, {}, {})",
                self.number(),
                self.number(),
                self.number()
            ),
        }
    }

    fn texture(&mut self) -> String {
        match self.pick(30) {
            0 => "image(\"missing.png\")".into(),
            1..=5 => format!("solid({})", self.color()),
            6..=9 => format!(
                "checker({}, {}, scale: {})",
                self.color(),
                self.color(),
                self.number()
            ),
            10..=13 => format!(
                "checker({}, {}, scale: {}, uv: true)",
                self.color(),
                self.color(),
                self.number()
            ),
            14..=17 => format!("noise(scale: {})", self.number()),
            _ => self.color(),
        }
    }

    fn material(&mut self) -> String {
        match self.pick(7) {
            0 => format!("lambertian({})", self.texture()),
            1 => format!("metal({}, fuzz: {})", self.color(), self.number()),
            2 => format!("dielectric({})", self.number()),
            3 => format!("light({})", self.color()),
            4 => format!("light({}, two_sided: true)", self.color()),
            _ => format!("isotropic({})", self.color()),
        }
    }

    fn curve(&mut self) -> String {
        let n = match self.pick(30) {
            0 => 0,
            1 => 1,
            _ => 2 + self.pick(6),
        };
        let same = self.chance(5);
        let points: Vec<String> = (0..n)
            .map(|_| {
                if same {
                    "(1, 1)".to_string()
                } else {
                    format!("({}, {})", self.expr(), self.expr())
                }
            })
            .collect();
        format!("bezier [{}]", points.join(", "))
    }

    fn transform(&mut self) -> String {
        match self.pick(8) {
            0 => format!("translate {}", self.vector()),
            1 => {
                let axis = ["x", "y", "z"][self.pick(3) as usize];
                format!("rotate {axis} {}", self.number())
            }
            2 => format!("rotate {} {}", self.vector(), self.number()),
            3 => format!("scale {}", self.number()),
            4 => format!("scale {}", self.vector()),
            5 => {
                let m: Vec<String> = (0..16).map(|_| self.number()).collect();
                format!("matrix [{}]", m.join(", "))
            }
            6 => format!("motion {{ translate ({} * t, 0, 0) }}", self.number()),
            _ => format!(
                "motion {{ rotate y keyframes(t, [(0, 0), ({}, {})]) }}",
                self.number(),
                self.number()
            ),
        }
    }

    fn statement(&mut self) -> String {
        match self.pick(60) {
            0 => format!("let self_ref = self_ref + {}", self.number()),
            1 => "include \"scene.rt\"".into(),
            2..=9 => format!("place o {{ {} }}", self.transform()),
            _ => self.object(),
        }
    }

    /// One object block with its properties and transforms.
    fn object(&mut self) -> String {
        if self.depth > 4 {
            return format!(
                "sphere {{ center (0, 0, 0) radius {} material m }}",
                self.number()
            );
        }
        self.depth += 1;
        let m = if self.chance(97) {
            format!("material {}", self.material())
        } else {
            String::new()
        };
        let mut s = match self.pick(13) {
            0 | 1 => format!(
                "sphere {{ center {} radius {} {m}",
                self.vector(),
                self.expr()
            ),
            2 => format!(
                "plane {{ point {} normal {} {m}",
                self.vector(),
                self.vector()
            ),
            3 => {
                let axes = ["xy", "xz", "yz"][self.pick(3) as usize];
                format!(
                    "rect {axes} {{ from ({}, {}) to ({}, {}) at {} {m}",
                    self.expr(),
                    self.expr(),
                    self.expr(),
                    self.expr(),
                    self.expr()
                )
            }
            4 => format!("box {{ min {} max {} {m}", self.vector(), self.vector()),
            5 => {
                let a = self.vector();
                let b = if self.chance(30) {
                    a.clone()
                } else {
                    self.vector()
                };
                format!("triangle {{ a {a} b {b} c {} {m}", self.vector())
            }
            6 if self.chance(20) => {
                let file = ["missing.obj", "", ".", "scene.rt"][self.pick(4) as usize];
                format!("mesh \"{file}\" {{ {m}")
            }
            7 => {
                let mode = ["analytic", "mesh"][self.pick(2) as usize];
                format!(
                    "revolve c {{ {m} mode {mode} resolution {} tolerance {}",
                    self.size(),
                    self.number()
                )
            }
            8 => format!(
                "medium {{ boundary {} density {} color {}",
                {
                    let outer = std::mem::replace(&mut self.in_group, false);
                    let b = self.object();
                    self.in_group = outer;
                    b
                },
                self.number(),
                self.color()
            ),
            9 => {
                let outer = std::mem::replace(&mut self.in_group, true);
                let inner: Vec<String> = (0..self.pick(3)).map(|_| self.object()).collect();
                self.in_group = outer;
                format!("group {{ {}", inner.join(" "))
            }
            10 => {
                let hi = ["0", "1", "3", "2", "4", "-2", "1e999", "(0/0)"][self.pick(8) as usize];
                format!("repeat i in 0..{hi} {{ {} ", self.object())
            }
            11 if self.in_group => "place o {".into(),
            _ => format!("revolve {} {{ {m}", self.curve()),
        };
        for _ in 0..self.pick(3) {
            s += " ";
            s += &self.transform();
        }
        self.depth -= 1;
        s + " }"
    }
}
