//! Cost of the runtime on the emitted tables, for the table in docs/measurements.md: SysTick ticks per
//! uncontrollable event applied and per controllable decision (enabled set, choice, firing), on supervisor
//! tables or on state tables (`mode = "state"`: the same names, `firmware::state`'s runtime), under
//! `qemu-system-arm -icount shift=7,sleep=off` (`cargo qemu-cost`), where virtual time is exact and
//! repeatable: one instruction is 128 ns and one SysTick tick 1/12 µs, so instructions ≈ ticks × 83.33 / 128;
//! the binary calibrates the ratio on a loop of exactly 2 000 instructions and converts with it.
//!
//! A plant runs inside the firmware: at each step, when an uncontrollable event is possible (every
//! automaton holding it has the transition; on state tables, it leaves a component's state as the word
//! reads), it is produced with probability ½; otherwise the runtime
//! decides. A decision is also timed in parts: the enabled set alone, then the whole `decide` (which
//! computes the enabled set again, chooses, checks the guard and fires).
//! Prints plain text over semihosting and exits.
#![no_std]
#![no_main]

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use defmt_semihosting as _;
use lm3s6965 as _;
use panic_semihosting as _;

/// The emitted tables.
#[allow(dead_code)]
mod tables {
    include!(env!("SCT_TABLES_FILE"));
}

use firmware::choice::Choose;
use firmware::event_set::EventSet;
use firmware::rng::{Entropy, Rng, SeedEntropy};
use firmware::runtime::{Decide, Decision, Runtime};
use firmware::state::StateRuntime;
use firmware::table::Position;

type Rt = tables::Runtime<tables::Policy, SeedEntropy>;

/// Steps of the run.
const STEPS: u32 = 20_000;

/// Running statistics of one measured operation, in SysTick ticks.
#[derive(Default)]
struct Stat {
    n: u32,
    sum: u64,
    max: u32,
}

impl Stat {
    fn add(&mut self, ticks: u32) {
        self.n += 1;
        self.sum += u64::from(ticks);
        self.max = self.max.max(ticks);
    }

    /// Prints the statistics; `per_2000` is the measured ticks of 2 000 instructions.
    fn print(&self, what: &str, overhead: u32, per_2000: u32) {
        let avg = if self.n == 0 { 0 } else { (self.sum / u64::from(self.n)) as u32 };
        let avg = avg.saturating_sub(overhead);
        let max = self.max.saturating_sub(overhead);
        hprintln!(
            "{}: n={} avg={} ticks (~{} instructions) max={} ticks (~{} instructions)",
            what,
            self.n,
            avg,
            avg * 2000 / per_2000.max(1),
            max,
            max * 2000 / per_2000.max(1)
        );
    }
}

/// Ticks elapsed between two readings of the down-counting 24-bit SysTick.
fn elapsed(t0: u32, t1: u32) -> u32 {
    t0.wrapping_sub(t1) & 0x00FF_FFFF
}

/// What the plant inside the firmware may send next, read off the decider's own tables.
trait Plant {
    /// The uncontrollable events possible now.
    fn possible_inputs(&self) -> EventSet<{ tables::EVENT_WORDS }>;
}

/// Supervisor tables: the events every automaton holding them can take now.
impl<
        P: Choose<{ tables::EVENT_WORDS }>,
        E: Entropy,
        const N: usize,
        const WIDE: bool,
        const MASK: usize,
        const LAYOUT: u8,
        Q: Position,
    > Plant for Runtime<'_, P, E, { tables::EVENT_WORDS }, N, WIDE, MASK, LAYOUT, Q>
{
    #[inline(never)]
    fn possible_inputs(&self) -> EventSet<{ tables::EVENT_WORDS }> {
        let set = self.set();
        let mut out = EventSet::EMPTY;
        for e in 0..set.events() {
            let Ok(e) = u8::try_from(e) else { break };
            let holders = set.holders_of(e, set.holder_bytes()).unwrap_or(0);
            let takes = |a: usize| set.step(a, self.states()[a], e).is_some();
            let held = (0..set.automata.len()).filter(|a| holders & (1 << a) != 0);
            if !firmware::table::bit(&set.controllable, e) && held.into_iter().all(takes) {
                out.insert(e);
            }
        }
        out
    }
}

/// State tables (`mode = "state"`): the sensor events leaving each component's state as the word reads.
impl<P: Choose<{ tables::EVENT_WORDS }>, E: Entropy, const C: usize> Plant
    for StateRuntime<'_, P, E, { tables::EVENT_WORDS }, C>
{
    #[inline(never)]
    fn possible_inputs(&self) -> EventSet<{ tables::EVENT_WORDS }> {
        let t = self.tables();
        let mut out = EventSet::EMPTY;
        for c in 0..C {
            if let Some(r) = t.reading(c, self.word()) {
                out = out.or(&EventSet(r.leaving));
            }
        }
        out.and_not(&EventSet(t.controllable))
    }
}

// The measured calls sit behind `#[inline(never)]`: otherwise the optimiser may move parts of the inlined
// computation across the volatile SysTick reads, which order only other volatile accesses.

#[inline(never)]
fn measured_apply(rt: &mut Rt, u: u8) {
    Decide::apply(rt, u);
}

#[inline(never)]
fn measured_enabled(rt: &Rt) -> EventSet<{ tables::EVENT_WORDS }> {
    rt.enabled()
}

#[inline(never)]
fn measured_decide(rt: &mut Rt) -> Decision {
    Decide::decide(rt, || false)
}

#[entry]
fn main() -> ! {
    let mut cp = cortex_m::Peripherals::take().unwrap_or_else(|| stop(1));
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
    let now = || cortex_m::peripheral::SYST::get_current();

    let mut rt =
        Rt::new(tables::CHECKED, tables::CONFIG, tables::Policy::default(), SeedEntropy::new(tables::SEED));
    let mut plant = Rng::new(SeedEntropy::new(0x5EED), 0);
    let (mut empty, mut inputs, mut fired, mut idle) =
        (Stat::default(), Stat::default(), Stat::default(), Stat::default());
    let mut enabled_only = Stat::default();
    for _ in 0..STEPS {
        let t0 = now();
        let t1 = now();
        empty.add(elapsed(t0, t1));
        let possible = rt.possible_inputs();
        if !possible.is_empty() && plant.below(2) == 0 {
            let u = possible.nth(plant.below(possible.len())).unwrap_or(0);
            let t0 = now();
            measured_apply(&mut rt, u);
            let t1 = now();
            inputs.add(elapsed(t0, t1));
            continue;
        }
        let t0 = now();
        let enabled = measured_enabled(&rt);
        let t1 = now();
        let t2 = now();
        let d = measured_decide(&mut rt);
        let t3 = now();
        match d {
            Decision::Fired(_) => {
                enabled_only.add(elapsed(t0, t1));
                fired.add(elapsed(t2, t3));
            }
            _ => idle.add(elapsed(t2, t3)),
        }
        core::hint::black_box(enabled);
    }
    let overhead = (empty.sum / u64::from(empty.n.max(1))) as u32;
    // Calibration: a loop of exactly 2 000 instructions (1 000 × subs + bne).
    let t0 = now();
    // SAFETY: a register-only countdown loop; it touches no memory and no flags anyone relies on.
    unsafe { core::arch::asm!("2:", "subs {0}, #1", "bne 2b", inout(reg) 1000u32 => _) };
    let t1 = now();
    let per_2000 = elapsed(t0, t1).saturating_sub(overhead);
    hprintln!("calibration: 2000 instructions = {} ticks", per_2000);
    hprintln!("{}: {} steps, measurement overhead {} ticks subtracted", tables::NAME, STEPS, overhead);
    inputs.print("uncontrollable event (apply)", overhead, per_2000);
    fired.print("controllable decision (enabled + choose + guard + fire)", overhead, per_2000);
    enabled_only.print("  enabled set alone", overhead, per_2000);
    idle.print("decision with nothing enabled", overhead, per_2000);
    let c = rt.counters();
    hprintln!("events in {}, commands out {}, unexpected {}", c.events_in, c.commands_out, c.unexpected);
    stop(if c.unexpected == 0 { 0 } else { 1 })
}

fn stop(status: u8) -> ! {
    debug::exit(if status == 0 { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    loop {
        cortex_m::asm::wfi();
    }
}
