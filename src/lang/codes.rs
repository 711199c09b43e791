//! The stable codes of language diagnostics: one enum, so a code cannot be
//! misspelt at its use, and `docs/language.md` is checked against [`Code::ALL`].

use std::fmt;

use serde::Serialize;

macro_rules! codes {
    ($($variant:ident = $text:literal,)*) => {
        /// A stable diagnostic code; [`Code::as_str`] is its `rtlang::...` text.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Code {
            $($variant,)*
        }

        impl Code {
            /// Every code, in the order of declaration.
            pub const ALL: &'static [Code] = &[$(Code::$variant,)*];

            /// The stable text, such as `rtlang::unknown-name`.
            pub fn as_str(self) -> &'static str {
                match self {
                    $(Code::$variant => $text,)*
                }
            }
        }
    };
}

codes! {
    Syntax = "rtlang::syntax",
    Number = "rtlang::number",
    BadEscape = "rtlang::bad-escape",
    BadColor = "rtlang::bad-color",
    UnknownName = "rtlang::unknown-name",
    UnknownFunction = "rtlang::unknown-function",
    UnknownProperty = "rtlang::unknown-property",
    UnknownArgument = "rtlang::unknown-argument",
    UnknownDefine = "rtlang::unknown-define",
    Duplicate = "rtlang::duplicate",
    Type = "rtlang::type",
    Arity = "rtlang::arity",
    ArgumentOrder = "rtlang::argument-order",
    Range = "rtlang::range",
    Degenerate = "rtlang::degenerate",
    Singular = "rtlang::singular",
    DivisionByZero = "rtlang::division-by-zero",
    NotFinite = "rtlang::not-finite",
    Domain = "rtlang::domain",
    TimeOutsideMotion = "rtlang::time-outside-motion",
    KeywordName = "rtlang::keyword-name",
    Cycle = "rtlang::cycle",
    TooDeep = "rtlang::too-deep",
    TooLarge = "rtlang::too-large",
    MissingProperty = "rtlang::missing-property",
    Misplaced = "rtlang::misplaced",
    Conflict = "rtlang::conflict",
    Io = "rtlang::io",
    Mesh = "rtlang::mesh",
    MeshWarning = "rtlang::mesh-warning",
    FileType = "rtlang::file-type",
    IncludeCycle = "rtlang::include-cycle",
    EmptyFile = "rtlang::empty-file",
    BinaryFile = "rtlang::binary-file",
    NotUtf8 = "rtlang::not-utf8",
    FileTooLarge = "rtlang::file-too-large",
    Unused = "rtlang::unused",
    MemoryBudget = "rtlang::memory-budget",
    StepBudget = "rtlang::step-budget",
    Interrupted = "rtlang::interrupted",
    LightFacingAway = "rtlang::light-facing-away",
    MotionNotFinite = "rtlang::motion-not-finite",
    MotionUnproven = "rtlang::motion-unproven",
}

impl Code {
    /// Whether an error of this code ends evaluation (a budget or depth
    /// limit, or a stop request): it is reported first, as the cause of
    /// whatever else was found.
    pub fn ends_evaluation(self) -> bool {
        matches!(
            self,
            Code::TooDeep | Code::MemoryBudget | Code::StepBudget | Code::Interrupted
        )
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for Code {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.as_str())
    }
}

/// Lets tests and callers compare a code with its text.
impl PartialEq<&str> for Code {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}
