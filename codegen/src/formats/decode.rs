//! Bytes to text: UTF-8 (a byte-order mark dropped), or the single-byte Latin encodings an XML
//! declaration names (Supremica writes `encoding="windows-1252"`).

use std::borrow::Cow;
use std::path::Path;

use super::error::ErrorKind;
use super::ParseError;

/// What windows-1252 puts at 0x80..=0x9F (where ISO-8859-1 has C1 controls); 0 marks the five
/// unassigned bytes, which are refused.
const CP1252_HIGH: [u16; 32] = [
    0x20AC, 0, 0x201A, 0x0192, 0x201E, 0x2026, 0x2020, 0x2021, 0x02C6, 0x2030, 0x0160, 0x2039, 0x0152, 0,
    0x017D, 0, 0, 0x2018, 0x2019, 0x201C, 0x201D, 0x2022, 0x2013, 0x2014, 0x02DC, 0x2122, 0x0161, 0x203A,
    0x0153, 0, 0x017E, 0x0178,
];

/// The text of `bytes`, the content of `path`.
///
/// UTF-8 is taken as is. Text that is not UTF-8 is decoded as windows-1252 or ISO-8859-1 only when its
/// XML declaration says so; anything else is refused with the line of the first bad byte.
pub(crate) fn decode<'b>(path: &Path, bytes: &'b [u8]) -> Result<Cow<'b, str>, ParseError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let err = match std::str::from_utf8(bytes) {
        Ok(text) => return Ok(Cow::Borrowed(text)),
        Err(e) => e,
    };
    let line_at = |i: usize| 1 + bytes[..i].iter().filter(|&&b| b == b'\n').count();
    let windows = match declared_encoding(bytes).as_deref() {
        Some("windows-1252" | "cp1252") => true,
        Some("iso-8859-1" | "latin1" | "latin-1" | "iso8859-1") => false,
        _ => return Err(ParseError::new(path, Some(line_at(err.valid_up_to())), ErrorKind::NotUtf8)),
    };
    let mut text = String::with_capacity(bytes.len() + 16);
    for (i, &b) in bytes.iter().enumerate() {
        let c = match b {
            0x80..=0x9F if windows => char::from_u32(u32::from(CP1252_HIGH[usize::from(b - 0x80)]))
                .filter(|&c| c != '\0')
                .ok_or_else(|| ParseError::new(path, Some(line_at(i)), ErrorKind::NotUtf8))?,
            b => char::from(b),
        };
        text.push(c);
    }
    Ok(Cow::Owned(text))
}

/// The lower-case `encoding` of a leading `<?xml ...?>` declaration.
fn declared_encoding(bytes: &[u8]) -> Option<String> {
    let head = bytes.get(..bytes.len().min(200))?;
    let end = head.windows(2).position(|w| w == b"?>")?;
    let decl = std::str::from_utf8(&head[..end]).ok()?.strip_prefix("<?xml")?;
    let value = decl.split("encoding").nth(1)?.trim_start().strip_prefix('=')?.trim_start();
    let quote = value.chars().next().filter(|&q| q == '"' || q == '\'')?;
    let value = &value[1..];
    Some(value[..value.find(quote)?].to_ascii_lowercase())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declared_latin_encodings_decode_and_others_are_refused() {
        let cp = b"<?xml version=\"1.0\" encoding=\"windows-1252\"?>\n<a>\x80 \xe7</a>";
        assert_eq!(
            decode(Path::new("a.wmod"), cp).unwrap(),
            "<?xml version=\"1.0\" encoding=\"windows-1252\"?>\n<a>\u{20ac} \u{e7}</a>"
        );
        let latin = b"<?xml version='1.0' encoding='ISO-8859-1'?><a>\x80</a>";
        assert!(decode(Path::new("a.xmd"), latin).unwrap().contains('\u{80}'));
        let msg = decode(Path::new("a.gen"), b"ok\n\xff").unwrap_err().to_string();
        assert_eq!(msg, "a.gen: line 2: not UTF-8 text");
        let undefined = b"<?xml version=\"1.0\" encoding=\"windows-1252\"?>\n\n\x81";
        assert_eq!(decode(Path::new("u.wmod"), undefined).unwrap_err().line(), Some(3));
    }
}
