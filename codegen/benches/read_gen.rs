//! Reading a large libFAUDES `.gen` file: 100 000 states and 1 000 000 transitions must read (tokenize,
//! resolve names, check determinism, sort) well under a second.
//!
//! Two spellings of the same automaton: states by quoted name (`"q17" "ev3" "q42"`, the slow case:
//! every reference is a name lookup) and anonymous states by index (`<Consecutive> 1 100000
//! </Consecutive>` and `17 "ev3" 42`, what libFAUDES itself writes for unnamed states).

use std::fmt::Write as _;
use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};

const STATES: u64 = 100_000;
const EVENTS: u64 = 10;

/// A generator where every state has one transition per event to a pseudo-random target (so the
/// automaton is deterministic with STATES * EVENTS transitions) and every tenth state is marked.
/// `state` spells a state reference.
fn big_gen(state: fn(u64) -> String, declare: &str) -> String {
    let mut out = String::with_capacity(32 << 20);
    out.push_str("<Generator>\n\"big\"\n<Alphabet>\n");
    for e in 0..EVENTS {
        let _ = writeln!(out, "\"ev{e}\"{}", if e % 2 == 0 { " +C+" } else { "" });
    }
    let _ = writeln!(out, "</Alphabet>\n<States>\n{declare}</States>\n<TransRel>");
    let mut x: u64 = 0x2545_F491_4F6C_DD1D;
    for s in 1..=STATES {
        for e in 0..EVENTS {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let _ = writeln!(out, "{} \"ev{e}\" {}", state(s), state(1 + x % STATES));
        }
    }
    let _ = writeln!(out, "</TransRel>\n<InitStates>\n{}\n</InitStates>\n<MarkedStates>", state(1));
    for s in (1..=STATES).step_by(10) {
        let _ = writeln!(out, "{}", state(s));
    }
    out.push_str("</MarkedStates>\n</Generator>\n");
    out
}

fn read_gen(c: &mut Criterion) {
    let names: String = (1..=STATES).map(|s| format!("\"q{s}\"\n")).collect();
    let by_name = big_gen(|s| format!("\"q{s}\""), &names);
    let by_index = big_gen(|s| s.to_string(), &format!("<Consecutive> 1 {STATES} </Consecutive>\n"));
    let mut group = c.benchmark_group("read_gen");
    group.sample_size(10);
    for (label, text) in [("by_name", &by_name), ("by_index", &by_index)] {
        let a = codegen::formats::gen::read(Path::new("big.gen"), text).expect("the generated file reads");
        assert_eq!((a.states.len(), a.transitions.len()), (STATES as usize, (STATES * EVENTS) as usize));
        group.throughput(Throughput::Bytes(text.len() as u64));
        group.bench_function(format!("100k_states_1M_transitions_{label}"), |b| {
            b.iter(|| codegen::formats::gen::read(Path::new("big.gen"), black_box(text)).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, read_gen);
criterion_main!(benches);
