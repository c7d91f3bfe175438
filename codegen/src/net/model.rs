//! The place/transition net itself: places with their initial marking, transitions, weighted arcs and
//! inhibitor arcs — the structure both a drawn sequence (Mušič & Matko's RTPN) and an automation net with a
//! supervisor coupled by inhibitor arcs (Uzam & Gelen) are made of. The interpretation (conditions,
//! actions, delays) is [`super::Interpretation`]'s.

/// A place or transition index into [`Net::places`] or [`Net::transitions`].
pub type Index = usize;

/// A place.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Place {
    /// Its id in the file (what the manifest and reports name it by).
    pub id: String,
    /// Tokens in the initial marking.
    pub initial: u32,
}

/// A transition with its arcs, each list sorted by place.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Transition {
    /// Its id in the file.
    pub id: String,
    /// Input places and the tokens each arc takes.
    pub inputs: Vec<(Index, u32)>,
    /// Output places and the tokens each arc puts.
    pub outputs: Vec<(Index, u32)>,
    /// Inhibitor arcs: the transition is disabled while the place holds at least that many tokens.
    pub inhibitors: Vec<(Index, u32)>,
}

/// A place/transition net; ids are unique across places and transitions.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Net {
    /// Name (the PNML net's id).
    pub name: String,
    /// Places, in file order.
    pub places: Vec<Place>,
    /// Transitions, in file order.
    pub transitions: Vec<Transition>,
}

/// A marking: tokens per place.
pub type Marking = Vec<u32>;

impl Net {
    /// The index of the place with id `id`.
    pub fn place(&self, id: &str) -> Option<Index> {
        self.places.iter().position(|p| p.id == id)
    }

    /// The index of the transition with id `id`.
    pub fn transition(&self, id: &str) -> Option<Index> {
        self.transitions.iter().position(|t| t.id == id)
    }

    /// The initial marking.
    pub fn initial_marking(&self) -> Marking {
        self.places.iter().map(|p| p.initial).collect()
    }

    /// Whether transition `t` is state-enabled under `m`: every input place holds the arc's weight and
    /// every inhibiting place fewer tokens than its arc's.
    pub fn state_enabled(&self, t: Index, m: &[u32]) -> bool {
        let t = &self.transitions[t];
        t.inputs.iter().all(|&(p, w)| m[p] >= w) && t.inhibitors.iter().all(|&(p, w)| m[p] < w)
    }

    /// The marking after firing `t` under `m` (which must state-enable it); `None` when a place would
    /// overflow.
    pub fn fire(&self, t: Index, m: &[u32]) -> Option<Marking> {
        let t = &self.transitions[t];
        let mut next = m.to_vec();
        for &(p, w) in &t.inputs {
            next[p] -= w;
        }
        for &(p, w) in &t.outputs {
            next[p] = next[p].checked_add(w)?;
        }
        Some(next)
    }

    /// The ids of the places marked in `m`, in place order.
    pub fn marked(&self, m: &[u32]) -> Vec<String> {
        self.places.iter().zip(m).filter(|(_, &k)| k > 0).map(|(p, _)| p.id.clone()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_places() -> Net {
        Net {
            name: "n".into(),
            places: vec![Place { id: "a".into(), initial: 2 }, Place { id: "b".into(), initial: 0 }],
            transitions: vec![Transition {
                id: "t".into(),
                inputs: vec![(0, 2)],
                outputs: vec![(1, 1)],
                inhibitors: vec![(1, 1)],
            }],
        }
    }

    #[test]
    fn weights_and_inhibitors_decide_enabling() {
        let n = two_places();
        let m0 = n.initial_marking();
        assert!(n.state_enabled(0, &m0));
        assert!(!n.state_enabled(0, &[1, 0]), "weight 2 needs two tokens");
        let m1 = n.fire(0, &m0).unwrap();
        assert_eq!(m1, vec![0, 1]);
        assert!(!n.state_enabled(0, &[2, 1]), "the inhibitor arc disables it");
        assert_eq!(n.marked(&m1), vec!["b".to_owned()]);
        assert_eq!((n.place("b"), n.transition("t"), n.place("t")), (Some(1), Some(0), None));
    }
}
