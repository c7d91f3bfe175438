//! CODESYS V3: the program as one PLCopen XML project for CODESYS' import (Project → Import PLCopenXML),
//! the generic TC6 2.01 document with what CODESYS' own exports carry besides: an object id on every
//! POU and data type (`http://www.3s-software.com/plcopenxml/objectid`) and the project structure
//! (`…/projectstructure`) placing them in one folder named after the program. The configuration's
//! resource and cyclic task become the application's task configuration; located variables
//! (`AT %IX0.2`) are the I/O mapping, by address, to the device's I/O image.
//!
//! Both additions sit in `<addData>` elements, which the schema allows anywhere it names them and
//! CODESYS' importer discards when unknown (`handleUnknown="discard"`): the logic is the generic file's.

use std::fmt::Write as _;

use super::guid;
use crate::formats::xml_escape;
use crate::scan::files::{File, Source};
use crate::scan::xml::{self, Additions};

/// The additions' namespace stem.
const THREE_S: &str = "http://www.3s-software.com/plcopenxml";

/// The object id of the POU or data type `name` in the project `base`.
fn object_id(base: &str, name: &str) -> String {
    guid(&format!("CODESYS {base} {name}"))
}

/// The CODESYS project file of `source`: `<base>_codesys.xml`.
pub fn files(source: &Source) -> Vec<File> {
    let program = &source.program;
    let base = program.base.as_str();
    let element = |name: &str| {
        format!(
            "<addData><data name=\"{THREE_S}/objectid\" handleUnknown=\"discard\"><ObjectId>{}</ObjectId></data></addData>",
            object_id(base, name)
        )
    };
    let mut structure = format!(
        "<addData><data name=\"{THREE_S}/projectstructure\" handleUnknown=\"discard\"><ProjectStructure><Folder Name=\"{}\">",
        xml_escape(base)
    );
    let names = program.types.iter().map(|(n, _)| n).chain(program.pous.iter().map(|(p, _)| &p.name));
    for name in names {
        let _ = write!(
            structure,
            "<Object Name=\"{}\" ObjectId=\"{}\"/>",
            xml_escape(name),
            object_id(base, name)
        );
    }
    structure.push_str("</Folder></ProjectStructure></data></addData>");
    let add = Additions { element: &element, project: structure };
    let text = xml::document_with(program, &source.header.lines(), Some(&add));
    vec![(format!("{base}_codesys.xml"), text)]
}
