//! The subset of IEC 61131-3 Structured Text the PLC back end writes, as a small syntax tree, with the
//! printer and the two measures the report takes of it: statements per section and a static bound on
//! the statements one scan executes.
//!
//! Building the program as a tree rather than as text is what makes the measures functions of the
//! emitted program: the text is this tree printed, and the counts are this tree walked. It is also what
//! lets [`super::strict`] hold the program to IEC 61131-3 Ed. 3 (2013) before it is printed: every
//! declaration carries its [`Type`], so each expression's type is known and an assignment or operator
//! that would need an implicit conversion is refused at build time rather than by the user's compiler.
//!
//! The printer itself follows the grammar (Annex A) where a strict compiler is stricter than the common
//! dialects: a `TYPE` declaration ends `END_STRUCT;` (the `;` after each type declaration), and located
//! variables are printed in a `VAR` block of their own (`Loc_Var_Decls`, never mixed with unlocated ones).

use std::fmt::Write as _;

/// An expression.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr {
    /// `TRUE` / `FALSE`.
    Bool(bool),
    /// An integer literal.
    Int(i64),
    /// A duration literal in milliseconds, `T#<n>ms` (6.3.4).
    Time(u32),
    /// A variable, possibly a member path (`EVENTS.s_c1`).
    Var(String),
    /// An array element `name[index]`.
    Index(String, Box<Expr>),
    /// `NOT e`.
    Not(Box<Expr>),
    /// A binary operation.
    Bin(Box<Expr>, Op, Box<Expr>),
    /// A standard function call (`DINT_TO_INT(x)`): conversions are always written
    /// out (6.6.2.5), never left implicit.
    Call(String, Vec<Expr>),
}

/// Binary operators, in the IEC precedence classes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `OR`
    Or,
    /// `XOR`
    Xor,
    /// `AND`
    And,
    /// `=`
    Eq,
    /// `<>`
    Ne,
    /// `<`
    Lt,
    /// `>`
    Gt,
    /// `<=`
    Le,
    /// `>=`
    Ge,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `MOD`
    Mod,
}

impl Op {
    /// The operator as ST writes it.
    pub fn text(self) -> &'static str {
        match self {
            Op::Or => "OR",
            Op::Xor => "XOR",
            Op::And => "AND",
            Op::Eq => "=",
            Op::Ne => "<>",
            Op::Lt => "<",
            Op::Gt => ">",
            Op::Le => "<=",
            Op::Ge => ">=",
            Op::Add => "+",
            Op::Sub => "-",
            Op::Mul => "*",
            Op::Div => "/",
            Op::Mod => "MOD",
        }
    }

    /// Binding strength: higher binds tighter.
    fn precedence(self) -> u8 {
        match self {
            Op::Or => 1,
            Op::Xor => 2,
            Op::And => 3,
            Op::Eq | Op::Ne => 4,
            Op::Lt | Op::Gt | Op::Le | Op::Ge => 5,
            Op::Add | Op::Sub => 6,
            Op::Mul | Op::Div | Op::Mod => 7,
        }
    }

    /// Whether `(a op b) op c` = `a op (b op c)`, so a chain needs no parentheses.
    fn associative(self) -> bool {
        matches!(self, Op::Or | Op::Xor | Op::And | Op::Add | Op::Mul)
    }
}

/// Shorthands for building expressions.
impl Expr {
    /// A variable.
    pub fn var(name: impl Into<String>) -> Expr {
        Expr::Var(name.into())
    }

    /// `name[i]`.
    pub fn at(name: &str, i: Expr) -> Expr {
        Expr::Index(name.to_owned(), Box::new(i))
    }

    /// The explicit conversion of `self` from elementary type `from` to `to` (`INT_TO_DINT(x)`, IEC
    /// 61131-3 Ed. 3 6.6.2.5); [`super::strict`] refuses it when either type is not elementary.
    pub fn convert(self, from: &Type, to: &Type) -> Expr {
        let name = |t: &Type| t.elementary().unwrap_or("?");
        Expr::Call(format!("{}_TO_{}", name(from), name(to)), vec![self])
    }

    /// `self op rhs`.
    pub fn op(self, op: Op, rhs: Expr) -> Expr {
        Expr::Bin(Box::new(self), op, Box::new(rhs))
    }

    /// The terms joined by `op`; `empty` when there are none.
    pub fn fold(terms: impl IntoIterator<Item = Expr>, op: Op, empty: Expr) -> Expr {
        terms.into_iter().reduce(|a, b| a.op(op, b)).unwrap_or(empty)
    }

    fn precedence(&self) -> u8 {
        match self {
            Expr::Bin(_, op, _) => op.precedence(),
            Expr::Not(_) => 8,
            _ => 9,
        }
    }

    fn write(&self, out: &mut String) {
        match self {
            Expr::Bool(b) => out.push_str(if *b { "TRUE" } else { "FALSE" }),
            Expr::Int(i) => {
                let _ = write!(out, "{i}");
            }
            Expr::Time(ms) => {
                let _ = write!(out, "T#{ms}ms");
            }
            Expr::Var(v) => out.push_str(v),
            Expr::Index(v, i) => {
                out.push_str(v);
                out.push('[');
                i.write(out);
                out.push(']');
            }
            Expr::Not(e) => {
                out.push_str("NOT ");
                e.write_operand(out, e.precedence() < 8);
            }
            Expr::Bin(a, op, b) => {
                let p = op.precedence();
                a.write_operand(out, a.precedence() < p);
                let _ = write!(out, " {} ", op.text());
                let same = matches!(&**b, Expr::Bin(_, o, _) if *o == *op);
                b.write_operand(
                    out,
                    b.precedence() < p || (b.precedence() == p && !(same && op.associative())),
                );
            }
            Expr::Call(f, args) => {
                out.push_str(f);
                out.push('(');
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    a.write(out);
                }
                out.push(')');
            }
        }
    }

    fn write_operand(&self, out: &mut String, parens: bool) {
        if parens {
            out.push('(');
        }
        self.write(out);
        if parens {
            out.push(')');
        }
    }

    /// The expression as ST text.
    pub fn text(&self) -> String {
        let mut s = String::new();
        self.write(&mut s);
        s
    }
}

/// `NOT e`.
impl std::ops::Not for Expr {
    type Output = Expr;

    fn not(self) -> Expr {
        Expr::Not(Box::new(self))
    }
}

/// A statement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stmt {
    /// `target := value;`
    Assign(Expr, Expr),
    /// `IF c1 THEN … ELSIF c2 THEN … ELSE … END_IF;`
    If(Vec<(Expr, Vec<Stmt>)>, Vec<Stmt>),
    /// `CASE e OF l1, l2: … ELSE … END_CASE;`
    Case(Expr, Vec<(Vec<i64>, Vec<Stmt>)>, Vec<Stmt>),
    /// `FOR v := from TO to DO … END_FOR;`
    For(String, i64, i64, Vec<Stmt>),
    /// `EXIT;`
    Exit,
    /// A function block call with named inputs: `inst(a := x);`
    Call(String, Vec<(String, Expr)>),
}

impl Stmt {
    /// `name := value;`
    pub fn set(name: impl Into<String>, value: Expr) -> Stmt {
        Stmt::Assign(Expr::Var(name.into()), value)
    }

    /// `name := name + 1;`
    pub fn incr(name: &str) -> Stmt {
        Stmt::set(name, Expr::var(name).op(Op::Add, Expr::Int(1)))
    }

    /// `IF cond THEN body END_IF;`
    pub fn when(cond: Expr, body: Vec<Stmt>) -> Stmt {
        Stmt::If(vec![(cond, body)], Vec::new())
    }

    /// The most statements executing this one can run, itself included (a loop's body bounded by its
    /// trip count; `EXIT` can only shorten it).
    pub fn bound(&self) -> u64 {
        match self {
            Stmt::Assign(..) | Stmt::Exit | Stmt::Call(..) => 1,
            Stmt::If(arms, els) => {
                1 + arms.iter().map(|(_, b)| bound(b)).chain([bound(els)]).max().unwrap_or(0)
            }
            Stmt::Case(_, arms, els) => {
                1 + arms.iter().map(|(_, b)| bound(b)).chain([bound(els)]).max().unwrap_or(0)
            }
            Stmt::For(_, from, to, body) => {
                let trips = u64::try_from(to - from + 1).unwrap_or(0);
                1 + trips * bound(body)
            }
        }
    }

    fn write(&self, out: &mut String, indent: usize) {
        let pad = "    ".repeat(indent);
        match self {
            Stmt::Assign(t, v) => {
                let _ = writeln!(out, "{pad}{} := {};", t.text(), v.text());
            }
            Stmt::If(arms, els) => {
                for (i, (c, body)) in arms.iter().enumerate() {
                    let kw = if i == 0 { "IF" } else { "ELSIF" };
                    let _ = writeln!(out, "{pad}{kw} {} THEN", c.text());
                    write_block(out, body, indent + 1);
                }
                if !els.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    write_block(out, els, indent + 1);
                }
                let _ = writeln!(out, "{pad}END_IF;");
            }
            Stmt::Case(e, arms, els) => {
                let _ = writeln!(out, "{pad}CASE {} OF", e.text());
                for (labels, body) in arms {
                    let labels: Vec<String> = labels.iter().map(i64::to_string).collect();
                    let _ = writeln!(out, "{pad}    {}:", labels.join(", "));
                    write_block(out, body, indent + 2);
                }
                if !els.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    write_block(out, els, indent + 2);
                }
                let _ = writeln!(out, "{pad}END_CASE;");
            }
            Stmt::For(v, from, to, body) => {
                let _ = writeln!(out, "{pad}FOR {v} := {from} TO {to} DO");
                write_block(out, body, indent + 1);
                let _ = writeln!(out, "{pad}END_FOR;");
            }
            Stmt::Exit => {
                let _ = writeln!(out, "{pad}EXIT;");
            }
            Stmt::Call(inst, args) => {
                let args: Vec<String> = args.iter().map(|(n, e)| format!("{n} := {}", e.text())).collect();
                let _ = writeln!(out, "{pad}{inst}({});", args.join(", "));
            }
        }
    }
}

/// The bound of a statement list run top to bottom.
pub fn bound(stmts: &[Stmt]) -> u64 {
    stmts.iter().map(Stmt::bound).sum()
}

fn write_block(out: &mut String, stmts: &[Stmt], indent: usize) {
    for s in stmts {
        s.write(out, indent);
    }
}

/// What a section of the function block's body does; the report counts statements by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SectionKind {
    /// Initial states on the first scan and on `reset`.
    Init,
    /// Sampling the inputs: edges against the previous scan, latched.
    Inputs,
    /// This scan's events: flags cleared, one latched input taken in event order.
    Events,
    /// Uncontrollable events an automaton holding them cannot take: counted.
    Faults,
    /// AEEM: the memory bit of an avalanche event set on the event.
    AeemSet,
    /// One statement per transition (bits) or a `CASE` per event (int).
    Transitions,
    /// The controllable events every holder allows.
    Enabled,
    /// At most one controllable event by the policy, behind the guard.
    Choice,
    /// AEEM: every memory bit reset at the end of the scan.
    AeemReset,
    /// Output actions.
    Outputs,
    /// The program: the function block called, its outputs copied.
    Run,
    /// A state-based program's rungs: one `IF` per controllable event on the signals.
    Rungs,
}

impl SectionKind {
    /// The name the text's section markers and the report use.
    pub fn name(self) -> &'static str {
        match self {
            SectionKind::Init => "init",
            SectionKind::Inputs => "inputs",
            SectionKind::Events => "events",
            SectionKind::Faults => "faults",
            SectionKind::AeemSet => "aeem-set",
            SectionKind::Transitions => "transitions",
            SectionKind::Enabled => "enabled",
            SectionKind::Choice => "choice",
            SectionKind::AeemReset => "aeem-reset",
            SectionKind::Outputs => "outputs",
            SectionKind::Run => "run",
            SectionKind::Rungs => "rungs",
        }
    }

    /// Every kind, in report order.
    pub const ALL: [SectionKind; 12] = [
        SectionKind::Init,
        SectionKind::Inputs,
        SectionKind::Events,
        SectionKind::Faults,
        SectionKind::AeemSet,
        SectionKind::Transitions,
        SectionKind::Enabled,
        SectionKind::Choice,
        SectionKind::AeemReset,
        SectionKind::Outputs,
        SectionKind::Run,
        SectionKind::Rungs,
    ];
}

/// A run of statements with one purpose, printed under a `(* section: NAME — title *)` marker.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// What it does.
    pub kind: SectionKind,
    /// A line saying more (which events, which pass).
    pub title: String,
    /// The statements, top to bottom.
    pub stmts: Vec<Stmt>,
}

/// An IEC 61131-3 data type as the writer declares it (6.4): the elementary types the program uses,
/// one-dimensional arrays from 0, and derived types (a structure or a function block, the standard's
/// `TON` included) by name.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Type {
    /// `BOOL`
    Bool,
    /// `INT` (16-bit signed)
    Int,
    /// `DINT` (32-bit signed)
    Dint,
    /// `UDINT` (32-bit unsigned)
    Udint,
    /// `TIME` (a duration)
    Time,
    /// `ARRAY[0..upper] OF T`
    Array(i64, Box<Type>),
    /// A structure or function block type by name.
    Named(String),
}

impl Type {
    /// `ARRAY[0..upper] OF of`.
    pub fn array(upper: i64, of: Type) -> Type {
        Type::Array(upper, Box::new(of))
    }

    /// The elementary type's keyword, if it is one.
    pub fn elementary(&self) -> Option<&'static str> {
        match self {
            Type::Bool => Some("BOOL"),
            Type::Int => Some("INT"),
            Type::Dint => Some("DINT"),
            Type::Udint => Some("UDINT"),
            Type::Time => Some("TIME"),
            Type::Array(..) | Type::Named(_) => None,
        }
    }

    /// The range of an integer type (6.4.2), `None` for the others.
    pub fn range(&self) -> Option<(i64, i64)> {
        match self {
            Type::Int => Some((-32_768, 32_767)),
            Type::Dint => Some((-2_147_483_648, 2_147_483_647)),
            Type::Udint => Some((0, 4_294_967_295)),
            _ => None,
        }
    }

    /// The type as a declaration writes it.
    pub fn text(&self) -> String {
        match self {
            Type::Array(upper, of) => format!("ARRAY[0..{upper}] OF {}", of.text()),
            Type::Named(n) => n.clone(),
            t => t.elementary().unwrap_or_default().to_owned(),
        }
    }
}

/// A variable declaration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Var {
    /// Name.
    pub name: String,
    /// Type.
    pub ty: Type,
    /// Initial value, if any: a literal of the variable's type.
    pub init: Option<Expr>,
    /// Located address (`%IX0.2`), if any: allowed in a `PROGRAM`'s `VAR` only (6.5.5; Annex A
    /// `Prog_Decl` takes `Loc_Var_Decls`, `FB_Decl` does not).
    pub address: Option<String>,
    /// What it is, printed after the declaration.
    pub comment: String,
}

impl Var {
    /// A variable of type `ty`, without initial value or address.
    pub fn new(name: impl Into<String>, ty: Type, comment: impl Into<String>) -> Var {
        Var { name: name.into(), ty, init: None, address: None, comment: comment.into() }
    }

    /// With an initial value.
    pub fn init(mut self, value: Expr) -> Var {
        self.init = Some(value);
        self
    }

    /// The declaration line, indented, with its comment.
    pub fn text(&self) -> String {
        let at = self.address.as_ref().map(|a| format!(" AT {a}")).unwrap_or_default();
        let init = self.init.as_ref().map(|v| format!(" := {}", v.text())).unwrap_or_default();
        let comment = if self.comment.is_empty() {
            String::new()
        } else {
            format!(" (* {} *)", safe_comment(&self.comment))
        };
        format!("    {}{at} : {}{init};{comment}\n", self.name, self.ty.text())
    }
}

/// A structure type's declaration: `TYPE name : STRUCT … END_STRUCT; END_TYPE`, with the `;` the grammar
/// puts after every type declaration (Annex A `Data_Type_Decl`; 6.4.4 structures).
pub fn struct_type(name: &str, members: &[Var]) -> String {
    let mut out = format!("TYPE {name} :\nSTRUCT\n");
    for m in members {
        out.push_str(&m.text());
    }
    out.push_str("END_STRUCT;\nEND_TYPE\n");
    out
}

/// Which block of declarations a variable is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarClass {
    /// `VAR_INPUT`
    Input,
    /// `VAR_OUTPUT`
    Output,
    /// `VAR`
    Local,
}

impl VarClass {
    /// The keyword opening the block.
    pub fn keyword(self) -> &'static str {
        match self {
            VarClass::Input => "VAR_INPUT",
            VarClass::Output => "VAR_OUTPUT",
            VarClass::Local => "VAR",
        }
    }
}

/// `text` with every comment delimiter broken up, so that it can stand inside `(* … *)`.
pub fn safe_comment(text: &str) -> String {
    text.replace("(*", "( *").replace("*)", "* )")
}

/// A program organisation unit: a function block or a program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pou {
    /// `FUNCTION_BLOCK` or `PROGRAM`.
    pub program: bool,
    /// Name.
    pub name: String,
    /// Declarations by block, in order.
    pub vars: Vec<(VarClass, Vec<Var>)>,
    /// The body.
    pub sections: Vec<Section>,
}

impl Pou {
    /// The declaration blocks as printed: each block of `vars` in order, its located variables split
    /// into a block of their own after the unlocated ones (a `VAR` block is either `Var_Decls` or
    /// `Loc_Var_Decls`, Annex A; matiec: "invalid located variable declaration"). Empty blocks are left out.
    pub fn blocks(&self) -> Vec<(VarClass, Vec<&Var>)> {
        let mut out = Vec::new();
        for (class, vars) in &self.vars {
            let (located, plain): (Vec<&Var>, Vec<&Var>) = vars.iter().partition(|v| v.address.is_some());
            out.extend([(*class, plain), (*class, located)].into_iter().filter(|(_, v)| !v.is_empty()));
        }
        out
    }

    /// The declarations as ST text (the `VAR…END_VAR` blocks of [`Pou::blocks`]).
    pub fn declarations(&self) -> String {
        let mut out = String::new();
        for (class, vars) in self.blocks() {
            let _ = writeln!(out, "{}", class.keyword());
            for v in vars {
                out.push_str(&v.text());
            }
            let _ = writeln!(out, "END_VAR");
        }
        out
    }

    /// The declaration of variable `name` (without regard to case, as ST reads names), with its block.
    pub fn var(&self, name: &str) -> Option<(VarClass, &Var)> {
        let all = self.vars.iter().flat_map(|(c, vs)| vs.iter().map(move |v| (*c, v)));
        all.into_iter().find(|(_, v)| v.name.eq_ignore_ascii_case(name))
    }

    /// The body as ST text, each section under its marker.
    pub fn body(&self) -> String {
        let mut out = String::new();
        for s in &self.sections {
            if s.stmts.is_empty() {
                continue;
            }
            let title = if s.title.is_empty() { String::new() } else { format!(" - {}", s.title) };
            let _ = writeln!(out, "(* section: {}{title} *)", s.kind.name());
            write_block(&mut out, &s.stmts, 0);
        }
        out
    }

    /// The whole POU as ST text.
    pub fn text(&self) -> String {
        let kw = if self.program { "PROGRAM" } else { "FUNCTION_BLOCK" };
        format!("{kw} {}\n{}{}END_{kw}\n", self.name, self.declarations(), self.body())
    }

    /// Top-level statements of the body, per section kind (kinds without statements left out).
    pub fn statements(&self) -> Vec<(SectionKind, usize)> {
        SectionKind::ALL
            .iter()
            .map(|&k| (k, self.sections.iter().filter(|s| s.kind == k).map(|s| s.stmts.len()).sum()))
            .filter(|&(_, n)| n > 0)
            .collect()
    }

    /// The most statements one execution of the body runs.
    pub fn bound(&self) -> u64 {
        self.sections.iter().map(|s| bound(&s.stmts)).sum()
    }
}

#[cfg(test)]
mod tests {
    use std::ops::Not as _;

    use super::*;

    #[test]
    fn expressions_print_with_the_parentheses_precedence_needs() {
        let (a, b, c) = (Expr::var("a"), Expr::var("b"), Expr::var("c"));
        assert_eq!(a.clone().op(Op::Or, b.clone()).op(Op::And, c.clone()).text(), "(a OR b) AND c");
        assert_eq!(a.clone().op(Op::And, b.clone().op(Op::And, c.clone())).text(), "a AND b AND c");
        assert_eq!(a.clone().op(Op::Sub, b.clone().op(Op::Sub, c.clone())).text(), "a - (b - c)");
        assert_eq!(a.clone().op(Op::Add, b.clone()).op(Op::Mod, Expr::Int(3)).text(), "(a + b) MOD 3");
        assert_eq!(a.clone().op(Op::Eq, Expr::Int(1)).not().text(), "NOT (a = 1)");
        assert_eq!(a.op(Op::And, b.not()).text(), "a AND NOT b");
    }

    #[test]
    fn bounds_take_the_longest_branch_and_loops_their_trips() {
        let two = vec![Stmt::incr("x"), Stmt::incr("y")];
        let s = Stmt::If(vec![(Expr::var("a"), two.clone())], vec![Stmt::Exit]);
        assert_eq!(s.bound(), 3);
        let f = Stmt::For("i".into(), 0, 9, vec![s]);
        assert_eq!(f.bound(), 31);
        assert_eq!(Stmt::Case(Expr::var("x"), vec![(vec![1, 2], two)], vec![]).bound(), 3);
    }
}
