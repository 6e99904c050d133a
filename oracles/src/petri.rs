//! A small generic token game for the nets of [`genom_model::petri`]:
//! place/transition nets with inhibitor arcs (the place holds fewer tokens
//! than the weight), read arcs (it holds at least the weight) and
//! priorities (only the enabled transitions of the highest enabled priority
//! may fire).
//!
//! An oracle: it reads the net alone and has its own exhaustive search, a
//! plain breadth-first search over markings bounded by a number of
//! markings ([`reachable`]), sharing nothing with the engines' explorer.
//! [`stable_graph`] works on *stable* markings (no transition above
//! [`PRIORITY_STEP`] enabled): from each, every step-level transition is
//! fired and the urgent cascade that follows is run to its stable ends.
//! Stable markings are what the component's configurations correspond to,
//! so this graph is the one to compare with the engine's untimed explorer
//! (`genom_engine::dialect::system`, `tests/petri_common`).

use std::collections::{HashMap, HashSet, VecDeque};

use genom_model::component::Idx;
use genom_model::petri::{PRIORITY_STEP, PetriNet, TransitionId};

/// A marking: one token count per place.
pub type Marking = Vec<u32>;

/// Every transition enabled in `m`, ignoring priorities.
pub fn enabled(net: &PetriNet, m: &[u32]) -> Vec<TransitionId> {
    net.transitions
        .iter()
        .enumerate()
        .filter(|(_, t)| t.enabled(m))
        .map(|(i, _)| TransitionId::new(i))
        .collect()
}

/// The transitions that may fire in `m`: the enabled ones of the highest
/// enabled priority.
pub fn fireable(net: &PetriNet, m: &[u32]) -> Vec<TransitionId> {
    let mut top = 0u8;
    let mut out = Vec::new();
    for (i, t) in net.transitions.iter().enumerate() {
        if t.priority < top || !t.enabled(m) {
            continue;
        }
        if t.priority > top {
            top = t.priority;
            out.clear();
        }
        out.push(TransitionId::new(i));
    }
    out
}

/// Whether no transition above the step level is enabled.
pub fn is_stable(net: &PetriNet, m: &[u32]) -> bool {
    !net.transitions
        .iter()
        .any(|t| t.priority > PRIORITY_STEP && t.enabled(m))
}

/// The marking after firing `t` (which must be enabled; `None` otherwise).
pub fn fire(net: &PetriNet, m: &[u32], t: TransitionId) -> Option<Marking> {
    let tr = net.transition(t).filter(|tr| tr.enabled(m))?;
    let mut next = m.to_vec();
    for &(p, w) in &tr.pre {
        let n = next.get_mut(p.index())?;
        *n = n.checked_sub(w)?;
    }
    for &(p, w) in &tr.post {
        let n = next.get_mut(p.index())?;
        *n = n.saturating_add(w);
    }
    Some(next)
}

/// The token game of a net: markings and their fireable transitions.
/// Transitions are indexed by their first input place, so only those of
/// marked places (and those without input place) are tried.
#[derive(Debug, Clone)]
pub struct TokenGame<'n> {
    /// The net.
    pub net: &'n PetriNet,
    /// Transitions by their first input place.
    by_place: Vec<Vec<usize>>,
    /// Transitions without input place.
    free: Vec<usize>,
}

impl<'n> TokenGame<'n> {
    /// The token game of `net`.
    pub fn new(net: &'n PetriNet) -> Self {
        let mut by_place = vec![Vec::new(); net.places.len()];
        let mut free = Vec::new();
        for (i, t) in net.transitions.iter().enumerate() {
            match t
                .pre
                .first()
                .and_then(|&(p, _)| by_place.get_mut(p.index()))
            {
                Some(list) => list.push(i),
                None => free.push(i),
            }
        }
        TokenGame {
            net,
            by_place,
            free,
        }
    }

    /// The transitions that may fire in `m` (as [`fireable`]), in
    /// transition order.
    pub fn fireable(&self, m: &[u32]) -> Vec<TransitionId> {
        let marked = m.iter().enumerate().filter(|&(_, &n)| n > 0);
        let mut candidates: Vec<usize> = self.free.clone();
        for (p, _) in marked {
            candidates.extend(self.by_place.get(p).into_iter().flatten().copied());
        }
        candidates.sort_unstable();
        let mut top = 0u8;
        let mut out = Vec::new();
        for i in candidates {
            let Some(t) = self.net.transitions.get(i) else {
                continue;
            };
            if t.priority < top || !t.enabled(m) {
                continue;
            }
            if t.priority > top {
                top = t.priority;
                out.clear();
            }
            out.push(TransitionId::new(i));
        }
        out
    }

    /// The fireable transitions of `m` when they are urgent (above the
    /// step level); empty when `m` is stable.
    fn urgent(&self, m: &[u32]) -> Vec<TransitionId> {
        let f = self.fireable(m);
        let top = f
            .first()
            .and_then(|&t| self.net.transition(t))
            .map_or(0, |t| t.priority);
        if top > PRIORITY_STEP { f } else { Vec::new() }
    }
}

/// Every marking reachable from the initial one, breadth-first.
#[derive(Debug, Clone, Default)]
pub struct Reachable {
    /// The markings, in the order they were found (the initial first).
    pub markings: Vec<Marking>,
    /// Whether the search saw them all (else it stopped at its bound).
    pub complete: bool,
}

/// The markings reachable in `net` by the token game (priorities
/// respected), at most `max_markings` of them.
pub fn reachable(net: &PetriNet, max_markings: usize) -> Reachable {
    let game = TokenGame::new(net);
    let mut out = Reachable::default();
    let mut seen: HashSet<Marking> = HashSet::new();
    let mut queue: VecDeque<Marking> = VecDeque::new();
    seen.insert(net.initial.clone());
    queue.push_back(net.initial.clone());
    while let Some(m) = queue.pop_front() {
        if out.markings.len() >= max_markings {
            return out;
        }
        for t in game.fireable(&m) {
            if let Some(next) = fire(net, &m, t) {
                if seen.insert(next.clone()) {
                    queue.push_back(next);
                }
            }
        }
        out.markings.push(m);
    }
    out.complete = true;
    out
}

/// The stable markings of a net and the steps between them.
#[derive(Debug, Clone, Default)]
pub struct StableGraph {
    /// Every reachable stable marking.
    pub markings: Vec<Marking>,
    /// Indices of the stable markings the initial cascade ends in.
    pub initial: Vec<usize>,
    /// `(from, step transition, to)`: firing the step-level transition in
    /// `from`, then urgent transitions until stable, can end in `to`.
    pub edges: Vec<(usize, TransitionId, usize)>,
    /// Urgent transitions fired by the cascades.
    pub urgent_firings: u64,
    /// Some urgent cascade can fire forever.
    pub urgent_cycle: bool,
    /// Steps whose urgent cascade can end in more than one stable marking.
    pub nondeterministic: usize,
    /// The largest token count seen in any place.
    pub max_tokens: u32,
    /// The construction stopped at its bound, before the end.
    pub stopped: bool,
}

/// Builds the [`StableGraph`] of `net`, breadth-first; `max_markings`
/// bounds the stable markings plus the markings where an urgent cascade
/// branches.
pub fn stable_graph(net: &PetriNet, max_markings: usize) -> StableGraph {
    let mut g = Graph {
        game: TokenGame::new(net),
        max_markings,
        out: StableGraph::default(),
        index: HashMap::new(),
        cascades: HashMap::new(),
    };
    let initial = g.settle(&net.initial);
    g.out.initial = initial.iter().map(|m| g.intern(m)).collect();
    let mut next = 0;
    while next < g.out.markings.len() && !g.out.stopped {
        g.expand(next);
        next += 1;
    }
    g.out
}

struct Graph<'n> {
    game: TokenGame<'n>,
    max_markings: usize,
    out: StableGraph,
    index: HashMap<Marking, usize>,
    /// Stable ends of the cascade from each unstable marking (`None` while
    /// it is being computed).
    cascades: HashMap<Marking, Option<Vec<Marking>>>,
}

impl<'n> Graph<'n> {
    fn intern(&mut self, m: &Marking) -> usize {
        if let Some(&i) = self.index.get(m) {
            return i;
        }
        let i = self.out.markings.len();
        self.out.max_tokens = self
            .out
            .max_tokens
            .max(m.iter().copied().max().unwrap_or(0));
        self.out.markings.push(m.clone());
        self.index.insert(m.clone(), i);
        i
    }

    fn expand(&mut self, i: usize) {
        if self.out.markings.len() + self.cascades.len() >= self.max_markings {
            self.out.stopped = true;
            return;
        }
        let m = self.out.markings[i].clone();
        for t in self.game.fireable(&m) {
            let Some(after) = fire(self.game.net, &m, t) else {
                continue;
            };
            let ends = self.settle(&after);
            if ends.len() > 1 {
                self.out.nondeterministic += 1;
            }
            for end in &ends {
                let j = self.intern(end);
                self.out.edges.push((i, t, j));
            }
        }
    }

    /// The stable markings the urgent cascade from `m` can end in. A
    /// deterministic stretch (one urgent transition at a time) is followed
    /// without memory; markings where the cascade branches are memoised.
    fn settle(&mut self, m: &Marking) -> Vec<Marking> {
        let mut cur = m.clone();
        let mut seen: HashSet<Marking> = HashSet::new();
        for step in 0usize.. {
            let urgent = self.game.urgent(&cur);
            match urgent.as_slice() {
                [] => {
                    let most = cur.iter().copied().max().unwrap_or(0);
                    self.out.max_tokens = self.out.max_tokens.max(most);
                    return vec![cur];
                }
                [t] => {
                    self.out.urgent_firings += 1;
                    if step > LINEAR && !seen.insert(cur.clone()) {
                        self.out.urgent_cycle = true;
                        return Vec::new();
                    }
                    let Some(next) = fire(self.game.net, &cur, *t) else {
                        return Vec::new();
                    };
                    cur = next;
                }
                _ => return self.branch(&cur, &urgent),
            }
        }
        Vec::new()
    }

    /// The stable ends of a cascade that branches at `m`.
    fn branch(&mut self, m: &Marking, urgent: &[TransitionId]) -> Vec<Marking> {
        match self.cascades.get(m) {
            Some(Some(ends)) => return ends.clone(),
            Some(None) => {
                self.out.urgent_cycle = true;
                return Vec::new();
            }
            None => {}
        }
        self.cascades.insert(m.clone(), None);
        let mut ends: Vec<Marking> = Vec::new();
        for &t in urgent {
            self.out.urgent_firings += 1;
            let Some(after) = fire(self.game.net, m, t) else {
                continue;
            };
            for end in self.settle(&after) {
                if !ends.contains(&end) {
                    ends.push(end);
                }
            }
        }
        self.cascades.insert(m.clone(), Some(ends.clone()));
        ends
    }
}

/// Urgent firings in a row after which a deterministic cascade starts
/// remembering markings to detect a cycle.
const LINEAR: usize = 1024;

#[cfg(test)]
mod tests {
    use genom_model::behaviour::Behaviour;
    use genom_model::petri::PetriNet;
    use genom_translate::petri::BuildPetriNet;

    use super::*;
    use crate::testing::{HEADER, check};

    /// Bound of the tests' searches.
    const MAX: usize = 1_000_000;

    fn net(body: &str) -> PetriNet {
        let c = check(&format!("{HEADER}{body}")).expect("a component");
        PetriNet::build(&c, &Behaviour::new(&c))
    }

    const LOOP: &str = "service s { thread: main; stops: s;\n\
        start codel { exec: f(); on-inter: halt; next: run; }\n\
        exec codel run { exec: g(); on-inter: halt; next: run, end; }\n\
        inter codel halt { exec: h(); } }\n";

    #[test]
    fn a_self_stopping_loop_is_safe_and_deterministic() {
        let n = net(LOOP);
        let g = stable_graph(&n, MAX);
        assert!(!g.stopped);
        assert!(!g.urgent_cycle);
        assert_eq!(g.nondeterministic, 0);
        assert_eq!(g.max_tokens, 1);
        assert_eq!(g.initial.len(), 1);
        assert!(g.markings.iter().all(|m| is_stable(&n, m)));
    }

    #[test]
    fn the_token_game_reaches_every_stable_marking() {
        let n = net(LOOP);
        let g = stable_graph(&n, MAX);
        let r = reachable(&n, MAX);
        assert!(r.complete);
        let stable = r.markings.iter().filter(|m| is_stable(&n, m)).count();
        assert_eq!(stable, g.markings.len());
        assert!(
            r.markings.len() > stable,
            "request chains pass through unstable markings"
        );
    }

    #[test]
    fn a_bounded_search_says_it_stopped() {
        let n = net(LOOP);
        let r = reachable(&n, 2);
        assert!(!r.complete);
        assert_eq!(r.markings.len(), 2);
        assert!(stable_graph(&n, 1).stopped);
    }

    #[test]
    fn the_index_finds_the_same_transitions() {
        let n = net(LOOP);
        let game = TokenGame::new(&n);
        let r = reachable(&n, MAX);
        assert!(r.complete);
        for m in &r.markings {
            assert_eq!(game.fireable(m), fireable(&n, m));
        }
    }

    #[test]
    fn priorities_hide_lower_transitions() {
        let n = net(LOOP);
        let request = n
            .transitions
            .iter()
            .position(|t| t.name == "s.request")
            .unwrap();
        let after = fire(&n, &n.initial, TransitionId::new(request)).unwrap();
        assert!(!is_stable(&n, &after));
        let f = fireable(&n, &after);
        assert!(!f.is_empty());
        assert!(
            f.iter()
                .all(|&t| n.transition(t).unwrap().priority > PRIORITY_STEP)
        );
        assert!(enabled(&n, &after).contains(&TransitionId::new(request)));
        assert!(!f.contains(&TransitionId::new(request)));
    }
}
