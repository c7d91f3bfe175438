//! The Structured Text printer of the program IR ([`super::ir`]): expressions with the parentheses
//! precedence needs, statements indented four spaces, declarations, POUs and comments.
//!
//! The printer follows the grammar (Annex A) where a strict compiler is stricter than the common
//! dialects: a `TYPE` declaration ends `END_STRUCT;` (the `;` after each type declaration), and located
//! variables are printed in a `VAR` block of their own (`Loc_Var_Decls`, never mixed with unlocated ones).

use std::fmt::Write as _;

use super::ir::{Expr, Pou, Stmt, Type, Var, VarClass};

/// How a printer writes a variable reference (the first name of a member path): the generic ST
/// writes it as it is; a dialect may mark it (SCL's `#local`, `"global"`).
pub type Names<'a> = &'a dyn Fn(&str) -> String;

/// The generic ST's names: as they are.
fn plain(name: &str) -> String {
    name.to_owned()
}

/// `path` (`a.b.c`) with its first name written by `names`.
fn reference(path: &str, names: Names) -> String {
    match path.split_once('.') {
        Some((head, tail)) => format!("{}.{tail}", names(head)),
        None => names(path),
    }
}

impl Expr {
    fn write(&self, out: &mut String, names: Names) {
        match self {
            Expr::Bool(b) => out.push_str(if *b { "TRUE" } else { "FALSE" }),
            Expr::Int(i) => {
                let _ = write!(out, "{i}");
            }
            Expr::Time(ms) => {
                let _ = write!(out, "T#{ms}ms");
            }
            Expr::Var(v) => out.push_str(&reference(v, names)),
            Expr::Index(v, i) => {
                out.push_str(&reference(v, names));
                out.push('[');
                i.write(out, names);
                out.push(']');
            }
            Expr::Not(e) => {
                out.push_str("NOT ");
                e.write_operand(out, e.precedence() < 8, names);
            }
            Expr::Bin(a, op, b) => {
                let p = op.precedence();
                a.write_operand(out, a.precedence() < p, names);
                let _ = write!(out, " {} ", op.text());
                let same = matches!(&**b, Expr::Bin(_, o, _) if *o == *op);
                b.write_operand(
                    out,
                    b.precedence() < p || (b.precedence() == p && !(same && op.associative())),
                    names,
                );
            }
            Expr::Call(f, args) => {
                out.push_str(f);
                out.push('(');
                for (i, a) in args.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    a.write(out, names);
                }
                out.push(')');
            }
        }
    }

    fn write_operand(&self, out: &mut String, parens: bool, names: Names) {
        if parens {
            out.push('(');
        }
        self.write(out, names);
        if parens {
            out.push(')');
        }
    }

    /// The expression as ST text.
    pub fn text(&self) -> String {
        self.text_with(&plain)
    }

    /// The expression as text, its variables written by `names`.
    pub fn text_with(&self, names: Names) -> String {
        let mut s = String::new();
        self.write(&mut s, names);
        s
    }
}

impl Stmt {
    fn write(&self, out: &mut String, indent: usize, names: Names) {
        let pad = "    ".repeat(indent);
        match self {
            Stmt::Assign(t, v) => {
                let _ = writeln!(out, "{pad}{} := {};", t.text_with(names), v.text_with(names));
            }
            Stmt::If(arms, els) => {
                for (i, (c, body)) in arms.iter().enumerate() {
                    let kw = if i == 0 { "IF" } else { "ELSIF" };
                    let _ = writeln!(out, "{pad}{kw} {} THEN", c.text_with(names));
                    write_block(out, body, indent + 1, names);
                }
                if !els.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    write_block(out, els, indent + 1, names);
                }
                let _ = writeln!(out, "{pad}END_IF;");
            }
            Stmt::Case(e, arms, els) => {
                let _ = writeln!(out, "{pad}CASE {} OF", e.text_with(names));
                for (labels, body) in arms {
                    let labels: Vec<String> = labels.iter().map(i64::to_string).collect();
                    let _ = writeln!(out, "{pad}    {}:", labels.join(", "));
                    write_block(out, body, indent + 2, names);
                }
                if !els.is_empty() {
                    let _ = writeln!(out, "{pad}ELSE");
                    write_block(out, els, indent + 2, names);
                }
                let _ = writeln!(out, "{pad}END_CASE;");
            }
            Stmt::For(v, from, to, body) => {
                let _ = writeln!(out, "{pad}FOR {} := {from} TO {to} DO", names(v));
                write_block(out, body, indent + 1, names);
                let _ = writeln!(out, "{pad}END_FOR;");
            }
            Stmt::Exit => {
                let _ = writeln!(out, "{pad}EXIT;");
            }
            Stmt::Call(inst, args) => {
                let args: Vec<String> = args
                    .iter()
                    .map(|(n, e)| match n.as_str() {
                        "" => e.text_with(names),
                        n => format!("{n} := {}", e.text_with(names)),
                    })
                    .collect();
                let _ = writeln!(out, "{pad}{}({});", reference(inst, names), args.join(", "));
            }
        }
    }
}

fn write_block(out: &mut String, stmts: &[Stmt], indent: usize, names: Names) {
    for s in stmts {
        s.write(out, indent, names);
    }
}

/// Statements as ST text, one per line at `indent` levels of four spaces.
pub fn statements(stmts: &[Stmt], indent: usize) -> String {
    let mut out = String::new();
    write_block(&mut out, stmts, indent, &plain);
    out
}

impl Type {
    /// The type as a declaration writes it.
    pub fn text(&self) -> String {
        match self {
            Type::Array(upper, of) => format!("ARRAY[0..{upper}] OF {}", of.text()),
            Type::Named(n) => n.clone(),
            t => t.elementary().unwrap_or_default().to_owned(),
        }
    }
}

impl Var {
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

/// `lines` as one ST comment (any comment delimiter inside them broken up).
pub fn comment(lines: &[String]) -> String {
    let mut out = String::from("(*\n");
    for l in lines {
        let l = safe_comment(l);
        let _ = writeln!(out, "{}", if l.is_empty() { l } else { format!("   {l}") });
    }
    out.push_str("*)\n");
    out
}

impl Pou {
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

    /// The body as ST text, each section under its marker.
    pub fn body(&self) -> String {
        self.body_with(&plain)
    }

    /// [`Pou::body`] with the variables written by `names`: a dialect's body of the same statements.
    pub fn body_with(&self, names: Names) -> String {
        let mut out = String::new();
        for s in &self.sections {
            if s.stmts.is_empty() {
                continue;
            }
            let title = if s.title.is_empty() { String::new() } else { format!(" - {}", s.title) };
            let _ = writeln!(out, "(* section: {}{title} *)", s.label);
            write_block(&mut out, &s.stmts, 0, names);
        }
        out
    }

    /// The whole POU as ST text.
    pub fn text(&self) -> String {
        let kw = if self.program { "PROGRAM" } else { "FUNCTION_BLOCK" };
        format!("{kw} {}\n{}{}END_{kw}\n", self.name, self.declarations(), self.body())
    }
}

/// The configuration running `<base>_main` every `cycle_ms` as ST text (its own file: some ST tools
/// take POUs only).
pub fn configuration(base: &str, cycle_ms: u32) -> String {
    format!(
        "CONFIGURATION {base}_config\n    RESOURCE {base}_resource ON PLC\n        TASK {base}_task (INTERVAL := T#{cycle_ms}ms, PRIORITY := 1);\n        PROGRAM {base}_instance WITH {base}_task : {base}_main;\n    END_RESOURCE\nEND_CONFIGURATION\n"
    )
}

#[cfg(test)]
mod tests {
    use std::ops::Not as _;

    use super::super::ir::Op;
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
}
