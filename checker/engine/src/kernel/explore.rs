//! The explorer: breadth-first (so counterexamples are shortest),
//! exhaustive exploration of any [`Model`], with a compact [`Store`] and
//! resource limits that end in an *incomplete* result, never a false
//! complete one.
//!
//! [`Model`] follows stateright: initial states, the actions enabled in a
//! state, and the state an action leads to. States are stored packed as
//! words (`encode`/`decode`), so a later timed model can add its clock zone
//! to the same discrete state.

use std::time::{Duration, Instant};

use super::store::{StateId, Store, Subsumes};

/// A transition system to explore.
pub trait Model {
    /// A decoded state.
    type State;
    /// An action (transition label); small and copyable.
    type Action: Copy + std::fmt::Debug;
    /// The symbolic part of a state stored beside its words (`()` when
    /// untimed, a clock zone when timed).
    type Zone: Subsumes;

    /// Words per encoded state.
    fn width(&self) -> usize;
    /// Bits an encoded state uses: its words' bits past it are zero, and
    /// the store keeps each state in this many bits rounded up to bytes
    /// (default: every bit of [`Model::width`] words).
    fn bits(&self) -> usize {
        64 * self.width()
    }
    /// The initial states.
    fn init_states(&self) -> Vec<Self::State>;
    /// The actions enabled in `state`, appended to `out`.
    fn actions(&self, state: &Self::State, out: &mut Vec<Self::Action>);
    /// The state `action` leads to (`None` if it changes nothing).
    fn next_state(&self, state: &Self::State, action: Self::Action) -> Option<Self::State>;
    /// Packs a state into `width()` words.
    fn encode(&self, state: &Self::State, out: &mut Vec<u64>);
    /// Unpacks a state.
    fn decode(&self, words: &[u64], zone: &Self::Zone) -> Self::State;
    /// The zone of a state.
    fn zone(&self, state: &Self::State) -> Self::Zone;
    /// [`Self::decode`] into a reused buffer (`out` holds a state decoded
    /// earlier, or nothing). The default decodes afresh; a model whose
    /// states own allocations overrides it to reuse them.
    fn decode_into(&self, words: &[u64], zone: &Self::Zone, out: &mut Option<Self::State>) {
        *out = Some(self.decode(words, zone));
    }
    /// [`Self::next_state`] into a reused buffer: `false` (and `out` left
    /// unspecified) when the action changes nothing, else the successor is
    /// in `out`. The default calls [`Self::next_state`].
    fn step_into(
        &self,
        state: &Self::State,
        action: Self::Action,
        out: &mut Option<Self::State>,
    ) -> bool {
        match self.next_state(state, action) {
            Some(next) => {
                *out = Some(next);
                true
            }
            None => false,
        }
    }
    /// Whether to expand the successors of a state (default: all).
    fn expand(&self, _state: &Self::State) -> bool {
        true
    }
    /// Partial-order reduction: moves a persistent (stubborn) subset of the
    /// enabled `actions` to the front and returns its length. The default,
    /// `actions.len()`, explores every action. The explorer expands the
    /// rest too when a reduced successor is already stored (the cycle
    /// proviso), so a reduction only has to be persistent and invisible.
    fn reduce(&self, _state: &Self::State, actions: &mut [Self::Action]) -> usize {
        actions.len()
    }
    /// Whether exploring further can no longer change anything the caller
    /// reads (default: never). The explorer then stops, and the exploration
    /// counts as complete: the partial-order reduction answers `true` once
    /// every fact the analysis can find has been found.
    fn finished(&self) -> bool {
        false
    }
    /// How many transitions pass between two looks at the clock and the
    /// memory (default 64, and 16 times as many expansions). A model whose
    /// transitions are costly (zones over many clocks) asks for fewer, so
    /// that `--timeout` is kept within about one transition.
    fn limit_period(&self) -> u64 {
        64
    }
    /// Whether the store keeps, per state, the action that first reached
    /// it (default: yes). A model that answers `false` saves those bytes
    /// per state; its paths are found again from the parents
    /// ([`Exploration::path`]), each step as the first action (in
    /// [`Model::actions`] order) from the parent to the stored state. Only
    /// for a model without [`Model::reduce`], whose exploration fires the
    /// actions in that order, so that the path is the one explored, and
    /// whose steps are functions of the state (firing one again changes
    /// nothing the analysis reads).
    const KEEPS_ACTIONS: bool = true;
}

/// Resource limits of one run.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Stop after storing this many states.
    pub max_states: usize,
    /// Stop at this instant.
    pub deadline: Option<Instant>,
    /// `--max-memory`: stop when the process's heap reaches its soft bound
    /// ([`genom_model::limits::soft_bound`]) or the store grows past it.
    pub max_bytes: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_states: 10_000_000,
            deadline: None,
            max_bytes: 8 << 30,
        }
    }
}

/// Why exploration stopped early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// `max_states` reached.
    States,
    /// The deadline passed.
    Time,
    /// `max_bytes` reached.
    Memory,
}

/// The result of an exploration.
#[derive(Debug)]
pub struct Exploration<A, Z = ()> {
    /// Every reached state, with parent links.
    pub store: Store<A, Z>,
    /// Transitions fired (including those to known states).
    pub transitions: u64,
    /// `None` when the whole reachable state space was explored.
    pub stopped: Option<Stop>,
    /// Time spent.
    pub elapsed: Duration,
    /// States expanded with a reduced set of actions (partial-order
    /// reduction).
    pub reduced: u64,
}

impl<A: Copy, Z: Subsumes> Exploration<A, Z> {
    /// The actions from an initial state to `id`: the stored ones, or, for
    /// a model that keeps none ([`Model::KEEPS_ACTIONS`]), found again
    /// step by step from the parents.
    pub fn path<M: Model<Action = A, Zone = Z>>(&self, model: &M, id: StateId) -> Vec<A> {
        if self.store.keeps_actions() {
            return self.store.path(id);
        }
        let mut ids = vec![id];
        while let Some(p) = self.store.parent(ids[ids.len() - 1]) {
            ids.push(p);
        }
        ids.reverse();
        let mut out = Vec::with_capacity(ids.len());
        let (mut actions, mut key, mut next) = (Vec::new(), Vec::new(), None);
        for pair in ids.windows(2) {
            let (from, to) = (pair[0], pair[1]);
            let state = self.store_config(model, from);
            actions.clear();
            model.actions(&state, &mut actions);
            let found = actions.iter().copied().find(|&a| {
                if !model.step_into(&state, a, &mut next) {
                    return false;
                }
                let Some(succ) = next.as_ref() else {
                    return false;
                };
                key.clear();
                model.encode(succ, &mut key);
                self.store.matches(to, &key) && model.zone(succ) == *self.store.zone(to)
            });
            // Every stored state was reached from its parent by one of its
            // actions; a path that could not be found again stops short.
            debug_assert!(found.is_some(), "no action from {from} to {to}");
            match found {
                Some(a) => out.push(a),
                None => break,
            }
        }
        out
    }

    /// The decoded state `id`.
    pub fn store_config<M: Model<Action = A, Zone = Z>>(&self, model: &M, id: StateId) -> M::State {
        model.decode(&self.store.get(id), self.store.zone(id))
    }
}

/// Explores `model` breadth-first, calling `visit` once per new state.
pub fn explore<M: Model>(
    model: &M,
    limits: Limits,
    mut visit: impl FnMut(StateId, &M::State),
) -> Exploration<M::Action, M::Zone> {
    explore_until(model, limits, |id, s| {
        visit(id, s);
        Found::Open
    })
}

/// What a visit tells the explorer: whether some fact its caller reads may
/// still be found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Found {
    /// Keep exploring.
    Open,
    /// Every fact the caller can read has been found: exploring further
    /// changes nothing it reads, so the exploration stops and counts as
    /// complete (the early stop; [`Model::finished`] is the same for a
    /// model that follows its facts itself).
    All,
}

/// [`explore`], stopping (complete) as soon as `visit` answers
/// [`Found::All`].
pub fn explore_until<M: Model>(
    model: &M,
    limits: Limits,
    mut visit: impl FnMut(StateId, &M::State) -> Found,
) -> Exploration<M::Action, M::Zone> {
    let started = Instant::now();
    let mut all_found = false;
    let mut store = Store::with_layout(model.width(), model.bits(), M::KEEPS_ACTIONS);
    let mut key = Vec::with_capacity(model.width());
    for s in model.init_states() {
        key.clear();
        model.encode(&s, &mut key);
        let (id, new) = store.insert(&key, model.zone(&s), None);
        if new {
            all_found |= visit(id, &s) == Found::All;
        }
    }
    let mut actions = Vec::new();
    // Reused buffers: the expanded state and one successor.
    let mut current: Option<M::State> = None;
    let mut words = Vec::with_capacity(model.width());
    let mut successor: Option<M::State> = None;
    let mut transitions = 0u64;
    let mut next: usize = 0;
    let mut stopped = None;
    let mut reduced = 0u64;
    let period = model.limit_period();
    'expansions: while next < store.len() {
        stopped = check_limits(&store, limits, next, period);
        if stopped.is_some() {
            break;
        }
        if all_found || model.finished() {
            break;
        }
        let id = StateId::try_from(next).unwrap_or(StateId::MAX);
        next += 1;
        if store.is_covered(id) {
            continue;
        }
        store.load(id, &mut words);
        model.decode_into(&words, store.zone(id), &mut current);
        let Some(state) = current.as_ref() else {
            continue;
        };
        if !model.expand(state) {
            continue;
        }
        actions.clear();
        model.actions(state, &mut actions);
        let mut limit = model.reduce(state, &mut actions).min(actions.len());
        let mut k = 0;
        let mut old_successor = false;
        while k < limit {
            let a = actions[k];
            k += 1;
            let succ = match model.step_into(state, a, &mut successor) {
                true => successor.as_ref(),
                false => None,
            };
            match succ {
                // No change: a self-loop, hence a stored successor.
                None => old_successor = true,
                Some(succ) => {
                    transitions += 1;
                    key.clear();
                    model.encode(succ, &mut key);
                    let (sid, new) = store.insert(&key, model.zone(succ), Some((id, a)));
                    if new && visit(sid, succ) == Found::All {
                        break 'expansions;
                    }
                    old_successor |= !new;
                    stopped = check_successor(&store, limits, new, transitions, period);
                    if stopped.is_some() {
                        break 'expansions;
                    }
                }
            }
            // The cycle proviso: a reduced expansion reaching a stored
            // state becomes a full one, so that every cycle of the reduced
            // graph has a fully expanded state.
            if k == limit && old_successor {
                limit = actions.len();
            }
        }
        if limit < actions.len() {
            reduced += 1;
        }
    }
    Exploration {
        store,
        transitions,
        stopped,
        elapsed: started.elapsed(),
        reduced,
    }
}

/// The state limit is checked before every expansion; time and memory
/// every `16 × period` expansions, when the states stored so far are also
/// reported for a progress display.
fn check_limits<A: Copy, Z: Subsumes>(
    store: &Store<A, Z>,
    limits: Limits,
    expanded: usize,
    period: u64,
) -> Option<Stop> {
    if store.len() >= limits.max_states {
        return Some(Stop::States);
    }
    if expanded as u64 % (16 * period.max(1)) != 0 {
        return None;
    }
    genom_model::limits::report_explored(store.len());
    if genom_model::limits::out_of_time(limits.deadline) {
        return Some(Stop::Time);
    }
    memory_exceeded(store, limits).then_some(Stop::Memory)
}

/// Whether the memory limit is reached: by the process's heap (counted by
/// the binary's allocator, see [`genom_model::limits`]), or, where no
/// allocator counts it, by this exploration's own storage.
fn memory_exceeded<A: Copy, Z: Subsumes>(store: &Store<A, Z>, limits: Limits) -> bool {
    store.bytes() >= limits.max_bytes
        || genom_model::limits::heap::in_use() >= genom_model::limits::soft_bound(limits.max_bytes)
}

/// The limits checked while one state is expanded (a state of a large
/// component has thousands of successors, each costly to visit): the state
/// limit after each new state (which is unexpanded, so stopping there is
/// what the next [`check_limits`] would do), time and memory every
/// `period` transitions.
fn check_successor<A: Copy, Z: Subsumes>(
    store: &Store<A, Z>,
    limits: Limits,
    new: bool,
    transitions: u64,
    period: u64,
) -> Option<Stop> {
    if new && store.len() >= limits.max_states {
        return Some(Stop::States);
    }
    if transitions % period.max(1) != 0 {
        return None;
    }
    genom_model::limits::report_explored(store.len());
    if genom_model::limits::out_of_time(limits.deadline) {
        return Some(Stop::Time);
    }
    memory_exceeded(store, limits).then_some(Stop::Memory)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two counters modulo 3 and 4: 12 states, reached breadth-first; in a
    /// store that keeps the action reaching each state or not (`KEEP`).
    struct Counters<const KEEP: bool>;

    impl<const KEEP: bool> Model for Counters<KEEP> {
        type State = (u64, u64);
        type Action = bool;
        type Zone = ();
        const KEEPS_ACTIONS: bool = KEEP;
        fn width(&self) -> usize {
            2
        }
        fn init_states(&self) -> Vec<(u64, u64)> {
            vec![(0, 0)]
        }
        fn actions(&self, _: &(u64, u64), out: &mut Vec<bool>) {
            out.extend([false, true]);
        }
        fn next_state(&self, s: &(u64, u64), first: bool) -> Option<(u64, u64)> {
            Some(if first {
                ((s.0 + 1) % 3, s.1)
            } else {
                (s.0, (s.1 + 1) % 4)
            })
        }
        fn encode(&self, s: &(u64, u64), out: &mut Vec<u64>) {
            out.extend([s.0, s.1]);
        }
        fn decode(&self, w: &[u64], (): &()) -> (u64, u64) {
            (w[0], w[1])
        }
        fn zone(&self, _: &(u64, u64)) {}
    }

    #[test]
    fn explores_everything_and_paths_are_shortest() {
        let mut seen = Vec::new();
        let e = explore(&Counters::<true>, Limits::default(), |id, s| {
            seen.push((id, *s));
        });
        assert_eq!(e.store.len(), 12);
        assert!(e.stopped.is_none());
        assert_eq!(e.transitions, 24);
        let (far, _) = seen.iter().copied().find(|&(_, s)| s == (2, 2)).unwrap();
        assert_eq!(e.store.path(far).len(), 4);
    }

    #[test]
    fn paths_found_again_from_the_parents_are_the_stored_ones() {
        let kept = explore(&Counters::<true>, Limits::default(), |_, _| {});
        let found = explore(&Counters::<false>, Limits::default(), |_, _| {});
        assert!(!found.store.keeps_actions() && kept.store.keeps_actions());
        assert_eq!(found.store.len(), kept.store.len());
        for id in 0..12 {
            let path = found.path(&Counters::<false>, id);
            assert_eq!(path, kept.path(&Counters::<true>, id), "state {id}");
            assert!(found.store.path(id).is_empty());
            // The path leads to the state.
            let end = path
                .iter()
                .fold((0, 0), |s, &a| Counters::<true>.next_state(&s, a).unwrap());
            assert_eq!(end, found.store_config(&Counters::<false>, id));
        }
        assert!(found.store.bytes() < kept.store.bytes());
    }

    #[test]
    fn the_state_limit_stops_early_and_says_so() {
        let limits = Limits {
            max_states: 5,
            ..Limits::default()
        };
        let e = explore(&Counters::<true>, limits, |_, _| {});
        assert_eq!(e.stopped, Some(Stop::States));
        assert!(e.store.len() < 12);
    }
}
