//! Ladder Diagram: rungs of contacts (in series and in parallel branches) driving coils (plain, SET,
//! RESET), written as a PLCopen TC6 2.01 `<LD>` body, and measured as the instruction list a PLC
//! compiles a rung to.
//!
//! A rung's condition is a tree of [`Element`]s: a contact, a series of elements (AND) or parallel
//! branches (OR). The XML numbers every object (`localId`) and wires each to the objects feeding it
//! (`connectionPointIn`/`connection refLocalId`): a parallel block is its branches fed from the same
//! points, and whatever follows it is fed by the last object of every branch. Positions are a plain
//! grid (the schema requires them; editors re-route). Output is deterministic.
//!
//! # Instruction-list cost model
//!
//! Each contact is one instruction (`LD`/`LDN` opening a block, `AND`/`ANDN` in series, `OR`/`ORN` as a
//! one-contact branch); an element in series or in parallel that is more than one contact opens a block
//! (a push on the logic stack) and costs one more instruction to close it (`ANDSTR`/`ORSTR`, Koyo's
//! `AND LD`/`OR LD`); each coil is one instruction (`OUT`, `SET`, `RST`). The stack depth is the most
//! blocks open at once, the rung's own included: a precondition in series with parallel products is 3.

use std::fmt::Write as _;

use super::ir::{Expr, Op, Stmt};
use crate::formats::xml_escape;

/// A piece of a rung's condition.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Element {
    /// A contact on a BOOL variable: closed when it is TRUE (`negated`: when it is FALSE).
    Contact {
        /// The variable.
        variable: String,
        /// Normally closed.
        negated: bool,
    },
    /// Elements one after the other: all must conduct. An empty series is a plain wire.
    Series(Vec<Element>),
    /// Branches side by side: one must conduct. No branch never conducts.
    Parallel(Vec<Element>),
}

/// What a coil does to its variable when the rung conducts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoilKind {
    /// The variable follows the rung (`OUT`).
    Out,
    /// The variable is set and stays set (`SET`, storage `set`).
    Set,
    /// The variable is reset and stays reset (`RST`, storage `reset`).
    Reset,
    /// The variable is an on-delay timer (`TON`) the rung starts: its `Q` turns TRUE once the rung has
    /// conducted for this many milliseconds, and FALSE when the rung stops conducting. Written as the
    /// standard block with its preset time, read elsewhere by a contact on `<variable>.Q`.
    OnDelay(u32),
}

impl CoilKind {
    /// Instructions under the cost model: one, and two for a timer (its preset loaded, the block called).
    fn instructions(self) -> usize {
        match self {
            CoilKind::OnDelay(_) => 2,
            _ => 1,
        }
    }
}

/// A coil.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coil {
    /// The variable driven.
    pub variable: String,
    /// How.
    pub kind: CoilKind,
}

/// A rung: a condition from the left power rail, coils to the right one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rung {
    /// What the rung is for (a comment object above it).
    pub comment: String,
    /// The condition.
    pub condition: Element,
    /// The coils, side by side.
    pub coils: Vec<Coil>,
}

/// Instruction-list figures of a rung or a diagram, under the module's cost model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct IlCost {
    /// Instructions.
    pub instructions: usize,
    /// Most logic blocks open at once.
    pub stack_depth: usize,
}

impl Element {
    /// A contact.
    pub fn contact(variable: impl Into<String>, negated: bool) -> Element {
        Element::Contact { variable: variable.into(), negated }
    }

    /// Contacts in the element.
    pub fn contacts(&self) -> usize {
        match self {
            Element::Contact { .. } => 1,
            Element::Series(es) | Element::Parallel(es) => es.iter().map(Element::contacts).sum(),
        }
    }

    /// The element reduced: a series or parallel of one element is that element.
    fn simple(&self) -> &Element {
        match self {
            Element::Series(es) | Element::Parallel(es) if es.len() == 1 => es[0].simple(),
            e => e,
        }
    }

    /// Whether the element conducts when `closed(variable)` says which variables are TRUE.
    pub fn conducts(&self, closed: &dyn Fn(&str) -> bool) -> bool {
        match self {
            Element::Contact { variable, negated } => closed(variable) != *negated,
            Element::Series(es) => es.iter().all(|e| e.conducts(closed)),
            Element::Parallel(es) => es.iter().any(|e| e.conducts(closed)),
        }
    }

    /// The instruction list the element compiles to, opening its own block.
    pub fn il(&self) -> IlCost {
        match self.simple() {
            Element::Contact { .. } => IlCost { instructions: 1, stack_depth: 1 },
            Element::Series(es) | Element::Parallel(es) => {
                let mut cost = IlCost::default();
                for (i, e) in es.iter().map(Element::simple).enumerate() {
                    let c = e.il();
                    if i == 0 {
                        cost = c;
                    } else if let Element::Contact { .. } = e {
                        cost.instructions += 1;
                    } else {
                        cost.instructions += c.instructions + 1;
                        cost.stack_depth = cost.stack_depth.max(c.stack_depth + 1);
                    }
                }
                cost
            }
        }
    }

    /// The element as ST (`AND`, `OR`, `NOT`), parenthesised as needed.
    pub fn st(&self) -> Expr {
        match self.simple() {
            Element::Contact { variable, negated: false } => Expr::var(variable.clone()),
            Element::Contact { variable, negated: true } => !Expr::var(variable.clone()),
            Element::Series(es) => Expr::fold(es.iter().map(Element::st), Op::And, Expr::Bool(true)),
            Element::Parallel(es) => Expr::fold(es.iter().map(Element::st), Op::Or, Expr::Bool(false)),
        }
    }
}

impl Rung {
    /// The rung as ST: `IF condition THEN` its SET/RESET coils `END_IF`, an `OUT` coil as an assignment
    /// of the condition, a timer as its call with the condition as `IN`; a rung without contacts runs its
    /// SET/RESET coils unconditionally.
    pub fn statements(&self) -> Vec<Stmt> {
        let cond = self.condition.st();
        let mut out = Vec::new();
        let mut latched = Vec::new();
        for c in &self.coils {
            match c.kind {
                CoilKind::Set | CoilKind::Reset => {
                    latched.push(Stmt::set(c.variable.clone(), Expr::Bool(c.kind == CoilKind::Set)))
                }
                CoilKind::Out => out.push(Stmt::set(c.variable.clone(), cond.clone())),
                CoilKind::OnDelay(ms) => out.push(Stmt::Call(
                    c.variable.clone(),
                    vec![("IN".into(), cond.clone()), ("PT".into(), Expr::Time(ms))],
                )),
            }
        }
        if !latched.is_empty() {
            if matches!(&self.condition, Element::Series(es) if es.is_empty()) {
                out.extend(latched);
            } else {
                out.push(Stmt::when(cond, latched));
            }
        }
        out
    }

    /// The rung's instruction list: its condition and one instruction per coil.
    pub fn il(&self) -> IlCost {
        let c = if self.condition.contacts() == 0 { IlCost::default() } else { self.condition.il() };
        let coils: usize = self.coils.iter().map(|c| c.kind.instructions()).sum();
        IlCost { instructions: c.instructions + coils, stack_depth: c.stack_depth }
    }
}

/// A `connectionPointIn` wired to each of `from`.
fn inputs(from: &[u64]) -> String {
    let mut s = String::from("<connectionPointIn>");
    for f in from {
        let _ = write!(s, "<connection refLocalId=\"{f}\"/>");
    }
    s.push_str("</connectionPointIn>");
    s
}

/// Allocates local ids and writes objects.
struct Writer {
    out: String,
    next: u64,
    row: u64,
}

impl Writer {
    fn id(&mut self) -> u64 {
        self.next += 1;
        self.next
    }

    /// Writes `e` fed from `from` at column `x` and branch row `y`; returns the ids feeding what follows
    /// and the next free column.
    fn element(&mut self, e: &Element, from: &[u64], x: u64, y: u64) -> (Vec<u64>, u64) {
        match e {
            Element::Contact { variable, negated } => {
                let id = self.id();
                let ins = inputs(from);
                let _ = writeln!(
                    self.out,
                    "          <contact localId=\"{id}\" negated=\"{negated}\" height=\"20\" width=\"20\"><position x=\"{x}\" y=\"{y}\"/>{ins}<connectionPointOut/><variable>{}</variable></contact>",
                    xml_escape(variable)
                );
                (vec![id], x + 40)
            }
            Element::Series(es) => {
                let (mut cur, mut col) = (from.to_vec(), x);
                for e in es {
                    (cur, col) = self.element(e, &cur, col, y);
                }
                (cur, col)
            }
            Element::Parallel(bs) => {
                let (mut outs, mut col) = (Vec::new(), x);
                for (i, b) in bs.iter().enumerate() {
                    let (o, c) = self.element(b, from, x, y + 40 * i as u64);
                    outs.extend(o);
                    col = col.max(c);
                }
                (outs, col)
            }
        }
    }

    fn rung(&mut self, r: &Rung) {
        let y = self.row;
        let comment = self.id();
        let _ = writeln!(
            self.out,
            "          <comment localId=\"{comment}\" height=\"20\" width=\"400\"><position x=\"0\" y=\"{y}\"/><content><xhtml:p>{}</xhtml:p></content></comment>",
            xml_escape(&r.comment)
        );
        let y = y + 30;
        let left = self.id();
        let _ = writeln!(
            self.out,
            "          <leftPowerRail localId=\"{left}\" height=\"40\" width=\"10\"><position x=\"0\" y=\"{y}\"/><connectionPointOut formalParameter=\"\"/></leftPowerRail>"
        );
        let (feed, col) = self.element(&r.condition, &[left], 40, y);
        let mut coils = Vec::new();
        for (i, c) in r.coils.iter().enumerate() {
            let (x, cy) = (col + 40, y + 40 * i as u64);
            let ins = inputs(&feed);
            let storage = match c.kind {
                CoilKind::Out => "none",
                CoilKind::Set => "set",
                CoilKind::Reset => "reset",
                CoilKind::OnDelay(ms) => {
                    coils.push(self.timer(&c.variable, ms, &ins, x, cy));
                    continue;
                }
            };
            let id = self.id();
            let _ = writeln!(
                self.out,
                "          <coil localId=\"{id}\" storage=\"{storage}\" height=\"20\" width=\"20\"><position x=\"{x}\" y=\"{cy}\"/>{ins}<connectionPointOut/><variable>{}</variable></coil>",
                xml_escape(&c.variable)
            );
            coils.push(format!("<connection refLocalId=\"{id}\"/>"));
        }
        let right = self.id();
        let ins: String =
            coils.iter().map(|c| format!("<connectionPointIn>{c}</connectionPointIn>")).collect();
        let _ = writeln!(
            self.out,
            "          <rightPowerRail localId=\"{right}\" height=\"40\" width=\"10\"><position x=\"{}\" y=\"{y}\"/>{ins}</rightPowerRail>",
            col + 100
        );
        let branches = match r.condition.simple() {
            Element::Parallel(bs) => bs.len(),
            Element::Series(es) => {
                es.iter().map(|e| if let Element::Parallel(bs) = e { bs.len() } else { 1 }).max().unwrap_or(1)
            }
            Element::Contact { .. } => 1,
        };
        self.row = y + 40 * branches.max(r.coils.len()).max(1) as u64 + 20;
    }
}

impl Writer {
    /// A `TON` block `instance` with `IN` wired as `ins` and `PT` from a literal of `ms`; returns the
    /// connection of its `Q` to the right rail.
    fn timer(&mut self, instance: &str, ms: u32, ins: &str, x: u64, y: u64) -> String {
        let pt = self.id();
        let _ = writeln!(
            self.out,
            "          <inVariable localId=\"{pt}\" height=\"20\" width=\"80\"><position x=\"{x}\" y=\"{}\"/><connectionPointOut/><expression>T#{ms}ms</expression></inVariable>",
            y + 30
        );
        let id = self.id();
        let _ = writeln!(
            self.out,
            "          <block localId=\"{id}\" typeName=\"TON\" instanceName=\"{}\" height=\"60\" width=\"60\"><position x=\"{}\" y=\"{y}\"/><inputVariables><variable formalParameter=\"IN\">{ins}</variable><variable formalParameter=\"PT\"><connectionPointIn><connection refLocalId=\"{pt}\"/></connectionPointIn></variable></inputVariables><inOutVariables/><outputVariables><variable formalParameter=\"Q\"><connectionPointOut/></variable><variable formalParameter=\"ET\"><connectionPointOut/></variable></outputVariables></block>",
            xml_escape(instance),
            x + 100
        );
        format!("<connection refLocalId=\"{id}\" formalParameter=\"Q\"/>")
    }
}

/// The rungs as the contents of a PLCopen `<body>`: `<LD>` with every rung's objects, top to bottom.
pub fn body(rungs: &[Rung]) -> String {
    let mut w = Writer { out: String::from("<LD>\n"), next: 0, row: 0 };
    for r in rungs {
        w.rung(r);
    }
    w.out.push_str("        </LD>");
    w.out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(v: &str) -> Element {
        Element::contact(v, false)
    }

    /// The seed's form: a precondition in series with parallel products (Fig. 7).
    fn seed_rung() -> Rung {
        Rung {
            comment: "right".into(),
            condition: Element::Series(vec![
                Element::contact("Y1", true),
                c("X2"),
                Element::Parallel(vec![
                    Element::Series(vec![c("a"), c("b")]),
                    Element::Series(vec![c("c"), c("d")]),
                    c("e"),
                ]),
            ]),
            coils: vec![
                Coil { variable: "Y0".into(), kind: CoilKind::Reset },
                Coil { variable: "Y1".into(), kind: CoilKind::Set },
            ],
        }
    }

    #[test]
    fn the_cost_model_counts_blocks_and_the_stack_is_three_deep() {
        // LDN Y1, AND X2, LD a, AND b, LD c, AND d, ORSTR, OR e, ANDSTR, RST Y0, SET Y1.
        assert_eq!(seed_rung().il(), IlCost { instructions: 11, stack_depth: 3 });
        let plain =
            Rung { comment: String::new(), condition: Element::Series(vec![c("a"), c("b")]), coils: vec![] };
        assert_eq!(plain.il(), IlCost { instructions: 2, stack_depth: 1 });
        assert_eq!(seed_rung().condition.st().text(), "NOT Y1 AND X2 AND (a AND b OR c AND d OR e)");
    }

    #[test]
    fn objects_are_wired_to_what_feeds_them() {
        let xml = body(&[seed_rung()]);
        // Objects: the comment 1, the rail 2, Y1 3, X2 4, then a b c d e 5 to 9. The coils are fed by the
        // last contact of each branch (b, d and e).
        assert!(xml.contains("<connection refLocalId=\"6\"/><connection refLocalId=\"8\"/><connection refLocalId=\"9\"/></connectionPointIn><connectionPointOut/><variable>Y0</variable>"), "{xml}");
        // Each branch starts from the contact before the block (X2, object 4).
        assert_eq!(xml.matches("<connection refLocalId=\"4\"/></connectionPointIn>").count(), 3, "{xml}");
        assert!(xml.contains("storage=\"reset\"") && xml.contains("negated=\"true\""));
        assert_eq!(body(&[seed_rung()]), xml, "deterministic");
    }

    #[test]
    fn a_timer_is_the_standard_block_with_its_preset_and_costs_two() {
        let r = Rung {
            comment: "t2".into(),
            condition: c("P_p2"),
            coils: vec![Coil { variable: "T_t2".into(), kind: CoilKind::OnDelay(1500) }],
        };
        assert_eq!(r.il(), IlCost { instructions: 3, stack_depth: 1 });
        let xml = body(&[r]);
        // Objects: comment 1, rail 2, contact 3, the preset 4, the block 5 fed by the contact.
        assert!(xml.contains("<expression>T#1500ms</expression>"), "{xml}");
        assert!(xml.contains("typeName=\"TON\" instanceName=\"T_t2\""), "{xml}");
        assert!(
            xml.contains(
                "<variable formalParameter=\"IN\"><connectionPointIn><connection refLocalId=\"3\"/>"
            ),
            "{xml}"
        );
        assert!(
            xml.contains(
                "<variable formalParameter=\"PT\"><connectionPointIn><connection refLocalId=\"4\"/>"
            ),
            "{xml}"
        );
        assert!(
            xml.contains(
                "<connection refLocalId=\"5\" formalParameter=\"Q\"/></connectionPointIn></rightPowerRail>"
            ),
            "{xml}"
        );
    }
}
