//! A parser for the subset of IEC 61131-3 Structured Text that `codegen plc` writes: `TYPE … STRUCT`,
//! `FUNCTION_BLOCK` and `PROGRAM` with `VAR_INPUT`/`VAR_OUTPUT`/`VAR` blocks (types `BOOL`, `INT`,
//! `DINT`, `UDINT`, `TIME`, `ARRAY[a..b] OF T`, named structs and blocks; initial values; `AT` addresses),
//! statements (assignment, `IF`/`ELSIF`/`ELSE`, `CASE` with integer labels and `ELSE`, `FOR … TO … DO`,
//! `EXIT`, block calls with named inputs), expressions (`OR`, `XOR`, `AND`, comparisons, `+ - * /
//! MOD`, `NOT`, unary minus, `TRUE`/`FALSE`, integers, durations `T#…ms`, member and index access), comments, and
//! `CONFIGURATION`/`RESOURCE`/`TASK`/`PROGRAM … WITH`. Written from the standard's grammar; it
//! reads the emitted text itself, never the program IR it was printed from.
//!
//! Strict where the grammar is (IEC 61131-3 Ed. 3): a keyword is never a name (6.1.3, the list of
//! `crate::scan::names`), an identifier has no `__` and no trailing `_` (6.1.2), located variables only
//! in a `PROGRAM`'s `VAR` block of located variables (6.5.5, Annex A `Loc_Var_Decls`), each address
//! bound once, and `END_STRUCT;` before `END_TYPE` (Annex A `Data_Type_Decl`).
//!
//! Comments are skipped except section markers `(* section: NAME … *)`, which become [`Stmt::Section`]
//! so that statements can be counted per section on the text. Identifiers are case-insensitive: they
//! are kept upper-cased.

use crate::scan::names::is_keyword;

/// A token.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Tok {
    Ident(String),
    Int(i64),
    /// A literal the interpreter does not compute with (`T#10ms`, `%IX0.2`).
    Word(String),
    Sym(&'static str),
    Section(String),
}

const SYMS: [&str; 18] =
    [":=", "<>", "<=", ">=", "..", ":", ";", ",", "(", ")", "[", "]", ".", "=", "<", ">", "+", "-"];
const MORE_SYMS: [&str; 2] = ["*", "/"];

fn lex(text: &str) -> Result<Vec<(Tok, usize)>, String> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < b.len() {
        let c = b[i];
        if c == b'\n' {
            line += 1;
            i += 1;
        } else if c.is_ascii_whitespace() {
            i += 1;
        } else if text[i..].starts_with("(*") {
            let end = text[i + 2..].find("*)").ok_or(format!("line {line}: unterminated comment"))? + i + 2;
            let body = text[i + 2..end].trim();
            if let Some(rest) = body.strip_prefix("section:") {
                let name = rest.split_whitespace().next().unwrap_or("").to_owned();
                out.push((Tok::Section(name), line));
            }
            line += text[i..end].matches('\n').count();
            i = end + 2;
        } else if c.is_ascii_digit() {
            let start = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'_') {
                i += 1;
            }
            let v = text[start..i].replace('_', "").parse().map_err(|e| format!("line {line}: {e}"))?;
            out.push((Tok::Int(v), line));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            if i < b.len() && b[i] == b'#' {
                while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'#' || b[i] == b'_') {
                    i += 1;
                }
                out.push((Tok::Word(text[start..i].to_owned()), line));
            } else {
                let word = &text[start..i];
                if word.contains("__") || word.ends_with('_') {
                    return Err(format!(
                        "line {line}: '{word}': no identifier has two underscores in a row or one at its end (IEC 61131-3 6.1.2)"
                    ));
                }
                out.push((Tok::Ident(word.to_ascii_uppercase()), line));
            }
        } else if c == b'%' {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'.') {
                i += 1;
            }
            out.push((Tok::Word(text[start..i].to_owned()), line));
        } else if let Some(s) = SYMS.iter().chain(&MORE_SYMS).find(|s| text[i..].starts_with(**s)) {
            out.push((Tok::Sym(s), line));
            i += s.len();
        } else {
            return Err(format!("line {line}: unexpected character {:?}", c as char));
        }
    }
    Ok(out)
}

/// A variable path: `a`, `a.b`, `a[i]`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Path(pub Vec<(String, Option<Expr>)>);

/// The milliseconds of a duration literal `T#<n>ms` or `T#<n>s` (`TIME#` too, any case), as the
/// writer prints them.
fn duration(word: &str) -> Option<i64> {
    let upper = word.to_ascii_uppercase();
    let body = upper.strip_prefix("T#").or_else(|| upper.strip_prefix("TIME#"))?;
    let (digits, scale) = match body.strip_suffix("MS") {
        Some(d) => (d, 1),
        None => (body.strip_suffix('S')?, 1000),
    };
    digits.replace('_', "").parse::<i64>().ok().map(|n| n * scale)
}

/// An expression.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr {
    /// `TRUE`/`FALSE`.
    Bool(bool),
    /// Integer literal.
    Int(i64),
    /// A duration literal (`T#500ms`, `T#4s`), in milliseconds.
    Time(i64),
    /// A variable.
    Var(Path),
    /// `NOT e`.
    Not(Box<Expr>),
    /// `-e`.
    Neg(Box<Expr>),
    /// `a op b`, the operator upper-cased as written (`AND`, `<>`, `MOD`, …).
    Bin(Box<Expr>, String, Box<Expr>),
    /// A function call.
    Call(String, Vec<Expr>),
}

/// A statement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Stmt {
    /// `path := e;`
    Assign(Path, Expr),
    /// `IF`/`ELSIF` arms and the `ELSE` statements.
    If(Vec<(Expr, Vec<Stmt>)>, Vec<Stmt>),
    /// `CASE e OF` arms (labels, statements) and the `ELSE` statements.
    Case(Expr, Vec<(Vec<i64>, Vec<Stmt>)>, Vec<Stmt>),
    /// `FOR v := a TO b DO … END_FOR;`
    For(String, Expr, Expr, Vec<Stmt>),
    /// `EXIT;`
    Exit,
    /// `inst(name := e, …);`
    Call(String, Vec<(String, Expr)>),
    /// A `(* section: NAME *)` marker (not a statement of the program; counted apart).
    Section(String),
}

/// A declared type.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Type {
    /// `BOOL`
    Bool,
    /// An integer type by name (`INT`, `DINT`, `UDINT`).
    Int(String),
    /// `ARRAY[lo..hi] OF T`
    Array(i64, i64, Box<Type>),
    /// `TIME`, in milliseconds.
    Time,
    /// A struct or function block by name.
    Named(String),
}

/// A variable declaration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Decl {
    /// `VAR_INPUT`, `VAR_OUTPUT` or `VAR` (members of a struct: `STRUCT`).
    pub class: String,
    /// Name.
    pub name: String,
    /// Type.
    pub ty: Type,
    /// Initial value.
    pub init: Option<Expr>,
    /// `AT` address.
    pub address: Option<String>,
}

/// A top-level declaration of a source file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unit {
    /// `TYPE name : STRUCT … END_STRUCT END_TYPE`
    Struct(String, Vec<Decl>),
    /// `FUNCTION_BLOCK` (`program` false) or `PROGRAM`.
    Pou {
        /// Whether a `PROGRAM`.
        program: bool,
        /// Name.
        name: String,
        /// Declarations.
        vars: Vec<Decl>,
        /// Body.
        body: Vec<Stmt>,
    },
    /// `CONFIGURATION name RESOURCE r ON x TASK t (INTERVAL := i, PRIORITY := p); PROGRAM inst WITH t : type; …`
    Configuration {
        /// Name.
        name: String,
        /// `(task, interval literal)`.
        tasks: Vec<(String, String)>,
        /// `(instance, task, program type)`.
        programs: Vec<(String, String, String)>,
    },
}

struct Parser {
    toks: Vec<(Tok, usize)>,
    at: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.at).map(|(t, _)| t)
    }

    fn line(&self) -> usize {
        self.toks.get(self.at).or(self.toks.last()).map_or(0, |(_, l)| *l)
    }

    fn err<T>(&self, what: &str) -> Result<T, String> {
        Err(format!("line {}: expected {what}, found {:?}", self.line(), self.peek()))
    }

    fn next(&mut self) -> Option<Tok> {
        let t = self.toks.get(self.at).map(|(t, _)| t.clone());
        self.at += 1;
        t
    }

    fn is_kw(&self, kw: &str) -> bool {
        matches!(self.peek(), Some(Tok::Ident(s)) if s == kw)
    }

    fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Some(Tok::Sym(x)) if *x == s)
    }

    fn kw(&mut self, kw: &str) -> Result<(), String> {
        if self.is_kw(kw) {
            self.at += 1;
            Ok(())
        } else {
            self.err(kw)
        }
    }

    fn sym(&mut self, s: &str) -> Result<(), String> {
        if self.is_sym(s) {
            self.at += 1;
            Ok(())
        } else {
            self.err(s)
        }
    }

    fn eat_sym(&mut self, s: &str) -> bool {
        let yes = self.is_sym(s);
        if yes {
            self.at += 1;
        }
        yes
    }

    fn ident(&mut self) -> Result<String, String> {
        match self.peek() {
            Some(Tok::Ident(s)) => {
                let s = s.clone();
                self.at += 1;
                Ok(s)
            }
            _ => self.err("an identifier"),
        }
    }

    /// An identifier a declaration introduces or a statement refers to: never a keyword of the
    /// standard (IEC 61131-3 Ed. 3 6.1.3: `EN`, `IF`, `TIME`, `R_TRIG`, … in any case).
    fn name(&mut self) -> Result<String, String> {
        let line = self.line();
        let name = self.ident()?;
        if is_keyword(&name) {
            return Err(format!("line {line}: '{name}' is a keyword, not an identifier (IEC 61131-3 6.1.3)"));
        }
        Ok(name)
    }

    fn int(&mut self) -> Result<i64, String> {
        let neg = self.eat_sym("-");
        match self.next() {
            Some(Tok::Int(v)) => Ok(if neg { -v } else { v }),
            _ => {
                self.at -= 1;
                self.err("an integer")
            }
        }
    }

    fn units(&mut self) -> Result<Vec<Unit>, String> {
        let mut out = Vec::new();
        while let Some(t) = self.peek() {
            match t {
                Tok::Ident(k) if k == "TYPE" => out.push(self.struct_type()?),
                Tok::Ident(k) if k == "FUNCTION_BLOCK" || k == "PROGRAM" => out.push(self.pou()?),
                Tok::Ident(k) if k == "CONFIGURATION" => out.push(self.configuration()?),
                _ => return self.err("TYPE, FUNCTION_BLOCK, PROGRAM or CONFIGURATION"),
            }
        }
        Ok(out)
    }

    fn struct_type(&mut self) -> Result<Unit, String> {
        self.kw("TYPE")?;
        let name = self.name()?;
        self.sym(":")?;
        self.kw("STRUCT")?;
        let mut fields = Vec::new();
        while !self.is_kw("END_STRUCT") {
            let line = self.line();
            let field = self.decl("STRUCT")?;
            if field.address.is_some() {
                return Err(format!("line {line}: a located structure member (IEC 61131-3 6.5.5)"));
            }
            fields.push(field);
        }
        self.kw("END_STRUCT")?;
        // Annex A `Data_Type_Decl`: every type declaration ends with `;`, the last one too.
        self.sym(";")?;
        self.kw("END_TYPE")?;
        Ok(Unit::Struct(name, fields))
    }

    fn pou(&mut self) -> Result<Unit, String> {
        let kind = self.ident()?;
        let program = kind == "PROGRAM";
        let name = self.name()?;
        let mut vars = Vec::new();
        while let Some(Tok::Ident(k)) = self.peek() {
            let class = k.clone();
            if !["VAR", "VAR_INPUT", "VAR_OUTPUT"].contains(&class.as_str()) {
                break;
            }
            let line = self.line();
            self.at += 1;
            let mut block = Vec::new();
            while !self.is_kw("END_VAR") {
                block.push(self.decl(&class)?);
            }
            self.kw("END_VAR")?;
            let located = block.iter().filter(|d| d.address.is_some()).count();
            if located > 0 && !(program && class == "VAR") {
                return Err(format!(
                    "line {line}: located variables in a {class} of a {kind}: only a PROGRAM's VAR binds addresses (IEC 61131-3 6.5.5; Annex A Loc_Var_Decls)"
                ));
            }
            if located > 0 && located < block.len() {
                return Err(format!(
                    "line {line}: a VAR block mixes located and unlocated variables: each is a block of its own (IEC 61131-3 Annex A Var_Decls, Loc_Var_Decls)"
                ));
            }
            vars.extend(block);
        }
        let end = format!("END_{kind}");
        let body = self.stmts(&[&end])?;
        self.kw(&end)?;
        Ok(Unit::Pou { program, name, vars, body })
    }

    fn decl(&mut self, class: &str) -> Result<Decl, String> {
        let name = self.name()?;
        let address = if self.is_kw("AT") {
            self.at += 1;
            match self.next() {
                Some(Tok::Word(w)) => Some(w),
                _ => return self.err("an address"),
            }
        } else {
            None
        };
        self.sym(":")?;
        let ty = self.ty()?;
        let init = if self.eat_sym(":=") { Some(self.expr()?) } else { None };
        self.sym(";")?;
        Ok(Decl { class: class.to_owned(), name, ty, init, address })
    }

    fn ty(&mut self) -> Result<Type, String> {
        let name = self.ident()?;
        Ok(match name.as_str() {
            "BOOL" => Type::Bool,
            "TIME" => Type::Time,
            "SINT" | "INT" | "DINT" | "LINT" | "USINT" | "UINT" | "UDINT" => Type::Int(name),
            "ARRAY" => {
                self.sym("[")?;
                let lo = self.int()?;
                self.sym("..")?;
                let hi = self.int()?;
                self.sym("]")?;
                self.kw("OF")?;
                Type::Array(lo, hi, Box::new(self.ty()?))
            }
            _ => Type::Named(name),
        })
    }

    fn configuration(&mut self) -> Result<Unit, String> {
        self.kw("CONFIGURATION")?;
        let name = self.name()?;
        let (mut tasks, mut programs) = (Vec::new(), Vec::new());
        while !self.is_kw("END_CONFIGURATION") {
            match self.ident()?.as_str() {
                "RESOURCE" => {
                    self.name()?;
                    self.kw("ON")?;
                    self.ident()?;
                }
                "END_RESOURCE" => {}
                "TASK" => {
                    let task = self.name()?;
                    self.sym("(")?;
                    let mut interval = String::new();
                    loop {
                        let key = self.ident()?;
                        self.sym(":=")?;
                        match self.next() {
                            Some(Tok::Word(w)) if key == "INTERVAL" => interval = w,
                            Some(Tok::Int(_)) if key == "PRIORITY" => {}
                            _ => return self.err("INTERVAL := T#… or PRIORITY := n"),
                        }
                        if !self.eat_sym(",") {
                            break;
                        }
                    }
                    self.sym(")")?;
                    self.sym(";")?;
                    tasks.push((task, interval));
                }
                "PROGRAM" => {
                    let inst = self.name()?;
                    self.kw("WITH")?;
                    let task = self.ident()?;
                    self.sym(":")?;
                    let ty = self.ident()?;
                    self.sym(";")?;
                    programs.push((inst, task, ty));
                }
                _ => return self.err("RESOURCE, TASK, PROGRAM or END_RESOURCE"),
            }
        }
        self.kw("END_CONFIGURATION")?;
        Ok(Unit::Configuration { name, tasks, programs })
    }

    /// Statements up to (not including) one of the keywords `until`.
    fn stmts(&mut self, until: &[&str]) -> Result<Vec<Stmt>, String> {
        let mut out = Vec::new();
        loop {
            match self.peek() {
                None => return self.err(&until.join(" or ")),
                Some(Tok::Ident(k)) if until.contains(&k.as_str()) => return Ok(out),
                Some(Tok::Section(s)) => {
                    out.push(Stmt::Section(s.clone()));
                    self.at += 1;
                }
                Some(Tok::Sym(";")) => self.at += 1,
                _ => out.push(self.stmt()?),
            }
        }
    }

    fn stmt(&mut self) -> Result<Stmt, String> {
        let s = if self.is_kw("IF") {
            self.at += 1;
            let mut arms = Vec::new();
            let mut els = Vec::new();
            loop {
                let c = self.expr()?;
                self.kw("THEN")?;
                arms.push((c, self.stmts(&["ELSIF", "ELSE", "END_IF"])?));
                match self.ident()?.as_str() {
                    "ELSIF" => continue,
                    "ELSE" => {
                        els = self.stmts(&["END_IF"])?;
                        self.kw("END_IF")?;
                        break;
                    }
                    _ => break,
                }
            }
            Stmt::If(arms, els)
        } else if self.is_kw("CASE") {
            self.at += 1;
            let e = self.expr()?;
            self.kw("OF")?;
            let mut arms = Vec::new();
            let mut els = Vec::new();
            loop {
                if self.is_kw("END_CASE") {
                    self.at += 1;
                    break;
                }
                if self.is_kw("ELSE") {
                    self.at += 1;
                    els = self.stmts(&["END_CASE"])?;
                    continue;
                }
                let mut labels = vec![self.int()?];
                while self.eat_sym(",") {
                    labels.push(self.int()?);
                }
                self.sym(":")?;
                let body = self.case_body()?;
                arms.push((labels, body));
            }
            Stmt::Case(e, arms, els)
        } else if self.is_kw("FOR") {
            self.at += 1;
            let v = self.name()?;
            self.sym(":=")?;
            let from = self.expr()?;
            self.kw("TO")?;
            let to = self.expr()?;
            self.kw("DO")?;
            let body = self.stmts(&["END_FOR"])?;
            self.kw("END_FOR")?;
            Stmt::For(v, from, to, body)
        } else if self.is_kw("EXIT") {
            self.at += 1;
            Stmt::Exit
        } else {
            let path = self.path()?;
            if self.eat_sym(":=") {
                Stmt::Assign(path, self.expr()?)
            } else if path.0.len() == 1 && path.0[0].1.is_none() && self.eat_sym("(") {
                let mut args = Vec::new();
                while !self.eat_sym(")") {
                    let n = self.ident()?;
                    self.sym(":=")?;
                    args.push((n, self.expr()?));
                    if !self.is_sym(")") {
                        self.sym(",")?;
                    }
                }
                Stmt::Call(path.0[0].0.clone(), args)
            } else {
                return self.err(":= or (");
            }
        };
        self.sym(";")?;
        Ok(s)
    }

    /// A CASE arm's statements: up to the next label, ELSE or END_CASE.
    fn case_body(&mut self) -> Result<Vec<Stmt>, String> {
        let mut out = Vec::new();
        loop {
            let label = matches!(self.peek(), Some(Tok::Int(_)))
                || (self.is_sym("-") && matches!(self.toks.get(self.at + 1), Some((Tok::Int(_), _))));
            if label || self.is_kw("ELSE") || self.is_kw("END_CASE") {
                return Ok(out);
            }
            if !self.eat_sym(";") {
                out.push(self.stmt()?);
            }
        }
    }

    fn path(&mut self) -> Result<Path, String> {
        let mut segs = Vec::new();
        loop {
            let name = self.name()?;
            let index = if self.eat_sym("[") {
                let i = self.expr()?;
                self.sym("]")?;
                Some(i)
            } else {
                None
            };
            segs.push((name, index));
            if !self.eat_sym(".") {
                return Ok(Path(segs));
            }
        }
    }

    fn expr(&mut self) -> Result<Expr, String> {
        self.binary(0)
    }

    fn binary(&mut self, level: usize) -> Result<Expr, String> {
        const LEVELS: [&[&str]; 7] = [
            &["OR"],
            &["XOR"],
            &["AND", "&"],
            &["=", "<>"],
            &["<", ">", "<=", ">="],
            &["+", "-"],
            &["*", "/", "MOD"],
        ];
        if level == LEVELS.len() {
            return self.unary();
        }
        let mut lhs = self.binary(level + 1)?;
        loop {
            let op = match self.peek() {
                Some(Tok::Ident(k)) if LEVELS[level].contains(&k.as_str()) => k.clone(),
                Some(Tok::Sym(s)) if LEVELS[level].contains(s) => (*s).to_owned(),
                _ => return Ok(lhs),
            };
            self.at += 1;
            let rhs = self.binary(level + 1)?;
            lhs = Expr::Bin(Box::new(lhs), op, Box::new(rhs));
        }
    }

    fn unary(&mut self) -> Result<Expr, String> {
        if self.is_kw("NOT") {
            self.at += 1;
            return Ok(Expr::Not(Box::new(self.unary()?)));
        }
        if self.eat_sym("-") {
            return Ok(Expr::Neg(Box::new(self.unary()?)));
        }
        match self.peek().cloned() {
            Some(Tok::Int(v)) => {
                self.at += 1;
                Ok(Expr::Int(v))
            }
            Some(Tok::Sym("(")) => {
                self.at += 1;
                let e = self.expr()?;
                self.sym(")")?;
                Ok(e)
            }
            Some(Tok::Word(w)) => {
                self.at += 1;
                duration(&w).map(Expr::Time).ok_or_else(|| {
                    format!("line {}: '{w}' is no duration the interpreter reads", self.line())
                })
            }
            Some(Tok::Ident(k)) if k == "TRUE" || k == "FALSE" => {
                self.at += 1;
                Ok(Expr::Bool(k == "TRUE"))
            }
            Some(Tok::Ident(k)) if matches!(self.toks.get(self.at + 1), Some((Tok::Sym("("), _))) => {
                self.at += 2;
                let mut args = Vec::new();
                while !self.eat_sym(")") {
                    args.push(self.expr()?);
                    if !self.is_sym(")") {
                        self.sym(",")?;
                    }
                }
                Ok(Expr::Call(k, args))
            }
            Some(Tok::Ident(_)) => Ok(Expr::Var(self.path()?)),
            _ => self.err("an expression"),
        }
    }
}

/// Parses a source file into its declarations.
pub fn parse(text: &str) -> Result<Vec<Unit>, String> {
    let mut p = Parser { toks: lex(text)?, at: 0 };
    let units = p.units()?;
    let mut bound: Vec<(&str, &str)> = Vec::new();
    for unit in &units {
        let Unit::Pou { vars, .. } = unit else { continue };
        for d in vars {
            let Some(address) = &d.address else { continue };
            if let Some((other, _)) = bound.iter().find(|(_, a)| a.eq_ignore_ascii_case(address)) {
                return Err(format!(
                    "{address} is bound twice, to {other} and {} (IEC 61131-3 6.5.5: one variable per address)",
                    d.name
                ));
            }
            bound.push((&d.name, address));
        }
    }
    Ok(units)
}

/// Top-level statements of a body per section marker, in order of first appearance.
pub fn sections(body: &[Stmt]) -> Vec<(String, usize)> {
    let mut out: Vec<(String, usize)> = Vec::new();
    let mut current: Option<usize> = None;
    for s in body {
        match s {
            Stmt::Section(name) => {
                current = Some(match out.iter().position(|(n, _)| n == name) {
                    Some(i) => i,
                    None => {
                        out.push((name.clone(), 0));
                        out.len() - 1
                    }
                });
            }
            _ => {
                if let Some(i) = current {
                    out[i].1 += 1;
                }
            }
        }
    }
    out
}
