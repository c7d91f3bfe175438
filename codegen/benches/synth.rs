//! Synthesis speed on the generated families (see `codegen::synth::families`) and on the cell.
//!
//! `cargo bench -p codegen --bench synth`; `scripts/reference/timing.py` times the same instances with
//! libFAUDES and TCT for the side-by-side table in docs/measurements.md.

use std::path::PathBuf;

use codegen::formats::read_path;
use codegen::model::Automaton;
use codegen::synth::{self, families, Config};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

fn monolithic(c: &mut Criterion) {
    let cfg = Config::default();
    let mut group = c.benchmark_group("monolithic");
    group.sample_size(10);
    for (family, sizes) in [
        ("factory", &[4, 5, 6][..]),
        ("transfer-line", &[8, 10][..]),
        ("philosophers", &[5, 6][..]),
        ("random", &[4, 5][..]),
    ] {
        for &n in sizes {
            let inst = families::generate(family, n).expect("known family");
            group.bench_with_input(BenchmarkId::new(family, n), &inst, |b, inst| {
                b.iter(|| synth::monolithic(&inst.plants, &inst.specs, &cfg).expect("synthesis"))
            });
        }
    }
    group.finish();
}

fn local_modular(c: &mut Criterion) {
    let cfg = Config { merge_conflicting: false, ..Config::default() };
    let mut group = c.benchmark_group("local_modular_conflict_check");
    group.sample_size(10);
    for n in [2, 3, 4] {
        let inst = families::generate("cat-mouse", n).expect("known family");
        group.bench_with_input(BenchmarkId::new("cat-mouse", n), &inst, |b, inst| {
            b.iter(|| synth::local_modular(&inst.plants, &inst.specs, &cfg).expect("synthesis"))
        });
    }
    let cell = |dir: &str, names: &[&str]| -> Vec<Automaton> {
        names
            .iter()
            .map(|n| {
                let p: PathBuf =
                    [env!("CARGO_MANIFEST_DIR"), "..", "examples", "cell", dir, &format!("{n}.xmd")]
                        .iter()
                        .collect();
                read_path(&p).expect("cell model").remove(0)
            })
            .collect()
    };
    let plants = cell("plants", &["G1", "G2", "G3", "G4"]);
    let specs = cell("specs", &["E1", "E2", "E3", "E4", "E5", "E6", "E7"]);
    let merge = Config::default();
    group.bench_function("cell (with merge)", |b| {
        b.iter(|| synth::local_modular(&plants, &specs, &merge).expect("synthesis"))
    });
    group.finish();
}

criterion_group!(benches, monolithic, local_modular);
criterion_main!(benches);
