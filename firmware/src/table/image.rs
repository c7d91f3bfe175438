//! This module is the home of the tables' *image*: a [`SupervisorSet`] as one run of bytes, which
//! `codegen` writes and checks, the build script that compiles it checks again, and the firmware reads
//! with no work at compile time beyond slicing.
//!
//! An image is a header, then the sections the set's slices lie in:
//!
//! ```text
//! header   "SCT1"  [words W][automata N][plants][layout][wide][position bytes][mask bytes][0]
//!          [controllable: W words]  [8 lengths, u32 each: one per section, in elements]
//! sections masks (u32) · automata (Automaton<W, Q>, as C lays it out) · plant events ([u32; W]) ·
//!          initials (Q) · sites (Q) · holder lists (u16) · block (u8) · holders (u8)
//! ```
//!
//! every number little-endian, each section aligned for its elements (in this order no padding falls
//! between them), the last padded to a multiple of 4 bytes. The emitted Rust file holds the image as a
//! byte string (`const IMAGE`), copies its sections — not the header — into a 4-byte aligned `static`
//! ([`sections`], [`Aligned`]) and builds the set over them with [`set`], which reads the header and
//! slices: constant work whatever the set's size, so a set of any size compiles in the time its bytes
//! take to read. The set's [`CheckedSet`] comes from [`checked`], which compares a digest: the build
//! script checks every image of the file it compiles with the runtime's own check
//! ([`SupervisorSet::check`], on the host) and hands the compiler the images' [`digest`]s
//! (`SCT_TABLES_CHECKED`); an image whose digest is not among them does not compile. So the hot path's
//! unchecked reads stand on a check that provably ran on these very bytes, and the firmware carries no
//! check code.

use core::mem::size_of;

use super::{Automaton, CheckedSet, SupervisorSet};

/// The image's first bytes: the format and its version.
pub const MAGIC: [u8; 4] = *b"SCT1";
/// Sections of an image, in order: masks, automata, plant events, initials, sites, holder lists, block,
/// holders.
pub const SECTIONS: usize = 8;
/// Bytes of the header before the controllable words and the lengths.
const SHAPE: usize = 12;

/// A value aligned for the sections' widest elements (4 bytes): the image's sections in flash.
#[repr(C, align(4))]
pub struct Aligned<T: ?Sized>(pub T);

/// Bytes of the header of an image of `words`-word bitsets.
pub const fn header_bytes(words: usize) -> usize {
    SHAPE + 4 * words + 4 * SECTIONS
}

/// Why bytes are not an image of the set the runtime was built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ImageError {
    /// The bytes do not start with [`MAGIC`]: not an image, or one of another format version.
    Magic,
    /// The image's event bitsets are not `W` words, or its positions not the type's bytes.
    Shape,
    /// The header or a section lies beyond the bytes, or the sections are not as long as the header says.
    Length,
}

/// What the header says: the shape, the controllable events' words and every section's place.
#[derive(Clone, Copy, Debug)]
pub struct Header<const W: usize> {
    /// Automata of the set.
    pub automata: u8,
    /// Plants among them (the first).
    pub plants: u8,
    /// The layout id ([`super::layout`]).
    pub layout: u8,
    /// Wide fields ([`SupervisorSet::wide`]).
    pub wide: bool,
    /// Bytes of a position: 2 or 4 ([`super::Position`]).
    pub position_bytes: u8,
    /// Bytes of a mask in the pool ([`SupervisorSet::mask_bytes`]).
    pub mask_bytes: u8,
    /// The controllable events.
    pub controllable: [u32; W],
    /// Per section: its byte offset from the sections' start and its length in elements.
    pub sections: [(usize, usize); SECTIONS],
    /// Bytes of the sections with the padding after the last: what follows the header.
    pub sections_bytes: usize,
}

/// The little-endian `u32` at `at` of `bytes` (which holds it).
const fn word(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Per section, the bytes of one element and their alignment, for `W`-word bitsets and positions of
/// `position` bytes.
const fn elements<const W: usize>(position: usize) -> [(usize, usize); SECTIONS] {
    // `Automaton<W, Q>` as C lays it out: the alphabet's words, the start, the scale, padding to 4.
    let automaton = (4 * W + position + 1).div_ceil(4) * 4;
    [(4, 4), (automaton, 4), (4 * W, 4), (position, position), (position, position), (2, 2), (1, 1), (1, 1)]
}

/// Reads the header of `image`, an image of `W`-word bitsets: the shape and where each section lies.
/// Constant work (the header only).
pub const fn header<const W: usize>(image: &[u8]) -> Result<Header<W>, ImageError> {
    let head = header_bytes(W);
    if image.len() < head {
        return Err(ImageError::Length);
    }
    if image[0] != MAGIC[0] || image[1] != MAGIC[1] || image[2] != MAGIC[2] || image[3] != MAGIC[3] {
        return Err(ImageError::Magic);
    }
    let position = image[9] as usize;
    if image[4] as usize != W || !(position == 2 || position == 4) {
        return Err(ImageError::Shape);
    }
    let mut controllable = [0u32; W];
    let mut w = 0;
    while w < W {
        controllable[w] = word(image, SHAPE + 4 * w);
        w += 1;
    }
    let sizes = elements::<W>(position);
    let mut sections = [(0, 0); SECTIONS];
    let mut end: usize = 0;
    let mut i = 0;
    while i < SECTIONS {
        let len = word(image, SHAPE + 4 * W + 4 * i) as usize;
        let (size, align) = sizes[i];
        let at = end.div_ceil(align) * align;
        sections[i] = (at, len);
        end = match len.checked_mul(size) {
            Some(bytes) => at + bytes,
            None => return Err(ImageError::Length),
        };
        i += 1;
    }
    let sections_bytes = end.div_ceil(4) * 4;
    if image.len() - head != sections_bytes {
        return Err(ImageError::Length);
    }
    Ok(Header {
        automata: image[5],
        plants: image[6],
        layout: image[7],
        wide: image[8] != 0,
        position_bytes: image[9],
        mask_bytes: image[10],
        controllable,
        sections,
        sections_bytes,
    })
}

/// The sections of `image` (all of it after the header), as an array to put in an [`Aligned`] static.
/// A compile-time panic when `S` is not their length. Constant work: one copy.
pub const fn sections<const I: usize, const S: usize>(image: &[u8; I]) -> &[u8; S] {
    match image.last_chunk::<S>() {
        Some(tail) => tail,
        None => panic!("the image is shorter than its sections"),
    }
}

/// The set over `sections`, as the header of `image` lays it out; `sections` are the image's bytes after
/// its header ([`sections`]). Constant work: the header is read and the sections sliced.
///
/// # Safety
///
/// `sections` is 4-byte aligned and `header` is `image`'s header, read with `sections` after it.
const unsafe fn slice<'t, const W: usize, Q>(
    header: &Header<W>,
    sections: &'t [u8],
) -> SupervisorSet<'t, W, Q> {
    let base = sections.as_ptr();
    let s = &header.sections;
    // SAFETY: the caller's promise; `header` measured every section within the sections' bytes, each at
    // an offset aligned for its elements from a 4-byte aligned start, and every element type is plain
    // integers (`Automaton` as C lays it out) for which any initialised bytes are a value.
    unsafe {
        SupervisorSet {
            controllable: header.controllable,
            plants: header.plants,
            masks: core::slice::from_raw_parts(base.add(s[0].0).cast::<u32>(), s[0].1),
            automata: core::slice::from_raw_parts(base.add(s[1].0).cast::<Automaton<W, Q>>(), s[1].1),
            plant_events: core::slice::from_raw_parts(base.add(s[2].0).cast::<[u32; W]>(), s[2].1),
            initials: core::slice::from_raw_parts(base.add(s[3].0).cast::<Q>(), s[3].1),
            sites: core::slice::from_raw_parts(base.add(s[4].0).cast::<Q>(), s[4].1),
            holder_lists: core::slice::from_raw_parts(base.add(s[5].0).cast::<u16>(), s[5].1),
            block: core::slice::from_raw_parts(base.add(s[6].0), s[6].1),
            holders: core::slice::from_raw_parts(base.add(s[7].0), s[7].1),
            wide: header.wide,
            mask_bytes: header.mask_bytes,
            layout: header.layout,
        }
    }
}

/// The set of `image` over its `sections` copied into an [`Aligned`] static, or why the bytes are no
/// image of a set with `W`-word bitsets and positions of type `Q`.
pub const fn read<'t, const W: usize, Q, const S: usize>(
    image: &[u8],
    sections: &'t Aligned<[u8; S]>,
) -> Result<SupervisorSet<'t, W, Q>, ImageError> {
    read_slice(image, &sections.0, true)
}

/// [`read`] over sections given as a slice, `aligned` saying whether they start 4-byte aligned (host
/// tools pass the bytes of a `u32` buffer).
pub const fn read_slice<'t, const W: usize, Q>(
    image: &[u8],
    sections: &'t [u8],
    aligned: bool,
) -> Result<SupervisorSet<'t, W, Q>, ImageError> {
    let header = match header::<W>(image) {
        Ok(h) => h,
        Err(e) => return Err(e),
    };
    if header.position_bytes as usize != size_of::<Q>()
        || size_of::<Automaton<W, Q>>() != elements::<W>(size_of::<Q>())[1].0
    {
        return Err(ImageError::Shape);
    }
    if !aligned || sections.len() != header.sections_bytes || image.len() != header_bytes(W) + sections.len()
    {
        return Err(ImageError::Length);
    }
    // SAFETY: aligned, and the header of `image` measured with these sections after it.
    Ok(unsafe { slice(&header, sections) })
}

/// The set the emitted tables define (`SET`): [`read`], a compile-time error naming the fault when the
/// bytes are no such image.
pub const fn set<'t, const W: usize, Q, const S: usize>(
    image: &[u8],
    sections: &'t Aligned<[u8; S]>,
) -> SupervisorSet<'t, W, Q> {
    match read(image, sections) {
        Ok(set) => set,
        Err(ImageError::Magic) => {
            panic!("the tables are no image of this firmware's format (SCT1): emit them again")
        }
        Err(ImageError::Shape) => {
            panic!("the tables' event words or position type are not EVENT_WORDS and Position")
        }
        Err(ImageError::Length) => panic!("the tables' sections are not as long as their header says"),
    }
}

/// Whether `digest` (16 hex digits) is one of the space-separated digests of `proof`.
const fn proves(proof: &str, digest: &str) -> bool {
    let (p, d) = (proof.as_bytes(), digest.as_bytes());
    let mut at = 0;
    while at + d.len() <= p.len() {
        let mut i = 0;
        while i < d.len() && p[at + i] == d[i] {
            i += 1;
        }
        let ends = at + d.len() == p.len() || p[at + d.len()] == b' ';
        if i == d.len() && ends && !d.is_empty() {
            return true;
        }
        // The next digest.
        while at < p.len() && p[at] != b' ' {
            at += 1;
        }
        at += 1;
    }
    false
}

/// The runtime's [`CheckedSet`] of the emitted set `set`, whose image has the digest `digest`, given
/// `proof` — `env!("SCT_TABLES_CHECKED")`, the digests of the images this build's build script checked
/// ([`SupervisorSet::check`] on the host). A compile-time error when the set's shape is not the
/// runtime's or the image is not among those checked: a build whose tables were not checked does not
/// compile. Constant work.
pub const fn checked<
    't,
    const W: usize,
    const N: usize,
    const WIDE: bool,
    const MASK: usize,
    const LAYOUT: u8,
    Q,
>(
    set: &'t SupervisorSet<'t, W, Q>,
    digest: &str,
    proof: &str,
) -> CheckedSet<'t, W, N, WIDE, MASK, LAYOUT, Q> {
    if !CheckedSet::<W, N, WIDE, MASK, LAYOUT, Q>::fits(set) {
        panic!("the tables' shape is not the runtime's: AUTOMATA, WIDE, MASK_BYTES or LAYOUT differs from the image's");
    }
    if !proves(proof, digest) {
        panic!("these tables were not checked by this build's build script (SCT_TABLES_CHECKED lacks their digest): build them through apps/cell/build.rs or codegen::project::build_script");
    }
    CheckedSet::trusted(set)
}

/// The digest of an image that [`checked`] compares: 64-bit FNV-1a of its bytes, as 16 lowercase hex
/// digits (it binds the image the build script checked to the image compiled; it is no seal against
/// forgery, which the check needs none of).
pub fn digest(image: &[u8]) -> [u8; 16] {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in image {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    let mut out = [0u8; 16];
    for (i, o) in out.iter_mut().enumerate() {
        let nibble = (h >> (60 - 4 * i)) & 0xf;
        *o = b"0123456789abcdef"[nibble as usize];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_proof_names_digests_whole() {
        assert!(proves("0123 abcd", "abcd"));
        assert!(proves("0123 abcd", "0123"));
        assert!(!proves("0123 abcd", "012"));
        assert!(!proves("0123abcd", "abcd"));
        assert!(!proves("", "abcd"));
        assert!(!proves("abcd", ""));
    }

    #[test]
    fn digests_are_hex_and_tell_images_apart() {
        let a = digest(b"SCT1");
        assert!(a.iter().all(u8::is_ascii_hexdigit));
        assert_ne!(a, digest(b"SCT2"));
    }

    #[test]
    fn a_header_measures_its_sections_and_refuses_what_it_does_not_describe() {
        // One word, one automaton, 2-byte positions; lengths: 2 mask words, 1 automaton, 1 plant, no
        // initials, 1 site, no lists, 3 block bytes, 2 holder bytes.
        let mut image = [0u8; 12 + 4 + 32];
        image[..4].copy_from_slice(&MAGIC);
        image[4..12].copy_from_slice(&[1, 1, 1, 0, 0, 2, 1, 0]);
        for (i, len) in [2u32, 1, 1, 0, 1, 0, 3, 2].into_iter().enumerate() {
            image[16 + 4 * i..20 + 4 * i].copy_from_slice(&len.to_le_bytes());
        }
        let mut full = image.to_vec();
        // masks 0..8, automaton 8..16, plant events 16..20, site 20..22, block 22..25, holders 25..27, pad.
        full.extend_from_slice(&[0; 28]);
        let h = header::<1>(&full).unwrap();
        assert_eq!(h.sections[1], (8, 1));
        assert_eq!(h.sections[4], (20, 1));
        assert_eq!(h.sections[7], (25, 2));
        assert_eq!(h.sections_bytes, 28);
        assert_eq!(header::<2>(&full).err(), Some(ImageError::Shape));
        assert_eq!(header::<1>(&full[..full.len() - 4]).err(), Some(ImageError::Length));
        full[0] = b'X';
        assert_eq!(header::<1>(&full).err(), Some(ImageError::Magic));
    }
}
