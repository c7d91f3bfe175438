//! The choice section's policies in ST: which one enabled controllable event (`en[id]`) becomes `c`, the
//! same rules as `firmware::choice` over the same event ids, so that with the deterministic policies the
//! program and the firmware fire the same events.

use crate::config::ScanPolicy;
use crate::scan::ir::{Expr, Op, Stmt, Type, Var};

/// The MINSTD multiplier (Park & Miller), and Schrage's split of the modulus 2³¹ − 1 by it, so that the
/// step fits a DINT.
const MINSTD_A: i64 = 16_807;
const MINSTD_Q: i64 = 127_773;
const MINSTD_R: i64 = 2_836;
const MINSTD_M: i64 = 2_147_483_647;
// Schrage's conditions, checked at compile time: m = a·q + r, and both products stay below 2³¹ for any
// state below the modulus.
const _: () = assert!(
    MINSTD_A * MINSTD_Q + MINSTD_R == MINSTD_M
        && MINSTD_A * (MINSTD_Q - 1) < 1 << 31
        && MINSTD_R * (MINSTD_M / MINSTD_Q) < 1 << 31
);

/// The initial value of the generator for a manifest seed (1 ..= 2³¹ − 2).
pub fn minstd_seed(seed: u64) -> i64 {
    1 + i64::try_from(seed % (MINSTD_M as u64 - 1)).unwrap_or(0)
}

/// What the local queue needs to know of one plant: its generated controllable events (ascending ids)
/// and, per choice site of it, the predicate of being at that state and the site's index.
pub struct PlantChoice {
    /// Events the plant generates.
    pub events: Vec<i64>,
    /// `(at the site's state, site index)`.
    pub sites: Vec<(Expr, i64)>,
}

/// The array of enabled controllable events, by id (not `en`: `EN` is reserved, IEC 61131-3 Ed. 3
/// 6.6.1).
pub const ENABLED: &str = "enabled";

fn en(i: Expr) -> Expr {
    Expr::at(ENABLED, i)
}

fn c_is(e: i64) -> Stmt {
    Stmt::set("c", Expr::Int(e))
}

/// Every name the choice section uses: a program that holds it keeps them free.
pub const VARIABLES: [&str; 13] =
    [ENABLED, "c", "i", "j", "k", "n", "p", "pc", "gq", "sc", "site", "cur", "rng"];

/// The variables of the choice section over `count` candidates (indexed as `what` says) with `policy`:
/// the enabled array, `c` and `i`, and the policy's cursors (`sites` choice sites for the local queue) or
/// generator (seeded from `seed`).
pub fn locals(policy: ScanPolicy, count: usize, sites: usize, seed: u64, what: &str) -> Vec<Var> {
    let mut locals = vec![
        Var::new(ENABLED, Type::array(count as i64 - 1, Type::Bool), format!("enabled, by {what}")),
        Var::new("c", Type::Int, format!("chosen {what}, -1 none")),
        Var::new("i", Type::Int, ""),
    ];
    match policy {
        ScanPolicy::First => {}
        ScanPolicy::GlobalQueue => {
            locals.push(Var::new("j", Type::Int, ""));
            locals.push(Var::new("gq", Type::Int, format!("global cursor ({what})")));
        }
        ScanPolicy::LocalQueue => {
            locals.push(Var::new("p", Type::Int, "plant"));
            locals.push(Var::new("pc", Type::Int, "plant cursor"));
            locals.push(Var::new("cur", Type::Int, "site cursor in use"));
            if sites > 0 {
                locals.push(Var::new("site", Type::Int, "choice site, -1 none"));
                locals.push(Var::new(
                    "sc",
                    Type::array(sites as i64 - 1, Type::Int),
                    "cursor per choice site",
                ));
            }
        }
        ScanPolicy::Random => {
            locals.push(Var::new("n", Type::Int, "enabled count"));
            locals.push(Var::new("k", Type::Int, ""));
            locals.push(Var::new("rng", Type::Dint, "MINSTD state").init(Expr::Int(minstd_seed(seed))));
        }
    }
    locals
}

/// Statements setting `c` (already -1) to the chosen event of `en[0..events-1]`, by `policy`.
pub fn statements(policy: ScanPolicy, events: i64, plants: &[PlantChoice]) -> Vec<Stmt> {
    let last = events - 1;
    match policy {
        ScanPolicy::First => vec![Stmt::For(
            "i".into(),
            0,
            last,
            vec![Stmt::when(en(Expr::var("i")), vec![Stmt::set("c", Expr::var("i")), Stmt::Exit])],
        )],
        ScanPolicy::GlobalQueue => vec![Stmt::For(
            "i".into(),
            0,
            last,
            vec![
                Stmt::set("j", Expr::var("gq").op(Op::Add, Expr::var("i")).op(Op::Mod, Expr::Int(events))),
                Stmt::when(
                    en(Expr::var("j")),
                    vec![
                        Stmt::set("c", Expr::var("j")),
                        Stmt::set("gq", Expr::var("j").op(Op::Add, Expr::Int(1))),
                        Stmt::Exit,
                    ],
                ),
            ],
        )],
        ScanPolicy::Random => {
            let var = Expr::var;
            let step = var("rng")
                .op(Op::Mod, Expr::Int(MINSTD_Q))
                .op(Op::Mul, Expr::Int(MINSTD_A))
                .op(Op::Sub, var("rng").op(Op::Div, Expr::Int(MINSTD_Q)).op(Op::Mul, Expr::Int(MINSTD_R)));
            vec![
                Stmt::set("n", Expr::Int(0)),
                Stmt::For("i".into(), 0, last, vec![Stmt::when(en(var("i")), vec![Stmt::incr("n")])]),
                Stmt::when(
                    var("n").op(Op::Gt, Expr::Int(0)),
                    vec![
                        Stmt::set("rng", step),
                        Stmt::when(
                            var("rng").op(Op::Le, Expr::Int(0)),
                            vec![Stmt::set("rng", var("rng").op(Op::Add, Expr::Int(MINSTD_M)))],
                        ),
                        // `rng` is a DINT, `k` and `n` INTs: both conversions written out (6.6.1.6).
                        Stmt::set(
                            "k",
                            var("rng")
                                .op(Op::Mod, var("n").convert(&Type::Int, &Type::Dint))
                                .convert(&Type::Dint, &Type::Int),
                        ),
                        Stmt::For(
                            "i".into(),
                            0,
                            last,
                            vec![Stmt::when(
                                en(var("i")),
                                vec![
                                    Stmt::when(
                                        var("k").op(Op::Eq, Expr::Int(0)),
                                        vec![Stmt::set("c", var("i")), Stmt::Exit],
                                    ),
                                    Stmt::set("k", var("k").op(Op::Sub, Expr::Int(1))),
                                ],
                            )],
                        ),
                    ],
                ),
            ]
        }
        ScanPolicy::LocalQueue => local_queue(plants),
    }
}

/// Plants in a cyclic order from `pc`; in the first with an enabled event, the first of its events at
/// or after its site's cursor (`sc[site]`, 0 off a site), cyclically; both cursors move past the pick.
fn local_queue(plants: &[PlantChoice]) -> Vec<Stmt> {
    let count = i64::try_from(plants.len()).unwrap_or(i64::MAX);
    let var = Expr::var;
    let arms = plants
        .iter()
        .enumerate()
        .filter(|(_, p)| !p.events.is_empty())
        .map(|(k, p)| {
            let mut body = Vec::new();
            if p.sites.is_empty() {
                body.push(Stmt::set("cur", Expr::Int(0)));
            } else {
                let arms = p
                    .sites
                    .iter()
                    .map(|(at, s)| (at.clone(), vec![Stmt::set("site", Expr::Int(*s))]))
                    .collect();
                body.push(Stmt::If(arms, vec![Stmt::set("site", Expr::Int(-1))]));
                body.push(Stmt::If(
                    vec![(
                        var("site").op(Op::Ge, Expr::Int(0)),
                        vec![Stmt::set("cur", Expr::at("sc", var("site")))],
                    )],
                    vec![Stmt::set("cur", Expr::Int(0))],
                ));
            }
            let at_or_after = p
                .events
                .iter()
                .map(|&e| (var("cur").op(Op::Le, Expr::Int(e)).op(Op::And, en(Expr::Int(e))), vec![c_is(e)]));
            let wrapped = p.events.iter().map(|&e| (en(Expr::Int(e)), vec![c_is(e)]));
            body.push(Stmt::If(at_or_after.chain(wrapped).collect(), Vec::new()));
            if !p.sites.is_empty() {
                body.push(Stmt::when(
                    var("c").op(Op::Ge, Expr::Int(0)).op(Op::And, var("site").op(Op::Ge, Expr::Int(0))),
                    vec![Stmt::Assign(Expr::at("sc", var("site")), var("c").op(Op::Add, Expr::Int(1)))],
                ));
            }
            (vec![i64::try_from(k).unwrap_or(i64::MAX)], body)
        })
        .collect();
    vec![Stmt::For(
        "i".into(),
        0,
        count - 1,
        vec![
            Stmt::set("p", var("pc").op(Op::Add, var("i")).op(Op::Mod, Expr::Int(count))),
            Stmt::Case(var("p"), arms, Vec::new()),
            Stmt::when(
                var("c").op(Op::Ge, Expr::Int(0)),
                vec![
                    Stmt::set("pc", var("p").op(Op::Add, Expr::Int(1)).op(Op::Mod, Expr::Int(count))),
                    Stmt::Exit,
                ],
            ),
        ],
    )]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_generator_seed_is_in_range_and_the_step_fits_a_dint() {
        assert_eq!(minstd_seed(0), 1);
        assert_eq!(minstd_seed(2_147_483_646), 1);
        assert!((1..MINSTD_M).contains(&minstd_seed(u64::MAX)));
    }
}
