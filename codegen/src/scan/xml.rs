//! A program as PLCopen TC6 XML 2.01 (namespace `http://www.plcopen.org/xml/tc6_0201`): its structure
//! types as data types, its POUs with their interfaces and ST bodies (and an `<LD>` or `<SFC>` body
//! where the program has one), and the configuration with its resource and cyclic task. Importable by
//! CODESYS, TwinCAT and Beremiz; validated in CI against the schema.
//!
//! The schema requires a creation time; it is fixed (`1970-01-01T00:00:00`) so the file's bytes depend
//! on its inputs only. The provenance header is an XML comment and the content header's `Comment`.

use std::fmt::Write as _;

use super::ir::{Pou, Type, Var, VarClass};
use super::ld;
use super::program::{Graphic, Program};
use crate::formats::xml_escape;

/// Schema namespace.
pub const NAMESPACE: &str = "http://www.plcopen.org/xml/tc6_0201";

/// The schema's form of a type.
fn data_type(ty: &Type) -> String {
    match ty {
        Type::Array(upper, of) => format!(
            "<array><dimension lower=\"0\" upper=\"{upper}\"/><baseType>{}</baseType></array>",
            data_type(of)
        ),
        Type::Named(n) => format!("<derived name=\"{}\"/>", xml_escape(n)),
        t => format!("<{}/>", t.elementary().unwrap_or_default()),
    }
}

fn variable(out: &mut String, v: &Var, indent: &str) {
    let address = v.address.as_ref().map(|a| format!(" address=\"{}\"", xml_escape(a))).unwrap_or_default();
    let _ = write!(
        out,
        "{indent}<variable name=\"{}\"{address}><type>{}</type>",
        xml_escape(&v.name),
        data_type(&v.ty)
    );
    if let Some(init) = &v.init {
        let _ =
            write!(out, "<initialValue><simpleValue value=\"{}\"/></initialValue>", xml_escape(&init.text()));
    }
    if !v.comment.is_empty() {
        let _ = write!(out, "<documentation><xhtml:p>{}</xhtml:p></documentation>", xml_escape(&v.comment));
    }
    out.push_str("</variable>\n");
}

/// What a vendor adds to the generic document ([`document_with`]): an `<addData>` element for each POU
/// and data type by name, and one for the project. The logic is the generic document's.
pub struct Additions<'a> {
    /// The `<addData>` of the POU or data type named.
    pub element: &'a dyn Fn(&str) -> String,
    /// The project's `<addData>`.
    pub project: String,
}

/// `p` as a `<pou>`: its ST body (unless a chart stands for it), then its graphical body and the
/// vendor's additions.
fn pou(out: &mut String, p: &Pou, graphic: &Graphic, add: Option<&Additions>) {
    let extra = match graphic {
        Graphic::Text | Graphic::LadderCallingSt(_) => None,
        Graphic::Ladder(rungs) => Some(ld::body(rungs)),
        Graphic::Chart(chart) => Some(format!("<SFC>\n{}        </SFC>", chart.body())),
    };
    let kind = if p.program { "program" } else { "functionBlock" };
    let _ = writeln!(out, "      <pou name=\"{}\" pouType=\"{kind}\">", xml_escape(&p.name));
    out.push_str("        <interface>\n");
    for (class, vars) in p.blocks() {
        let tag = match class {
            VarClass::Input => "inputVars",
            VarClass::Output => "outputVars",
            VarClass::Local => "localVars",
        };
        let _ = writeln!(out, "          <{tag}>");
        for v in vars {
            variable(out, v, "            ");
        }
        let _ = writeln!(out, "          </{tag}>");
    }
    out.push_str("        </interface>\n");
    if !p.sections.is_empty() || extra.is_none() {
        let _ = writeln!(out, "        <body><ST><xhtml:p><![CDATA[{}]]></xhtml:p></ST></body>", p.body());
    }
    if let Some(body) = extra {
        let _ = writeln!(out, "        <body>{body}</body>");
    }
    if let Some(add) = add {
        let _ = writeln!(out, "        {}", (add.element)(&p.name));
    }
    out.push_str("      </pou>\n");
}

/// The project file of `program` under the comment `header`; its configuration runs `<base>_main`
/// every cycle.
pub fn document(program: &Program, header: &[String]) -> String {
    document_with(program, header, None)
}

/// [`document`] with a vendor's additions.
pub fn document_with(program: &Program, header: &[String], add: Option<&Additions>) -> String {
    let (base, cycle_ms) = (program.base.as_str(), program.cycle_ms);
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!--\n");
    for l in header {
        let _ = writeln!(out, "  {}", l.replace("--", "- -"));
    }
    out.push_str("-->\n");
    let _ = writeln!(out, "<project xmlns=\"{NAMESPACE}\" xmlns:xhtml=\"http://www.w3.org/1999/xhtml\">");
    let _ = writeln!(
        out,
        "  <fileHeader companyName=\"sct-codegen\" productName=\"codegen\" productVersion=\"{}\" creationDateTime=\"1970-01-01T00:00:00\"/>",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(out, "  <contentHeader name=\"{}\">", xml_escape(base));
    let _ = writeln!(out, "    <Comment>{}</Comment>", xml_escape(&header.join("\n")));
    out.push_str("    <coordinateInfo><fbd><scaling x=\"1\" y=\"1\"/></fbd><ld><scaling x=\"1\" y=\"1\"/></ld><sfc><scaling x=\"1\" y=\"1\"/></sfc></coordinateInfo>\n");
    out.push_str("  </contentHeader>\n  <types>\n    <dataTypes>\n");
    for (name, members) in &program.types {
        let _ = writeln!(out, "      <dataType name=\"{}\"><baseType><struct>", xml_escape(name));
        for m in members {
            variable(&mut out, m, "        ");
        }
        out.push_str("      </struct></baseType>");
        if let Some(add) = add {
            out.push_str(&(add.element)(name));
        }
        out.push_str("</dataType>\n");
    }
    out.push_str("    </dataTypes>\n    <pous>\n");
    for (p, graphic) in program.xml_pous() {
        pou(&mut out, &p, graphic, add);
    }
    out.push_str("    </pous>\n  </types>\n  <instances>\n    <configurations>\n");
    let _ = writeln!(out, "      <configuration name=\"{base}_config\">");
    let _ = writeln!(out, "        <resource name=\"{base}_resource\">");
    let _ = writeln!(out, "          <task name=\"{base}_task\" interval=\"T#{cycle_ms}ms\" priority=\"1\">");
    let _ = writeln!(out, "            <pouInstance name=\"{base}_instance\" typeName=\"{base}_main\"/>");
    out.push_str("          </task>\n        </resource>\n      </configuration>\n    </configurations>\n  </instances>\n");
    if let Some(add) = add {
        let _ = writeln!(out, "  {}", add.project);
    }
    out.push_str("</project>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn types_map_to_the_schema() {
        assert_eq!(data_type(&Type::Bool), "<BOOL/>");
        assert_eq!(
            data_type(&Type::array(22, Type::Bool)),
            "<array><dimension lower=\"0\" upper=\"22\"/><baseType><BOOL/></baseType></array>"
        );
        assert_eq!(data_type(&Type::Named("cell_sct".into())), "<derived name=\"cell_sct\"/>");
        assert_eq!(xml_escape("a<b & 'c'"), "a&lt;b &amp; &apos;c&apos;");
    }
}
