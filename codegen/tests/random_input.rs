//! The readers' contract ([`check_reader`], [`check_pnml`] for nets) under random and mutated input, on
//! the stable toolchain. (`fuzz/` runs the same checks under libFuzzer on nightly.)

use std::path::Path;

use codegen::formats::check_reader;
use codegen::net::check_pnml;
use proptest::prelude::*;

const SEEDS: [(&str, &[u8]); 4] = [
    ("seed.xmd", include_bytes!("../../examples/cell/published/S1.xmd")),
    ("seed.ADS", include_bytes!("data/TEST.ADS")),
    ("seed.gen", include_bytes!("data/plant1.gen")),
    ("seed.wmod", include_bytes!("data/kyllercg_digit_sequence_detector.wmod")),
];

/// A net the PNML reader reads.
const PNML_SEED: &[u8] = include_bytes!("../../examples/station-rtpn/net3.pnml");

/// A seed file with a few random edits: bytes replaced, inserted or deleted, or the tail cut off.
fn mutated() -> impl Strategy<Value = (&'static str, Vec<u8>)> {
    mutated_from(SEEDS.to_vec())
}

/// One of `seeds` with a few random edits.
fn mutated_from(seeds: Vec<(&'static str, &'static [u8])>) -> impl Strategy<Value = (&'static str, Vec<u8>)> {
    let edits = prop::collection::vec((0u8..4, any::<prop::sample::Index>(), any::<u8>()), 1..8);
    (prop::sample::select(seeds), edits).prop_map(|((name, text), edits)| {
        let mut bytes = text.to_vec();
        for (op, at, byte) in edits {
            let i = at.index(bytes.len().max(1));
            match op {
                0 if !bytes.is_empty() => bytes[i] = byte,
                1 => bytes.insert(i.min(bytes.len()), byte),
                2 if !bytes.is_empty() => {
                    bytes.remove(i);
                }
                _ => bytes.truncate(i),
            }
        }
        (name, bytes)
    })
}

/// Bytes made mostly of the format's own punctuation, so that random input reaches past the first token.
fn soup() -> impl Strategy<Value = Vec<u8>> {
    let pieces = prop::sample::select(vec![
        "<",
        ">",
        "/",
        "\"",
        "=",
        " ",
        "\n",
        "%",
        "+C+",
        "#",
        "1",
        "0",
        "99999999999999999999",
        "a",
        "<Generator>",
        "</Generator>",
        "<States>",
        "</States>",
        "<TransRel>",
        "</TransRel>",
        "<Alphabet>",
        "</Alphabet>",
        "<Consecutive>",
        "</Consecutive>",
        "<InitStates>",
        "</InitStates>",
        "State size",
        "Marker states:",
        "Transitions:",
        "*",
        "\u{e9}",
        "\u{ff}",
    ]);
    prop::collection::vec(pieces, 0..60).prop_map(|p| p.concat().into_bytes())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn mutated_model_files_keep_the_contract((name, bytes) in mutated()) {
        check_reader(Path::new(name), &bytes);
    }

    #[test]
    fn random_bytes_keep_the_contract(bytes in prop::collection::vec(any::<u8>(), 0..256), ext in 0usize..4) {
        check_reader(Path::new(SEEDS[ext].0), &bytes);
    }

    #[test]
    fn token_soup_keeps_the_contract(bytes in soup(), ext in 0usize..4) {
        check_reader(Path::new(SEEDS[ext].0), &bytes);
    }
}

/// Bytes made of PNML's elements and attributes, so that random input reaches the net's structure.
fn pnml_soup() -> impl Strategy<Value = Vec<u8>> {
    let pieces = prop::sample::select(vec![
        "<pnml>",
        "</pnml>",
        "<net id=\"n\" type=\"P/T net\">",
        "</net>",
        "<page id=\"g\">",
        "</page>",
        "<place id=\"p\">",
        "<place id=\"q\"/>",
        "</place>",
        "<transition id=\"t\"/>",
        "<arc id=\"a\" source=\"p\" target=\"t\">",
        "<arc id=\"b\" source=\"t\" target=\"q\"/>",
        "</arc>",
        "<initialMarking><text>",
        "<inscription><value>Default,",
        "</value></inscription>",
        "</text></initialMarking>",
        "<type value=\"inhibitor\"/>",
        "1",
        "0",
        "99999999999",
        " ",
        "\n",
    ]);
    prop::collection::vec(pieces, 0..40).prop_map(|p| p.concat().into_bytes())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    #[test]
    fn mutated_nets_keep_the_contract((name, bytes) in mutated_from(vec![("seed.pnml", PNML_SEED)])) {
        check_pnml(Path::new(name), &bytes);
    }

    #[test]
    fn pnml_soup_keeps_the_contract(bytes in pnml_soup()) {
        check_pnml(Path::new("soup.pnml"), &bytes);
    }
}
