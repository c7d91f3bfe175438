//! Whether a net is safe: no reachable marking puts two tokens in one place. A PLC program keeps a place
//! in one `BOOL`, so it is written for safe nets only; an unsafe (or unbounded) net is refused naming
//! the place and a shortest firing sequence that puts the second token there.
//!
//! The walk fires every state-enabled transition (marking and inhibitor arcs; conditions and delays
//! aside, as the verification's graph does), breadth first from the initial marking, and stops at the
//! first marking with a place above one token. A safe net has at most 2^places markings; the walk is
//! bounded by a limit all the same. Arcs of weight above one are refused too: in a safe net such an
//! input arc never lets its transition fire, such an output arc always overfills, and such an inhibitor
//! arc never inhibits — in each case the program's one-bit place could not say what the net says.

use std::collections::{HashMap, VecDeque};

use super::model::{Marking, Net};
use super::NetError;

/// Refuses `net` unless it is safe (see the module documentation); explores at most `limit` markings.
pub fn check(net: &Net, limit: usize) -> Result<(), NetError> {
    for t in &net.transitions {
        let arcs = t.inputs.iter().chain(&t.outputs).chain(&t.inhibitors);
        if let Some(&(p, w)) = arcs.clone().find(|&&(_, w)| w > 1) {
            return Err(NetError::Weight {
                transition: t.id.clone(),
                place: net.places[p].id.clone(),
                weight: w,
            });
        }
    }
    let start = net.initial_marking();
    let mut parent: HashMap<Marking, Option<(Marking, usize)>> = HashMap::from([(start.clone(), None)]);
    let mut queue = VecDeque::from([start]);
    while let Some(m) = queue.pop_front() {
        if let Some(p) = m.iter().position(|&k| k > 1) {
            return Err(NetError::Unsafe {
                place: net.places[p].id.clone(),
                tokens: m[p],
                sequence: sequence(net, &parent, &m),
            });
        }
        for t in (0..net.transitions.len()).filter(|&t| net.state_enabled(t, &m)) {
            let Some(next) = net.fire(t, &m) else { continue };
            if parent.contains_key(&next) {
                continue;
            }
            if parent.len() >= limit {
                return Err(NetError::Markings { limit });
            }
            parent.insert(next.clone(), Some((m.clone(), t)));
            queue.push_back(next);
        }
    }
    Ok(())
}

/// The transitions fired from the initial marking to `m`, by id.
fn sequence(net: &Net, parent: &HashMap<Marking, Option<(Marking, usize)>>, m: &Marking) -> Vec<String> {
    let mut out = Vec::new();
    let mut at = m.clone();
    while let Some(Some((before, t))) = parent.get(&at) {
        out.push(net.transitions[*t].id.clone());
        at = before.clone();
    }
    out.reverse();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::net::model::{Place, Transition};

    fn net(initial: &[u32], arcs: &[(&str, &[usize], &[usize])]) -> Net {
        Net {
            name: "n".into(),
            places: initial
                .iter()
                .enumerate()
                .map(|(i, &k)| Place { id: format!("p{i}"), initial: k })
                .collect(),
            transitions: arcs
                .iter()
                .map(|(id, i, o)| Transition {
                    id: id.to_string(),
                    inputs: i.iter().map(|&p| (p, 1)).collect(),
                    outputs: o.iter().map(|&p| (p, 1)).collect(),
                    inhibitors: Vec::new(),
                })
                .collect(),
        }
    }

    #[test]
    fn a_cycle_is_safe_and_two_initial_tokens_are_not() {
        let cycle = [("t1", &[0][..], &[1][..]), ("t2", &[1], &[0])];
        assert!(check(&net(&[1, 0], &cycle), 100).is_ok());
        let err = check(&net(&[2, 0], &cycle), 100).unwrap_err();
        assert!(
            matches!(&err, NetError::Unsafe { place, tokens: 2, sequence } if place == "p0" && sequence.is_empty())
        );
        assert_eq!(err.to_string(), "place 'p0' holds 2 tokens in the initial marking: a PLC program keeps a place in one BOOL, so only safe nets are written");
    }

    #[test]
    fn the_shortest_firing_sequence_to_a_second_token_is_named() {
        // p0 forks into p1 and p2; p1 and p2 each lead to p3: the second of them puts a second token.
        let fork = [("fork", &[0][..], &[1, 2][..]), ("a", &[1], &[3]), ("b", &[2], &[3])];
        let err = check(&net(&[1, 0, 0, 0], &fork), 100).unwrap_err();
        assert_eq!(
            err.to_string(),
            "place 'p3' holds 2 tokens after the firing sequence fork a b (conditions and delays aside): a PLC program keeps a place in one BOOL, so only safe nets are written"
        );
        // An unbounded net is unsafe: its first place above one token is found.
        let pump = [("t", &[0][..], &[0, 1][..])];
        assert!(
            matches!(check(&net(&[1, 0], &pump), 100), Err(NetError::Unsafe { sequence, .. }) if sequence == ["t", "t"])
        );
    }

    #[test]
    fn weights_above_one_and_the_limit_are_refused() {
        let mut n = net(&[1, 0], &[("t", &[0], &[1])]);
        n.transitions[0].outputs[0].1 = 2;
        assert!(matches!(check(&n, 100), Err(NetError::Weight { weight: 2, .. })));
        let chain = [("t1", &[0][..], &[1][..]), ("t2", &[1], &[2]), ("t3", &[2], &[3])];
        assert!(matches!(check(&net(&[1, 0, 0, 0], &chain), 2), Err(NetError::Markings { limit: 2 })));
    }
}
