//! The tables' image on the host ([`crate::table::image`] describes the format): written from a
//! [`Packed`] set and its [`SideTables`], checked with the runtime's own check whatever its word count
//! and position width ([`check`]), and carried in Rust source as the byte string the emitted file
//! holds ([`literal`]), which build scripts find and check again ([`check_source`]).

use alloc::format;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;
use core::fmt::Write as _;

use super::{Packed, SideTables};
use crate::table::image::{digest, header_bytes, read_slice, ImageError, MAGIC, SECTIONS};
use crate::table::{Position, TableError};

/// The sections' names, in image order, as reports name them.
pub const SECTION_NAMES: [&str; SECTIONS] = [
    "mask pool",
    "automaton descriptors",
    "plant events",
    "initial states",
    "choice sites",
    "holder lists",
    "blocks",
    "holders",
];

/// Index of the plant events among the sections.
pub const PLANT_EVENTS: usize = 2;
/// Index of the choice sites among the sections.
pub const SITES: usize = 4;
/// Index of the blocks among the sections.
pub const BLOCKS: usize = 6;
/// Index of the holders among the sections.
pub const HOLDERS: usize = 7;

/// The image of `packed` with its side tables `side`: header, then the sections, each aligned, the last
/// padded to 4 bytes.
pub fn write(packed: &Packed, side: &SideTables) -> Vec<u8> {
    let words = packed.words();
    let position = packed.position_bytes;
    let le_position =
        |v: usize, out: &mut Vec<u8>| out.extend_from_slice(&(v as u32).to_le_bytes()[..position]);
    let mut sections: [Vec<u8>; SECTIONS] = Default::default();
    let starts = packed.starts();
    for w in packed.mask_pool() {
        sections[0].extend_from_slice(&w.to_le_bytes());
    }
    // `Automaton<W, Q>` as C lays it out: alphabet words, start, scale, padding to a multiple of 4.
    let descriptor = (4 * words + position + 1).div_ceil(4) * 4;
    for (b, &start) in packed.automata.iter().zip(&starts) {
        let d = &mut sections[1];
        let at = d.len();
        for w in 0..words {
            d.extend_from_slice(&b.alphabet.get(w).copied().unwrap_or(0).to_le_bytes());
        }
        le_position(start, d);
        d.push(b.scale);
        d.resize(at + descriptor, 0);
    }
    for p in &side.plant_events {
        for w in p {
            sections[2].extend_from_slice(&w.to_le_bytes());
        }
    }
    for h in packed.initials() {
        le_position(h, &mut sections[3]);
    }
    for &s in &side.sites {
        le_position(s, &mut sections[4]);
    }
    for l in packed.holder_lists() {
        sections[5].extend_from_slice(&l.to_le_bytes());
    }
    for b in &packed.automata {
        sections[6].extend_from_slice(&b.block);
    }
    sections[7].extend_from_slice(&side.holders);
    let lengths = [
        packed.mask_pool().len(),
        packed.automata.len(),
        side.plant_events.len(),
        packed.initials().len(),
        side.sites.len(),
        packed.holder_lists().len(),
        sections[6].len(),
        sections[7].len(),
    ];
    let aligns = [4, 4, 4, position, position, 2, 1, 1];
    let mut image =
        Vec::with_capacity(header_bytes(words) + sections.iter().map(Vec::len).sum::<usize>() + 32);
    image.extend_from_slice(&MAGIC);
    // Words ≤ 8, automata ≤ 32, layout ids, widths ≤ 32 bytes: each fits its byte (`encode_as`, `SideTables`).
    image.extend_from_slice(&[
        words as u8,
        packed.automata.len() as u8,
        side.plants,
        packed.layout.id(),
        u8::from(packed.wide),
        position as u8,
        packed.mask_width() as u8,
        0,
    ]);
    for w in 0..words {
        image.extend_from_slice(&packed.controllable.get(w).copied().unwrap_or(0).to_le_bytes());
    }
    for len in lengths {
        image.extend_from_slice(&(len as u32).to_le_bytes());
    }
    let head = image.len();
    for (section, align) in sections.iter().zip(aligns) {
        image.resize(head + (image.len() - head).next_multiple_of(align), 0);
        image.extend_from_slice(section);
    }
    image.resize(head + (image.len() - head).next_multiple_of(4), 0);
    image
}

/// Each section's byte offset from the sections' start and its bytes, in image order (what the size
/// report names): read off the header of `image`.
pub fn section_bytes(image: &[u8]) -> Option<[(usize, usize); SECTIONS]> {
    let words = usize::from(*image.get(4)?);
    let position = usize::from(*image.get(9)?);
    let at = 12 + 4 * words;
    let len = |i: usize| -> Option<usize> {
        let b = image.get(at + 4 * i..at + 4 * i + 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let descriptor = (4 * words + position + 1).div_ceil(4) * 4;
    let sizes = [4, descriptor, 4 * words, position, position, 2, 1, 1];
    let aligns = [4, 4, 4, position, position, 2, 1, 1];
    let mut out = [(0, 0); SECTIONS];
    let mut end: usize = 0;
    for i in 0..SECTIONS {
        let start = end.next_multiple_of(aligns[i]);
        out[i] = (start, len(i)? * sizes[i]);
        end = start + out[i].1;
    }
    Some(out)
}

/// Why an image cannot be run: it is none, or its tables fail the runtime's check.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CheckError {
    /// The bytes are no image of this format, or of more event words than a set has.
    #[error("not an image of this firmware's tables: {0:?}")]
    Image(ImageError),
    /// The tables fail the runtime's check ([`crate::table::SupervisorSet::check`]).
    #[error("the {layout} tables fail the runtime's check: {error:?}")]
    Table {
        /// The layout's name.
        layout: &'static str,
        /// What the check found.
        error: TableError,
    },
}

/// Runs the runtime's check on the set of `image`, for the word count and position width its header
/// names: the check the hot path's unchecked reads stand on.
pub fn check(image: &[u8]) -> Result<(), CheckError> {
    let (Some(&words), Some(&position)) = (image.get(4), image.get(9)) else {
        return Err(CheckError::Image(ImageError::Length));
    };
    macro_rules! by_words {
        ($($w:literal)*) => {
            match (words, position) {
                $(($w, 2) => check_as::<$w, u16>(image),
                  ($w, 4) => check_as::<$w, u32>(image),)*
                _ => Err(CheckError::Image(ImageError::Shape)),
            }
        };
    }
    by_words!(0 1 2 3 4 5 6 7 8)
}

/// [`check`] for `W` words and positions of type `Q`.
fn check_as<const W: usize, Q: Position>(image: &[u8]) -> Result<(), CheckError> {
    let head = header_bytes(W).min(image.len());
    // The sections copied into words: aligned for every element, as the firmware's static is.
    let tail = &image[head..];
    let mut words = vec![0u32; tail.len().div_ceil(4)];
    for (w, chunk) in words.iter_mut().zip(tail.chunks(4)) {
        let mut b = [0; 4];
        b[..chunk.len()].copy_from_slice(chunk);
        *w = u32::from_ne_bytes(b);
    }
    // SAFETY: `u32` words viewed as their bytes; `tail.len()` of them lie in the buffer.
    let sections = unsafe { core::slice::from_raw_parts(words.as_ptr().cast::<u8>(), tail.len()) };
    let set = read_slice::<W, Q>(image, sections, true).map_err(CheckError::Image)?;
    let layout = crate::table::layout::name(set.layout);
    set.check(set.automata.len()).map_err(|error| CheckError::Table { layout, error })
}

/// The hex digits of `image`'s digest ([`crate::table::image::digest`]), what `SCT_TABLES_CHECKED`
/// holds for it.
pub fn digest_hex(image: &[u8]) -> String {
    digest(image).iter().map(|&b| char::from(b)).collect()
}

/// The start of the timer table a tables file ends with (`codegen::emit::timers`).
const TIMERS_ITEM: &str = "pub static TIMERS: [firmware::timer::TimerSpec; ";

/// The timer table of the tables `text` — its text from `pub static TIMERS` to the closing `];` — when
/// it holds at least one timer; `None` for an empty one or none.
pub fn timers_item(text: &str) -> Option<&str> {
    let rest = &text[text.find(TIMERS_ITEM)?..];
    if rest[TIMERS_ITEM.len()..].starts_with("0]") {
        return None;
    }
    rest.find("\n];").map(|end| &rest[..end + 3])
}

/// The digest a tables file declares (`DIGEST`) for tables whose own digest is `tables`: that digest
/// itself without timers, so a project without any keeps the digest of its image alone; with a timer
/// table (`timers`, [`timers_item`]), the digest of `tables` followed by its text — the timers run
/// outside the image, and a timer's delay or events changed must change what the firmware reports
/// over the link's TABLES as well.
pub fn tables_digest(tables: &str, timers: Option<&str>) -> String {
    match timers {
        None => String::from(tables),
        Some(timers) => digest_hex(&[tables.as_bytes(), timers.as_bytes()].concat()),
    }
}

/// The name of the constant the emitted file holds an image in.
pub const IMAGE_CONST: &str = "const IMAGE: &[u8; ";

/// Bytes of an image per line of [`literal`].
const PER_LINE: usize = 24;

/// `image` as the item `const IMAGE: &[u8; N] = b"…";` of Rust source, every byte as `\xHH`, lines of
/// `PER_LINE` bytes continued with `\`, each line after the first indented by `indent`.
pub fn literal(image: &[u8], indent: &str) -> String {
    let mut out = format!("{IMAGE_CONST}{}] = b\"\\\n", image.len());
    for row in image.chunks(PER_LINE) {
        out.push_str(indent);
        out.push_str("    ");
        for b in row {
            let _ = write!(out, "\\x{b:02x}");
        }
        out.push_str("\\\n");
    }
    out.push_str(indent);
    out.push_str("\";");
    out
}

/// Why the tables of a Rust file cannot be checked.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SourceError {
    /// An image literal that is not as [`literal`] writes it.
    #[error("line {line}: the image is not a byte string of \\xHH escapes as codegen writes it")]
    Literal {
        /// Its first line (1-based).
        line: usize,
    },
    /// An image that is no image or fails the check.
    #[error("line {line}: {error}")]
    Check {
        /// Its first line (1-based).
        line: usize,
        /// Why.
        error: CheckError,
    },
}

/// Every image the Rust source `text` holds (items written by [`literal`]), with the line it starts on.
pub fn images_in(text: &str) -> Result<Vec<(usize, Vec<u8>)>, SourceError> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(IMAGE_CONST) {
        let line = text.len() - rest.len() + at;
        let line = text[..line].matches('\n').count() + 1;
        let bad = SourceError::Literal { line };
        let item = &rest[at + IMAGE_CONST.len()..];
        let (len, item) = item.split_once("] = b\"").ok_or(bad.clone())?;
        let len: usize = len.parse().map_err(|_| bad.clone())?;
        let mut bytes = Vec::with_capacity(len);
        let mut chars = item.char_indices();
        let end = loop {
            match chars.next() {
                Some((_, '\\')) => match chars.next() {
                    Some((_, 'x')) => {
                        let hex: String = chars.by_ref().take(2).map(|(_, c)| c).collect();
                        bytes.push(u8::from_str_radix(&hex, 16).map_err(|_| bad.clone())?);
                    }
                    // A continued line: the newline and the next line's leading blanks are no bytes.
                    Some((_, '\n')) => {
                        let mut peek = chars.clone();
                        while let Some((_, ' ')) = peek.next() {
                            chars.next();
                        }
                    }
                    _ => return Err(bad),
                },
                Some((i, '"')) => break i,
                _ => return Err(bad),
            }
        };
        if bytes.len() != len {
            return Err(bad);
        }
        out.push((line, bytes));
        rest = &item[end..];
    }
    Ok(out)
}

/// Checks every image of the Rust source `text` ([`images_in`], [`check`]): the value of
/// `SCT_TABLES_CHECKED` for them, their digests separated by spaces (empty for a file without images:
/// the state tables) — each the one the file declares, with its timer table ([`tables_digest`]).
pub fn check_source(text: &str) -> Result<String, SourceError> {
    let mut proof = Vec::new();
    let timers = timers_item(text);
    for (line, image) in images_in(text)? {
        check(&image).map_err(|error| SourceError::Check { line, error })?;
        proof.push(tables_digest(&digest_hex(&image), timers));
    }
    Ok(proof.join(" "))
}
