//! IEC 61131-3 identifiers for the names of automata, states and events, which may be anything a model
//! file allows (`1`, `m1-ini.a`): letters, digits and single underscores, not starting with a digit,
//! unique without regard to case (ST is case-insensitive).

use std::collections::BTreeSet;

/// Reserved words a user-chosen variable name must not be (the keywords of the emitted subset and the
/// elementary types).
const RESERVED: &[&str] = &[
    "AND",
    "ARRAY",
    "AT",
    "BOOL",
    "BY",
    "CASE",
    "CONFIGURATION",
    "DINT",
    "DO",
    "ELSE",
    "ELSIF",
    "END_CASE",
    "END_FOR",
    "END_FUNCTION_BLOCK",
    "END_IF",
    "END_PROGRAM",
    "END_STRUCT",
    "END_TYPE",
    "END_VAR",
    "EXIT",
    "FALSE",
    "FOR",
    "FUNCTION",
    "FUNCTION_BLOCK",
    "IF",
    "INT",
    "MOD",
    "NOT",
    "OF",
    "OR",
    "PROGRAM",
    "RESOURCE",
    "RETURN",
    "STRUCT",
    "TASK",
    "THEN",
    "TO",
    "TRUE",
    "TYPE",
    "UDINT",
    "VAR",
    "VAR_INPUT",
    "VAR_OUTPUT",
    "WHILE",
    "XOR",
];

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

/// Whether `name` can be used as it is for a variable the user names.
pub fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.contains("__")
        && !name.ends_with('_')
        && !RESERVED.contains(&name.to_ascii_uppercase().as_str())
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

    /// `prefix_` + the sanitised `name`, with `_2`, `_3`, … added until it is free.
    pub fn fresh(&mut self, prefix: &str, name: &str) -> String {
        self.unique(format!("{prefix}_{}", sanitize(name)))
    }

    /// The sanitised `name` itself when it is an identifier, else `e_` + it; made unique as [`Names::fresh`].
    pub fn plain(&mut self, name: &str) -> String {
        let base = sanitize(name);
        self.unique(if is_identifier(&base) { base } else { format!("e_{base}") })
    }

    fn unique(&mut self, base: String) -> String {
        let mut candidate = base.clone();
        let mut n = 2;
        while !self.reserve(&candidate) {
            candidate = format!("{base}_{n}");
            n += 1;
        }
        candidate
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
}
