//! The readers' contract as one executable check, shared by the fuzz targets (`fuzz/`) and the
//! stable-toolchain random-input tests.

use std::path::Path;

use super::{ads, detect, gen, read_bytes, wmod, xmd, xml, Format};

/// Reads `bytes` as the file `path` and panics if a reader broke its contract.
///
/// The contract: no input panics; whatever reads is valid ([`Automaton::validate`]) and canonical
/// (sorted, deduplicated transitions); and writing it back in the same format and reading that gives
/// the same automata. Errors are fine: the point is that nothing else happens.
///
/// [`Automaton::validate`]: crate::model::Automaton::validate
pub fn check_reader(path: &Path, bytes: &[u8]) {
    let Ok(automata) = read_bytes(path, bytes) else { return };
    for a in &automata {
        assert_eq!(a.validate(), Ok(()), "reader output must be valid");
        let mut sorted = a.clone();
        sorted.canonicalize();
        assert_eq!(&sorted, a, "reader output must be canonical");
    }
    let text = String::from_utf8_lossy(bytes);
    let Ok(format) = detect(path, &text) else { return };
    for a in &automata {
        let back = match format {
            Format::Xmd if xml::check_names(a).is_ok() => xmd::read(path, &xmd::write(a)),
            Format::Gen if gen::check(a).is_ok() => gen::read(path, &gen::write(a)),
            Format::Ads => {
                let Ok(files) = ads::write(a) else { continue };
                let map = files.event_map.as_deref().map(|m| (Path::new("fuzz.events"), m));
                ads::read(path, &files.ads, map)
            }
            Format::Wmod if xml::check_names(a).is_ok() => {
                let module =
                    wmod::write("m", std::slice::from_ref(a)).expect("one automaton always makes a module");
                let mut back = wmod::read(path, &module).expect("written module reads back");
                assert_eq!(back.len(), 1, "a module of one automaton reads back as one");
                Ok(back.remove(0))
            }
            _ => continue,
        };
        assert_eq!(
            &back.expect("written automaton reads back"),
            a,
            "write then read must give the automaton back"
        );
    }
}
