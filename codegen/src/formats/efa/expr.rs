//! Guard and action expressions of an extended finite automaton, and their value over integers.
//!
//! Booleans are the integers 0 (false) and 1 (true), and any non-zero value counts as true, as in
//! Supremica's evaluator. Arithmetic is on `i64` and checked: an overflow or a division by zero has no
//! value, and the edge whose guard or action has no value is not taken (see [`super::unfold`]).

/// An operator with one operand.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnaryOp {
    /// Logical negation `!`.
    Not,
    /// Arithmetic negation `-`.
    Neg,
}

/// An operator with two operands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinaryOp {
    /// `==`
    Eq,
    /// `!=`
    Ne,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `&` (also written `&&`)
    And,
    /// `|` (also written `||`)
    Or,
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`, truncating toward zero (Java's integer division, which Supremica uses)
    Div,
    /// `%`, with the sign of the dividend (Java's remainder)
    Rem,
}

impl BinaryOp {
    /// The operator a Supremica `Operator` attribute names, if it is one of these.
    pub fn from_symbol(symbol: &str) -> Option<BinaryOp> {
        Some(match symbol {
            "==" => BinaryOp::Eq,
            "!=" => BinaryOp::Ne,
            "<" => BinaryOp::Lt,
            "<=" => BinaryOp::Le,
            ">" => BinaryOp::Gt,
            ">=" => BinaryOp::Ge,
            "&" | "&&" => BinaryOp::And,
            "|" | "||" => BinaryOp::Or,
            "+" => BinaryOp::Add,
            "-" => BinaryOp::Sub,
            "*" => BinaryOp::Mul,
            "/" => BinaryOp::Div,
            "%" => BinaryOp::Rem,
            _ => return None,
        })
    }
}

/// An integer or boolean expression over the module's variables.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Expr {
    /// A constant.
    Int(i64),
    /// The current value of the variable with this index in the module.
    Var(usize),
    /// `op operand`.
    Unary(UnaryOp, Box<Expr>),
    /// `left op right`.
    Binary(BinaryOp, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// The value of the expression when variable `i` holds `values[i]`; `None` on an overflow, a
    /// division by zero, or a variable outside `values`.
    pub fn eval(&self, values: &[i64]) -> Option<i64> {
        match self {
            Expr::Int(n) => Some(*n),
            Expr::Var(i) => values.get(*i).copied(),
            Expr::Unary(UnaryOp::Not, e) => Some(i64::from(e.eval(values)? == 0)),
            Expr::Unary(UnaryOp::Neg, e) => e.eval(values)?.checked_neg(),
            Expr::Binary(op, l, r) => {
                let (a, b) = (l.eval(values)?, r.eval(values)?);
                match op {
                    BinaryOp::Eq => Some(i64::from(a == b)),
                    BinaryOp::Ne => Some(i64::from(a != b)),
                    BinaryOp::Lt => Some(i64::from(a < b)),
                    BinaryOp::Le => Some(i64::from(a <= b)),
                    BinaryOp::Gt => Some(i64::from(a > b)),
                    BinaryOp::Ge => Some(i64::from(a >= b)),
                    BinaryOp::And => Some(i64::from(a != 0 && b != 0)),
                    BinaryOp::Or => Some(i64::from(a != 0 || b != 0)),
                    BinaryOp::Add => a.checked_add(b),
                    BinaryOp::Sub => a.checked_sub(b),
                    BinaryOp::Mul => a.checked_mul(b),
                    BinaryOp::Div => a.checked_div(b),
                    BinaryOp::Rem => a.checked_rem(b),
                }
            }
        }
    }

    /// Whether the expression holds (has a non-zero value) when variable `i` holds `values[i]`.
    pub fn holds(&self, values: &[i64]) -> bool {
        self.eval(values).is_some_and(|v| v != 0)
    }

    /// Calls `f` with the index of every variable the expression reads.
    pub fn visit_vars(&self, f: &mut impl FnMut(usize)) {
        match self {
            Expr::Int(_) => {}
            Expr::Var(i) => f(*i),
            Expr::Unary(_, e) => e.visit_vars(f),
            Expr::Binary(_, l, r) => {
                l.visit_vars(f);
                r.visit_vars(f);
            }
        }
    }
}

/// How an action changes its variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AssignOp {
    /// `x = e`
    Set,
    /// `x += e`
    Add,
    /// `x -= e`
    Sub,
}

impl AssignOp {
    /// The assignment a Supremica `Operator` attribute names, if it is one of these.
    pub fn from_symbol(symbol: &str) -> Option<AssignOp> {
        Some(match symbol {
            "=" => AssignOp::Set,
            "+=" => AssignOp::Add,
            "-=" => AssignOp::Sub,
            _ => return None,
        })
    }
}

/// An action on an edge: `var op value`, evaluated over the values before the event.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Action {
    /// The variable assigned.
    pub var: usize,
    /// How.
    pub op: AssignOp,
    /// The right-hand side.
    pub value: Expr,
}

impl Action {
    /// The variable's new value given the values before the event; `None` on an overflow or a
    /// division by zero.
    pub fn apply(&self, values: &[i64]) -> Option<i64> {
        let v = self.value.eval(values)?;
        match self.op {
            AssignOp::Set => Some(v),
            AssignOp::Add => values.get(self.var)?.checked_add(v),
            AssignOp::Sub => values.get(self.var)?.checked_sub(v),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bin(op: BinaryOp, l: Expr, r: Expr) -> Expr {
        Expr::Binary(op, Box::new(l), Box::new(r))
    }

    #[test]
    fn arithmetic_follows_java_integers() {
        let x = Expr::Var(0);
        assert_eq!(bin(BinaryOp::Div, x.clone(), Expr::Int(2)).eval(&[-7]), Some(-3));
        assert_eq!(bin(BinaryOp::Rem, x.clone(), Expr::Int(2)).eval(&[-7]), Some(-1));
        assert_eq!(bin(BinaryOp::Div, x.clone(), Expr::Int(0)).eval(&[1]), None);
        assert_eq!(bin(BinaryOp::Add, x, Expr::Int(1)).eval(&[i64::MAX]), None);
    }

    #[test]
    fn booleans_are_zero_and_one() {
        let g = bin(
            BinaryOp::Or,
            Expr::Unary(UnaryOp::Not, Box::new(bin(BinaryOp::Gt, Expr::Var(0), Expr::Int(2)))),
            bin(BinaryOp::Eq, Expr::Var(1), Expr::Int(5)),
        );
        assert!(g.holds(&[1, 0]) && g.holds(&[3, 5]) && !g.holds(&[3, 4]));
        let a = Action { var: 1, op: AssignOp::Sub, value: Expr::Var(0) };
        assert_eq!(a.apply(&[2, 5]), Some(3));
    }
}
