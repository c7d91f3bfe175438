//! A scan-cycle interpreter for the parsed ST subset: one [`Plc::scan`] runs the program's body once,
//! calling function block instances as they are called, and counts the statements it executes.
//!
//! Values: `BOOL`, integers (kept as `i64` and checked against their declared type's range on every
//! assignment, so an overflow the PLC would wrap is an error here), arrays (index checked), structs and
//! block instances. Unset variables start at their initial value or zero/FALSE, as on a PLC.
//!
//! Strict as a strict compiler is: [`Plc::load`] refuses what [`super::parse`](fn@super::parse)
//! refuses (keywords as names, located variables outside a `PROGRAM`'s own `VAR` block or bound twice, a
//! missing `;`) and what [`super::check`] refuses (an implicit conversion the standard does not allow, a
//! write to an input or into a block instance).

use std::collections::BTreeMap;

use super::check::{check, range, ton, TON};
use super::parse::{parse, Decl, Expr, Path, Stmt, Type, Unit};

/// A value.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Value {
    /// `BOOL`
    Bool(bool),
    /// An integer and its type's range.
    Int(i64, i64, i64),
    /// An array and its lower bound.
    Array(i64, Vec<Value>),
    /// A struct or block instance: its variables.
    Struct(BTreeMap<String, Value>),
}

/// A block's code, shared so a call does not copy it.
#[derive(Clone, Debug)]
struct Block {
    body: std::sync::Arc<Vec<Stmt>>,
}

/// The program of a source file, ready to scan.
#[derive(Clone, Debug)]
pub struct Plc {
    types: BTreeMap<String, Vec<Decl>>,
    blocks: BTreeMap<String, (Vec<Decl>, Block)>,
    program: String,
    vars: BTreeMap<String, Value>,
    executed: u64,
    /// The scan clock: the time of the current scan, in milliseconds.
    now_ms: i64,
    /// The time between two scans (the task's interval), in milliseconds.
    cycle_ms: i64,
    /// Per top-level statement of the `PROGRAM`'s body, whether the last scan took one of its `IF`
    /// arms.
    taken: Vec<bool>,
}

enum Flow {
    Next,
    Exit,
}

impl Plc {
    /// Parses `text` and instantiates its (single) `PROGRAM`.
    pub fn load(text: &str) -> Result<Plc, String> {
        let mut plc = Plc {
            types: BTreeMap::new(),
            blocks: BTreeMap::new(),
            program: String::new(),
            vars: BTreeMap::new(),
            executed: 0,
            now_ms: 0,
            cycle_ms: 10,
            taken: Vec::new(),
        };
        plc.blocks.insert(TON.into(), (ton(), Block { body: std::sync::Arc::new(Vec::new()) }));
        let units = parse(text)?;
        check(&units)?;
        for unit in units {
            match unit {
                Unit::Struct(name, fields) => {
                    plc.types.insert(name, fields);
                }
                Unit::Pou { program, name, vars, body } => {
                    if program {
                        if !plc.program.is_empty() {
                            return Err("more than one PROGRAM".into());
                        }
                        plc.program.clone_from(&name);
                    }
                    plc.blocks.insert(name, (vars, Block { body: std::sync::Arc::new(body) }));
                }
                Unit::Configuration { .. } => return Err("a CONFIGURATION among the POUs".into()),
            }
        }
        if plc.program.is_empty() {
            return Err("no PROGRAM".into());
        }
        plc.vars = plc.instance(&plc.program.clone())?;
        Ok(plc)
    }

    /// The body of POU `name` as parsed (for counting statements per section).
    pub fn body(&self, name: &str) -> Option<&[Stmt]> {
        self.blocks.get(&name.to_ascii_uppercase()).map(|(_, b)| b.body.as_slice())
    }

    /// The POU names, upper-cased.
    pub fn pous(&self) -> impl Iterator<Item = &str> {
        self.blocks.keys().map(String::as_str)
    }

    fn instance(&self, block: &str) -> Result<BTreeMap<String, Value>, String> {
        let (decls, _) = self.blocks.get(block).ok_or_else(|| format!("no block {block}"))?;
        decls.iter().map(|d| Ok((d.name.clone(), self.initial(d)?))).collect()
    }

    fn zero(&self, ty: &Type) -> Result<Value, String> {
        Ok(match ty {
            Type::Bool => Value::Bool(false),
            Type::Time => Value::Int(0, i64::MIN, i64::MAX),
            Type::Int(n) => {
                let (lo, hi) = range(n).ok_or_else(|| format!("no integer type {n}"))?;
                Value::Int(0, lo, hi)
            }
            Type::Array(lo, hi, t) => {
                Value::Array(*lo, (*lo..=*hi).map(|_| self.zero(t)).collect::<Result<_, _>>()?)
            }
            Type::Named(n) if self.types.contains_key(n) => Value::Struct(
                self.types[n]
                    .iter()
                    .map(|d| Ok((d.name.clone(), self.initial(d)?)))
                    .collect::<Result<_, String>>()?,
            ),
            Type::Named(n) => Value::Struct(self.instance(n)?),
        })
    }

    fn initial(&self, d: &Decl) -> Result<Value, String> {
        let mut v = self.zero(&d.ty)?;
        if let Some(init) = &d.init {
            let x = eval(init, &BTreeMap::new())?;
            assign(&mut v, x).map_err(|e| format!("{}: {e}", d.name))?;
        }
        Ok(v)
    }

    /// Sets the time between two scans, which drives the timers (`TON`); 10 ms unless set.
    pub fn set_cycle_ms(&mut self, ms: u32) {
        self.cycle_ms = i64::from(ms);
    }

    /// Runs one scan, `cycle_ms` after the previous one; returns the statements it executed.
    pub fn scan(&mut self) -> Result<u64, String> {
        self.executed = 0;
        self.now_ms += self.cycle_ms;
        let program = self.program.clone();
        let mut vars = std::mem::take(&mut self.vars);
        let r = self.run_program(&program, &mut vars);
        self.vars = vars;
        r.map(|()| self.executed)
    }

    /// Per top-level statement of the `PROGRAM`'s body (section markers included), whether the last
    /// scan took one of its `IF` arms (`false` for any other statement): which rungs of a state-based
    /// program conducted, read off the program as it ran.
    pub fn arms_taken(&self) -> &[bool] {
        &self.taken
    }

    /// The program's body, statement by statement, noting which top-level `IF` took an arm.
    fn run_program(&mut self, name: &str, vars: &mut BTreeMap<String, Value>) -> Result<(), String> {
        let body =
            std::sync::Arc::clone(&self.blocks.get(name).ok_or_else(|| format!("no block {name}"))?.1.body);
        self.taken.clear();
        for s in body.iter() {
            let mut took = false;
            if let Stmt::If(arms, _) = s {
                for (c, _) in arms {
                    if as_bool(&eval(c, vars)?)? {
                        took = true;
                        break;
                    }
                }
            }
            self.taken.push(took);
            if let Flow::Exit = self.exec(name, std::slice::from_ref(s), vars)? {
                break;
            }
        }
        Ok(())
    }

    fn run_block(&mut self, name: &str, vars: &mut BTreeMap<String, Value>) -> Result<(), String> {
        let body =
            std::sync::Arc::clone(&self.blocks.get(name).ok_or_else(|| format!("no block {name}"))?.1.body);
        self.exec(name, &body, vars).map(|_| ())
    }

    /// A call of a `TON` instance (IEC 61131-3 6.6.3.5.4): while `IN`, `ET` counts the scan clock from
    /// the call `IN` rose in, up to `PT`, and `Q` is `ET >= PT`; `IN` low resets both.
    fn ton(&self, vars: &mut BTreeMap<String, Value>) -> Result<(), String> {
        let get =
            |vars: &BTreeMap<String, Value>, n: &str| vars.get(n).cloned().ok_or(format!("TON has no {n}"));
        let input = as_bool(&get(vars, "IN")?)?;
        let (pt, running, start) =
            (as_int(&get(vars, "PT")?)?, as_bool(&get(vars, "RUNNING")?)?, as_int(&get(vars, "START")?)?);
        let start = if input && !running { self.now_ms } else { start };
        let et = if input { (self.now_ms - start).min(pt) } else { 0 };
        for (n, v) in [
            ("RUNNING", Value::Bool(input)),
            ("START", int(start)),
            ("ET", int(et)),
            ("Q", Value::Bool(input && et >= pt)),
        ] {
            vars.insert(n.into(), v);
        }
        Ok(())
    }

    fn exec(
        &mut self,
        block: &str,
        stmts: &[Stmt],
        vars: &mut BTreeMap<String, Value>,
    ) -> Result<Flow, String> {
        for s in stmts {
            if !matches!(s, Stmt::Section(_)) {
                self.executed += 1;
            }
            match s {
                Stmt::Section(_) => {}
                Stmt::Assign(path, e) => {
                    let v = eval(e, vars)?;
                    let place = lookup_mut(vars, path)?;
                    assign(place, v).map_err(|err| format!("{}: {err}", show(path)))?;
                }
                Stmt::If(arms, els) => {
                    let mut taken = None;
                    for (c, body) in arms {
                        if as_bool(&eval(c, vars)?)? {
                            taken = Some(body);
                            break;
                        }
                    }
                    if let Flow::Exit = self.exec(block, taken.unwrap_or(els), vars)? {
                        return Ok(Flow::Exit);
                    }
                }
                Stmt::Case(e, arms, els) => {
                    let x = as_int(&eval(e, vars)?)?;
                    let body = arms.iter().find(|(l, _)| l.contains(&x)).map_or(els, |(_, b)| b);
                    if let Flow::Exit = self.exec(block, body, vars)? {
                        return Ok(Flow::Exit);
                    }
                }
                Stmt::For(v, from, to, body) => {
                    let (from, to) = (as_int(&eval(from, vars)?)?, as_int(&eval(to, vars)?)?);
                    let path = Path(vec![(v.clone(), None)]);
                    for i in from..=to {
                        assign(lookup_mut(vars, &path)?, Value::Int(i, i, i))?;
                        if let Flow::Exit = self.exec(block, body, vars)? {
                            break;
                        }
                    }
                }
                Stmt::Exit => return Ok(Flow::Exit),
                Stmt::Call(inst, args) => {
                    let values: Vec<(String, Value)> = args
                        .iter()
                        .map(|(n, e)| Ok((n.clone(), eval(e, vars)?)))
                        .collect::<Result<_, String>>()?;
                    let Some(Value::Struct(mut inner)) = vars.remove(inst) else {
                        return Err(format!("{inst} is no block instance"));
                    };
                    let ty = self.type_of_instance(block, inst)?;
                    for (n, v) in values {
                        let place = inner.get_mut(&n).ok_or_else(|| format!("{inst} has no input {n}"))?;
                        assign(place, v).map_err(|e| format!("{inst}.{n}: {e}"))?;
                    }
                    let r = if ty == TON { self.ton(&mut inner) } else { self.run_block(&ty, &mut inner) };
                    vars.insert(inst.clone(), Value::Struct(inner));
                    r?;
                }
            }
        }
        Ok(Flow::Next)
    }

    /// The block type of instance `inst` declared in `block`.
    fn type_of_instance(&self, block: &str, inst: &str) -> Result<String, String> {
        self.blocks
            .get(block)
            .ok_or_else(|| format!("no block {block}"))?
            .0
            .iter()
            .find(|d| d.name == inst)
            .and_then(|d| match &d.ty {
                Type::Named(n) if self.blocks.contains_key(n) => Some(n.clone()),
                _ => None,
            })
            .ok_or_else(|| format!("{inst} is no block instance of {block}"))
    }

    fn path(&self, name: &str) -> Result<&Value, String> {
        let path = parse_path(name)?;
        lookup(&self.vars, &path)
    }

    /// Every variable's value, block instances' and timers' included: the program's whole state but
    /// its clock — two scans of equal states on the same clock behave alike.
    pub fn variables(&self) -> &BTreeMap<String, Value> {
        &self.vars
    }

    /// The BOOL at `path` (`sct.conveyor`, `EVENTS.s_c1`), case-insensitive.
    pub fn get_bool(&self, path: &str) -> Result<bool, String> {
        as_bool(self.path(path)?)
    }

    /// The integer at `path`.
    pub fn get_int(&self, path: &str) -> Result<i64, String> {
        as_int(self.path(path)?)
    }

    /// Sets the BOOL at `path`.
    pub fn set_bool(&mut self, path: &str, value: bool) -> Result<(), String> {
        let path = parse_path(path)?;
        assign(lookup_mut(&mut self.vars, &path)?, Value::Bool(value))
    }
}

fn parse_path(text: &str) -> Result<Path, String> {
    Ok(Path(text.split('.').map(|s| (s.to_ascii_uppercase(), None)).collect()))
}

fn show(p: &Path) -> String {
    p.0.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(".")
}

fn as_bool(v: &Value) -> Result<bool, String> {
    match v {
        Value::Bool(b) => Ok(*b),
        other => Err(format!("expected BOOL, found {other:?}")),
    }
}

fn as_int(v: &Value) -> Result<i64, String> {
    match v {
        Value::Int(i, ..) => Ok(*i),
        other => Err(format!("expected an integer, found {other:?}")),
    }
}

/// Stores `v` in `place`, which keeps its type: a BOOL takes a BOOL, an integer an integer in its range.
fn assign(place: &mut Value, v: Value) -> Result<(), String> {
    match (place, v) {
        (Value::Bool(p), Value::Bool(b)) => *p = b,
        (Value::Int(p, lo, hi), Value::Int(i, ..)) => {
            if i < *lo || i > *hi {
                return Err(format!("{i} is out of range {lo}..{hi}"));
            }
            *p = i;
        }
        (Value::Struct(p), Value::Struct(v)) if p.keys().eq(v.keys()) => {
            for (place, x) in p.values_mut().zip(v.into_values()) {
                assign(place, x)?;
            }
        }
        (p, v) => return Err(format!("cannot store {v:?} in {p:?}")),
    }
    Ok(())
}

fn index_of(lo: i64, len: usize, i: i64) -> Result<usize, String> {
    usize::try_from(i - lo).ok().filter(|&k| k < len).ok_or_else(|| format!("index {i} out of bounds"))
}

fn lookup<'v>(vars: &'v BTreeMap<String, Value>, path: &Path) -> Result<&'v Value, String> {
    let mut scope = vars;
    let mut found: Option<&Value> = None;
    for (name, index) in &path.0 {
        let mut v = scope.get(name).ok_or_else(|| format!("unknown variable {}", show(path)))?;
        if let Some(i) = index {
            let i = as_int(&eval(i, vars)?)?;
            let Value::Array(lo, items) = v else { return Err(format!("{name} is no array")) };
            v = &items[index_of(*lo, items.len(), i)?];
        }
        found = Some(v);
        if let Value::Struct(inner) = v {
            scope = inner;
        }
    }
    found.ok_or_else(|| format!("empty path {}", show(path)))
}

fn lookup_mut<'v>(vars: &'v mut BTreeMap<String, Value>, path: &Path) -> Result<&'v mut Value, String> {
    // Indices are evaluated first, against the unborrowed scope.
    let mut indices = Vec::new();
    for (_, index) in &path.0 {
        indices.push(match index {
            Some(i) => Some(as_int(&eval(i, vars)?)?),
            None => None,
        });
    }
    let mut segs = path.0.iter().zip(indices);
    let ((first, _), i0) = segs.next().ok_or_else(|| "empty path".to_owned())?;
    let mut v = vars.get_mut(first).ok_or_else(|| format!("unknown variable {}", show(path)))?;
    let mut index = i0;
    loop {
        if let Some(i) = index {
            let Value::Array(lo, items) = v else { return Err(format!("{} is no array", show(path))) };
            let k = index_of(*lo, items.len(), i)?;
            v = &mut items[k];
        }
        match segs.next() {
            None => return Ok(v),
            Some(((name, _), i)) => {
                let Value::Struct(inner) = v else { return Err(format!("{} is no struct", show(path))) };
                v = inner.get_mut(name).ok_or_else(|| format!("unknown member {}", show(path)))?;
                index = i;
            }
        }
    }
}

fn int(i: i64) -> Value {
    Value::Int(i, i64::MIN, i64::MAX)
}

fn eval(e: &Expr, vars: &BTreeMap<String, Value>) -> Result<Value, String> {
    Ok(match e {
        Expr::Bool(b) => Value::Bool(*b),
        Expr::Int(i) | Expr::Time(i) => int(*i),
        Expr::Var(p) => lookup(vars, p)?.clone(),
        Expr::Not(x) => Value::Bool(!as_bool(&eval(x, vars)?)?),
        Expr::Neg(x) => int(-as_int(&eval(x, vars)?)?),
        Expr::Call(f, args) => {
            let (Some((from, to)), [x]) = (f.split_once("_TO_"), args.as_slice()) else {
                return Err(format!("unknown function {f}"));
            };
            let v = match (from, eval(x, vars)?) {
                ("BOOL", Value::Bool(b)) => i64::from(b),
                (_, Value::Int(i, ..)) => i,
                (_, v) => return Err(format!("{f} of {v:?}")),
            };
            if to == "BOOL" {
                Value::Bool(v != 0)
            } else {
                // A narrowing conversion of a value out of range is the program's error here.
                let (lo, hi) = range(to).ok_or_else(|| format!("unknown function {f}"))?;
                if v < lo || v > hi {
                    return Err(format!("{f}({v}): out of range"));
                }
                int(v)
            }
        }
        Expr::Bin(a, op, b) => {
            let (a, b) = (eval(a, vars)?, eval(b, vars)?);
            match op.as_str() {
                "AND" | "&" => Value::Bool(as_bool(&a)? && as_bool(&b)?),
                "OR" => Value::Bool(as_bool(&a)? || as_bool(&b)?),
                "XOR" => Value::Bool(as_bool(&a)? != as_bool(&b)?),
                "=" | "<>" => {
                    let eq = match (&a, &b) {
                        (Value::Bool(x), Value::Bool(y)) => x == y,
                        _ => as_int(&a)? == as_int(&b)?,
                    };
                    Value::Bool(eq == (op == "="))
                }
                _ => {
                    let (x, y) = (as_int(&a)?, as_int(&b)?);
                    match op.as_str() {
                        "<" => Value::Bool(x < y),
                        ">" => Value::Bool(x > y),
                        "<=" => Value::Bool(x <= y),
                        ">=" => Value::Bool(x >= y),
                        "+" => int(x.checked_add(y).ok_or("overflow")?),
                        "-" => int(x.checked_sub(y).ok_or("overflow")?),
                        "*" => int(x.checked_mul(y).ok_or("overflow")?),
                        "/" => int(x.checked_div(y).ok_or("division by zero")?),
                        "MOD" => int(x.checked_rem(y).ok_or("MOD by zero")?),
                        _ => return Err(format!("unknown operator {op}")),
                    }
                }
            }
        }
    })
}
