//! The size report: every layout's bytes per automaton and in total, the floor, and the paper's columns.
//!
//! Two scopes are measured. *All* is what the firmware holds: plants and supervisors. *Supervisors* is what
//! the reference paper counted, over the same event numbering; it is where the paper's 2347 bytes for the
//! manufacturing cell are reproduced and the denser layouts are compared with it.

use std::fmt::{self, Write as _};

use serde_json::{json, Value};

use super::fit::{self, Core};
use super::{floor, paper::Columns, Layout, PackSet, Role, Size};
use crate::config::RuntimeConfig;

/// The paper's columns for one approach (local modular, modular, monolithic), or why they are missing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comparison {
    /// Approach name, e.g. `local modular`.
    pub approach: String,
    /// Its counts, or the reason they could not be had (e.g. a synthesis that exceeded a limit).
    pub columns: Result<Columns, String>,
}

/// One layout measured on both scopes; a layout that refuses the set keeps its error message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Measured {
    /// The layout.
    pub layout: Layout,
    /// Plants and supervisors.
    pub all: Result<Size, String>,
    /// Supervisors only, same events.
    pub supervisors: Result<Size, String>,
}

/// Everything `codegen pack` prints.
#[derive(Clone, Debug)]
pub struct Report {
    set: PackSet,
    measured: Vec<Measured>,
    comparisons: Vec<Comparison>,
    /// Per core (Cortex-M3, Cortex-M0+): the layout its firmware runs, or why none does.
    runs: Vec<(Core, Result<Layout, String>)>,
}

impl Report {
    /// Measures `layouts` on `set`. `comparisons` are the paper's columns for other supervisor sets of the
    /// same problem (modular, monolithic); the set's own supervisors come first as `local modular`.
    pub fn new(set: PackSet, layouts: &[Layout], comparisons: Vec<Comparison>) -> Report {
        let sups = set.only(Role::Supervisor);
        let measured = layouts
            .iter()
            .map(|&layout| Measured {
                layout,
                all: layout.size(&set).map_err(|e| e.to_string()),
                supervisors: layout.size(&sups).map_err(|e| e.to_string()),
            })
            .collect();
        let own = Comparison {
            approach: "local modular".to_owned(),
            columns: Ok(Columns::of(sups.members().iter().map(|m| &m.automaton), set.events().len())),
        };
        let report =
            Report { set, measured, comparisons: [vec![own], comparisons].concat(), runs: Vec::new() };
        report.with_runtime(&RuntimeConfig::default())
    }

    /// The report marking the layouts the firmware runs under `runtime` (its `layout`, else the
    /// defaults, [`fit::choose`]) on each core, within its board's flash; [`Report::new`] marks the
    /// defaults.
    pub fn with_runtime(self, runtime: &RuntimeConfig) -> Report {
        let runs = Core::ALL
            .into_iter()
            .map(|core| {
                let chosen = fit::choose(&self.set, runtime, core, Some(&core.flash()));
                (core, chosen.map(|f| f.layout).map_err(|refusal| refusal.to_string()))
            })
            .collect();
        Report { runs, ..self }
    }

    /// The cores (`cortex-m3`, `cortex-m0+`) whose firmware runs `layout`: the layout they choose, and
    /// its tables fit their board's flash.
    pub fn cores_running(&self, layout: Layout) -> Vec<&'static str> {
        self.runs.iter().filter(|(_, run)| *run == Ok(layout)).map(|(core, _)| core.name()).collect()
    }

    /// The boards whose flash holds `layout`'s tables of the whole set (what the size says).
    pub fn boards_holding(&self, layout: Layout) -> Vec<&'static str> {
        let Some(Ok(size)) = self.measured.iter().find(|m| m.layout == layout).map(|m| &m.all) else {
            return Vec::new();
        };
        let controllability = size.side_tables.iter().find(|t| t.0 == "controllability").map_or(0, |t| t.1);
        // The image's sections: what the firmware's flash holds.
        let bytes = size.total() - controllability + size.shared_bytes();
        Core::ALL
            .into_iter()
            .map(|core| core.flash())
            .filter(|flash| bytes <= flash.for_tables())
            .map(|flash| flash.board)
            .collect()
    }

    /// The layouts as measured.
    pub fn measured(&self) -> &[Measured] {
        &self.measured
    }

    /// The floor of every automaton of the set, in bytes.
    pub fn floor_bytes(&self) -> usize {
        self.set.members().iter().map(floor::bytes).sum()
    }

    /// The floor of the supervisors only.
    pub fn supervisor_floor_bytes(&self) -> usize {
        self.set.members().iter().filter(|m| m.role == Role::Supervisor).map(floor::bytes).sum()
    }

    /// The paper's columns, the set's own supervisors first.
    pub fn comparisons(&self) -> &[Comparison] {
        &self.comparisons
    }

    /// The report as JSON (schema 1): `layouts` (each `name`, `bytes`, `per_automaton`, `side_tables`,
    /// `shared_tables` (the runtime's, every layout alike), `supervisor_bytes`, `runs_on`: the cores
    /// whose firmware runs it, `fits`: the boards whose flash holds it), `cores` (each `core`, `board`
    /// and the `layout` it runs or why it is `refused`), `floor_bytes`, `paper` (the set's own
    /// supervisors: `matrix`, `chained_list`, `memory_safe`), `comparisons` (every approach) and
    /// `automata`.
    pub fn to_json(&self) -> Value {
        let size_json = |s: &Result<Size, String>| match s {
            Ok(s) => json!(s.total()),
            Err(_) => Value::Null,
        };
        let layouts: Vec<Value> = self
            .measured
            .iter()
            .map(|m| {
                let mut v = json!({
                    "name": m.layout.name(),
                    "bytes": size_json(&m.all),
                    "supervisor_bytes": size_json(&m.supervisors),
                    "runs_on": self.cores_running(m.layout),
                    "fits": self.boards_holding(m.layout),
                });
                match &m.all {
                    Ok(size) => {
                        v["blocks"] = json!(size.blocks());
                        v["per_automaton"] = size
                            .per_automaton
                            .iter()
                            .map(|(name, bytes)| json!({"name": name, "bytes": bytes}))
                            .collect();
                        let named = |tables: &[(&str, usize)]| -> Value {
                            tables.iter().map(|(name, bytes)| json!({"name": name, "bytes": bytes})).collect()
                        };
                        v["side_tables"] = named(&size.side_tables);
                        v["shared_tables"] = named(&size.shared);
                    }
                    Err(e) => v["error"] = json!(e),
                }
                v
            })
            .collect();
        let columns_json = |c: &Columns| {
            json!({
                "states": c.states,
                "transitions": c.transitions,
                "events": c.events,
                "matrix": c.matrix(),
                "chained_list": c.chained_list(),
                "memory_safe": c.memory_safe(),
            })
        };
        let comparisons: Vec<Value> = self
            .comparisons
            .iter()
            .map(|c| match &c.columns {
                Ok(cols) => {
                    let mut v = columns_json(cols);
                    v["approach"] = json!(c.approach);
                    v
                }
                Err(why) => json!({"approach": c.approach, "missing": why}),
            })
            .collect();
        let automata: Vec<Value> = self
            .set
            .members()
            .iter()
            .map(|m| {
                json!({
                    "name": m.name(),
                    "role": m.role.as_str(),
                    "states": m.state_count(),
                    "transitions": m.transition_count(),
                    "alphabet": m.dfa.alphabet().len(),
                    "floor_bytes": floor::bytes(m),
                })
            })
            .collect();
        let paper = match &self.comparisons[0].columns {
            Ok(c) => columns_json(c),
            Err(_) => Value::Null,
        };
        let cores: Vec<Value> = self
            .runs
            .iter()
            .map(|(core, run)| match run {
                Ok(layout) => {
                    json!({"core": core.name(), "board": core.flash().board, "layout": layout.name()})
                }
                Err(why) => json!({"core": core.name(), "board": core.flash().board, "refused": why}),
            })
            .collect();
        json!({
            "schema": 1,
            "events": self.set.events().len(),
            "cores": cores,
            "automata": automata,
            "layouts": layouts,
            "floor_bytes": self.floor_bytes(),
            "supervisor_floor_bytes": self.supervisor_floor_bytes(),
            "paper": paper,
            "comparisons": comparisons,
        })
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let events = self.set.events();
        let controllable = events.ids().filter(|&e| events.is_controllable(e)).count();
        writeln!(
            f,
            "{} automata, {} events ({} controllable)",
            self.set.members().len(),
            events.len(),
            controllable
        )?;
        writeln!(f)?;
        let mut head = format!(
            "{:<12} {:<10} {:>6} {:>6} {:>5} {:>6}",
            "automaton", "role", "states", "trans", "alph", "floor"
        );
        for m in &self.measured {
            write!(head, " {:>11}", m.layout.name())?;
        }
        writeln!(f, "{head}")?;
        for (i, member) in self.set.members().iter().enumerate() {
            let mut line = format!(
                "{:<12} {:<10} {:>6} {:>6} {:>5} {:>6}",
                member.name(),
                member.role.as_str(),
                member.state_count(),
                member.transition_count(),
                member.dfa.alphabet().len(),
                floor::bytes(member)
            );
            for m in &self.measured {
                match &m.all {
                    Ok(size) => write!(line, " {:>11}", size.per_automaton[i].1)?,
                    Err(_) => write!(line, " {:>11}", "-")?,
                }
            }
            writeln!(f, "{line}")?;
        }
        for (label, floor, pick) in [
            ("all", self.floor_bytes(), (|m: &Measured| &m.all) as fn(&Measured) -> &Result<Size, String>),
            ("supervisors", self.supervisor_floor_bytes(), |m: &Measured| &m.supervisors),
        ] {
            writeln!(f)?;
            writeln!(f, "{label}: floor {floor} bytes")?;
            for m in &self.measured {
                match pick(m) {
                    Ok(size) => {
                        let side: Vec<String> =
                            size.side_tables.iter().map(|(n, b)| format!("{n} {b}")).collect();
                        let ratio = if floor > 0 { size.total() as f64 / floor as f64 } else { 0.0 };
                        let runs: Vec<String> = self
                            .runs
                            .iter()
                            .filter(|(_, run)| *run == Ok(m.layout))
                            .map(|(core, _)| format!("{} ({})", core.name(), core.flash().board))
                            .collect();
                        let runs = if runs.is_empty() || label != "all" {
                            String::new()
                        } else {
                            format!("  ← runs on {}", runs.join(", "))
                        };
                        writeln!(
                            f,
                            "  {:<11} {:>7} bytes = blocks {} + side tables {} ({}); {:.2}× floor{runs}",
                            m.layout.name(),
                            size.total(),
                            size.blocks(),
                            size.side(),
                            side.join(", "),
                            ratio
                        )?;
                    }
                    Err(e) => writeln!(f, "  {:<11} refused: {e}", m.layout.name())?,
                }
            }
            if let Some(size) = self.measured.iter().find_map(|m| pick(m).as_ref().ok()) {
                let shared: Vec<String> = size.shared.iter().map(|(n, b)| format!("{n} {b}")).collect();
                writeln!(
                    f,
                    "  every layout adds the runtime's side tables: {} bytes ({})",
                    size.shared_bytes(),
                    shared.join(", ")
                )?;
            }
        }
        for (core, run) in &self.runs {
            if let Err(why) = run {
                writeln!(f, "  {} ({}) runs none: {why}", core.name(), core.flash().board)?;
            }
        }
        if let Some(Ok(ms)) =
            self.measured.iter().find(|m| m.layout == Layout::MemorySafe).map(|m| &m.supervisors)
        {
            // The reference tool's controllability vector: a byte per event.
            let controllability = events.len();
            writeln!(
                f,
                "  memory-safe transition vector {} + controllability vector {} = {} bytes (the paper's column)",
                ms.blocks(),
                controllability,
                ms.blocks() + controllability
            )?;
        }
        writeln!(f)?;
        writeln!(f, "paper's columns (supervisors; e = {}):", events.len())?;
        writeln!(
            f,
            "  {:<14} {:>6} {:>6} {:>10} {:>13} {:>12}",
            "approach", "states", "trans", "matrix", "chained list", "memory safe"
        )?;
        for c in &self.comparisons {
            match &c.columns {
                Ok(cols) => writeln!(
                    f,
                    "  {:<14} {:>6} {:>6} {:>10} {:>13} {:>12}",
                    c.approach,
                    cols.states,
                    cols.transitions,
                    cols.matrix(),
                    cols.chained_list(),
                    cols.memory_safe()
                )?,
                Err(why) => writeln!(f, "  {:<14} missing: {why}", c.approach)?,
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::testing::toggle;

    #[test]
    fn memory_safe_supervisors_match_the_paper_formula() {
        let set = PackSet::new(vec![toggle("G")], vec![toggle("S1"), toggle("S2")]).unwrap();
        let report = Report::new(set, &Layout::ALL, vec![]);
        let ms = &report.measured()[0];
        let sups = ms.supervisors.as_ref().unwrap();
        let paper = report.comparisons()[0].columns.as_ref().unwrap();
        // Blocks plus a byte per event: the paper's memory-safe figure.
        assert_eq!(sups.blocks() + report.set.events().len(), paper.memory_safe());
        assert_eq!(paper.memory_safe(), 4 + 3 * 4 + 2);
        let json = report.to_json();
        assert_eq!(json["paper"]["memory_safe"], 18);
        assert_eq!(json["layouts"][0]["name"], "memory-safe");
        assert_eq!(json["layouts"][0]["per_automaton"][1]["bytes"], 8);
        assert!(report.to_string().contains("local modular"));
        // The defaults: ranked on the Cortex-M3, indexed on the Cortex-M0+; a manifest's layout on both.
        assert_eq!(json["layouts"][2]["runs_on"], json!(["cortex-m3"]));
        assert_eq!(json["layouts"][3]["runs_on"], json!(["cortex-m0+"]));
        assert_eq!(json["layouts"][0]["runs_on"], json!([]));
        assert_eq!(json["layouts"][0]["fits"], json!(["lm3s6965 (QEMU)", "RP2040 (Pico)"]));
        assert_eq!(json["cores"][1]["layout"], "indexed");
        assert!(report.to_string().contains("← runs on cortex-m3 (lm3s6965 (QEMU))"));
        let compact = RuntimeConfig { layout: Some(Layout::Compact), ..RuntimeConfig::default() };
        let report = report.with_runtime(&compact);
        assert_eq!(report.cores_running(Layout::Compact), ["cortex-m3", "cortex-m0+"]);
        assert!(report.cores_running(Layout::Ranked).is_empty());
    }
}
