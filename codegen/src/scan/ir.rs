//! The program IR: the subset of IEC 61131-3 the PLC writers build — expressions, statements, typed
//! declarations and program organisation units whose bodies are labelled sections — as a syntax tree.
//!
//! Every form (event-based, state-based, sequence, hybrid) builds its program as this tree; the
//! printers ([`super::st`] for Structured Text, [`super::xml`] for PLCopen XML) write it, and the
//! report's measures (statements per section, a static bound on the statements one scan executes) are
//! this tree walked, so they are functions of the emitted program. Every declaration carries its
//! [`Type`], so [`super::strict`] knows each expression's type and can refuse an implicit conversion
//! before anything is printed. A vendor's project format is another printer of the same tree.

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

/// Binary operators, in the IEC precedence classes (6.7.2, Table 71).
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
    /// The operator's symbol in the standard's textual languages.
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
    pub fn precedence(self) -> u8 {
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
    pub fn associative(self) -> bool {
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

    /// Binding strength of the expression as an operand: its operator's, tighter for the rest.
    pub fn precedence(&self) -> u8 {
        match self {
            Expr::Bin(_, op, _) => op.precedence(),
            Expr::Not(_) => 8,
            _ => 9,
        }
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
    /// A function block call with named inputs: `inst(a := x);` — an empty name passes its argument by
    /// position (a dialect's instruction, such as Logix's `TONR(timer);`).
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
}

/// The bound of a statement list run top to bottom.
pub fn bound(stmts: &[Stmt]) -> u64 {
    stmts.iter().map(Stmt::bound).sum()
}

/// A run of statements with one purpose, printed under a `(* section: LABEL - title *)` marker. The
/// label is the writer's own word for what the run does (`init`, `transitions`, `rungs`, …): each form
/// names its sections, and the report counts statements by label.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// What it does, in one word.
    pub label: &'static str,
    /// A line saying more (which events, which pass).
    pub title: String,
    /// The statements, top to bottom.
    pub stmts: Vec<Stmt>,
}

impl Section {
    /// The section `label` with `title` and `stmts`.
    pub fn new(label: &'static str, title: impl Into<String>, stmts: Vec<Stmt>) -> Section {
        Section { label, title: title.into(), stmts }
    }
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
}

/// A structure type (6.4.4): its name and members.
pub type StructType = (String, Vec<Var>);

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

/// A program organisation unit: a function block or a program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Pou {
    /// `PROGRAM` (true) or `FUNCTION_BLOCK`.
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

    /// The declaration of variable `name` (without regard to case, as ST reads names), with its block.
    pub fn var(&self, name: &str) -> Option<(VarClass, &Var)> {
        let all = self.vars.iter().flat_map(|(c, vs)| vs.iter().map(move |v| (*c, v)));
        all.into_iter().find(|(_, v)| v.name.eq_ignore_ascii_case(name))
    }

    /// Top-level statements of the body per section label, in order of the labels' first appearance
    /// (labels without statements left out).
    pub fn statements(&self) -> Vec<(&'static str, usize)> {
        let mut out: Vec<(&'static str, usize)> = Vec::new();
        for s in self.sections.iter().filter(|s| !s.stmts.is_empty()) {
            match out.iter_mut().find(|(l, _)| *l == s.label) {
                Some((_, n)) => *n += s.stmts.len(),
                None => out.push((s.label, s.stmts.len())),
            }
        }
        out
    }

    /// The most statements one execution of the body runs.
    pub fn bound(&self) -> u64 {
        self.sections.iter().map(|s| bound(&s.stmts)).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_take_the_longest_branch_and_loops_their_trips() {
        let two = vec![Stmt::incr("x"), Stmt::incr("y")];
        let s = Stmt::If(vec![(Expr::var("a"), two.clone())], vec![Stmt::Exit]);
        assert_eq!(s.bound(), 3);
        let f = Stmt::For("i".into(), 0, 9, vec![s]);
        assert_eq!(f.bound(), 31);
        assert_eq!(Stmt::Case(Expr::var("x"), vec![(vec![1, 2], two)], vec![]).bound(), 3);
    }

    #[test]
    fn statements_are_counted_by_label_in_order_of_appearance() {
        let s = |label, n: usize| Section::new(label, "", vec![Stmt::Exit; n]);
        let pou = Pou {
            program: true,
            name: "p".into(),
            vars: Vec::new(),
            sections: vec![s("b", 2), s("a", 1), s("empty", 0), s("b", 3)],
        };
        assert_eq!(pou.statements(), [("b", 5), ("a", 1)]);
    }
}
