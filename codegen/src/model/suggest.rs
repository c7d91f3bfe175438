//! "Did you mean …?": the known names closest in spelling to a name that is not known, for every error
//! that refuses a name (an event no plant has, an unknown `[events]`, `[board]` or `[plc]` entry).
//!
//! Closeness is the optimal-string-alignment edit distance ([`strsim::osa_distance`]: insertions,
//! deletions, substitutions and swaps of two neighbours) of the names in lower case, taken twice: once
//! on the names with the characters a reader confuses folded together (`1`, `l`, `i`, `|` and `0`, `o`),
//! once as written. A name is suggested when it is within a third of the unknown name's length (at least
//! one edit, but never all of it: any one-letter name is one edit from any other); of those, only the ones at the smallest distance are given, at most [`MAX`], in order of
//! the names, so the same input gives the same words.
//!
//! ```
//! use codegen::model::suggest::{closest, did_you_mean};
//! let plant = ["sb1", "sf1", "sl1", "sr1"];
//! assert_eq!(closest("s11", plant), ["sl1"]);
//! assert_eq!(did_you_mean("s11", plant), " (did you mean 'sl1'?)");
//! assert_eq!(did_you_mean("conveyor", plant), "");
//! ```

/// At most this many names are suggested.
pub const MAX: usize = 3;

/// `name` in lower case with the characters a reader confuses folded to one each.
fn folded(name: &str) -> String {
    name.chars()
        .flat_map(char::to_lowercase)
        .map(|c| match c {
            '1' | 'l' | 'i' | '|' => '1',
            'o' => '0',
            c => c,
        })
        .collect()
}

/// How far `candidate` is from `name`: (distance with confusable characters folded, distance in lower
/// case); smaller is closer.
fn distance(name: &str, candidate: &str) -> (usize, usize) {
    (
        strsim::osa_distance(&folded(name), &folded(candidate)),
        strsim::osa_distance(&name.to_lowercase(), &candidate.to_lowercase()),
    )
}

/// The names of `known` closest in spelling to `name`, at most [`MAX`], sorted; empty when none is
/// close enough (see the module documentation). `name` itself, if known, is not suggested.
pub fn closest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let length = name.chars().count();
    let limit = (length / 3).max(1);
    let mut near: Vec<((usize, usize), &str)> = known
        .into_iter()
        .filter(|k| *k != name)
        .map(|k| (distance(name, k), k))
        .filter(|((folded, plain), _)| *folded == 0 || (*plain <= limit && *plain < length))
        .collect();
    near.sort_unstable();
    near.dedup_by_key(|(_, k)| *k);
    let Some(&(best, _)) = near.first() else { return Vec::new() };
    near.into_iter().take_while(|(d, _)| *d == best).take(MAX).map(|(_, k)| k).collect()
}

/// The suggestion as the tail of an error message: ` (did you mean 'a'?)`, ` (did you mean 'a' or
/// 'b'?)`, or the empty string when no known name is close.
pub fn did_you_mean<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> String {
    let names: Vec<String> = closest(name, known).iter().map(|k| format!("'{k}'")).collect();
    match names.as_slice() {
        [] => String::new(),
        [one] => format!(" (did you mean {one}?)"),
        [init @ .., last] => format!(" (did you mean {} or {last}?)", init.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STATION: &[&str] =
        &["af", "sb1", "sb0", "sf1", "sf0", "al", "ar", "sl1", "sr1", "ag1", "ag0", "sg"];

    fn station() -> impl Iterator<Item = &'static str> {
        STATION.iter().copied()
    }

    #[test]
    fn a_confusable_character_wins_over_an_edit_of_another_letter() {
        // `s11` is one substitution from `sb1`, `sf1`, `sl1` and `sr1`; only `sl1` is a misreading.
        assert_eq!(closest("s11", station()), ["sl1"]);
        assert_eq!(closest("sbO", station()), ["sb0"]);
        assert_eq!(closest("SL1", station()), ["sl1"]);
    }

    #[test]
    fn several_equally_close_names_are_all_given_in_order() {
        assert_eq!(closest("sx1", station()), ["sb1", "sf1", "sl1"]);
        assert_eq!(did_you_mean("sx1", station()), " (did you mean 'sb1', 'sf1' or 'sl1'?)");
        assert_eq!(did_you_mean("agl", station()), " (did you mean 'ag1'?)");
        assert_eq!(did_you_mean("asg", ["sg", "ag"]), " (did you mean 'ag' or 'sg'?)");
    }

    #[test]
    fn a_swap_of_neighbours_is_one_edit() {
        assert_eq!(closest("fa", station()), ["af"]);
        assert_eq!(closest("conveyor_stop", ["conveyor_stpo", "conveyor_start"]), ["conveyor_stpo"]);
    }

    #[test]
    fn far_names_and_the_name_itself_are_not_suggested() {
        assert!(closest("conveyor", station()).is_empty());
        assert!(closest("sl1", ["sl1"]).is_empty());
        assert!(closest("", station()).is_empty());
        assert!(closest("f", ["a", "b"]).is_empty(), "a one-letter name is one edit from any other");
        assert_eq!(closest("I", ["l", "b"]), ["l"]);
        assert_eq!(did_you_mean("emergency_stop", station()), "");
    }

    #[test]
    fn the_limit_grows_with_the_length() {
        // Two edits are close for a long name, not for a short one.
        assert_eq!(closest("start_belt", ["start_bolts"]), ["start_bolts"]);
        assert!(closest("abc", ["axy"]).is_empty());
    }
}
