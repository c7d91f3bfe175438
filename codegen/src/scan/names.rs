//! IEC 61131-3 identifiers for the names of automata, states and events, which may be anything a model
//! file allows (`1`, `m1-ini.a`, `if`, `en`): letters, digits and single underscores, not starting with a
//! digit, not a keyword, unique without regard to case (ST is case-insensitive).
//!
//! The rules, by clause of IEC 61131-3 Ed. 3 (2013):
//! * 6.1.2 (identifiers): a letter or underscore, then letters, digits and underscores; no two
//!   underscores in a row, none at the end; case is not significant.
//! * 6.1.3 (keywords): no keyword may be an identifier, in any case — the whole list is [`KEYWORDS`]
//!   (the language's keywords, `EN`/`ENO`, the elementary and generic data type names of 6.4.2/6.4.3,
//!   and the standard function and function block names of 6.6.2.5 and 6.6.3), plus every
//!   `<type>_TO_<type>`/`TO_<type>` conversion function name of 6.6.2.5 ([`is_keyword`]).
//! * 6.1.2 leaves the significant length to the implementer; identifiers are kept to [`MAX_LEN`]
//!   characters, which the toolchains with the lowest limits accept.

use std::collections::BTreeSet;

/// The longest identifier written: IEC leaves the significant length to the implementer (6.1.2), so
/// the writer stays under the lowest limit among the toolchains it targets.
pub const MAX_LEN: usize = 63;

/// Every word IEC 61131-3 Ed. 3 reserves (6.1.3), upper-case, sorted; conversion function names are
/// matched by pattern in [`is_keyword`]. Groups: the language's keywords (ST, SFC, configurations,
/// classes, namespaces, IL operators of 7.2), `EN`/`ENO` (6.6.1), the elementary and generic data types
/// (6.4.2, 6.4.3), the standard functions (6.6.2.5) and function blocks (6.6.3).
pub const KEYWORDS: &[&str] = &[
    "ABS",
    "ABSTRACT",
    "ACOS",
    "ACTION",
    "ADD",
    "ADD_DT_TIME",
    "ADD_LDT_LTIME",
    "ADD_LTIME",
    "ADD_LTOD_LTIME",
    "ADD_TIME",
    "ADD_TOD_TIME",
    "AND",
    "ANDN",
    "ANY",
    "ANY_BIT",
    "ANY_CHAR",
    "ANY_CHARS",
    "ANY_DATE",
    "ANY_DERIVED",
    "ANY_DURATION",
    "ANY_ELEMENTARY",
    "ANY_INT",
    "ANY_MAGNITUDE",
    "ANY_NUM",
    "ANY_REAL",
    "ANY_SIGNED",
    "ANY_STRING",
    "ANY_UNSIGNED",
    "ARRAY",
    "AS",
    "ASIN",
    "AT",
    "ATAN",
    "ATAN2",
    "BOOL",
    "BY",
    "BYTE",
    "CAL",
    "CALC",
    "CALCN",
    "CASE",
    "CHAR",
    "CLASS",
    "CONCAT",
    "CONCAT_DATE",
    "CONCAT_DATE_LTOD",
    "CONCAT_DATE_TOD",
    "CONCAT_DT",
    "CONCAT_LDT",
    "CONCAT_LTOD",
    "CONCAT_TOD",
    "CONFIGURATION",
    "CONSTANT",
    "CONTINUE",
    "COS",
    "CTD",
    "CTD_DINT",
    "CTD_INT",
    "CTD_LINT",
    "CTD_UDINT",
    "CTD_ULINT",
    "CTU",
    "CTUD",
    "CTUD_DINT",
    "CTUD_INT",
    "CTUD_LINT",
    "CTUD_UDINT",
    "CTUD_ULINT",
    "CTU_DINT",
    "CTU_INT",
    "CTU_LINT",
    "CTU_UDINT",
    "CTU_ULINT",
    "DATE",
    "DATE_AND_TIME",
    "DAY_OF_WEEK",
    "DELETE",
    "DINT",
    "DIV",
    "DIVTIME",
    "DIV_LTIME",
    "DIV_TIME",
    "DO",
    "DT",
    "DWORD",
    "ELSE",
    "ELSIF",
    "EN",
    "END_ACTION",
    "END_CASE",
    "END_CLASS",
    "END_CONFIGURATION",
    "END_FOR",
    "END_FUNCTION",
    "END_FUNCTION_BLOCK",
    "END_IF",
    "END_INTERFACE",
    "END_METHOD",
    "END_NAMESPACE",
    "END_PROGRAM",
    "END_REPEAT",
    "END_RESOURCE",
    "END_STEP",
    "END_STRUCT",
    "END_TRANSITION",
    "END_TYPE",
    "END_VAR",
    "END_WHILE",
    "ENO",
    "EQ",
    "EXIT",
    "EXP",
    "EXPT",
    "EXTENDS",
    "FALSE",
    "FINAL",
    "FIND",
    "FOR",
    "FROM",
    "FROM_BIG_ENDIAN",
    "FROM_LITTLE_ENDIAN",
    "FUNCTION",
    "FUNCTION_BLOCK",
    "F_EDGE",
    "F_TRIG",
    "GE",
    "GT",
    "IF",
    "IMPLEMENTS",
    "INITIAL_STEP",
    "INSERT",
    "INT",
    "INTERFACE",
    "INTERNAL",
    "INTERVAL",
    "IS_VALID",
    "IS_VALID_BCD",
    "JMP",
    "JMPC",
    "JMPCN",
    "LD",
    "LDATE",
    "LDATE_AND_TIME",
    "LDN",
    "LDT",
    "LE",
    "LEFT",
    "LEN",
    "LIMIT",
    "LINT",
    "LN",
    "LOG",
    "LREAL",
    "LT",
    "LTIME",
    "LTIME_OF_DAY",
    "LTOD",
    "LWORD",
    "MAX",
    "METHOD",
    "MID",
    "MIN",
    "MOD",
    "MOVE",
    "MUL",
    "MULTIME",
    "MUL_LTIME",
    "MUL_TIME",
    "MUX",
    "NAMESPACE",
    "NE",
    "NON_RETAIN",
    "NOT",
    "NULL",
    "OF",
    "ON",
    "OR",
    "ORN",
    "OVERLAP",
    "OVERRIDE",
    "PRIORITY",
    "PRIVATE",
    "PROGRAM",
    "PROTECTED",
    "PUBLIC",
    "READ_ONLY",
    "READ_WRITE",
    "REAL",
    "REF",
    "REFERENCE",
    "REF_TO",
    "REPEAT",
    "REPLACE",
    "RESOURCE",
    "RET",
    "RETAIN",
    "RETC",
    "RETCN",
    "RETURN",
    "RIGHT",
    "ROL",
    "ROR",
    "RS",
    "R_EDGE",
    "R_TRIG",
    "SEL",
    "SHL",
    "SHR",
    "SIN",
    "SINGLE",
    "SINT",
    "SPLIT_DATE",
    "SPLIT_DT",
    "SPLIT_LDT",
    "SPLIT_LTOD",
    "SPLIT_TOD",
    "SQRT",
    "SR",
    "ST",
    "STEP",
    "STN",
    "STRING",
    "STRUCT",
    "SUB",
    "SUB_DATE_DATE",
    "SUB_DT_DT",
    "SUB_DT_TIME",
    "SUB_LDATE_LDATE",
    "SUB_LDT_LDT",
    "SUB_LDT_LTIME",
    "SUB_LTIME",
    "SUB_LTOD_LTIME",
    "SUB_LTOD_LTOD",
    "SUB_TIME",
    "SUB_TOD_TIME",
    "SUB_TOD_TOD",
    "SUPER",
    "TAN",
    "TASK",
    "THEN",
    "THIS",
    "TIME",
    "TIME_OF_DAY",
    "TO",
    "TOD",
    "TOF",
    "TOF_LTIME",
    "TON",
    "TON_LTIME",
    "TO_BIG_ENDIAN",
    "TO_LITTLE_ENDIAN",
    "TP",
    "TP_LTIME",
    "TRANSITION",
    "TRUE",
    "TRUNC",
    "TYPE",
    "UDINT",
    "UINT",
    "ULINT",
    "UNTIL",
    "USING",
    "USINT",
    "VAR",
    "VAR_ACCESS",
    "VAR_CONFIG",
    "VAR_EXTERNAL",
    "VAR_GLOBAL",
    "VAR_INPUT",
    "VAR_IN_OUT",
    "VAR_OUTPUT",
    "VAR_TEMP",
    "WCHAR",
    "WHILE",
    "WITH",
    "WORD",
    "WSTRING",
    "XOR",
    "XORN",
];

/// The elementary type names a conversion function's name is made of (6.6.2.5: `INT_TO_DINT`,
/// `TO_INT`, `BCD_TO_INT`, `INT_TRUNC_…`).
const CONVERTIBLE: &[&str] = &[
    "BCD",
    "BOOL",
    "BYTE",
    "CHAR",
    "DATE",
    "DATE_AND_TIME",
    "DINT",
    "DT",
    "DWORD",
    "INT",
    "LDATE",
    "LDATE_AND_TIME",
    "LDT",
    "LINT",
    "LREAL",
    "LTIME",
    "LTIME_OF_DAY",
    "LTOD",
    "LWORD",
    "REAL",
    "SINT",
    "STRING",
    "TIME",
    "TIME_OF_DAY",
    "TOD",
    "UDINT",
    "UINT",
    "ULINT",
    "USINT",
    "WCHAR",
    "WORD",
    "WSTRING",
];

/// Whether `name` is reserved in any case: a keyword of [`KEYWORDS`] or a conversion function name
/// (`X_TO_Y`, `TO_Y`, `X_TRUNC_Y`, 6.6.2.5).
pub fn is_keyword(name: &str) -> bool {
    let up = name.to_ascii_uppercase();
    let ty = |t: &str| CONVERTIBLE.contains(&t);
    KEYWORDS.binary_search(&up.as_str()).is_ok()
        || up.strip_prefix("TO_").is_some_and(ty)
        || ["_TO_", "_TRUNC_"]
            .iter()
            .any(|sep| up.match_indices(sep).any(|(i, _)| ty(&up[..i]) && ty(&up[i + sep.len()..])))
}

/// `name` reduced to identifier characters: every other character an underscore, runs of underscores
/// one, none at the ends; empty becomes `x`.
pub fn sanitize(name: &str) -> String {
    let mut out = String::new();
    for c in name.chars() {
        let c = if c.is_ascii_alphanumeric() { c } else { '_' };
        if c == '_' && (out.is_empty() || out.ends_with('_')) {
            continue;
        }
        out.push(c);
    }
    while out.ends_with('_') {
        out.pop();
    }
    if out.is_empty() {
        out.push('x');
    }
    out
}

/// The stem of the POU and configuration names of a set named `name` (`NAME_sct`, `NAME_main`,
/// `NAME_resource`, …): the sanitised name, cut so that the longest of them stays within [`MAX_LEN`].
pub fn stem(name: &str) -> String {
    let mut out: String = sanitize(name).chars().take(MAX_LEN - "_resource".len()).collect();
    while out.ends_with('_') {
        out.pop();
    }
    out
}

/// Whether `name` can be used as it is for a variable: an identifier of 6.1.2 of at most
/// [`MAX_LEN`] characters, no keyword (6.1.3).
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.contains("__")
        && !name.ends_with('_')
        && name.len() <= MAX_LEN
        && !is_keyword(name)
}

/// Hands out identifiers that are unique without regard to case.
#[derive(Debug, Default)]
pub struct Names {
    taken: BTreeSet<String>,
}

impl Names {
    /// Reserves `name` as it is; `false` if it is taken already.
    pub fn reserve(&mut self, name: &str) -> bool {
        self.taken.insert(name.to_ascii_uppercase())
    }

    /// `prefix_` + the sanitised `name` (cut to fit [`MAX_LEN`]), with `_2`, `_3`, … added until it is
    /// free. A prefix keeps the result off the keywords (none of [`KEYWORDS`] is a prefix the writer uses
    /// followed by `_` and a name; checked with the rest by `super::strict`).
    pub fn fresh(&mut self, prefix: &str, name: &str) -> String {
        self.unique(format!("{prefix}_{}", sanitize(name)))
    }

    /// The sanitised `name` itself when it is an identifier, else `e_` + it; made unique as [`Names::fresh`].
    pub fn plain(&mut self, name: &str) -> String {
        let base = sanitize(name);
        self.unique(if is_identifier(&base) { base } else { format!("e_{base}") })
    }

    fn unique(&mut self, base: String) -> String {
        let mut n = 1;
        loop {
            let suffix = if n == 1 { String::new() } else { format!("_{n}") };
            let mut head: String = base.chars().take(MAX_LEN - suffix.len()).collect();
            while head.ends_with('_') {
                head.pop();
            }
            let candidate = format!("{head}{suffix}");
            if !is_keyword(&candidate) && self.reserve(&candidate) {
                return candidate;
            }
            n += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_become_identifiers_and_stay_unique() {
        assert_eq!(sanitize("m1-ini.a"), "m1_ini_a");
        assert_eq!(sanitize("__a__b__"), "a_b");
        assert_eq!(sanitize("é"), "x");
        let mut names = Names::default();
        assert_eq!(names.fresh("ev", "1"), "ev_1");
        assert_eq!(names.fresh("ev", "a.b"), "ev_a_b");
        assert_eq!(names.fresh("EV", "A-B"), "EV_A_B_2", "case-insensitive clash");
        assert!(is_identifier("sensor_c1") && !is_identifier("1x") && !is_identifier("a__b"));
        let mut members = Names::default();
        assert_eq!(
            (members.plain("s_c1"), members.plain("1"), members.plain("AND")),
            ("s_c1".into(), "e_1".into(), "e_AND".into())
        );
        assert!(!is_identifier("end_if") && !is_identifier("a b") && !is_identifier(""));
    }

    #[test]
    fn every_keyword_group_is_reserved_in_any_case() {
        assert!(KEYWORDS.windows(2).all(|w| w[0] < w[1]), "sorted, for the binary search");
        for word in ["en", "ENO", "If", "time", "R_TRIG", "ton", "int_to_dint", "TO_INT", "real_trunc_int"] {
            assert!(is_keyword(word) && !is_identifier(word), "{word}");
        }
        for word in ["enabled", "sensor", "x_TO_y", "INT_TO_x", "ready", "hold", "st_TIME"] {
            assert!(!is_keyword(word), "{word}");
        }
        let mut members = Names::default();
        let got: Vec<String> =
            ["if", "Time", "en", "R_TRIG", "ok"].iter().map(|n| members.plain(n)).collect();
        assert_eq!(got, ["e_if", "e_Time", "e_en", "e_R_TRIG", "ok"]);
    }

    #[test]
    fn long_names_are_cut_and_stay_unique() {
        let stem = stem(&format!("{}_b", "a".repeat(60)));
        assert!(is_identifier(&format!("{stem}_resource")) && stem.len() == MAX_LEN - 9);
        let long = "a".repeat(100);
        let mut names = Names::default();
        let (x, y) = (names.fresh("ev", &long), names.fresh("ev", &long));
        assert_eq!((x.len(), y.len()), (MAX_LEN, MAX_LEN));
        assert!(x != y && y.ends_with("_2") && is_identifier(&x) && is_identifier(&y));
    }
}
