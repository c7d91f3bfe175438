//! The static type check a strict IEC 61131-3 Ed. 3 compiler makes, on the parsed program: every
//! assignment, operator, comparison, call argument, `CASE` selector and `FOR` bound is typed against the
//! declarations, and a conversion the standard does not make implicitly is refused, as are writes the
//! standard forbids. Written from the standard (it judges the emitted text; it shares nothing with
//! `crate::scan::strict`, the rules the printer keeps, but the keyword list).
//!
//! Implicit conversions (6.6.1.6, its figure of implicit conversions) are the value-preserving ones: a signed integer to a
//! wider signed one (`INT` → `DINT`), an unsigned to a wider unsigned one, an unsigned to a wider signed
//! one (`UINT` → `DINT`). Everything else (narrowing `DINT` → `INT`, sign changes, `BOOL` ↔ integers)
//! must be written out with a conversion function (`DINT_TO_INT`, 6.6.2.5). An untyped integer
//! literal takes the type of its context when its value is in range (6.3.2).
//!
//! Writes: a function block writes no `VAR_INPUT` of its own (6.5.2), and nobody writes a member of a
//! block instance from outside it (6.6.3); from outside, an instance shows its inputs and outputs only.

use std::collections::BTreeMap;

use super::parse::{Decl, Expr, Path, Stmt, Type, Unit};

/// An expression's type: a declared one, or an untyped integer literal (its value when it is one).
#[derive(Clone, Debug, PartialEq, Eq)]
enum Ty {
    Is(Type),
    Literal(Option<i64>),
}

/// The width in bits and signedness of an integer type.
fn integer(name: &str) -> Option<(u32, bool)> {
    Some(match name {
        "SINT" => (8, true),
        "INT" => (16, true),
        "DINT" => (32, true),
        "LINT" => (64, true),
        "USINT" => (8, false),
        "UINT" => (16, false),
        "UDINT" => (32, false),
        _ => return None,
    })
}

/// The standard on-delay timer's name (IEC 61131-3 6.6.3.5.4, Table 46).
pub const TON: &str = "TON";

/// The standard on-delay timer's declarations: `IN`, `PT` in; `Q`, `ET` out; and the local state the
/// interpreter keeps for it (`RUNNING`, `START`: the clock when `IN` rose), which no caller sees.
pub fn ton() -> Vec<Decl> {
    let d = |class: &str, name: &str, ty: Type| Decl {
        class: class.into(),
        name: name.into(),
        ty,
        init: None,
        address: None,
    };
    vec![
        d("VAR_INPUT", "IN", Type::Bool),
        d("VAR_INPUT", "PT", Type::Time),
        d("VAR_OUTPUT", "Q", Type::Bool),
        d("VAR_OUTPUT", "ET", Type::Time),
        d("VAR", "RUNNING", Type::Bool),
        d("VAR", "START", Type::Time),
    ]
}

/// The range of an integer type.
pub fn range(name: &str) -> Option<(i64, i64)> {
    let (bits, signed) = integer(name)?;
    Some(match (bits, signed) {
        (64, _) => (i64::MIN, i64::MAX),
        (b, true) => (-(1 << (b - 1)), (1 << (b - 1)) - 1),
        (b, false) => (0, (1 << b) - 1),
    })
}

/// Whether a value of type `from` may be stored in `to` without a conversion function (6.6.1.6).
fn implicit(from: &Type, to: &Type) -> bool {
    match (from, to) {
        (Type::Int(a), Type::Int(b)) => match (integer(a), integer(b)) {
            (Some((wa, sa)), Some((wb, sb))) => a == b || (wa < wb && (sa == sb || (!sa && sb))),
            _ => false,
        },
        _ => from == to,
    }
}

fn show(t: &Ty) -> String {
    match t {
        Ty::Is(Type::Bool) => "BOOL".into(),
        Ty::Is(Type::Int(n)) => n.clone(),
        Ty::Is(Type::Array(lo, hi, of)) => format!("ARRAY[{lo}..{hi}] OF {}", show(&Ty::Is((**of).clone()))),
        Ty::Is(Type::Named(n)) => n.clone(),
        Ty::Is(Type::Time) => "TIME".into(),
        Ty::Literal(_) => "an integer literal".into(),
    }
}

/// The program's declarations, by upper-case name.
struct Program<'a> {
    structs: BTreeMap<&'a str, &'a [Decl]>,
    blocks: BTreeMap<&'a str, (bool, &'a [Decl])>,
}

/// Checks every POU of `units` (see the module documentation).
pub fn check(units: &[Unit]) -> Result<(), String> {
    let ton = ton();
    let mut program =
        Program { structs: BTreeMap::new(), blocks: BTreeMap::from([(TON, (false, ton.as_slice()))]) };
    for u in units {
        match u {
            Unit::Struct(name, fields) => {
                program.structs.insert(name, fields);
            }
            Unit::Pou { program: p, name, vars, .. } => {
                program.blocks.insert(name, (*p, vars));
            }
            Unit::Configuration { .. } => {}
        }
    }
    for u in units {
        let Unit::Pou { program: is_program, name, vars, body } = u else { continue };
        let pou = Pou { program: &program, is_program: *is_program, vars };
        for d in vars {
            if let Some(init) = &d.init {
                pou.store(&d.ty, init).map_err(|e| format!("{name}: {} := …: {e}", d.name))?;
            }
        }
        for s in body {
            pou.stmt(s).map_err(|e| format!("{name}: {e}"))?;
        }
    }
    Ok(())
}

/// One POU's scope.
struct Pou<'a> {
    program: &'a Program<'a>,
    is_program: bool,
    vars: &'a [Decl],
}

impl Pou<'_> {
    /// The type at `path`, whether it reaches into a block instance, and the root's class.
    fn path(&self, path: &Path) -> Result<(Type, bool, &str), String> {
        let mut segs = path.0.iter();
        let (first, index) = segs.next().ok_or("an empty path")?;
        let d = self
            .vars
            .iter()
            .find(|d| &d.name == first)
            .ok_or_else(|| format!("'{first}' is not declared"))?;
        let mut ty = self.index(&d.ty, index.as_ref(), first)?;
        let mut instance = false;
        for (member, index) in segs {
            let Type::Named(n) = &ty else {
                return Err(format!("'{}' has no member '{member}'", show(&Ty::Is(ty))));
            };
            let fields: Vec<&Decl> = if let Some(fields) = self.program.structs.get(n.as_str()) {
                fields.iter().collect()
            } else if let Some((false, decls)) = self.program.blocks.get(n.as_str()) {
                instance = true;
                decls.iter().filter(|d| d.class != "VAR").collect()
            } else {
                Vec::new()
            };
            let d = fields
                .into_iter()
                .find(|d| &d.name == member)
                .ok_or_else(|| format!("{n} shows no member '{member}' (IEC 61131-3 6.6.3)"))?;
            ty = self.index(&d.ty, index.as_ref(), member)?;
        }
        Ok((ty, instance, &d.class))
    }

    fn index(&self, ty: &Type, index: Option<&Expr>, name: &str) -> Result<Type, String> {
        let Some(i) = index else { return Ok(ty.clone()) };
        let Type::Array(_, _, of) = ty else { return Err(format!("'{name}' is no array")) };
        match self.expr(i)? {
            Ty::Is(Type::Int(_)) | Ty::Literal(_) => Ok((**of).clone()),
            t => Err(format!("'{name}' indexed by {} (IEC 61131-3 6.4.4)", show(&t))),
        }
    }

    fn expr(&self, e: &Expr) -> Result<Ty, String> {
        Ok(match e {
            Expr::Bool(_) => Ty::Is(Type::Bool),
            Expr::Int(i) => Ty::Literal(Some(*i)),
            Expr::Time(_) => Ty::Is(Type::Time),
            Expr::Var(p) => Ty::Is(self.path(p)?.0),
            Expr::Not(x) => match self.expr(x)? {
                Ty::Is(Type::Bool) => Ty::Is(Type::Bool),
                t => return Err(format!("NOT of {} (IEC 61131-3 7.3.2)", show(&t))),
            },
            Expr::Neg(x) => match self.expr(x)? {
                Ty::Literal(v) => Ty::Literal(v.map(|v| -v)),
                Ty::Is(Type::Int(n)) if integer(&n).is_some_and(|(_, signed)| signed) => Ty::Is(Type::Int(n)),
                t => return Err(format!("- of {} (IEC 61131-3 7.3.2)", show(&t))),
            },
            Expr::Call(f, args) => {
                let (from, to) = f.split_once("_TO_").ok_or_else(|| format!("unknown function {f}"))?;
                let ty = |n: &str| match n {
                    "BOOL" => Some(Type::Bool),
                    n => integer(n).map(|_| Type::Int(n.to_owned())),
                };
                let (Some(from), Some(to), [x]) = (ty(from), ty(to), args.as_slice()) else {
                    return Err(format!(
                        "{f}: not a conversion function of one argument the interpreter knows"
                    ));
                };
                self.store(&from, x).map_err(|e| format!("{f}: {e}"))?;
                Ty::Is(to)
            }
            Expr::Bin(a, op, b) => {
                let (ta, tb) = (self.expr(a)?, self.expr(b)?);
                let mixed = || {
                    format!(
                        "{} {op} {}: no implicit conversion between them (IEC 61131-3 6.6.1.6)",
                        show(&ta),
                        show(&tb)
                    )
                };
                let common = match (&ta, &tb) {
                    (Ty::Literal(_), Ty::Literal(_)) => Ty::Literal(None),
                    (Ty::Literal(v), Ty::Is(t)) | (Ty::Is(t), Ty::Literal(v)) => {
                        let fits = match (t, v) {
                            (Type::Int(n), Some(v)) => range(n).is_some_and(|(lo, hi)| (lo..=hi).contains(v)),
                            (Type::Int(_), None) => true,
                            _ => false,
                        };
                        if !fits {
                            return Err(mixed());
                        }
                        Ty::Is(t.clone())
                    }
                    (Ty::Is(x), Ty::Is(y)) if implicit(x, y) => tb.clone(),
                    (Ty::Is(x), Ty::Is(y)) if implicit(y, x) => ta.clone(),
                    _ => return Err(mixed()),
                };
                let is_bool = common == Ty::Is(Type::Bool);
                let is_int = matches!(common, Ty::Literal(_) | Ty::Is(Type::Int(_)));
                match op.as_str() {
                    "AND" | "&" | "OR" | "XOR" if is_bool => common,
                    "=" | "<>" if is_bool || is_int => Ty::Is(Type::Bool),
                    "<" | ">" | "<=" | ">=" if is_int => Ty::Is(Type::Bool),
                    "+" | "-" | "*" | "/" | "MOD" if is_int => match common {
                        Ty::Literal(_) => Ty::Literal(None),
                        t => t,
                    },
                    _ => return Err(format!("{op} on {} (IEC 61131-3 7.3.2)", show(&common))),
                }
            }
        })
    }

    /// `e` stored in a place of type `to`: its type converts to `to` implicitly (6.6.1.6).
    fn store(&self, to: &Type, e: &Expr) -> Result<(), String> {
        let t = self.expr(e)?;
        let ok = match (&t, to) {
            (Ty::Literal(Some(v)), Type::Int(n)) => range(n).is_some_and(|(lo, hi)| (lo..=hi).contains(v)),
            (Ty::Literal(None), Type::Int(_)) => true,
            (Ty::Is(from), to) => implicit(from, to),
            _ => false,
        };
        if ok {
            Ok(())
        } else {
            let to = show(&Ty::Is(to.clone()));
            Err(format!(
                "{} into {to}: no implicit conversion (IEC 61131-3 6.6.1.6; write it out, e.g. {}_TO_{to})",
                show(&t),
                show(&t)
            ))
        }
    }

    fn stmt(&self, s: &Stmt) -> Result<(), String> {
        let all = |body: &[Stmt]| body.iter().try_for_each(|s| self.stmt(s));
        match s {
            Stmt::Section(_) | Stmt::Exit => Ok(()),
            Stmt::Assign(path, e) => {
                let (ty, instance, class) = self.path(path)?;
                let name = path.0.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(".");
                if instance {
                    return Err(format!(
                        "{name} := …: a block instance's member written from outside (IEC 61131-3 6.6.3)"
                    ));
                }
                if !self.is_program && class == "VAR_INPUT" {
                    return Err(format!(
                        "{name} := …: the block writes its own VAR_INPUT (IEC 61131-3 6.5.2)"
                    ));
                }
                self.store(&ty, e).map_err(|err| format!("{name} := …: {err}"))
            }
            Stmt::If(arms, els) => {
                for (c, body) in arms {
                    self.store(&Type::Bool, c).map_err(|e| format!("IF: {e}"))?;
                    all(body)?;
                }
                all(els)
            }
            Stmt::Case(e, arms, els) => {
                let Ty::Is(ty @ Type::Int(_)) = self.expr(e)? else {
                    return Err("CASE: the selector is no integer (IEC 61131-3 7.3.3.3)".into());
                };
                for (labels, body) in arms {
                    for l in labels {
                        self.store(&ty, &Expr::Int(*l)).map_err(|e| format!("CASE label {l}: {e}"))?;
                    }
                    all(body)?;
                }
                all(els)
            }
            Stmt::For(v, from, to, body) => {
                let (ty, ..) = self.path(&Path(vec![(v.clone(), None)]))?;
                if !matches!(ty, Type::Int(_)) {
                    return Err(format!("FOR {v}: the control variable is no integer (IEC 61131-3 7.3.3.4)"));
                }
                self.store(&ty, from).map_err(|e| format!("FOR {v}: {e}"))?;
                self.store(&ty, to).map_err(|e| format!("FOR {v}: {e}"))?;
                all(body)
            }
            Stmt::Call(inst, args) => {
                let (ty, ..) = self.path(&Path(vec![(inst.clone(), None)]))?;
                let Type::Named(n) = ty else { return Err(format!("{inst} is no block instance")) };
                let Some((false, decls)) = self.program.blocks.get(n.as_str()) else {
                    return Err(format!("{inst} is no block instance"));
                };
                for (name, e) in args {
                    let d = decls
                        .iter()
                        .find(|d| &d.name == name && d.class == "VAR_INPUT")
                        .ok_or_else(|| format!("{inst}: {name} is no input of {n}"))?;
                    self.store(&d.ty, e).map_err(|err| format!("{inst}({name} := …): {err}"))?;
                }
                Ok(())
            }
        }
    }
}
