//! Transition conditions Y(t): Boolean expressions over signals, as the seed paper's Table 1 writes
//! them (`sl AND NOT si`, `sr OR d6s OR NOT sg`).
//!
//! Grammar (NOT binds tighter than AND, AND tighter than OR; keywords in any case):
//! `expr := and (OR and)*`, `and := not (AND not)*`, `not := NOT not | '(' expr ')' | TRUE | FALSE | name`,
//! with `&`/`&&`, `|`/`||` and `!` accepted for AND, OR and NOT. A name is a letter or `_` followed by
//! letters, digits and `_`.

/// A Boolean expression over variables of type `V` (names as parsed, indices once bound).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr<V> {
    /// A constant.
    Const(bool),
    /// A signal's value.
    Var(V),
    /// Negation.
    Not(Box<Expr<V>>),
    /// Conjunction of all.
    And(Vec<Expr<V>>),
    /// Disjunction of all.
    Or(Vec<Expr<V>>),
}

/// A signal's value as a condition sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Value {
    /// Known.
    Is(bool),
    /// Free: may be either.
    Either,
}

impl<V> Expr<V> {
    /// The same expression with every variable mapped by `f` (which may refuse one).
    pub fn bind<W, E>(&self, f: &mut impl FnMut(&V) -> Result<W, E>) -> Result<Expr<W>, E> {
        Ok(match self {
            Expr::Const(b) => Expr::Const(*b),
            Expr::Var(v) => Expr::Var(f(v)?),
            Expr::Not(e) => Expr::Not(Box::new(e.bind(f)?)),
            Expr::And(es) => Expr::And(es.iter().map(|e| e.bind(f)).collect::<Result<_, _>>()?),
            Expr::Or(es) => Expr::Or(es.iter().map(|e| e.bind(f)).collect::<Result<_, _>>()?),
        })
    }

    /// Every variable, in order of appearance (with repeats).
    pub fn vars(&self) -> Vec<&V> {
        let mut out = Vec::new();
        self.visit(&mut |v| out.push(v));
        out
    }

    fn visit<'a>(&'a self, f: &mut impl FnMut(&'a V)) {
        match self {
            Expr::Const(_) => {}
            Expr::Var(v) => f(v),
            Expr::Not(e) => e.visit(f),
            Expr::And(es) | Expr::Or(es) => es.iter().for_each(|e| e.visit(f)),
        }
    }

    /// The value under `value`, free variables read as `choice` gives them.
    fn eval_with(&self, value: &impl Fn(&V) -> Value, choice: &impl Fn(&V) -> bool) -> bool {
        match self {
            Expr::Const(b) => *b,
            Expr::Var(v) => match value(v) {
                Value::Is(b) => b,
                Value::Either => choice(v),
            },
            Expr::Not(e) => !e.eval_with(value, choice),
            Expr::And(es) => es.iter().all(|e| e.eval_with(value, choice)),
            Expr::Or(es) => es.iter().any(|e| e.eval_with(value, choice)),
        }
    }
}

impl<V: PartialEq> Expr<V> {
    /// Whether some choice of the free variables makes the expression true (the seed paper's
    /// "undefined" inputs: a timeout may or may not have expired).
    pub fn satisfiable(&self, value: impl Fn(&V) -> Value) -> bool {
        let mut free: Vec<&V> = Vec::new();
        for v in self.vars() {
            if value(v) == Value::Either && !free.contains(&v) {
                free.push(v);
            }
        }
        // A condition names a handful of signals; 2^k stays tiny (and k is capped by the text length).
        (0u64..1 << free.len().min(20)).any(|bits| {
            let choice = |v: &V| free.iter().position(|f| *f == v).is_some_and(|i| bits >> i & 1 == 1);
            self.eval_with(&value, &choice)
        })
    }
}

impl Expr<String> {
    /// Parses `text`; the error says what was expected at which character (1-based).
    pub fn parse(text: &str) -> Result<Expr<String>, String> {
        let tokens = tokens(text)?;
        let mut p = Parser { tokens, at: 0 };
        let e = p.or()?;
        match p.tokens.get(p.at) {
            None => Ok(e),
            Some((col, t)) => Err(format!("unexpected '{}' at character {col}", t.text())),
        }
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Token {
    And,
    Or,
    Not,
    Open,
    Close,
    Name(String),
}

impl Token {
    fn text(&self) -> &str {
        match self {
            Token::And => "AND",
            Token::Or => "OR",
            Token::Not => "NOT",
            Token::Open => "(",
            Token::Close => ")",
            Token::Name(n) => n,
        }
    }
}

/// Tokens of `text` with their 1-based character positions.
fn tokens(text: &str) -> Result<Vec<(usize, Token)>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        let (token, len) = match c {
            c if c.is_whitespace() => {
                i += 1;
                continue;
            }
            '(' => (Token::Open, 1),
            ')' => (Token::Close, 1),
            '!' => (Token::Not, 1),
            '&' => (Token::And, if chars.get(i + 1) == Some(&'&') { 2 } else { 1 }),
            '|' => (Token::Or, if chars.get(i + 1) == Some(&'|') { 2 } else { 1 }),
            c if c.is_ascii_alphabetic() || c == '_' => {
                let len = chars[i..].iter().take_while(|c| c.is_ascii_alphanumeric() || **c == '_').count();
                let word: String = chars[i..i + len].iter().collect();
                let token = match word.to_ascii_uppercase().as_str() {
                    "AND" => Token::And,
                    "OR" => Token::Or,
                    "NOT" => Token::Not,
                    _ => Token::Name(word),
                };
                (token, len)
            }
            c => return Err(format!("unexpected '{c}' at character {col}")),
        };
        out.push((col, token));
        i += len;
    }
    Ok(out)
}

struct Parser {
    tokens: Vec<(usize, Token)>,
    at: usize,
}

impl Parser {
    fn eat(&mut self, t: &Token) -> bool {
        let hit = self.tokens.get(self.at).is_some_and(|(_, x)| x == t);
        self.at += usize::from(hit);
        hit
    }

    fn or(&mut self) -> Result<Expr<String>, String> {
        let mut es = vec![self.and()?];
        while self.eat(&Token::Or) {
            es.push(self.and()?);
        }
        Ok(if es.len() == 1 { es.remove(0) } else { Expr::Or(es) })
    }

    fn and(&mut self) -> Result<Expr<String>, String> {
        let mut es = vec![self.not()?];
        while self.eat(&Token::And) {
            es.push(self.not()?);
        }
        Ok(if es.len() == 1 { es.remove(0) } else { Expr::And(es) })
    }

    fn not(&mut self) -> Result<Expr<String>, String> {
        // Nesting is bounded by the text, which a manifest keeps short; refuse absurd depths anyway.
        if self.at > 1_000 {
            return Err("condition too long".into());
        }
        let Some((col, t)) = self.tokens.get(self.at).cloned() else {
            return Err("unexpected end: expected a signal, NOT or '('".into());
        };
        self.at += 1;
        match t {
            Token::Not => Ok(Expr::Not(Box::new(self.not()?))),
            Token::Open => {
                let e = self.or()?;
                if self.eat(&Token::Close) {
                    Ok(e)
                } else {
                    Err(format!("'(' at character {col} is never closed"))
                }
            }
            Token::Name(n) if n.eq_ignore_ascii_case("true") => Ok(Expr::Const(true)),
            Token::Name(n) if n.eq_ignore_ascii_case("false") => Ok(Expr::Const(false)),
            Token::Name(n) => Ok(Expr::Var(n)),
            t => Err(format!("unexpected '{}' at character {col}: expected a signal, NOT or '('", t.text())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn known<'a>(vals: &'a [(&'a str, bool)]) -> impl Fn(&String) -> Value + 'a {
        move |v| vals.iter().find(|(n, _)| n == v).map_or(Value::Either, |&(_, b)| Value::Is(b))
    }

    #[test]
    fn precedence_is_not_and_or() {
        let e = Expr::parse("sr OR d6s OR NOT sg").unwrap();
        assert_eq!(e.vars(), vec!["sr", "d6s", "sg"]);
        let e = Expr::parse("a or b and not c").unwrap();
        assert_eq!(
            e,
            Expr::Or(vec![
                Expr::Var("a".into()),
                Expr::And(vec![Expr::Var("b".into()), Expr::Not(Box::new(Expr::Var("c".into())))])
            ])
        );
        assert_eq!(Expr::parse("!(a & b) || TRUE").unwrap().vars().len(), 2);
    }

    #[test]
    fn free_signals_are_read_existentially() {
        let e = Expr::parse("d05s AND (NOT si OR NOT cycle)").unwrap();
        assert!(e.satisfiable(known(&[("cycle", true)])), "si free may be 0");
        assert!(!e.satisfiable(known(&[("cycle", true), ("si", true)])));
        let contradiction = Expr::parse("x AND NOT x").unwrap();
        assert!(!contradiction.satisfiable(known(&[])), "one free signal takes one value at a time");
    }

    #[test]
    fn errors_say_where() {
        assert_eq!(Expr::parse("a AND").unwrap_err(), "unexpected end: expected a signal, NOT or '('");
        assert_eq!(Expr::parse("(a").unwrap_err(), "'(' at character 1 is never closed");
        assert_eq!(Expr::parse("a b").unwrap_err(), "unexpected 'b' at character 3");
        assert_eq!(Expr::parse("a + b").unwrap_err(), "unexpected '+' at character 3");
    }
}
