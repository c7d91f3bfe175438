//! Where a key of a TOML file is written: the line a message about the key names.
//!
//! The sections of a manifest deserialise into plain values ([`crate::config`]) without positions; a
//! check that finds a value wrong later names it by its [`Key`] (`board.inputs[2].pin`) and asks the
//! manifest's [`Lines`] for the line, which reads the text again with spans.

use std::fmt;

use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// A key of a TOML document as a path of table fields and array items: `board.inputs[2].pin`.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Key(Vec<Step>);

/// One step of a [`Key`].
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Step {
    /// A field of a table.
    Field(String),
    /// An item of an array (of an array of tables too).
    Item(usize),
}

impl Key {
    /// The top-level key `name`.
    pub fn new(name: &str) -> Key {
        Key(vec![Step::Field(name.to_owned())])
    }

    /// The key `text` names as [`Key`]'s `Display` writes it (`state.components.G1.inputs[0]`); dots
    /// split fields, `[N]` are items.
    pub fn parse(text: &str) -> Key {
        let mut steps = Vec::new();
        for part in text.split('.') {
            let (name, items) = part.split_once('[').map_or((part, ""), |(n, rest)| (n, rest));
            if !name.is_empty() {
                steps.push(Step::Field(name.to_owned()));
            }
            for item in items.split('[') {
                if let Ok(n) = item.trim_end_matches(']').parse() {
                    steps.push(Step::Item(n));
                }
            }
        }
        Key(steps)
    }

    /// The field `name` of the table at this key.
    pub fn field(&self, name: &str) -> Key {
        let mut steps = self.0.clone();
        steps.push(Step::Field(name.to_owned()));
        Key(steps)
    }

    /// Item `i` of the array at this key.
    pub fn item(&self, i: usize) -> Key {
        let mut steps = self.0.clone();
        steps.push(Step::Item(i));
        Key(steps)
    }
}

impl fmt::Display for Key {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, step) in self.0.iter().enumerate() {
            match step {
                Step::Field(name) if i == 0 => f.write_str(name)?,
                Step::Field(name) => write!(f, ".{name}")?,
                Step::Item(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// A TOML file's text, kept to tell the line of a key.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Lines {
    text: String,
}

impl Lines {
    /// The lines of `text`.
    pub fn new(text: impl Into<String>) -> Lines {
        Lines { text: text.into() }
    }

    /// The 1-based line where `key` is written; for a key the text does not hold (a field left out),
    /// the line of its closest enclosing entry that it does hold. `None` when the text holds none of
    /// it (or is not TOML).
    pub fn line(&self, key: &Key) -> Option<usize> {
        let doc = DeTable::parse(&self.text).ok()?;
        let mut at: Option<usize> = None;
        let mut here: Option<&DeValue> = None;
        for step in &key.0 {
            let next: Option<(usize, &Spanned<DeValue>)> = match (step, here) {
                (Step::Field(name), None) => field(doc.get_ref(), name),
                (Step::Field(name), Some(DeValue::Table(t))) => field(t, name),
                (Step::Item(i), Some(DeValue::Array(a))) => a.get(*i).map(|v| (v.span().start, v)),
                _ => None,
            };
            let Some((start, value)) = next else { break };
            at = Some(start);
            here = Some(value.get_ref());
        }
        at.map(|offset| {
            self.text.as_bytes()[..offset.min(self.text.len())].iter().filter(|&&b| b == b'\n').count() + 1
        })
    }
}

/// The field `name` of `table`: where its key is written, and its value.
fn field<'a, 'i>(table: &'a DeTable<'i>, name: &str) -> Option<(usize, &'a Spanned<DeValue<'i>>)> {
    table.iter().find(|(k, _)| k.get_ref().as_ref() == name).map(|(k, v)| (k.span().start, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "name = \"m\"\n\n[board]\nname = \"pico\"\n[[board.inputs]]\nevent = \"a\"\npin = 2\n\n[[board.inputs]]\nevent = \"b\"\npin = 3\n[plc]\ninputs = [{ event = \"a\", variable = \"x\" },\n  { event = \"b\", variable = \"y\" }]\n";

    #[test]
    fn keys_print_as_paths_and_find_their_lines() {
        let lines = Lines::new(TEXT);
        let second = Key::new("board").field("inputs").item(1);
        assert_eq!(second.field("pin").to_string(), "board.inputs[1].pin");
        assert_eq!(lines.line(&second.field("pin")), Some(11));
        assert_eq!(lines.line(&second.field("event")), Some(10));
        assert_eq!(lines.line(&Key::new("board").field("name")), Some(4));
        // A field left out: the line of its entry.
        let left_out = lines.line(&second.field("pull")).unwrap();
        assert!((9..=10).contains(&left_out), "{left_out}");
        let inline = Key::new("plc").field("inputs").item(1).field("variable");
        assert_eq!(lines.line(&inline), Some(14));
        assert_eq!(lines.line(&Key::new("state")), None);
        assert_eq!(Key::parse("board.inputs[1].pin"), second.field("pin"));
        assert_eq!(Key::parse("plc"), Key::new("plc"));
        assert_eq!(Lines::new("not toml [").line(&Key::new("a")), None);
    }
}
