//! Vendor projects: the one program ([`super::files::Source`]) printed in a PLC vendor's dialect and
//! file packaging, for the user to import into the vendor's IDE.
//!
//! | vendor | module | files |
//! |---|---|---|
//! | Beckhoff TwinCAT 3 | [`twincat`] | `.TcPOU` per POU, `.TcDUT` per structure, `.TcGVL` for the I/O, `.TcTTO` task |
//! | CODESYS V3 | [`codesys`] | one PLCopen XML project with CODESYS' project structure and object ids |
//! | Siemens TIA Portal | [`tia`] | SCL sources (`.scl`, `.udt`, `.db`) and a PLC tag table (`_tags.csv`) |
//! | Rockwell Studio 5000 | [`rockwell`] | one `.L5X` project: data types, Add-On Instructions, controller tags, the program, the task |
//!
//! No vendor module builds logic: each prints the IR the generic files print, renaming only what the
//! dialect asks (located I/O moved to a global list, the task in the vendor's task object), so the
//! file the user imports is the program `codegen run --target plc` scans. Identifiers that come from
//! the same program give the same bytes: object ids are name-derived ([`guid`]), never random.

pub mod codesys;
pub mod rockwell;
pub mod tia;
pub mod twincat;

use sha2::{Digest, Sha256};

use super::files::{File, Source};
use super::ir::{Pou, Var};
use super::strict::Violation;

/// A PLC vendor whose project format `codegen plc --vendor` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Vendor {
    /// Beckhoff TwinCAT 3 (PLC project files).
    Twincat,
    /// CODESYS V3 (PLCopen XML import).
    Codesys,
    /// Siemens TIA Portal, S7-1200/1500 (SCL external sources and a tag table).
    Tia,
    /// Rockwell Studio 5000 Logix Designer (one `.L5X` project file).
    Rockwell,
}

impl Vendor {
    /// The vendor's files for `sources` (each program's files in turn). A program that breaks a strict
    /// rule is not written, as for the generic files.
    pub fn files(self, sources: &[Source]) -> Result<Vec<File>, Violation> {
        let mut out = Vec::new();
        for s in sources {
            // The same strict check the generic files pass: a vendor file is never written from a
            // program the generic writer would refuse.
            s.files()?;
            out.extend(match self {
                Vendor::Twincat => twincat::files(s),
                Vendor::Codesys => codesys::files(s),
                Vendor::Tia => tia::files(s),
                Vendor::Rockwell => rockwell::files(s)?,
            });
        }
        Ok(out)
    }
}

/// A GUID in the registry form (`8-4-4-4-12` lower-case hex) derived from `name` by SHA-256, with the
/// version nibble set to 5 and the RFC 4122 variant: stable across runs (deterministic output), unique
/// per name.
pub fn guid(name: &str) -> String {
    let d = Sha256::digest(name.as_bytes());
    let mut b = [0u8; 16];
    b.copy_from_slice(&d[..16]);
    b[6] = (b[6] & 0x0f) | 0x50;
    b[8] = (b[8] & 0x3f) | 0x80;
    let h: String = b.iter().map(|x| format!("{x:02x}")).collect();
    format!("{}-{}-{}-{}-{}", &h[..8], &h[8..12], &h[12..16], &h[16..20], &h[20..])
}

/// `pou` without its located variables, and those variables: a vendor that declares the I/O in a
/// global list (TwinCAT's `.TcGVL`) takes them out of the `PROGRAM`. The body keeps reading them by
/// the same names, which the global list declares.
pub fn split_io(pou: &Pou) -> (Pou, Vec<Var>) {
    let mut rest = pou.clone();
    let mut io = Vec::new();
    for (_, vars) in &mut rest.vars {
        let (located, plain): (Vec<Var>, Vec<Var>) = vars.drain(..).partition(|v| v.address.is_some());
        io.extend(located);
        *vars = plain;
    }
    rest.vars.retain(|(_, vars)| !vars.is_empty());
    (rest, io)
}

/// The text `s` safe inside `<![CDATA[…]]>` (a `]]>` split across two sections).
pub fn cdata(s: &str) -> String {
    format!("<![CDATA[{}]]>", s.replace("]]>", "]]]]><![CDATA[>"))
}

/// The I/O direction of a located variable from its address: `%I…` input, `%Q…` output.
pub fn is_input(v: &Var) -> bool {
    v.address.as_deref().is_some_and(|a| a.starts_with("%I"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guids_are_stable_version_5_and_distinct() {
        let a = guid("cell_main");
        assert_eq!(a, guid("cell_main"));
        assert_ne!(a, guid("cell_sct"));
        assert_eq!(a.len(), 36);
        assert_eq!(&a[14..15], "5");
        assert!(matches!(&a[19..20], "8" | "9" | "a" | "b"));
    }

    #[test]
    fn cdata_never_closes_early() {
        assert_eq!(cdata("a]]>b"), "<![CDATA[a]]]]><![CDATA[>b]]>");
    }
}
