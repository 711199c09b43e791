//! Well-formedness of compiled programs: stack depth within
//! [`MAX_STACK`](super::MAX_STACK), no underflow, exactly one result, and
//! keyframe tables in range, non-empty, finite and sorted by time.

use glam::Vec3;

use super::{Op, Program, MAX_STACK};

/// Why a [`Program`] or a [`Motion`](super::Motion) is not well-formed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ProgramError {
    #[error("expression needs a stack of {depth} values; at most {max} are allowed")]
    TooDeep { depth: usize, max: usize },
    #[error("instruction {at} pops more values than the stack holds")]
    Underflow { at: usize },
    #[error("program leaves {left} values on the stack instead of one")]
    NotOneResult { left: usize },
    #[error("keyframe table {start}..{end} lies outside the {len} stored keys")]
    KeysOutOfRange {
        start: usize,
        end: usize,
        len: usize,
    },
    #[error("keyframe table at {start} is empty")]
    KeysEmpty { start: usize },
    #[error("keyframe table at {start} is not sorted by time or holds a non-finite number")]
    KeysUnsorted { start: usize },
    #[error("rotation axis {axis} is not a unit vector")]
    AxisNotUnit { axis: Vec3 },
}

impl Program {
    /// Checks that [`Program::eval`] can run this program without leaving its
    /// fixed stack and that every keyframe table is usable. The language calls
    /// this once after compiling an expression.
    pub fn validate(&self) -> Result<(), ProgramError> {
        let mut depth = 0usize;
        for (at, op) in self.ops.iter().enumerate() {
            let (pops, pushes) = stack_effect(op);
            if depth < pops {
                return Err(ProgramError::Underflow { at });
            }
            depth = depth - pops + pushes;
            if depth > MAX_STACK {
                return Err(ProgramError::TooDeep {
                    depth,
                    max: MAX_STACK,
                });
            }
            if let Op::Keyframes { start, len, .. } = *op {
                self.check_keys(start as usize, len as usize)?;
            }
        }
        if depth != 1 {
            return Err(ProgramError::NotOneResult { left: depth });
        }
        Ok(())
    }

    fn check_keys(&self, start: usize, len: usize) -> Result<(), ProgramError> {
        let end = start.saturating_add(len);
        let table = self
            .keys
            .get(start..end)
            .ok_or(ProgramError::KeysOutOfRange {
                start,
                end,
                len: self.keys.len(),
            })?;
        if table.is_empty() {
            return Err(ProgramError::KeysEmpty { start });
        }
        let finite = table.iter().all(|k| k.0.is_finite() && k.1.is_finite());
        if !finite || table.windows(2).any(|w| w[0].0 > w[1].0) {
            return Err(ProgramError::KeysUnsorted { start });
        }
        Ok(())
    }
}

/// How many values an instruction pops and pushes.
fn stack_effect(op: &Op) -> (usize, usize) {
    match op {
        Op::Const(_) | Op::Time => (0, 1),
        Op::Neg | Op::Call1(_) | Op::Keyframes { .. } => (1, 1),
        Op::Add | Op::Sub | Op::Mul | Op::Div | Op::Call2(_) => (2, 1),
        Op::Call3(_) => (3, 1),
    }
}
