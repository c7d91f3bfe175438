//! The token stream of libFAUDES text files: markup `<Begin>` / `</End>`, quoted and bare strings,
//! unsigned integers, `+Option+` flags and `%` comments (skipped).

use std::borrow::Cow;
use std::path::Path;

use super::ParseError;

/// One token of a libFAUDES file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Token<'t> {
    /// `<Name ...>` (attributes are skipped); `empty` for `<Name/>`.
    Begin { name: &'t str, empty: bool },
    /// `</Name>`.
    End(&'t str),
    /// A quoted string (entities decoded) or a bare word that is not a number.
    Str(Cow<'t, str>),
    /// A bare unsigned decimal integer.
    Int(u64),
    /// `+X+`: an attribute flag such as `+C+` (controllable).
    Option(&'t str),
}

/// Splits a libFAUDES text into tokens, tracking the line of each.
pub(crate) struct Tokens<'t> {
    file: &'t Path,
    text: &'t str,
    pos: usize,
    line: usize,
    peeked: Option<(Token<'t>, usize)>,
}

impl<'t> Tokens<'t> {
    /// A tokenizer over `text`, read from `file`.
    pub(crate) fn new(file: &'t Path, text: &'t str) -> Self {
        Tokens { file, text, pos: 0, line: 1, peeked: None }
    }

    /// The file, for errors.
    pub(crate) fn file(&self) -> &'t Path {
        self.file
    }

    /// The line of the next token (or of the end of the text).
    pub(crate) fn line(&mut self) -> Result<usize, ParseError> {
        self.peek()?;
        Ok(self.peeked.as_ref().map_or(self.line, |(_, l)| *l))
    }

    /// The next token without consuming it; `None` at the end.
    pub(crate) fn peek(&mut self) -> Result<Option<&Token<'t>>, ParseError> {
        if self.peeked.is_none() {
            self.peeked = self.scan()?;
        }
        Ok(self.peeked.as_ref().map(|(t, _)| t))
    }

    /// The next token and its line; `None` at the end.
    pub(crate) fn next(&mut self) -> Result<Option<(Token<'t>, usize)>, ParseError> {
        match self.peeked.take() {
            Some(t) => Ok(Some(t)),
            None => self.scan(),
        }
    }

    /// An error at `line`.
    pub(crate) fn error(&self, line: usize, msg: impl Into<String>) -> ParseError {
        ParseError::syntax(self.file, line, msg)
    }

    fn scan(&mut self) -> Result<Option<(Token<'t>, usize)>, ParseError> {
        let bytes = self.text.as_bytes();
        loop {
            match bytes.get(self.pos) {
                None => return Ok(None),
                Some(b'\n') => {
                    self.line += 1;
                    self.pos += 1;
                }
                Some(b) if b.is_ascii_whitespace() || b.is_ascii_control() => self.pos += 1,
                Some(b'%') => {
                    while self.pos < bytes.len() && bytes[self.pos] != b'\n' {
                        self.pos += 1;
                    }
                }
                Some(_) => break,
            }
        }
        let line = self.line;
        let token = match bytes[self.pos] {
            b'<' => self.markup(line)?,
            b'"' => self.quoted(line)?,
            b'+' => self.option(line)?,
            _ => self.bare(line)?,
        };
        Ok(token.map(|t| (t, line)))
    }

    fn markup(&mut self, line: usize) -> Result<Option<Token<'t>>, ParseError> {
        let rest = &self.text[self.pos..];
        for (open, close) in [("<!--", "-->"), ("<?", "?>"), ("<!", ">")] {
            if rest.starts_with(open) {
                let end =
                    rest.find(close).ok_or_else(|| self.error(line, format!("'{open}' is never closed")))?;
                self.advance(end + close.len());
                return self.scan().map(|t| t.map(|(t, _)| t));
            }
        }
        let end = rest.find('>').ok_or_else(|| self.error(line, "'<' is never closed by '>'"))?;
        let inner = &rest[1..end];
        self.advance(end + 1);
        if let Some(name) = inner.strip_prefix('/') {
            return Ok(Some(Token::End(name.trim())));
        }
        let (inner, empty) = match inner.strip_suffix('/') {
            Some(i) => (i, true),
            None => (inner, false),
        };
        let name = inner.split(|c: char| c.is_whitespace()).next().unwrap_or("");
        if name.is_empty() {
            return Err(self.error(line, "markup without a name"));
        }
        Ok(Some(Token::Begin { name, empty }))
    }

    fn quoted(&mut self, line: usize) -> Result<Option<Token<'t>>, ParseError> {
        let rest = &self.text[self.pos + 1..];
        // Like libFAUDES, markup ends a quoted name: a missing quote is reported where it is missing.
        let (mut newlines, mut entities) = (0, false);
        let end = rest.bytes().position(|b| {
            newlines += usize::from(b == b'\n');
            entities |= b == b'&';
            matches!(b, b'"' | b'<' | b'>')
        });
        let end = end
            .filter(|&i| rest.as_bytes()[i] == b'"')
            .ok_or_else(|| self.error(line, "quoted name is never closed"))?;
        // The quotes are ASCII, so `end` is a character boundary.
        let raw = &rest[..end];
        self.line += newlines;
        self.pos += end + 2;
        // The scan above saw every byte: names without '&' skip `unescape`'s own search.
        Ok(Some(Token::Str(if entities { unescape(raw) } else { Cow::Borrowed(raw) })))
    }

    fn option(&mut self, line: usize) -> Result<Option<Token<'t>>, ParseError> {
        let rest = &self.text[self.pos + 1..];
        let end = rest
            .find(|c: char| c == '+' || c.is_whitespace() || c == '<')
            .filter(|&i| rest.as_bytes()[i] == b'+')
            .ok_or_else(|| self.error(line, "attribute flag '+…+' is never closed"))?;
        let flag = &rest[..end];
        self.advance(end + 2);
        Ok(Some(Token::Option(flag)))
    }

    fn bare(&mut self, line: usize) -> Result<Option<Token<'t>>, ParseError> {
        let rest = &self.text[self.pos..];
        let end = rest
            .find(|c: char| c.is_ascii_whitespace() || c.is_ascii_control() || matches!(c, '<' | '>' | '"'))
            .unwrap_or(rest.len());
        if end == 0 {
            return Err(self.error(line, "stray '>'"));
        }
        let word = &rest[..end];
        self.advance(end);
        if word.bytes().all(|b| b.is_ascii_digit()) {
            let n =
                word.parse::<u64>().map_err(|_| self.error(line, format!("number {word} is too large")))?;
            return Ok(Some(Token::Int(n)));
        }
        Ok(Some(Token::Str(unescape(word))))
    }

    /// Moves past `n` bytes, counting the newlines among them.
    fn advance(&mut self, n: usize) {
        let end = (self.pos + n).min(self.text.len());
        self.line += self.text.as_bytes()[self.pos..end].iter().filter(|&&b| b == b'\n').count();
        self.pos = end;
    }
}

/// Decodes the five XML entities libFAUDES uses in names; anything else stays as written.
fn unescape(raw: &str) -> Cow<'_, str> {
    if !raw.contains('&') {
        return Cow::Borrowed(raw);
    }
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(i) = rest.find('&') {
        out.push_str(&rest[..i]);
        rest = &rest[i..];
        let entity = [("&amp;", '&'), ("&quot;", '"'), ("&apos;", '\''), ("&lt;", '<'), ("&gt;", '>')]
            .into_iter()
            .find(|(e, _)| rest.starts_with(e));
        match entity {
            Some((e, c)) => {
                out.push(c);
                rest = &rest[e.len()..];
            }
            None => {
                out.push('&');
                rest = &rest[1..];
            }
        }
    }
    out.push_str(rest);
    Cow::Owned(out)
}

/// `s` as a quoted libFAUDES string (the entities `&amp;`, `&quot;`, `&lt;`, `&gt;` escaped).
pub(crate) fn quote(s: &str, out: &mut String) {
    out.push('"');
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(text: &str) -> Vec<(Token<'_>, usize)> {
        let mut t = Tokens::new(Path::new("t.gen"), text);
        std::iter::from_fn(|| t.next().unwrap()).collect()
    }

    #[test]
    fn splits_markup_strings_numbers_flags_and_skips_comments() {
        let toks = all("<Generator> % comment <no>\n\"a b&amp;\" 12 x1 +C+\n<Consecutive/></Generator>");
        assert_eq!(
            toks,
            [
                (Token::Begin { name: "Generator", empty: false }, 1),
                (Token::Str("a b&".into()), 2),
                (Token::Int(12), 2),
                (Token::Str("x1".into()), 2),
                (Token::Option("C"), 2),
                (Token::Begin { name: "Consecutive", empty: true }, 3),
                (Token::End("Generator"), 3),
            ]
        );
    }

    #[test]
    fn unterminated_pieces_name_their_line() {
        let mut t = Tokens::new(Path::new("t.gen"), "\n\n\"abc");
        assert_eq!(t.next().unwrap_err().to_string(), "t.gen: line 3: quoted name is never closed");
        let mut t = Tokens::new(Path::new("t.gen"), "<Alph");
        assert_eq!(t.next().unwrap_err().to_string(), "t.gen: line 1: '<' is never closed by '>'");
    }

    #[test]
    fn quote_then_read_gives_the_name_back() {
        let mut q = String::new();
        quote("a \"<b>\" & c", &mut q);
        assert_eq!(all(&q), [(Token::Str("a \"<b>\" & c".into()), 1)]);
    }
}
