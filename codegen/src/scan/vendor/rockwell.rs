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
//! `[a ,b ]` branches, `OTE`/`OTL`/`OTU` coils and `TON(t,n,0)` timers read by `t.DN`.

use std::collections::HashSet;
use std::fmt::Write as _;

use super::{cdata, split_io};
use crate::formats::xml_escape;
use crate::scan::files::{File, Source};
use crate::scan::ir::{Expr, Pou, Stmt, Type, Var, VarClass};
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

    /// A nested statement in Logix ST (a call is written at the top level only: [`Logix::body`]).
    fn stmt(&self, s: &Stmt) -> Result<Stmt, Violation> {
        let block = |b: &[Stmt]| b.iter().map(|s| self.stmt(s)).collect::<Result<Vec<_>, _>>();
        Ok(match s {
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
            Stmt::Call(inst, _) => {
                return Err(Violation {
                    pou: self.pou.to_owned(),
                    what: format!("the call of '{inst}' inside another statement has no Logix form here"),
                    clause: "Logix ST",
                })
            }
        })
    }

    /// A top-level call: a timer's inputs and `TONR`, or a block's input parameters and its Add-On
    /// Instruction call (in-out parameters passed in order after the instance).
    fn call(&self, inst: &str, args: &[(String, Expr)], out: &mut String) -> Result<(), Violation> {
        let key = inst.to_ascii_lowercase();
        let mut set = |member: &str, e: &Expr| {
            out.push_str(&statements(&[Stmt::set(format!("{inst}.{member}"), self.expr(e))], 0));
        };
        if self.timers.contains(&key) {
            for (name, e) in args {
                set(if name.eq_ignore_ascii_case("IN") { "TimerEnable" } else { "PRE" }, e);
            }
            let _ = writeln!(out, "TONR({inst});");
            return Ok(());
        }
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
        let mut out = String::new();
        for s in pou.sections.iter().filter(|s| !s.stmts.is_empty()) {
            let title = if s.title.is_empty() { String::new() } else { format!(" - {}", s.title) };
            let _ = writeln!(out, "(* section: {}{title} *)", s.label);
            for st in &s.stmts {
                match st {
                    Stmt::Call(inst, args) => self.call(inst, args, &mut out)?,
                    st => out.push_str(&statements(&[self.stmt(st)?], 0)),
                }
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

/// The rungs as `RLLContent`.
fn rll_content(logix: &Logix, rungs: &[Rung], pad: &str) -> String {
    let mut out = format!("{pad}<RLLContent>\n");
    for (i, r) in rungs.iter().enumerate() {
        let comment = description(&r.comment, &format!("{pad}    ")).replace("Description>", "Comment>");
        let _ = write!(
            out,
            "{pad}  <Rung Number=\"{i}\" Type=\"N\">\n{comment}{pad}    <Text>{}</Text>\n{pad}  </Rung>\n",
            cdata(&logix.rung(r))
        );
    }
    let _ = writeln!(out, "{pad}</RLLContent>");
    out
}

/// The rungs of `pou` when they are its whole body (its statements are the rungs' statements, in
/// order), else `None`.
fn whole_ladder<'a>(pou: &Pou, graphic: &'a Graphic) -> Option<&'a [Rung]> {
    let Graphic::Ladder(rungs) = graphic else { return None };
    let body: Vec<&Stmt> = pou.sections.iter().flat_map(|s| &s.stmts).collect();
    let ladder: Vec<Stmt> = rungs.iter().flat_map(Rung::statements).collect();
    (body.len() == ladder.len() && body.iter().zip(&ladder).all(|(a, b)| *a == b)).then_some(rungs.as_slice())
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

/// A `PROGRAM` (its located variables taken out) as a Logix program: its variables as program tags,
/// its body as the `MainRoutine` — ladder when the body is its rungs, else ST.
fn logix_program(pou: &Pou, graphic: &Graphic, blocks: &[&Pou]) -> Result<String, Violation> {
    let name = checked(&pou.name, &pou.name)?;
    let logix = Logix::new(pou, blocks);
    let rungs = whole_ladder(pou, graphic);
    let language = if rungs.is_some() { Language::Rll } else { Language::St };
    let mut out = format!(
        "      <Program Name=\"{name}\" TestEdits=\"false\" MainRoutineName=\"MainRoutine\" Disabled=\"false\" UseAsFolder=\"false\">\n        <Tags>\n"
    );
    for v in pou.vars.iter().flat_map(|(_, vs)| vs) {
        checked(name, &v.name)?;
        out.push_str(&tag(v, language, "          "));
    }
    out.push_str("        </Tags>\n        <Routines>\n");
    let pad = "            ";
    let routine = match rungs {
        Some(rungs) => format!(
            "          <Routine Name=\"MainRoutine\" Type=\"RLL\">\n{}",
            rll_content(&logix, rungs, pad)
        ),
        None => format!(
            "          <Routine Name=\"MainRoutine\" Type=\"ST\">\n{}",
            st_content(&logix.body(pou)?, pad)
        ),
    };
    let _ = write!(out, "{routine}          </Routine>\n        </Routines>\n      </Program>\n");
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
    use crate::scan::ir::Section;

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
}
