//! The strict IEC 61131-3 Ed. 3 (2013) rules the writer holds its syntax trees to before printing them,
//! so that a strict compiler (matiec, IronPLC) takes what it writes. [`check`] walks the declarations
//! and bodies with the declared [`Type`]s and refuses, naming the POU, the variable and the clause:
//!
//! * an identifier that is no identifier or is a keyword (6.1.2, 6.1.3; see [`super::names`]), or two
//!   declarations of one name in a scope without regard to case (6.1.2);
//! * a located variable (`AT %…`) anywhere but a `PROGRAM`'s `VAR` (6.5.5; Annex A: `FB_Decl` has no
//!   `Loc_Var_Decls`, and `VAR_INPUT`/`VAR_OUTPUT` never take `AT`), or one address bound twice;
//! * an implicit conversion: an assignment, operator, comparison, call argument, `CASE` selector or
//!   `FOR` bound whose operand types differ (6.6.1.6: the writer never relies on implicit conversion,
//!   even the widenings Ed. 3 allows, because Ed. 2 compilers allow none; conversions are written out
//!   as `INT_TO_DINT` and the like, 6.6.2.5); an integer literal out of its type's range (6.3.2);
//! * a write to the block's own `VAR_INPUT` (6.5.2: inputs are set by the caller) or to a member of a
//!   block instance from outside (6.6.3: an instance's outputs are read-only to its caller).
//!
//! The grammar's punctuation is the printer's ([`super::st`]): `END_STRUCT;`, located and unlocated
//! variables in separate blocks.

use super::ir::{Expr, Op, Pou, Stmt, StructType, Type, Var, VarClass};
use super::names::is_identifier;

/// A rule the program breaks. It is the writer's bug, never the user's: `generate` refuses to print a
/// program that breaks one.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{pou}: {what} (IEC 61131-3 Ed. 3, {clause})")]
pub struct Violation {
    /// The POU or type it is in.
    pub pou: String,
    /// What is wrong, naming the variable.
    pub what: String,
    /// The clause of the standard.
    pub clause: &'static str,
}

/// An expression's type: a declared type, or an untyped integer literal (`ANY_INT`, 6.3.2), which takes
/// the integer type of its context when its value is in that type's range.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Ty {
    Is(Type),
    Literal(Option<i64>),
}

/// The declarations a program's POUs see: structure types and the POUs themselves.
struct Scope<'a> {
    structs: &'a [(String, Vec<Var>)],
    pous: &'a [&'a Pou],
}

impl Scope<'_> {
    /// The function block named `n`: one of the program's, or the standard's on-delay timer `TON`.
    fn block(&self, n: &str) -> Option<&Pou> {
        if n == TON.name {
            return Some(&TON);
        }
        self.pous.iter().copied().find(|p| !p.program && p.name == n)
    }
}

/// The standard on-delay timer's interface (IEC 61131-3 6.6.3.5.4, Table 46): `Q` rises once `IN` has
/// been high for `PT`; `ET` the time elapsed.
static TON: std::sync::LazyLock<Pou> = std::sync::LazyLock::new(|| Pou {
    program: false,
    name: "TON".into(),
    vars: vec![
        (VarClass::Input, vec![Var::new("IN", Type::Bool, ""), Var::new("PT", Type::Time, "")]),
        (VarClass::Output, vec![Var::new("Q", Type::Bool, ""), Var::new("ET", Type::Time, "")]),
    ],
    sections: Vec::new(),
});

/// Checks the structure types and POUs of one program (see the module documentation for the rules).
pub fn check(structs: &[StructType], pous: &[&Pou]) -> Result<(), Violation> {
    let scope = Scope { structs, pous };
    let mut addresses: Vec<(&str, &str)> = Vec::new();
    for (name, members) in structs {
        let fail = |what: String, clause| Violation { pou: name.clone(), what, clause };
        identifier(name).map_err(|c| fail(format!("type name '{name}'"), c))?;
        declarations(name, members.iter().map(|m| (VarClass::Local, m)))?;
        if let Some(m) = members.iter().find(|m| m.address.is_some()) {
            return Err(fail(format!("member '{}' is located", m.name), "6.5.5"));
        }
    }
    for pou in pous {
        let fail = |what: String, clause| Violation { pou: pou.name.clone(), what, clause };
        identifier(&pou.name).map_err(|c| fail(format!("POU name '{}'", pou.name), c))?;
        let vars = pou.vars.iter().flat_map(|(c, vs)| vs.iter().map(move |v| (*c, v)));
        declarations(&pou.name, vars.clone())?;
        for (class, v) in vars {
            let Some(address) = &v.address else { continue };
            if !(pou.program && class == VarClass::Local) {
                let what = format!("'{}' is located in a {} of a {}", v.name, class.keyword(), kind(pou));
                return Err(fail(what, "6.5.5, Annex A Loc_Var_Decls"));
            }
            if let Some((other, _)) = addresses.iter().find(|(_, a)| a.eq_ignore_ascii_case(address)) {
                let what = format!("'{}' and '{other}' are both bound to {address}", v.name);
                return Err(fail(what, "6.5.5"));
            }
            addresses.push((&v.name, address));
        }
        let body = Body { scope: &scope, pou };
        for s in pou.sections.iter().flat_map(|s| &s.stmts) {
            body.stmt(s).map_err(|(what, clause)| fail(what, clause))?;
        }
    }
    Ok(())
}

fn kind(pou: &Pou) -> &'static str {
    if pou.program {
        "PROGRAM"
    } else {
        "FUNCTION_BLOCK"
    }
}

/// `Ok` when `name` may be declared; else the clause it breaks.
fn identifier(name: &str) -> Result<(), &'static str> {
    if is_identifier(name) {
        Ok(())
    } else {
        Err("6.1.2, 6.1.3")
    }
}

/// Names, uniqueness without regard to case, and initial values of one scope's declarations.
fn declarations<'v>(
    pou: &str,
    vars: impl Iterator<Item = (VarClass, &'v Var)> + Clone,
) -> Result<(), Violation> {
    let fail = |what: String, clause| Violation { pou: pou.to_owned(), what, clause };
    for (i, (_, v)) in vars.clone().enumerate() {
        identifier(&v.name).map_err(|c| fail(format!("'{}' is no identifier or is a keyword", v.name), c))?;
        if vars.clone().take(i).any(|(_, w)| w.name.eq_ignore_ascii_case(&v.name)) {
            return Err(fail(format!("'{}' is declared twice", v.name), "6.1.2"));
        }
        if let Some(init) = &v.init {
            let ok = match (&v.ty, init) {
                (Type::Bool, Expr::Bool(_)) => true,
                (t, Expr::Int(i)) => t.range().is_some_and(|(lo, hi)| (lo..=hi).contains(i)),
                _ => false,
            };
            if !ok {
                let what =
                    format!("'{}': initial value {} is no {} literal", v.name, init.text(), v.ty.text());
                return Err(fail(what, "6.5.1"));
            }
        }
    }
    Ok(())
}

type Found = Result<Ty, (String, &'static str)>;

/// The body of one POU, typed against its declarations.
struct Body<'a> {
    scope: &'a Scope<'a>,
    pou: &'a Pou,
}

impl Body<'_> {
    /// Type and block of a declared name of this POU.
    fn own(&self, name: &str) -> Option<(VarClass, &Var)> {
        self.pou.var(name)
    }

    /// The type of a member path `a.b.c`, and whether it reaches into a block instance.
    fn path(&self, path: &str) -> Result<(Type, bool), (String, &'static str)> {
        let mut parts = path.split('.');
        let first = parts.next().unwrap_or_default();
        let (_, v) = self.own(first).ok_or_else(|| (format!("'{first}' is not declared"), "6.5.1"))?;
        let (mut ty, mut instance) = (v.ty.clone(), false);
        for member in parts {
            let Type::Named(n) = &ty else {
                return Err((format!("'{path}': {} has no members", ty.text()), "6.5.1"));
            };
            let found = if let Some((_, ms)) = self.scope.structs.iter().find(|(s, _)| s == n) {
                ms.iter().find(|m| m.name.eq_ignore_ascii_case(member)).map(|m| m.ty.clone())
            } else if let Some(b) = self.scope.block(n) {
                instance = true;
                // From outside, an instance shows its inputs and outputs only (6.6.3).
                b.var(member).filter(|(c, _)| *c != VarClass::Local).map(|(_, v)| v.ty.clone())
            } else {
                None
            };
            ty = found.ok_or_else(|| (format!("'{path}': no visible member '{member}'"), "6.6.3"))?;
        }
        Ok((ty, instance))
    }

    fn expr(&self, e: &Expr) -> Found {
        let mismatch = |a: &Ty, b: &Ty| {
            (format!("'{}' mixes {} and {}: no implicit conversion", e.text(), show(a), show(b)), "6.6.1.6")
        };
        Ok(match e {
            Expr::Bool(_) => Ty::Is(Type::Bool),
            Expr::Int(i) => Ty::Literal(Some(*i)),
            Expr::Time(_) => Ty::Is(Type::Time),
            Expr::Var(p) => Ty::Is(self.path(p)?.0),
            Expr::Index(a, i) => {
                let Type::Array(upper, of) = self.path(a)?.0 else {
                    return Err((format!("'{a}' is no array"), "6.4.4"));
                };
                match self.expr(i)? {
                    Ty::Literal(Some(k)) if !(0..=upper).contains(&k) => {
                        return Err((format!("'{}': index out of 0..{upper}", e.text()), "6.4.4"))
                    }
                    Ty::Literal(_) => {}
                    Ty::Is(t) if t.range().is_some() => {}
                    t => return Err((format!("'{}': index of type {}", e.text(), show(&t)), "6.4.4")),
                }
                Ty::Is(*of)
            }
            Expr::Not(x) => {
                let t = self.expr(x)?;
                if t != Ty::Is(Type::Bool) {
                    return Err(mismatch(&t, &Ty::Is(Type::Bool)));
                }
                t
            }
            Expr::Bin(a, op, b) => {
                let (ta, tb) = (self.expr(a)?, self.expr(b)?);
                let common = unify(&ta, &tb).ok_or_else(|| mismatch(&ta, &tb))?;
                let logic = matches!(op, Op::And | Op::Or | Op::Xor);
                let compare = matches!(op, Op::Eq | Op::Ne | Op::Lt | Op::Gt | Op::Le | Op::Ge);
                let is_bool = common == Ty::Is(Type::Bool);
                if logic != is_bool && !(compare && is_bool && matches!(op, Op::Eq | Op::Ne)) {
                    let what = format!("'{}': {} operands for {}", e.text(), show(&common), op.text());
                    return Err((what, "7.3.2"));
                }
                match (compare, common) {
                    (true, _) => Ty::Is(Type::Bool),
                    (false, Ty::Literal(_)) => Ty::Literal(None),
                    (false, t) => t,
                }
            }
            Expr::Call(f, args) => {
                let (from, to) =
                    f.split_once("_TO_").ok_or_else(|| (format!("unknown function {f}"), "6.6.2.5"))?;
                let ty = |n: &str| {
                    [Type::Bool, Type::Int, Type::Dint, Type::Udint]
                        .into_iter()
                        .find(|t| t.elementary() == Some(n))
                };
                let (Some(from), Some(to), [x]) = (ty(from), ty(to), args.as_slice()) else {
                    return Err((format!("'{}': not a conversion of one argument", e.text()), "6.6.2.5"));
                };
                let tx = self.expr(x)?;
                unify(&tx, &Ty::Is(from.clone()))
                    .filter(|t| *t == Ty::Is(from.clone()))
                    .ok_or_else(|| mismatch(&tx, &Ty::Is(from)))?;
                Ty::Is(to)
            }
        })
    }

    /// `value` stored in a place of type `ty`, without conversion.
    fn store(&self, ty: &Type, value: &Expr, what: &str) -> Result<(), (String, &'static str)> {
        let t = self.expr(value)?;
        let ok = match &t {
            Ty::Is(x) => x == ty,
            Ty::Literal(Some(i)) => ty.range().is_some_and(|(lo, hi)| (lo..=hi).contains(i)),
            Ty::Literal(None) => ty.range().is_some(),
        };
        if ok {
            Ok(())
        } else {
            let why = format!(
                "{what} := {}: {} into {}, no implicit conversion",
                value.text(),
                show(&t),
                ty.text()
            );
            Err((why, "6.6.1.6"))
        }
    }

    fn stmt(&self, s: &Stmt) -> Result<(), (String, &'static str)> {
        match s {
            Stmt::Assign(target, value) => {
                let (name, ty) = match target {
                    Expr::Var(p) => {
                        let (ty, instance) = self.path(p)?;
                        if instance {
                            return Err((format!("'{p}' written from outside its block"), "6.6.3"));
                        }
                        (p.as_str(), ty)
                    }
                    Expr::Index(a, _) => (
                        a.as_str(),
                        match self.expr(target)? {
                            Ty::Is(t) => t,
                            Ty::Literal(_) => return Err((format!("'{a}' is no variable"), "7.3.3.2")),
                        },
                    ),
                    _ => return Err((format!("'{}' is no variable", target.text()), "7.3.3.2")),
                };
                let root = name.split('.').next().unwrap_or_default();
                if !self.pou.program && matches!(self.own(root), Some((VarClass::Input, _))) {
                    return Err((format!("'{root}' is a VAR_INPUT: the block cannot write it"), "6.5.2"));
                }
                self.store(&ty, value, &target.text())
            }
            Stmt::If(arms, els) => {
                for (c, body) in arms {
                    self.store(&Type::Bool, c, "IF")?;
                    body.iter().try_for_each(|s| self.stmt(s))?;
                }
                els.iter().try_for_each(|s| self.stmt(s))
            }
            Stmt::Case(e, arms, els) => {
                let t = match self.expr(e)? {
                    Ty::Is(t) if t.range().is_some() => t,
                    t => {
                        return Err((format!("CASE {}: selector of type {}", e.text(), show(&t)), "7.3.3.3"))
                    }
                };
                for (labels, body) in arms {
                    for l in labels {
                        self.store(&t, &Expr::Int(*l), "CASE label")?;
                    }
                    body.iter().try_for_each(|s| self.stmt(s))?;
                }
                els.iter().try_for_each(|s| self.stmt(s))
            }
            Stmt::For(v, from, to, body) => {
                let (ty, _) = self.path(v)?;
                if ty.range().is_none() {
                    return Err((format!("FOR {v}: control variable of type {}", ty.text()), "7.3.3.4"));
                }
                self.store(&ty, &Expr::Int(*from), v)?;
                self.store(&ty, &Expr::Int(*to), v)?;
                body.iter().try_for_each(|s| self.stmt(s))
            }
            Stmt::Exit => Ok(()),
            Stmt::Call(inst, args) => {
                let Some((_, Var { ty: Type::Named(n), .. })) = self.own(inst) else {
                    return Err((format!("'{inst}' is no block instance"), "6.6.3"));
                };
                let block = self.scope.block(n);
                let block = block.ok_or_else(|| (format!("'{inst}' is no block instance"), "6.6.3"))?;
                for (name, value) in args {
                    match block.var(name) {
                        Some((VarClass::Input, v)) => self.store(&v.ty, value, &format!("{inst}.{name}"))?,
                        _ => return Err((format!("{inst}: '{name}' is no input of {n}"), "6.6.3")),
                    }
                }
                Ok(())
            }
        }
    }
}

/// The type two operands share without conversion: equal types, or a literal and an integer type.
fn unify(a: &Ty, b: &Ty) -> Option<Ty> {
    match (a, b) {
        (Ty::Literal(_), Ty::Literal(_)) => Some(Ty::Literal(None)),
        (Ty::Literal(v), Ty::Is(t)) | (Ty::Is(t), Ty::Literal(v)) => {
            let (lo, hi) = t.range()?;
            v.is_none_or(|v| (lo..=hi).contains(&v)).then(|| Ty::Is(t.clone()))
        }
        (Ty::Is(x), Ty::Is(y)) => (x == y && x.elementary().is_some()).then(|| a.clone()),
    }
}

fn show(t: &Ty) -> String {
    match t {
        Ty::Is(t) => t.text(),
        Ty::Literal(_) => "an integer literal".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::super::ir::Section;
    use super::*;

    fn pou(program: bool, vars: Vec<(VarClass, Vec<Var>)>, stmts: Vec<Stmt>) -> Pou {
        let sections = vec![Section::new("run", "", stmts)];
        Pou { program, name: if program { "p".into() } else { "fb".into() }, vars, sections }
    }

    fn locals(vars: Vec<Var>) -> Vec<(VarClass, Vec<Var>)> {
        vec![(VarClass::Local, vars)]
    }

    fn one(p: &Pou) -> Result<(), Violation> {
        check(&[], &[p])
    }

    #[test]
    fn a_narrowing_assignment_is_refused_and_its_conversion_accepted() {
        let vars = || locals(vec![Var::new("k", Type::Int, ""), Var::new("rng", Type::Dint, "")]);
        let narrow = Stmt::set("k", Expr::var("rng").op(Op::Mod, Expr::Int(7)));
        let err = one(&pou(true, vars(), vec![narrow.clone()])).unwrap_err();
        assert!(err.what.contains("DINT into INT") && err.clause == "6.6.1.6", "{err}");
        let Stmt::Assign(_, e) = narrow else { unreachable!() };
        let fixed = Stmt::set("k", e.convert(&Type::Dint, &Type::Int));
        assert_eq!(one(&pou(true, vars(), vec![fixed])), Ok(()));
        let mixed = Stmt::set("rng", Expr::var("rng").op(Op::Mod, Expr::var("k")));
        assert!(one(&pou(true, vars(), vec![mixed])).unwrap_err().what.contains("mixes DINT and INT"));
        let big = Stmt::set("k", Expr::Int(40_000));
        assert!(one(&pou(true, vars(), vec![big])).is_err(), "a literal out of INT");
    }

    #[test]
    fn keywords_located_interfaces_and_double_bindings_are_refused() {
        let en = locals(vec![Var::new("EN", Type::Bool, "")]);
        assert_eq!(one(&pou(true, en, vec![])).unwrap_err().clause, "6.1.2, 6.1.3");
        let mut x = Var::new("x", Type::Bool, "");
        x.address = Some("%IX0.0".into());
        let fb = pou(false, vec![(VarClass::Input, vec![x.clone()])], vec![]);
        assert!(one(&fb).unwrap_err().what.contains("located in a VAR_INPUT of a FUNCTION_BLOCK"));
        assert_eq!(one(&pou(true, locals(vec![x.clone()]), vec![])), Ok(()));
        let mut y = x.clone();
        y.name = "y".into();
        let err = one(&pou(true, locals(vec![x, y]), vec![])).unwrap_err();
        assert!(err.what.contains("both bound to %IX0.0"), "{err}");
        let twice = locals(vec![Var::new("a", Type::Bool, ""), Var::new("A", Type::Int, "")]);
        assert!(one(&pou(true, twice, vec![])).unwrap_err().what.contains("declared twice"));
    }

    #[test]
    fn writes_to_inputs_and_to_instances_are_refused() {
        let fb = pou(
            false,
            vec![
                (VarClass::Input, vec![Var::new("i", Type::Bool, "")]),
                (VarClass::Output, vec![Var::new("o", Type::Bool, "")]),
            ],
            vec![Stmt::set("o", Expr::var("i"))],
        );
        assert_eq!(one(&fb), Ok(()));
        let mut bad = fb.clone();
        bad.sections[0].stmts = vec![Stmt::set("i", Expr::Bool(true))];
        assert_eq!(one(&bad).unwrap_err().clause, "6.5.2");
        let vars = locals(vec![Var::new("b", Type::Named("fb".into()), ""), Var::new("v", Type::Bool, "")]);
        let call = Stmt::Call("b".into(), vec![("i".into(), Expr::var("v"))]);
        let read = Stmt::set("v", Expr::var("b.o"));
        let main = pou(true, vars.clone(), vec![call, read]);
        assert_eq!(check(&[], &[&fb, &main]), Ok(()));
        let write = pou(true, vars.clone(), vec![Stmt::set("b.o", Expr::Bool(true))]);
        assert_eq!(check(&[], &[&fb, &write]).unwrap_err().clause, "6.6.3");
        let wrong = pou(true, vars, vec![Stmt::Call("b".into(), vec![("i".into(), Expr::Int(1))])]);
        assert!(check(&[], &[&fb, &wrong]).is_err(), "an INT literal into a BOOL input");
    }

    #[test]
    fn the_standard_on_delay_timer_is_known_with_its_types() {
        let vars = locals(vec![Var::new("t", Type::Named("TON".into()), ""), Var::new("v", Type::Bool, "")]);
        let call = |pt: Expr| Stmt::Call("t".into(), vec![("IN".into(), Expr::var("v")), ("PT".into(), pt)]);
        let read = Stmt::set("v", Expr::var("t.Q"));
        assert_eq!(check(&[], &[&pou(true, vars.clone(), vec![call(Expr::Time(700)), read])]), Ok(()));
        let wrong = check(&[], &[&pou(true, vars.clone(), vec![call(Expr::Int(700))])]).unwrap_err();
        assert_eq!(wrong.clause, "6.6.1.6");
        let write = check(&[], &[&pou(true, vars, vec![Stmt::set("t.Q", Expr::Bool(true))])]).unwrap_err();
        assert_eq!(write.clause, "6.6.3");
    }
}
