//! Where a generated file comes from: the input files with their SHA-256 and the command that
//! reproduces it, written into its header so a table in flash or a PLC program can be traced back to
//! its models. Below every writer (the firmware's tables in [`crate::emit`], the PLC programs in
//! [`crate::plc`]), so that each takes the same facts.

use sha2::{Digest, Sha256};
use std::io;
use std::path::Path;

/// One input file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Input {
    /// The path as given (with `/` separators), so the header does not depend on the machine.
    pub path: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
}

impl Input {
    /// Reads and hashes the file at `path`.
    pub fn read(path: &Path) -> io::Result<Input> {
        let bytes = std::fs::read(path)?;
        Ok(Input::of(&path.to_string_lossy().replace('\\', "/"), &bytes))
    }

    /// The input named `path` with content `bytes`.
    pub fn of(path: &str, bytes: &[u8]) -> Input {
        let digest = Sha256::digest(bytes);
        let sha256 = digest.iter().map(|b| format!("{b:02x}")).collect();
        Input { path: path.to_string(), sha256 }
    }
}

/// The header's facts.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Provenance {
    /// Input files in the order they were read.
    pub inputs: Vec<Input>,
    /// The command line that reproduces the file (without the output path).
    pub command: String,
    /// Which supervisors the file holds and how they were proven to keep the full set's closed loop
    /// (`[runtime] supervisors`), when a project says.
    pub supervisors: Option<String>,
}

impl Provenance {
    /// The header's lines, without comment markers: the command, the supervisors, then every input
    /// with its SHA-256.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!("Command: {}", self.command)];
        out.extend(self.supervisors.iter().map(|s| format!("Supervisors: {s}")));
        out.push(String::from("Inputs (SHA-256):"));
        out.extend(self.inputs.iter().map(|i| format!("  {}  {}", i.sha256, i.path)));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_of_abc() {
        assert_eq!(
            Input::of("x", b"abc").sha256,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
