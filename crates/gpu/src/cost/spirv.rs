//! Counting the instructions of an optimised SPIR-V module, read from its binary words (the
//! SPIR-V specification's layout: a 5-word header, then instructions whose first word holds
//! the word count in its high 16 bits and the opcode in its low 16 bits). The classes are
//! [`super`]'s table; opcodes are those of the SPIR-V 1.6 unified specification and of the
//! `GLSL.std.450` extended instruction set.

use super::Counts;
use std::collections::{BTreeSet, HashMap};

const MAGIC: u32 = 0x0723_0203;

// Core opcodes used below (SPIR-V unified specification, section 3.52).
const OP_NOP: u16 = 0;
const OP_LINE: u16 = 8;
const OP_EXT_INST_IMPORT: u16 = 11;
const OP_EXT_INST: u16 = 12;
const OP_ENTRY_POINT: u16 = 15;
const OP_FUNCTION: u16 = 54;
const OP_FUNCTION_PARAMETER: u16 = 55;
const OP_FUNCTION_END: u16 = 56;
const OP_FUNCTION_CALL: u16 = 57;
const OP_VARIABLE: u16 = 59;
const OP_LOAD: u16 = 61;
const OP_STORE: u16 = 62;
const OP_COPY_MEMORY: u16 = 63;
const OP_ACCESS_CHAIN: u16 = 65;
const OP_IN_BOUNDS_ACCESS_CHAIN: u16 = 66;
const OP_PTR_ACCESS_CHAIN: u16 = 67;
const OP_SELECT: u16 = 169;
const OP_PHI: u16 = 245;
const OP_LOOP_MERGE: u16 = 246;
const OP_SELECTION_MERGE: u16 = 247;
const OP_LABEL: u16 = 248;
const OP_BRANCH: u16 = 249;
const OP_BRANCH_CONDITIONAL: u16 = 250;
const OP_SWITCH: u16 = 251;
const OP_RETURN: u16 = 253;
const OP_RETURN_VALUE: u16 = 254;
const OP_UNREACHABLE: u16 = 255;
const OP_NO_LINE: u16 = 317;

// Storage classes whose variables are the wrapper's inputs and outputs.
const SC_INPUT: u32 = 1;
const SC_UNIFORM: u32 = 2;
const SC_OUTPUT: u32 = 3;
const SC_PUSH_CONSTANT: u32 = 9;
const SC_STORAGE_BUFFER: u32 = 12;

/// The class of a core opcode inside a function body; `None`: not counted.
fn core_class(op: u16) -> Option<Class> {
    Some(match op {
        // SNegate, FNegate, IAdd, FAdd, ISub, FSub, IMul, FMul.
        126..=133 => Class::Arithmetic,
        // VectorTimesScalar, MatrixTimesScalar, VectorTimesMatrix, MatrixTimesVector,
        // MatrixTimesMatrix, OuterProduct, Dot.
        142..=148 => Class::Arithmetic,
        // UDiv, SDiv, FDiv, UMod, SRem, SMod, FRem, FMod.
        134..=141 => Class::DivisionSqrt,
        OP_BRANCH_CONDITIONAL | OP_SWITCH => Class::Branch,
        OP_SELECT => Class::Select,
        // Structure, not work: labels, merges, unconditional branches, phis, returns,
        // declarations, debug lines.
        OP_NOP
        | OP_LINE
        | OP_NO_LINE
        | OP_FUNCTION
        | OP_FUNCTION_PARAMETER
        | OP_FUNCTION_END
        | OP_VARIABLE
        | OP_PHI
        | OP_LOOP_MERGE
        | OP_SELECTION_MERGE
        | OP_LABEL
        | OP_BRANCH
        | OP_RETURN
        | OP_RETURN_VALUE
        | OP_UNREACHABLE => return None,
        _ => Class::Other,
    })
}

/// The class of a `GLSL.std.450` instruction (its number in that set).
fn glsl_class(n: u32) -> Class {
    match n {
        // Sin, Cos, Tan, Asin, Acos, Atan, Sinh, Cosh, Tanh, Asinh, Acosh, Atanh, Atan2, Pow,
        // Exp, Log, Exp2, Log2.
        13..=30 => Class::Transcendental,
        // Sqrt, InverseSqrt, Determinant, MatrixInverse; Length, Distance, Normalize, Refract.
        31..=34 | 66 | 67 | 69 | 72 => Class::DivisionSqrt,
        // Round, RoundEven, Trunc, FAbs, SAbs, FSign, SSign, Floor, Ceil, Fract, Radians,
        // Degrees; FMin .. SClamp, FMix, IMix, Step, SmoothStep, Fma; Cross; FaceForward,
        // Reflect; NMin, NMax, NClamp.
        1..=12 | 37..=50 | 68 | 70 | 71 | 79..=81 => Class::Arithmetic,
        // Modf, Frexp, Ldexp, packing, FindLsb/Msb, interpolation.
        _ => Class::Other,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Arithmetic,
    Transcendental,
    DivisionSqrt,
    Branch,
    Select,
    Other,
}

/// One instruction: opcode and operands (the words after the first).
struct Inst<'a> {
    op: u16,
    args: &'a [u32],
}

fn instructions(words: &[u32]) -> Result<Vec<Inst<'_>>, String> {
    if words.len() < 5 || words[0] != MAGIC {
        return Err("not a SPIR-V module (no magic number 0x07230203)".into());
    }
    let mut out = Vec::new();
    let mut at = 5;
    while at < words.len() {
        let (count, op) = ((words[at] >> 16) as usize, (words[at] & 0xffff) as u16);
        if count == 0 || at + count > words.len() {
            return Err(format!(
                "malformed SPIR-V: instruction at word {at} (opcode {op}) has word count {count}"
            ));
        }
        out.push(Inst {
            op,
            args: &words[at + 1..at + count],
        });
        at += count;
    }
    Ok(out)
}

/// A literal string operand (null-terminated, little-endian bytes in words).
fn string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take_while(|b| *b != 0)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Counts the instructions of the functions reachable from entry point `entry` (each function
/// once), leaving out the loads, stores and access chains of input/output variables (see
/// [`super`]).
pub fn count(words: &[u32], entry: &str) -> Result<Counts, String> {
    let insts = instructions(words)?;
    let mut glsl = None;
    let mut non_semantic = BTreeSet::new();
    let mut entry_fn = None;
    let mut io: BTreeSet<u32> = BTreeSet::new();
    let mut in_function = false;
    // Function id -> index range of its body in `insts`.
    let mut functions: HashMap<u32, (usize, usize)> = HashMap::new();
    let mut current = (0u32, 0usize);
    for (i, inst) in insts.iter().enumerate() {
        match inst.op {
            OP_EXT_INST_IMPORT if inst.args.len() >= 2 => {
                let name = string(&inst.args[1..]);
                if name == "GLSL.std.450" {
                    glsl = Some(inst.args[0]);
                } else if name.starts_with("NonSemantic.") {
                    non_semantic.insert(inst.args[0]);
                }
            }
            OP_ENTRY_POINT if inst.args.len() >= 3 && string(&inst.args[2..]) == entry => {
                entry_fn = Some(inst.args[1]);
            }
            OP_VARIABLE
                if !in_function
                    && inst.args.len() >= 3
                    && [
                        SC_INPUT,
                        SC_UNIFORM,
                        SC_OUTPUT,
                        SC_PUSH_CONSTANT,
                        SC_STORAGE_BUFFER,
                    ]
                    .contains(&inst.args[2]) =>
            {
                io.insert(inst.args[1]);
            }
            OP_FUNCTION if inst.args.len() >= 2 => {
                in_function = true;
                current = (inst.args[1], i);
            }
            OP_FUNCTION_END => {
                in_function = false;
                functions.insert(current.0, (current.1, i));
            }
            _ => {}
        }
    }
    let entry_fn =
        entry_fn.ok_or_else(|| format!("the optimised module has no entry point {entry}"))?;
    // Pointers into the I/O variables: access chains based on them (blocks come after their
    // dominators, but a fixed point does not rely on it).
    loop {
        let before = io.len();
        for inst in &insts {
            let chain = matches!(
                inst.op,
                OP_ACCESS_CHAIN | OP_IN_BOUNDS_ACCESS_CHAIN | OP_PTR_ACCESS_CHAIN
            );
            if chain && inst.args.len() >= 3 && io.contains(&inst.args[2]) {
                io.insert(inst.args[1]);
            }
        }
        if io.len() == before {
            break;
        }
    }
    // The functions reachable from the entry point.
    let mut reach = BTreeSet::new();
    let mut todo = vec![entry_fn];
    while let Some(f) = todo.pop() {
        if !reach.insert(f) {
            continue;
        }
        let &(lo, hi) = functions
            .get(&f)
            .ok_or_else(|| format!("malformed SPIR-V: no body for function %{f}"))?;
        for inst in &insts[lo..hi] {
            if inst.op == OP_FUNCTION_CALL && inst.args.len() >= 3 {
                todo.push(inst.args[2]);
            }
        }
    }
    let mut c = Counts::default();
    for f in &reach {
        let (lo, hi) = functions[f];
        for inst in &insts[lo..=hi] {
            let a = inst.args;
            let class = match inst.op {
                OP_ACCESS_CHAIN | OP_IN_BOUNDS_ACCESS_CHAIN | OP_PTR_ACCESS_CHAIN
                    if a.len() >= 3 && io.contains(&a[2]) =>
                {
                    None
                }
                OP_LOAD if a.len() >= 3 && io.contains(&a[2]) => None,
                OP_STORE if !a.is_empty() && io.contains(&a[0]) => None,
                OP_COPY_MEMORY if a.len() >= 2 && (io.contains(&a[0]) || io.contains(&a[1])) => {
                    None
                }
                OP_EXT_INST if a.len() >= 4 => {
                    if Some(a[2]) == glsl {
                        Some(glsl_class(a[3]))
                    } else if non_semantic.contains(&a[2]) {
                        None
                    } else {
                        Some(Class::Other)
                    }
                }
                op => core_class(op),
            };
            match class {
                Some(Class::Arithmetic) => c.arithmetic += 1,
                Some(Class::Transcendental) => c.transcendental += 1,
                Some(Class::DivisionSqrt) => c.division_sqrt += 1,
                Some(Class::Branch) => c.branches += 1,
                Some(Class::Select) => c.select += 1,
                Some(Class::Other) => c.other += 1,
                None => {}
            }
        }
    }
    c.total = c.arithmetic + c.transcendental + c.division_sqrt + c.branches + c.select + c.other;
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_of_known_instructions() {
        assert_eq!(glsl_class(26), Class::Transcendental); // Pow
        assert_eq!(glsl_class(29), Class::Transcendental); // Exp2
        assert_eq!(glsl_class(32), Class::DivisionSqrt); // InverseSqrt
        assert_eq!(glsl_class(69), Class::DivisionSqrt); // Normalize
        assert_eq!(glsl_class(50), Class::Arithmetic); // Fma
        assert_eq!(glsl_class(43), Class::Arithmetic); // FClamp
        assert_eq!(core_class(136), Some(Class::DivisionSqrt)); // FDiv
        assert_eq!(core_class(148), Some(Class::Arithmetic)); // Dot
        assert_eq!(core_class(184), Some(Class::Other)); // FOrdLessThan
        assert_eq!(core_class(OP_LABEL), None);
    }

    #[test]
    fn malformed_modules_are_errors() {
        assert!(count(&[1, 2, 3], "main").unwrap_err().contains("magic"));
        let e = count(&[MAGIC, 0x10000, 0, 1, 0, 0], "main").unwrap_err();
        assert!(e.contains("word count 0"), "{e}");
        let e = count(&[MAGIC, 0x10000, 0, 1, 0], "main").unwrap_err();
        assert!(e.contains("no entry point main"), "{e}");
    }
}
