//! Rockwell Studio 5000 Logix Designer (ControlLogix/CompactLogix): the program as one `.L5X` project
//! file (`RSLogix5000Content`, `TargetType="Controller"`), the layout of Rockwell's import/export
//! format (publication 1756-RM084): `Controller` > `DataTypes` (a user data type per structure),
//! `AddOnInstructionDefinitions` (an Add-On Instruction per `FUNCTION_BLOCK`), `Tags` (the I/O as
//! controller tags), `Programs` > `Program` (the `PROGRAM`: its variables as program tags, its body as
//! the `MainRoutine`) and `Tasks` (a periodic task at the program's cycle scheduling it).
//!
//! Logix has no located variables: each `AT %IX…`/`%QX…` variable is a plain `BOOL` controller tag of
//! the same name, its generic address in the description; the user makes it an alias of a module
//! point (or copies the module's data to it). The dialect's rewrites of the generic statements, and
//! nothing else ([`Logix`]):
//!
//! | generic ST | Logix ST |
//! |---|---|
//! | `TRUE`, `FALSE` | `1`, `0` (a BOOL is 1 or 0) |
//! | `INT_TO_DINT(e)`, `DINT_TO_INT(e)` | `e` (an assignment converts) |
//! | `t(IN := c, PT := T#nms);` with `t : TON` | `t.TimerEnable := c;` `t.PRE := n;` `TONR(t);` (`t : FBD_TIMER`, ms) |
//! | `t.Q` | `t.DN` |
//! | `i(a := x, …);` with `i` a block instance | `i.a := x;` … `block(i);` (an input parameter is written through the instance, an Add-On Instruction call names the instance only) |
//!
//! Types: `UDINT` and `TIME` become `DINT` (Logix 5570 and earlier have no unsigned types; a `TIME`
//! is milliseconds), a `BOOL` array's size is rounded up to a multiple of 32, `TON` is `FBD_TIMER` in ST
//! and `TIMER` in ladder. A `PROGRAM` whose body is exactly its ladder rungs' statements (the
//! state-based and hybrid programs) is written as a ladder (`RLL`) routine: `XIC`/`XIO` contacts,
//! `[a ,b ]` branches, `OTE`/`OTL`/`OTU` coils and `TON(t,n,0)` timers read by `t.DN`. A `PROGRAM`
//! whose body holds rungs that each run ST after their coils ([`Graphic::LadderCallingSt`], the
//! state-based program with memory) is written as routines its ladder `MainRoutine` calls by
//! `JSR` in the body's order: the ST before the rungs, the rungs as ladder — each rung's ST an ST
//! routine its last instruction `JSR` calls, so it runs when the rung conducts, after its coils — and
//! the ST after them. An Add-On Instruction cannot call routines (`JSR`), so a block stays one ST
//! `Logic` routine.

use std::collections::HashSet;
use std::fmt::Write as _;

use super::{cdata, split_io};
use crate::formats::xml_escape;
use crate::scan::files::{File, Source};
use crate::scan::ir::{Expr, Pou, Section, Stmt, Type, Var, VarClass};
use crate::scan::ld::{CoilKind, Element, Rung};
use crate::scan::program::Graphic;
use crate::scan::st::statements;
use crate::scan::strict::Violation;

/// The Logix Designer release the file says it is from (`SoftwareRevision`) and the controller it
/// is for; both can be changed in the IDE after the import.
const SOFTWARE_REVISION: &str = "33.00";
/// A ControlLogix 5580 controller.
const PROCESSOR: &str = "1756-L83E";

/// What a Logix name must be: at most 40 characters, a letter or `_` then letters, digits and `_`,
/// no `__` and no trailing `_` (Logix Designer's rule for tags, routines, programs, tasks and types).
pub fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    let first = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    first
        && name.len() <= 40
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.contains("__")
        && !name.ends_with('_')
}

/// `name` checked against [`valid_name`].
fn checked<'a>(pou: &str, name: &'a str) -> Result<&'a str, Violation> {
    if valid_name(name) {
        Ok(name)
    } else {
        Err(Violation {
            pou: pou.to_owned(),
            what: format!("'{name}' is no Logix name (at most 40 characters, [A-Za-z_][A-Za-z0-9_]*, no '__', no trailing '_')"),
            clause: "Logix names",
        })
    }
}

/// How a routine is written: its timers' type differs.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Language {
    /// Structured text (`FBD_TIMER` timers, `TONR`).
    St,
    /// Relay ladder (`TIMER` timers, `TON`).
    Rll,
}

/// A type as Logix declares it: the data type and the array size, if any.
fn data_type(ty: &Type, language: Language) -> (String, Option<i64>) {
    match ty {
        Type::Bool => ("BOOL".into(), None),
        Type::Int => ("INT".into(), None),
        Type::Dint | Type::Udint | Type::Time => ("DINT".into(), None),
        Type::Array(upper, of) => {
            let (t, _) = data_type(of, language);
            let n = upper + 1;
            (t, Some(if **of == Type::Bool { (n + 31) / 32 * 32 } else { n }))
        }
        Type::Named(n) if n == "TON" => {
            (if language == Language::St { "FBD_TIMER" } else { "TIMER" }.into(), None)
        }
        Type::Named(n) => (n.clone(), None),
    }
}

/// Whether Logix's type is atomic (it takes a radix and a scalar initial value).
fn atomic(ty: &str) -> bool {
    matches!(ty, "BOOL" | "SINT" | "INT" | "DINT")
}

/// The attributes `DataType="…"` with ` Dimensions="n"` (named `dims`) and ` Radix="Decimal"` as
/// they apply.
fn type_attributes(v: &Var, language: Language, dims: &str) -> String {
    let (ty, n) = data_type(&v.ty, language);
    let mut out = format!("DataType=\"{}\"", xml_escape(&ty));
    if let Some(n) = n {
        let _ = write!(out, " {dims}=\"{n}\"");
    }
    if atomic(&ty) {
        out.push_str(" Radix=\"Decimal\"");
    }
    out
}

/// A description element, or nothing.
fn description(text: &str, pad: &str) -> String {
    if text.is_empty() {
        String::new()
    } else {
        format!("{pad}<Description>{}</Description>\n", cdata(text))
    }
}

/// The initial value of `v` as a `Decorated` data element named `element`, or nothing.
fn initial(v: &Var, element: &str, pad: &str) -> String {
    let value = match &v.init {
        Some(Expr::Bool(b)) => i64::from(*b),
        Some(Expr::Int(i)) => *i,
        Some(Expr::Time(ms)) => i64::from(*ms),
        _ => return String::new(),
    };
    let (ty, _) = data_type(&v.ty, Language::St);
    if !atomic(&ty) {
        return String::new();
    }
    format!(
        "{pad}<{element} Format=\"Decorated\"><DataValue DataType=\"{ty}\" Radix=\"Decimal\" Value=\"{value}\"/></{element}>\n"
    )
}

/// A tag (controller or program scope).
fn tag(v: &Var, language: Language, pad: &str) -> String {
    let inner = format!("{pad}  ");
    let body = format!("{}{}", description(&v.comment, &inner), initial(v, "Data", &inner));
    format!(
        "{pad}<Tag Name=\"{}\" TagType=\"Base\" {} Constant=\"false\" ExternalAccess=\"Read/Write\">\n{body}{pad}</Tag>\n",
        xml_escape(&v.name),
        type_attributes(v, language, "Dimensions")
    )
}

/// The rewrites of the generic statements into Logix ST, for one POU: which of its variables are
/// timers, and which are instances of which Add-On Instruction (with its parameters).
pub struct Logix<'a> {
    /// The POU's `TON` variables, lower case (ST names are case-insensitive).
    timers: HashSet<String>,
    /// The POU's block instances: name (lower case) and the block.
    instances: Vec<(String, &'a Pou)>,
    /// The POU's name, for errors.
    pou: &'a str,
}

impl<'a> Logix<'a> {
    /// The rewrites for `pou`, whose blocks are among `blocks`.
    pub fn new(pou: &'a Pou, blocks: &'a [&'a Pou]) -> Logix<'a> {
        let vars = pou.vars.iter().flat_map(|(_, vs)| vs);
        let mut timers = HashSet::new();
        let mut instances = Vec::new();
        for v in vars {
            match &v.ty {
                Type::Named(n) if n == "TON" => {
                    timers.insert(v.name.to_ascii_lowercase());
                }
                Type::Named(n) => {
                    if let Some(b) = blocks.iter().find(|b| b.name.eq_ignore_ascii_case(n)) {
                        instances.push((v.name.to_ascii_lowercase(), *b));
                    }
                }
                _ => {}
            }
        }
        Logix { timers, instances, pou: &pou.name }
    }

    /// A variable path with a timer's `Q` read as `DN`.
    fn path(&self, path: &str) -> String {
        match path.split_once('.') {
            Some((head, "Q")) if self.timers.contains(&head.to_ascii_lowercase()) => format!("{head}.DN"),
            _ => path.to_owned(),
        }
    }

    /// The expression in Logix ST.
    fn expr(&self, e: &Expr) -> Expr {
        match e {
            Expr::Bool(b) => Expr::Int(i64::from(*b)),
            Expr::Time(ms) => Expr::Int(i64::from(*ms)),
            Expr::Int(_) => e.clone(),
            Expr::Var(v) => Expr::Var(self.path(v)),
            Expr::Index(v, i) => Expr::Index(self.path(v), Box::new(self.expr(i))),
            Expr::Not(a) => Expr::Not(Box::new(self.expr(a))),
            Expr::Bin(a, op, b) => Expr::Bin(Box::new(self.expr(a)), *op, Box::new(self.expr(b))),
            Expr::Call(f, args) if f.contains("_TO_") && args.len() == 1 => self.expr(&args[0]),
            Expr::Call(f, args) => Expr::Call(f.clone(), args.iter().map(|a| self.expr(a)).collect()),
        }
    }

    /// A nested statement in Logix ST: a timer's call becomes its inputs and `TONR` where it stands; a
    /// block's call is written at the top level only ([`Logix::body`]).
    fn stmt(&self, s: &Stmt) -> Result<Vec<Stmt>, Violation> {
        let block = |b: &[Stmt]| -> Result<Vec<Stmt>, Violation> {
            Ok(b.iter().map(|s| self.stmt(s)).collect::<Result<Vec<_>, _>>()?.concat())
        };
        Ok(vec![match s {
            Stmt::Assign(t, v) => Stmt::Assign(self.expr(t), self.expr(v)),
            Stmt::If(arms, els) => Stmt::If(
                arms.iter().map(|(c, b)| Ok((self.expr(c), block(b)?))).collect::<Result<_, Violation>>()?,
                block(els)?,
            ),
            Stmt::Case(e, arms, els) => Stmt::Case(
                self.expr(e),
                arms.iter().map(|(l, b)| Ok((l.clone(), block(b)?))).collect::<Result<_, Violation>>()?,
                block(els)?,
            ),
            Stmt::For(v, from, to, body) => Stmt::For(v.clone(), *from, *to, block(body)?),
            Stmt::Exit => Stmt::Exit,
            Stmt::Call(inst, args) if self.timers.contains(&inst.to_ascii_lowercase()) => {
                return Ok(self.timer_call(inst, args))
            }
            Stmt::Call(inst, _) => {
                return Err(Violation {
                    pou: self.pou.to_owned(),
                    what: format!("the call of '{inst}' inside another statement has no Logix form here"),
                    clause: "Logix ST",
                })
            }
        }])
    }

    /// A timer's call: its inputs set (`IN` as `TimerEnable`, `PT` as `PRE`), then `TONR(timer)`.
    fn timer_call(&self, inst: &str, args: &[(String, Expr)]) -> Vec<Stmt> {
        let inputs = args.iter().map(|(name, e)| {
            let member = if name.eq_ignore_ascii_case("IN") { "TimerEnable" } else { "PRE" };
            Stmt::set(format!("{inst}.{member}"), self.expr(e))
        });
        inputs.chain([Stmt::Call("TONR".into(), vec![(String::new(), Expr::Var(inst.to_owned()))])]).collect()
    }

    /// A top-level call: a timer's inputs and `TONR`, or a block's input parameters and its Add-On
    /// Instruction call (in-out parameters passed in order after the instance).
    fn call(&self, inst: &str, args: &[(String, Expr)], out: &mut String) -> Result<(), Violation> {
        let key = inst.to_ascii_lowercase();
        if self.timers.contains(&key) {
            out.push_str(&statements(&self.timer_call(inst, args), 0));
            return Ok(());
        }
        let mut set = |member: &str, e: &Expr| {
            out.push_str(&statements(&[Stmt::set(format!("{inst}.{member}"), self.expr(e))], 0));
        };
        let Some((_, block)) = self.instances.iter().find(|(n, _)| *n == key) else {
            return Err(Violation {
                pou: self.pou.to_owned(),
                what: format!("'{inst}' is called but is no timer or block instance"),
                clause: "Logix ST",
            });
        };
        let mut positional = vec![inst.to_owned()];
        for (name, e) in args {
            match block.var(name) {
                Some((VarClass::Input, v)) if in_out(v) => positional.push(self.expr(e).text()),
                _ => set(name, e),
            }
        }
        let _ = writeln!(out, "{}({});", block.name, positional.join(", "));
        Ok(())
    }

    /// The body of `pou` in Logix ST: each section under its marker, the statements rewritten.
    pub fn body(&self, pou: &Pou) -> Result<String, Violation> {
        self.sections(&pou.sections)
    }

    /// `sections` in Logix ST, each under its marker (an empty one left out).
    fn sections(&self, sections: &[Section]) -> Result<String, Violation> {
        let mut out = String::new();
        for s in sections.iter().filter(|s| !s.stmts.is_empty()) {
            let title = if s.title.is_empty() { String::new() } else { format!(" - {}", s.title) };
            let _ = writeln!(out, "(* section: {}{title} *)", s.label);
            out.push_str(&self.statements(&s.stmts)?);
        }
        Ok(out)
    }

    /// Top-level statements in Logix ST.
    fn statements(&self, stmts: &[Stmt]) -> Result<String, Violation> {
        let mut out = String::new();
        for st in stmts {
            match st {
                Stmt::Call(inst, args) => self.call(inst, args, &mut out)?,
                st => out.push_str(&statements(&self.stmt(st)?, 0)),
            }
        }
        Ok(out)
    }

    /// A contact's or coil's operand.
    fn operand(&self, v: &str) -> String {
        self.path(v)
    }

    /// A rung's condition as Logix rung text.
    fn condition(&self, e: &Element) -> String {
        match e {
            Element::Contact { variable, negated } => {
                format!("{}({})", if *negated { "XIO" } else { "XIC" }, self.operand(variable))
            }
            Element::Series(es) => es.iter().map(|e| self.condition(e)).collect(),
            Element::Parallel(bs) => {
                let branches: Vec<String> = bs.iter().map(|b| self.condition(b)).collect();
                format!("[{} ]", branches.join(" ,"))
            }
        }
    }

    /// A rung as Logix rung text: the condition, then its coils in series.
    pub fn rung(&self, r: &Rung) -> String {
        self.rung_calling(r, None)
    }

    /// A rung as Logix rung text, its coils followed by `JSR(routine,0)` (the routine runs when the
    /// rung conducts, after the coils) when `routine` is given.
    fn rung_calling(&self, r: &Rung, routine: Option<&str>) -> String {
        let mut out = self.condition(&r.condition);
        for c in &r.coils {
            let v = self.operand(&c.variable);
            let _ = match c.kind {
                CoilKind::Out => write!(out, "OTE({v})"),
                CoilKind::Set => write!(out, "OTL({v})"),
                CoilKind::Reset => write!(out, "OTU({v})"),
                CoilKind::OnDelay(ms) => write!(out, "TON({v},{ms},0)"),
            };
        }
        if let Some(routine) = routine {
            let _ = write!(out, "JSR({routine},0)");
        }
        out.push(';');
        out
    }
}

/// Whether a block's input `v` is an in-out parameter in Logix (an Add-On Instruction's input
/// parameters are atomic; a structure or an array is passed by reference).
fn in_out(v: &Var) -> bool {
    !atomic(&data_type(&v.ty, Language::St).0) || matches!(v.ty, Type::Array(..))
}

/// The lines of a routine's ST as `STContent`.
fn st_content(text: &str, pad: &str) -> String {
    let mut out = format!("{pad}<STContent>\n");
    for (i, line) in text.lines().enumerate() {
        let _ = writeln!(out, "{pad}  <Line Number=\"{i}\">{}</Line>", cdata(line));
    }
    let _ = writeln!(out, "{pad}</STContent>");
    out
}

/// Rungs as `RLLContent`: each its comment and its text.
fn rll_content<'t>(rungs: impl IntoIterator<Item = (&'t str, String)>, pad: &str) -> String {
    let mut out = format!("{pad}<RLLContent>\n");
    for (i, (comment, text)) in rungs.into_iter().enumerate() {
        let comment = description(comment, &format!("{pad}    ")).replace("Description>", "Comment>");
        let _ = write!(
            out,
            "{pad}  <Rung Number=\"{i}\" Type=\"N\">\n{comment}{pad}    <Text>{}</Text>\n{pad}  </Rung>\n",
            cdata(&text)
        );
    }
    let _ = writeln!(out, "{pad}</RLLContent>");
    out
}

/// The ST each rung calls, when the body is the rungs with ST after their coils
/// ([`Graphic::LadderCallingSt`]): the body statement of a rung is `IF` its condition `THEN` its
/// coils' statements and then that ST. `None` when the statement is not the rung's.
fn st_after(stmt: &Stmt, rung: &Rung) -> Option<Vec<Stmt>> {
    let statements = rung.statements();
    let [Stmt::If(want, want_else)] = statements.as_slice() else { return None };
    let Stmt::If(arms, els) = stmt else { return None };
    match (want.as_slice(), arms.as_slice()) {
        ([(c, coils)], [(cond, body)]) if want_else.is_empty() && els.is_empty() && c == cond => {
            body.strip_prefix(coils.as_slice()).map(<[Stmt]>::to_vec)
        }
        _ => None,
    }
}

/// A part of a program written as routines the `MainRoutine` calls in turn.
enum Part<'a> {
    /// An ST routine: its name and sections.
    St(String, Vec<Section>),
    /// A ladder routine: its name and rungs, each with the ST it calls (none when empty).
    Rll(String, Vec<(&'a Rung, Vec<Stmt>)>),
}

/// How a `PROGRAM` is written: one ST `MainRoutine`, one ladder `MainRoutine` (its body is its rungs)
/// or a ladder `MainRoutine` calling its parts by `JSR` in the body's order.
enum Layout<'a> {
    /// Structured text.
    St,
    /// Ladder, the whole body.
    Rll(&'a [Rung]),
    /// ST and ladder routines called in turn.
    Parts(Vec<Part<'a>>),
}

/// A routine name from a section label (`aeem-set` → `aeem_set`).
fn routine_name(label: &str) -> String {
    label.replace('-', "_")
}

/// The parts of `pou` when a run of one section's statements is `rungs` with ST after their coils
/// (none of them a timer: a timer is a `TIMER` in ladder, an `FBD_TIMER` in ST, one tag cannot be
/// both): the sections before as one ST routine, the rungs as a ladder routine, the sections after
/// as one ST routine.
fn parts<'a>(pou: &Pou, rungs: &'a [Rung]) -> Option<Vec<Part<'a>>> {
    let timers = rungs.iter().flat_map(|r| &r.coils).any(|c| matches!(c.kind, CoilKind::OnDelay(_)));
    if rungs.is_empty() || timers {
        return None;
    }
    for (i, section) in pou.sections.iter().enumerate() {
        for k in 0..section.stmts.len().saturating_sub(rungs.len() - 1) {
            let window = &section.stmts[k..k + rungs.len()];
            let Some(after) =
                window.iter().zip(rungs).map(|(s, r)| st_after(s, r)).collect::<Option<Vec<_>>>()
            else {
                continue;
            };
            let piece = |stmts: &[Stmt]| Section::new(section.label, section.title.clone(), stmts.to_vec());
            let before: Vec<Section> =
                pou.sections[..i].iter().cloned().chain([piece(&section.stmts[..k])]).collect();
            let rest: Vec<Section> = [piece(&section.stmts[k + rungs.len()..])]
                .into_iter()
                .chain(pou.sections[i + 1..].iter().cloned())
                .collect();
            let ladder = routine_name(section.label);
            // An ST routine is named after its first section, `<ladder>_before`/`_after` when that
            // is the ladder's own.
            let st = |sections: Vec<Section>, side: &str| {
                let sections: Vec<Section> = sections.into_iter().filter(|s| !s.stmts.is_empty()).collect();
                let name = sections.first().map(|s| routine_name(s.label))?;
                let name = if name == ladder { format!("{ladder}_{side}") } else { name };
                Some(Part::St(name, sections))
            };
            let mut out: Vec<Part> = st(before, "before").into_iter().collect();
            out.push(Part::Rll(ladder.clone(), rungs.iter().zip(after).collect()));
            out.extend(st(rest, "after"));
            return Some(out);
        }
    }
    None
}

/// The rungs of `pou` when they are its whole body (its statements are the rungs' statements, in
/// order), else `None`.
fn whole_ladder<'a>(pou: &Pou, graphic: &'a Graphic) -> Option<&'a [Rung]> {
    let Graphic::Ladder(rungs) = graphic else { return None };
    let body: Vec<&Stmt> = pou.sections.iter().flat_map(|s| &s.stmts).collect();
    let ladder: Vec<Stmt> = rungs.iter().flat_map(Rung::statements).collect();
    (body.len() == ladder.len() && body.iter().zip(&ladder).all(|(a, b)| *a == b)).then_some(rungs.as_slice())
}

/// How `pou` with `graphic` is written.
fn layout<'a>(pou: &Pou, graphic: &'a Graphic) -> Layout<'a> {
    if let Some(rungs) = whole_ladder(pou, graphic) {
        return Layout::Rll(rungs);
    }
    match graphic {
        Graphic::LadderCallingSt(rungs) => parts(pou, rungs).map_or(Layout::St, Layout::Parts),
        _ => Layout::St,
    }
}

/// A structure as a user data type: `BOOL` members as bits of hidden `SINT` hosts, as Logix stores them.
fn data_type_element(name: &str, members: &[Var]) -> Result<String, Violation> {
    let mut out = format!(
        "    <DataType Name=\"{}\" Family=\"NoFamily\" Class=\"User\">\n      <Members>\n",
        checked(name, name)?
    );
    let mut bits = 0usize;
    for m in members {
        checked(name, &m.name)?;
        let desc = description(&m.comment, "          ");
        if m.ty == Type::Bool {
            let host = format!("ZZZZZZZZZZ{name}{}", bits / 8);
            if bits.is_multiple_of(8) {
                let _ = writeln!(
                    out,
                    "        <Member Name=\"{host}\" DataType=\"SINT\" Dimension=\"0\" Radix=\"Decimal\" Hidden=\"true\" ExternalAccess=\"Read/Write\"/>"
                );
            }
            let _ = write!(
                out,
                "        <Member Name=\"{}\" DataType=\"BIT\" Dimension=\"0\" Radix=\"Decimal\" Hidden=\"false\" Target=\"{host}\" BitNumber=\"{}\" ExternalAccess=\"Read/Write\">\n{desc}        </Member>\n",
                m.name,
                bits % 8
            );
            bits += 1;
        } else {
            let (ty, n) = data_type(&m.ty, Language::St);
            let radix = if atomic(&ty) { " Radix=\"Decimal\"" } else { "" };
            let _ = write!(
                out,
                "        <Member Name=\"{}\" DataType=\"{ty}\" Dimension=\"{}\"{radix} Hidden=\"false\" ExternalAccess=\"Read/Write\">\n{desc}        </Member>\n",
                m.name,
                n.unwrap_or(0)
            );
        }
    }
    out.push_str("      </Members>\n    </DataType>\n");
    Ok(out)
}

/// A `FUNCTION_BLOCK` as an Add-On Instruction: inputs and outputs as parameters (a structure or array
/// input in-out), locals as local tags, the body as its `Logic` routine in ST.
fn add_on(pou: &Pou, blocks: &[&Pou]) -> Result<String, Violation> {
    let name = checked(&pou.name, &pou.name)?;
    let mut out = format!(
        "    <AddOnInstructionDefinition Name=\"{name}\" Revision=\"1.0\" ExecutePrescan=\"false\" ExecutePostscan=\"false\" ExecuteEnableInFalse=\"false\" SoftwareRevision=\"v{SOFTWARE_REVISION}\">\n      <Parameters>\n"
    );
    for (n, usage) in [("EnableIn", "Input"), ("EnableOut", "Output")] {
        let _ = writeln!(
            out,
            "        <Parameter Name=\"{n}\" TagType=\"Base\" DataType=\"BOOL\" Usage=\"{usage}\" Radix=\"Decimal\" Required=\"false\" Visible=\"false\" ExternalAccess=\"Read Only\"/>"
        );
    }
    let mut locals = String::new();
    for (class, vars) in &pou.vars {
        for v in vars {
            checked(name, &v.name)?;
            let pad = "          ";
            let desc = description(&v.comment, pad);
            match class {
                VarClass::Local => {
                    let _ = write!(
                        locals,
                        "        <LocalTag Name=\"{}\" {} ExternalAccess=\"None\">\n{desc}{}        </LocalTag>\n",
                        v.name,
                        type_attributes(v, Language::St, "Dimensions"),
                        initial(v, "DefaultData", pad)
                    );
                }
                VarClass::Input if in_out(v) => {
                    let _ = write!(
                        out,
                        "        <Parameter Name=\"{}\" TagType=\"Base\" {} Usage=\"InOut\" Required=\"true\" Visible=\"true\" Constant=\"false\">\n{desc}        </Parameter>\n",
                        v.name,
                        type_attributes(v, Language::St, "Dimensions")
                    );
                }
                VarClass::Input | VarClass::Output => {
                    let (usage, access) = if *class == VarClass::Input {
                        ("Input", "Read/Write")
                    } else {
                        ("Output", "Read Only")
                    };
                    let _ = write!(
                        out,
                        "        <Parameter Name=\"{}\" TagType=\"Base\" {} Usage=\"{usage}\" Required=\"false\" Visible=\"false\" ExternalAccess=\"{access}\">\n{desc}{}        </Parameter>\n",
                        v.name,
                        type_attributes(v, Language::St, "Dimensions"),
                        initial(v, "DefaultData", pad)
                    );
                }
            }
        }
    }
    let body = Logix::new(pou, blocks).body(pou)?;
    let _ = write!(
        out,
        "      </Parameters>\n      <LocalTags>\n{locals}      </LocalTags>\n      <Routines>\n        <Routine Name=\"Logic\" Type=\"ST\">\n{}        </Routine>\n      </Routines>\n    </AddOnInstructionDefinition>\n",
        st_content(&body, "          ")
    );
    Ok(out)
}

/// A routine element of type `kind` holding `content`.
fn routine(name: &str, kind: &str, content: &str) -> String {
    format!("          <Routine Name=\"{name}\" Type=\"{kind}\">\n{content}          </Routine>\n")
}

/// The routines of a program laid out in `parts`: a ladder `MainRoutine` calling each part by `JSR`
/// in turn, then each part's routine (a ladder part followed by the ST routines its rungs call,
/// `<part>_<rung>`).
fn part_routines(pou: &Pou, logix: &Logix, parts: &[Part], pad: &str) -> Result<String, Violation> {
    let mut calls = Vec::new();
    let mut out = String::new();
    for part in parts {
        match part {
            Part::St(name, sections) => {
                let name = checked(&pou.name, name)?;
                calls.push((format!("the {name} section (ST)"), format!("JSR({name},0);")));
                out.push_str(&routine(name, "ST", &st_content(&logix.sections(sections)?, pad)));
            }
            Part::Rll(name, rungs) => {
                let name = checked(&pou.name, name)?;
                calls.push((format!("the {name} section (ladder)"), format!("JSR({name},0);")));
                let mut called = String::new();
                let mut texts = Vec::new();
                for (i, (rung, after)) in rungs.iter().enumerate() {
                    let callee = format!("{name}_{i}");
                    let callee = if after.is_empty() { None } else { Some(checked(&pou.name, &callee)?) };
                    texts.push((rung.comment.as_str(), logix.rung_calling(rung, callee)));
                    if let Some(callee) = callee {
                        called.push_str(&routine(callee, "ST", &st_content(&logix.statements(after)?, pad)));
                    }
                }
                out.push_str(&routine(name, "RLL", &rll_content(texts, pad)));
                out.push_str(&called);
            }
        }
    }
    let main = rll_content(calls.iter().map(|(c, t)| (c.as_str(), t.clone())), pad);
    Ok(format!("{}{out}", routine("MainRoutine", "RLL", &main)))
}

/// A `PROGRAM` (its located variables taken out) as a Logix program: its variables as program tags,
/// its body as the `MainRoutine` — ladder when the body is its rungs, ST and ladder routines called
/// in turn when part of it is rungs calling ST, else ST.
fn logix_program(pou: &Pou, graphic: &Graphic, blocks: &[&Pou]) -> Result<String, Violation> {
    let name = checked(&pou.name, &pou.name)?;
    let logix = Logix::new(pou, blocks);
    let layout = layout(pou, graphic);
    let language = if matches!(layout, Layout::Rll(_)) { Language::Rll } else { Language::St };
    let mut out = format!(
        "      <Program Name=\"{name}\" TestEdits=\"false\" MainRoutineName=\"MainRoutine\" Disabled=\"false\" UseAsFolder=\"false\">\n        <Tags>\n"
    );
    for v in pou.vars.iter().flat_map(|(_, vs)| vs) {
        checked(name, &v.name)?;
        out.push_str(&tag(v, language, "          "));
    }
    out.push_str("        </Tags>\n        <Routines>\n");
    let pad = "            ";
    let routines = match &layout {
        Layout::Rll(rungs) => routine(
            "MainRoutine",
            "RLL",
            &rll_content(rungs.iter().map(|r| (r.comment.as_str(), logix.rung(r))), pad),
        ),
        Layout::St => routine("MainRoutine", "ST", &st_content(&logix.body(pou)?, pad)),
        Layout::Parts(parts) => part_routines(pou, &logix, parts, pad)?,
    };
    let _ = write!(out, "{routines}        </Routines>\n      </Program>\n");
    Ok(out)
}

/// The Studio 5000 project of `source`: `<base>.L5X`.
pub fn files(source: &Source) -> Result<Vec<File>, Violation> {
    let program = &source.program;
    let base = checked(&program.base, &program.base)?;
    let blocks: Vec<&Pou> = program.pous.iter().map(|(p, _)| p).filter(|p| !p.program).collect();
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"yes\"?>\n<!--\n");
    for l in source.header.lines() {
        let _ = writeln!(out, "  {}", l.replace("--", "- -"));
    }
    let _ = write!(
        out,
        "-->\n<RSLogix5000Content SchemaRevision=\"1.0\" SoftwareRevision=\"{SOFTWARE_REVISION}\" TargetName=\"{base}\" TargetType=\"Controller\" ContainsContext=\"false\" Owner=\"codegen\">\n  <Controller Use=\"Target\" Name=\"{base}\" ProcessorType=\"{PROCESSOR}\" MajorRev=\"33\" MinorRev=\"11\">\n    <DataTypes>\n"
    );
    for (name, members) in &program.types {
        out.push_str(&data_type_element(name, members)?);
    }
    out.push_str("    </DataTypes>\n    <AddOnInstructionDefinitions>\n");
    for b in &blocks {
        out.push_str(&add_on(b, &blocks)?);
    }
    out.push_str("    </AddOnInstructionDefinitions>\n    <Tags>\n");
    let mut programs = String::new();
    let mut scheduled = String::new();
    for (p, graphic) in program.pous.iter().filter(|(p, _)| p.program) {
        let (p, io) = split_io(p);
        for v in &io {
            checked(&p.name, &v.name)?;
            let mut v = v.clone();
            let at = v.address.take().unwrap_or_default();
            v.comment = if v.comment.is_empty() {
                format!("generic {at}")
            } else {
                format!("{}; generic {at}", v.comment)
            };
            out.push_str(&tag(&v, Language::St, "      "));
        }
        programs.push_str(&logix_program(&p, graphic, &blocks)?);
        let _ = writeln!(scheduled, "          <ScheduledProgram Name=\"{}\"/>", p.name);
    }
    let task = checked(base, &format!("{base}_task"))?.to_owned();
    let _ = write!(
        out,
        "    </Tags>\n    <Programs>\n{programs}    </Programs>\n    <Tasks>\n      <Task Name=\"{task}\" Type=\"PERIODIC\" Rate=\"{}\" Priority=\"10\" Watchdog=\"500\" DisableUpdateOutputs=\"false\" InhibitTask=\"false\">\n        <ScheduledPrograms>\n{scheduled}        </ScheduledPrograms>\n      </Task>\n    </Tasks>\n  </Controller>\n</RSLogix5000Content>\n",
        program.cycle_ms
    );
    Ok(vec![(format!("{base}.L5X"), out)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_follow_logix_rules() {
        assert!(valid_name("cell_main") && valid_name("_x1"));
        for bad in ["1x", "a__b", "a_", "a-b", "", &"x".repeat(41)] {
            assert!(!valid_name(bad), "{bad}");
        }
    }

    #[test]
    fn timers_conversions_booleans_and_block_calls_are_rewritten() {
        let fb = Pou {
            program: false,
            name: "p_sct".into(),
            vars: vec![(VarClass::Input, vec![Var::new("a", Type::Bool, "")])],
            sections: Vec::new(),
        };
        let main = Pou {
            program: true,
            name: "p_main".into(),
            vars: vec![(
                VarClass::Local,
                vec![
                    Var::new("t", Type::Named("TON".into()), ""),
                    Var::new("sct", Type::Named("p_sct".into()), ""),
                    Var::new("x", Type::Bool, ""),
                    Var::new("n", Type::Dint, ""),
                ],
            )],
            sections: vec![Section::new(
                "run",
                "",
                vec![
                    Stmt::Call(
                        "t".into(),
                        vec![("IN".into(), Expr::var("x")), ("PT".into(), Expr::Time(20))],
                    ),
                    Stmt::set("x", Expr::var("t.Q").op(crate::scan::Op::And, Expr::Bool(true))),
                    Stmt::set("n", Expr::var("x").convert(&Type::Int, &Type::Dint)),
                    Stmt::Call("sct".into(), vec![("a".into(), Expr::var("x"))]),
                ],
            )],
        };
        let blocks = [&fb];
        let body = Logix::new(&main, &blocks).body(&main).unwrap();
        assert_eq!(
            body,
            "(* section: run *)\nt.TimerEnable := x;\nt.PRE := 20;\nTONR(t);\nx := t.DN AND 1;\nn := x;\nsct.a := x;\np_sct(sct);\n"
        );
    }

    #[test]
    fn a_rung_is_contacts_branches_and_coils() {
        let main = Pou {
            program: true,
            name: "m".into(),
            vars: vec![(VarClass::Local, vec![Var::new("T", Type::Named("TON".into()), "")])],
            sections: Vec::new(),
        };
        let r = Rung {
            comment: String::new(),
            condition: Element::Series(vec![
                Element::contact("a", true),
                Element::Parallel(vec![Element::contact("b", false), Element::contact("T.Q", false)]),
            ]),
            coils: vec![
                crate::scan::ld::Coil { variable: "a".into(), kind: CoilKind::Set },
                crate::scan::ld::Coil { variable: "c".into(), kind: CoilKind::Reset },
            ],
        };
        assert_eq!(Logix::new(&main, &[]).rung(&r), "XIO(a)[XIC(b) ,XIC(T.DN) ]OTL(a)OTU(c);");
    }

    #[test]
    fn rungs_running_st_are_a_ladder_routine_calling_st_routines_between_st_routines() {
        let rung = |c: &str, x: &str| Rung {
            comment: format!("set {x}"),
            condition: Element::contact(c, false),
            coils: vec![crate::scan::ld::Coil { variable: x.into(), kind: CoilKind::Set }],
        };
        let rungs = vec![rung("a", "x"), rung("b", "y")];
        let bool_vars = ["a", "b", "x", "y"].map(|n| Var::new(n, Type::Bool, ""));
        let main = Pou {
            program: true,
            name: "m".into(),
            vars: vec![(VarClass::Local, [bool_vars.to_vec(), vec![Var::new("n", Type::Int, "")]].concat())],
            sections: vec![
                Section::new("events", "", vec![Stmt::set("n", Expr::Int(0))]),
                Section::new(
                    "rungs",
                    "",
                    vec![
                        // The first rung runs ST after its coil; the second none.
                        Stmt::when(
                            Expr::var("a"),
                            vec![Stmt::set("x", Expr::Bool(true)), Stmt::set("n", Expr::Int(1))],
                        ),
                        Stmt::when(Expr::var("b"), vec![Stmt::set("y", Expr::Bool(true))]),
                        Stmt::set("n", Expr::Int(2)),
                    ],
                ),
            ],
        };
        let out = logix_program(&main, &Graphic::LadderCallingSt(rungs.clone()), &[]).unwrap();
        let routines: Vec<&str> = out.lines().filter(|l| l.contains("<Routine ")).map(str::trim).collect();
        assert_eq!(
            routines,
            [
                "<Routine Name=\"MainRoutine\" Type=\"RLL\">",
                "<Routine Name=\"events\" Type=\"ST\">",
                "<Routine Name=\"rungs\" Type=\"RLL\">",
                "<Routine Name=\"rungs_0\" Type=\"ST\">",
                "<Routine Name=\"rungs_after\" Type=\"ST\">",
            ]
        );
        for text in [
            "JSR(events,0);",
            "JSR(rungs,0);",
            "JSR(rungs_after,0);",
            "XIC(a)OTL(x)JSR(rungs_0,0);",
            "XIC(b)OTL(y);",
            "n := 1;",
            "(* section: rungs *)]]></Line>\n              <Line Number=\"1\"><![CDATA[n := 2;",
        ] {
            assert!(out.contains(text), "{text}\n{out}");
        }
        // Statements that are not the rungs' keep the program ST.
        let other = vec![rung("a", "y"), rung("b", "y")];
        let st = logix_program(&main, &Graphic::LadderCallingSt(other), &[]).unwrap();
        assert!(st.contains("<Routine Name=\"MainRoutine\" Type=\"ST\">") && !st.contains("JSR"));
    }
}
