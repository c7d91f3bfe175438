//! libFAUDES `.gen` (also DESTool): the plain token format of a `<Generator>`.
//!
//! Sections, in this order and each optional: `<Alphabet>` (event names, `+C+` after a controllable
//! one), `<States>`, `<TransRel>` (`source event target` triples), `<InitStates>`, `<MarkedStates>`.
//! Names may be quoted (`"a b"`, XML entities decoded) or bare; `%` starts a comment.
//!
//! States follow libFAUDES's numbering: a bare number is an anonymous state with that index, a name
//! gets the next index in order (or the one after a `#` suffix, `"idle#7"`), and `<Consecutive> a b
//! </Consecutive>` declares anonymous states `a..=b`. Later sections refer to states by index (bare
//! number) or by name. Anonymous states are named by their index. Other attribute flags (`+o+`, `+F+`)
//! and attribute sections are skipped: they carry nothing this tool uses. The XML form libFAUDES also
//! writes (`<?xml …?>`, `<StateSet>`, `<TransitionRelation>`) is read by `faudes_xml`. The
//! automaton is named after the file stem.

use std::borrow::Cow;

use std::path::Path;

use super::builder::Builder;
use super::faudes_xml;
use super::gen_tokens::{quote, Token, Tokens};
use super::hash::FastMap;
use super::{file_stem, ParseError};
use crate::model::{Automaton, Kind, StateId};

/// The most states one generator may declare: a guard against `<Consecutive> 1 4000000000
/// </Consecutive>` exhausting memory.
pub const MAX_STATES: u64 = 10_000_000;

/// The sections of a generator, in file order.
const SECTIONS: [&str; 5] = ["Alphabet", "States", "TransRel", "InitStates", "MarkedStates"];

/// Reads one automaton from the text of a `.gen` file; `file` names it in errors and gives its name.
pub fn read(file: &Path, text: &str) -> Result<Automaton, ParseError> {
    if faudes_xml::is_xml(text) {
        return faudes_xml::read(file, text);
    }
    let mut r = Reader {
        t: Tokens::new(file, text),
        b: Builder::new(file, file_stem(file), Kind::Unknown),
        index: StateIndex::default(),
    };
    r.generator()?;
    let mut a = r.b.finish()?;
    // libFAUDES keeps controllability with the plant (a System); a plain generator without `+C+`
    // anywhere says nothing of it.
    a.controllability_unsaid = !a.events.iter().any(|e| e.controllable);
    Ok(a)
}

struct Reader<'t> {
    t: Tokens<'t>,
    b: Builder<'t>,
    /// libFAUDES state index → our state id.
    index: StateIndex,
}

impl<'t> Reader<'t> {
    fn generator(&mut self) -> Result<(), ParseError> {
        let (top, line) = self.expect_begin()?;
        if top != "Generator" && top != "System" {
            return Err(self.t.error(line, format!("expected <Generator>, found <{top}>")));
        }
        if matches!(self.t.peek()?, Some(Token::Str(_) | Token::Int(_))) {
            self.t.next()?; // The generator's own name: the file stem names the automaton.
        }
        let mut next_section = 0;
        loop {
            let (tok, line) = self.next_token(top)?;
            match tok {
                Token::End(name) if name == top => break,
                Token::Begin { name, empty } => {
                    let rank = SECTIONS.iter().position(|&s| s == name).ok_or_else(|| {
                        ParseError::unsupported(
                            self.t.file(),
                            line,
                            format!(
                                "section <{name}> (only {} are read)",
                                SECTIONS.map(|s| format!("<{s}>")).join(", ")
                            ),
                        )
                    })?;
                    if rank < next_section {
                        return Err(self
                            .t
                            .error(line, format!("section <{name}> is out of order or repeated")));
                    }
                    next_section = rank + 1;
                    if !empty {
                        self.section(name)?;
                    }
                }
                other => {
                    return Err(self.t.error(line, format!("unexpected {} in <{top}>", describe(&other))))
                }
            }
        }
        if let Some((tok, _)) = self.t.next()? {
            let line = self.t.line()?;
            return Err(self.t.error(line, format!("unexpected {} after </{top}>", describe(&tok))));
        }
        Ok(())
    }

    fn section(&mut self, name: &str) -> Result<(), ParseError> {
        match name {
            "Alphabet" => self.alphabet(),
            "States" => self.states(),
            "TransRel" => self.transitions(),
            "InitStates" => self.state_set(name, |b, s, line| b.initial(s, line)),
            _ => self.state_set(name, |b, s, _| {
                b.mark(s);
                Ok(())
            }),
        }
    }

    fn alphabet(&mut self) -> Result<(), ParseError> {
        loop {
            let (tok, line) = self.next_token("Alphabet")?;
            let name = match tok {
                Token::End("Alphabet") => return Ok(()),
                Token::Str(s) => s,
                Token::Int(n) => n.to_string().into(),
                other => {
                    return Err(self.t.error(line, format!("unexpected {} in <Alphabet>", describe(&other))))
                }
            };
            let controllable = self.attributes()?.is_some_and(|flags| flags.contains('C'));
            self.b.event(&name, controllable, line)?;
        }
    }

    fn states(&mut self) -> Result<(), ParseError> {
        let mut next_index: u64 = 1;
        loop {
            let (tok, line) = self.next_token("States")?;
            match tok {
                Token::End("States") => return Ok(()),
                Token::Int(i) => self.declare(i, i.to_string().into(), line)?,
                Token::Str(s) => {
                    let (name, index) = match s.split_once('#') {
                        Some((name, suffix)) => {
                            let index = suffix
                                .parse::<u64>()
                                .ok()
                                .filter(|_| suffix.bytes().all(|b| b.is_ascii_digit()));
                            let index = index.ok_or_else(|| {
                                self.t.error(line, format!("state '{s}': '#' must be followed by an index"))
                            })?;
                            (Cow::Owned(name.to_owned()), index)
                        }
                        None => (s, next_index),
                    };
                    self.declare(index, name, line)?;
                }
                Token::Begin { name: "Consecutive", empty: false } => {
                    let (from, to) = self.range(line)?;
                    for i in from..=to {
                        self.declare(i, i.to_string().into(), line)?;
                    }
                    next_index += to - from;
                }
                other => {
                    return Err(self.t.error(line, format!("unexpected {} in <States>", describe(&other))))
                }
            }
            next_index += 1;
            self.attributes()?;
        }
    }

    fn declare(&mut self, index: u64, name: Cow<'t, str>, line: usize) -> Result<(), ParseError> {
        if self.b.state_count() as u64 >= MAX_STATES {
            return Err(self.t.error(line, format!("more than {MAX_STATES} states")));
        }
        if self.index.get(index).is_some() {
            return Err(self.t.error(line, format!("state index {index} is declared twice")));
        }
        let id = self.b.state(name, false, line)?;
        self.index.insert(index, id);
        Ok(())
    }

    /// `a b </Consecutive>` after `<Consecutive>`, checked to be a non-empty range of at most
    /// [`MAX_STATES`] indices.
    fn range(&mut self, line: usize) -> Result<(u64, u64), ParseError> {
        let mut bound = || match self.t.next()? {
            Some((Token::Int(n), _)) => Ok(n),
            _ => Err(self.t.error(line, "<Consecutive> needs two state indices")),
        };
        let (from, to) = (bound()?, bound()?);
        match self.t.next()? {
            Some((Token::End("Consecutive"), _)) => {}
            _ => return Err(self.t.error(line, "<Consecutive> needs two state indices and </Consecutive>")),
        }
        if from == 0 || to < from {
            return Err(self.t.error(line, format!("invalid range {from} to {to} in <Consecutive>")));
        }
        if to - from >= MAX_STATES {
            return Err(self
                .t
                .error(line, format!("range {from} to {to} has more than {MAX_STATES} states")));
        }
        Ok((from, to))
    }

    fn transitions(&mut self) -> Result<(), ParseError> {
        // Files list transitions grouped by source state: remembering the last source saves most
        // name lookups in large files.
        let mut last: Option<(Token<'t>, StateId)> = None;
        loop {
            let (tok, line) = self.next_token("TransRel")?;
            if tok == Token::End("TransRel") {
                return Ok(());
            }
            let source = match &last {
                Some((name, id)) if *name == tok => *id,
                _ => {
                    let id = self.state_ref(tok.clone(), line, "TransRel")?;
                    last = Some((tok, id));
                    id
                }
            };
            let event = match self.next_token("TransRel")? {
                (Token::Str(s), l) => self.b.event_named(&s, l)?,
                (Token::Int(n), l) => self.b.event_named(&n.to_string(), l)?,
                (other, l) => {
                    return Err(self.t.error(l, format!("expected an event, found {}", describe(&other))))
                }
            };
            let (tok, l) = self.next_token("TransRel")?;
            let target = self.state_ref(tok, l, "TransRel")?;
            self.b.transition(source, event, target, line);
            self.attributes()?;
        }
    }

    fn state_set(
        &mut self,
        section: &str,
        mut apply: impl FnMut(&mut Builder<'t>, StateId, usize) -> Result<(), ParseError>,
    ) -> Result<(), ParseError> {
        loop {
            let (tok, line) = self.next_token(section)?;
            match tok {
                Token::End(name) if name == section => return Ok(()),
                Token::Begin { name: "Consecutive", empty: false } => {
                    let (from, to) = self.range(line)?;
                    for i in from..=to {
                        let s = self.state_ref(Token::Int(i), line, section)?;
                        apply(&mut self.b, s, line)?;
                    }
                }
                tok => {
                    let s = self.state_ref(tok, line, section)?;
                    apply(&mut self.b, s, line)?;
                }
            }
            self.attributes()?;
        }
    }

    fn state_ref(&self, tok: Token<'t>, line: usize, section: &str) -> Result<StateId, ParseError> {
        match tok {
            Token::Int(i) => self
                .index
                .get(i)
                .ok_or_else(|| self.t.error(line, format!("state index {i} is not declared in <States>"))),
            Token::Str(s) => self.b.state_named(&s, line),
            other => Err(self
                .t
                .error(line, format!("expected a state in <{section}>, found {}", describe(&other)))),
        }
    }

    /// Skips the attributes after an element: `+X+` flags (returned, concatenated) and attribute
    /// sections.
    fn attributes(&mut self) -> Result<Option<String>, ParseError> {
        let mut flags: Option<String> = None;
        loop {
            match self.t.peek()? {
                Some(Token::Option(f)) => {
                    flags.get_or_insert_with(String::new).push_str(f);
                    self.t.next()?;
                }
                Some(&Token::Begin { name, empty }) if name != "Consecutive" => {
                    let line = self.t.line()?;
                    self.t.next()?;
                    if !empty {
                        self.skip_section(name, line)?;
                    }
                }
                _ => return Ok(flags),
            }
        }
    }

    fn skip_section(&mut self, name: &str, line: usize) -> Result<(), ParseError> {
        let mut depth = 1usize;
        while depth > 0 {
            match self.t.next()? {
                None => return Err(self.t.error(line, format!("<{name}> is never closed"))),
                Some((Token::Begin { empty: false, .. }, _)) => depth += 1,
                Some((Token::End(_), _)) => depth -= 1,
                Some(_) => {}
            }
        }
        Ok(())
    }

    fn expect_begin(&mut self) -> Result<(&'t str, usize), ParseError> {
        match self.t.next()? {
            Some((Token::Begin { name, empty: false }, line)) => Ok((name, line)),
            Some((other, line)) => {
                Err(self.t.error(line, format!("expected <Generator>, found {}", describe(&other))))
            }
            None => Err(self.t.error(1, "empty file: expected <Generator>")),
        }
    }

    /// The next token inside `<section>`, or an error naming the unclosed section at the end of the text.
    fn next_token(&mut self, section: &str) -> Result<(Token<'t>, usize), ParseError> {
        match self.t.next()? {
            Some(t) => Ok(t),
            None => {
                let line = self.t.line()?;
                Err(self.t.error(line, format!("file ends inside <{section}>")))
            }
        }
    }
}

/// libFAUDES state indices to our ids: a vector for the usual dense `1..=n`, a map for indices far
/// beyond the number of states (so a stray `<States> 4000000000 </States>` costs one entry, not 16 GB).
#[derive(Default)]
struct StateIndex {
    dense: Vec<Option<StateId>>,
    sparse: FastMap<u64, StateId>,
}

impl StateIndex {
    fn get(&self, index: u64) -> Option<StateId> {
        match usize::try_from(index).ok().and_then(|i| self.dense.get(i)) {
            Some(&Some(id)) => Some(id),
            _ => self.sparse.get(&index).copied(),
        }
    }

    fn insert(&mut self, index: u64, id: StateId) {
        // Dense while the vector stays within a few times the number of states declared so far.
        let bound = 1024 + 4 * (id.index() as u64 + 1);
        match usize::try_from(index) {
            Ok(i) if index < bound => {
                if i >= self.dense.len() {
                    self.dense.resize(i + 1, None);
                }
                self.dense[i] = Some(id);
            }
            _ => {
                self.sparse.insert(index, id);
            }
        }
    }
}

fn describe(tok: &Token) -> String {
    match tok {
        Token::Begin { name, .. } => format!("<{name}>"),
        Token::End(name) => format!("</{name}>"),
        Token::Str(s) => format!("'{s}'"),
        Token::Int(n) => format!("number {n}"),
        Token::Option(f) => format!("flag +{f}+"),
    }
}

/// Whether `a` can be written as `.gen` and read back unchanged: state names must not contain `#`
/// (libFAUDES reads what follows it as an index).
pub(crate) fn check(a: &Automaton) -> Result<(), String> {
    match a.states.iter().find(|s| s.name.contains('#')) {
        Some(s) => {
            Err(format!("state name '{}' contains '#', which libFAUDES reads as an index suffix", s.name))
        }
        None => Ok(()),
    }
}

/// Writes `a` as a `.gen` generator with quoted names. A state name containing `#` does not read back
/// unchanged ([`write_path`](super::write_path) refuses it).
pub fn write(a: &Automaton) -> String {
    let mut out =
        String::with_capacity(64 + 16 * a.events.len() + 8 * a.states.len() + 24 * a.transitions.len());
    out.push_str("<Generator>\n");
    quote(&a.name, &mut out);
    out.push_str("\n\n<Alphabet>\n");
    for e in &a.events {
        quote(&e.name, &mut out);
        out.push_str(if e.controllable { " +C+\n" } else { "\n" });
    }
    out.push_str("</Alphabet>\n\n<States>\n");
    for s in &a.states {
        quote(&s.name, &mut out);
        out.push('\n');
    }
    out.push_str("</States>\n\n<TransRel>\n");
    for t in &a.transitions {
        quote(&a.states[t.source.index()].name, &mut out);
        out.push(' ');
        quote(&a.events[t.event.index()].name, &mut out);
        out.push(' ');
        quote(&a.states[t.target.index()].name, &mut out);
        out.push('\n');
    }
    out.push_str("</TransRel>\n\n<InitStates>\n");
    if let Some(init) = a.initial {
        quote(&a.states[init.index()].name, &mut out);
        out.push('\n');
    }
    out.push_str("</InitStates>\n\n<MarkedStates>\n");
    for s in a.states.iter().filter(|s| s.marked) {
        quote(&s.name, &mut out);
        out.push('\n');
    }
    out.push_str("</MarkedStates>\n\n</Generator>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(a: &Automaton) -> Vec<(String, String, String)> {
        let n = |s: StateId| a.states[s.index()].name.clone();
        a.transitions
            .iter()
            .map(|t| (n(t.source), a.events[t.event.index()].name.clone(), n(t.target)))
            .collect()
    }

    #[test]
    fn numbers_refer_to_state_indices_not_names() {
        // States "1" "3" "2" get the indices 1 2 3, so `1 "g" 3` goes from "1" to "2" (as in libFAUDES).
        let a = read(Path::new("g1.gen"), include_str!("../../tests/data/core_parallel_g1.gen")).unwrap();
        assert!(names(&a).contains(&("1".into(), "g".into(), "2".into())), "{:?}", names(&a));
        assert_eq!(a.marked_count(), 2);
    }

    #[test]
    fn flags_comments_and_bare_numbers() {
        let a = read(Path::new("plant1.gen"), include_str!("../../tests/data/plant1.gen")).unwrap();
        let c: Vec<_> = a.events.iter().map(|e| (e.name.as_str(), e.controllable)).collect();
        assert_eq!(c, [("alpha", true), ("beta", true), ("gamma", false), ("delta", false)]);
        assert_eq!((a.states.len(), a.transitions.len()), (6, 9));
        assert_eq!(a.initial, a.state_id("1"));
    }

    #[test]
    fn consecutive_ranges_and_index_suffixes() {
        let text = "<Generator> g <Alphabet> a +C+ b </Alphabet>
            <States> <Consecutive> 1 3 </Consecutive> \"x#7\" </States>
            <TransRel> 1 a 2 2 b 7 x a 3 </TransRel>
            <InitStates> 1 </InitStates> <MarkedStates> <Consecutive> 2 3 </Consecutive> </MarkedStates>
            </Generator>";
        let a = read(Path::new("r.gen"), text).unwrap();
        let states: Vec<_> = a.states.iter().map(|s| (s.name.as_str(), s.marked)).collect();
        assert_eq!(states, [("1", false), ("2", true), ("3", true), ("x", false)]);
        assert_eq!(
            names(&a),
            [("1", "a", "2"), ("2", "b", "x"), ("x", "a", "3")].map(|(s, e, t)| (
                s.into(),
                e.into(),
                t.into()
            ))
        );
    }

    #[test]
    fn far_indices_mix_with_dense_ones() {
        let text = "<Generator> <Alphabet> a </Alphabet> <States> 3000 1 2 </States>
            <TransRel> 3000 a 1 1 a 3000 </TransRel> <InitStates> 3000 </InitStates> </Generator>";
        let a = read(Path::new("far.gen"), text).unwrap();
        assert_eq!(
            names(&a),
            [("3000", "a", "1"), ("1", "a", "3000")].map(|(s, e, t)| (s.into(), e.into(), t.into()))
        );
        assert_eq!(a.initial, a.state_id("3000"));
    }

    #[test]
    fn write_then_read_gives_the_same_automaton() {
        for text in
            [include_str!("../../tests/data/plant1.gen"), include_str!("../../tests/data/wplant3.gen")]
        {
            let a = read(Path::new("p.gen"), text).unwrap();
            assert_eq!(read(Path::new("p.gen"), &write(&a)).unwrap(), a);
        }
    }

    #[test]
    fn errors_name_the_line() {
        let err = |text: &str| read(Path::new("b.gen"), text).unwrap_err().to_string();
        assert_eq!(
            err("<Generator>\n<Alphabet> a </Alphabet>\n<States> s </States>\n<TransRel>\ns a 9\n</TransRel>\n</Generator>"),
            "b.gen: line 5: state index 9 is not declared in <States>"
        );
        assert_eq!(err("<Generator>\n<Alphabet> a"), "b.gen: line 2: file ends inside <Alphabet>");
        assert_eq!(
            err("<Generator> <States> <Consecutive> 1 99999999999 </Consecutive> </States> </Generator>"),
            "b.gen: line 1: range 1 to 99999999999 has more than 10000000 states"
        );
        assert_eq!(
            err("<Generator>\n<Attributes> </Attributes> </Generator>"),
            "b.gen: line 2: unsupported: section <Attributes> (only <Alphabet>, <States>, <TransRel>, <InitStates>, <MarkedStates> are read)"
        );
    }
}
