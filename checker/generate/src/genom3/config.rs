//! What to generate in GenoM3: [`Genom3Config`] and its presets.

use crate::rng::SplitMix;

/// What GenoM3 component to generate. Build with [`Genom3Config::new`] or
/// [`Genom3Config::small`] and adjust the public fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Genom3Config {
    /// The seed of the random choices.
    pub seed: u64,
    /// Number of tasks (at least 1).
    pub tasks: usize,
    /// Number of activities.
    pub activities: usize,
    /// Number of functions.
    pub functions: usize,
    /// Number of attributes.
    pub attributes: usize,
    /// Codel states of each activity's (and permanent task's) state
    /// machine: `start` and `states - 1` others (at least 1); a `stop`
    /// state, when drawn, comes on top.
    pub states: usize,
    /// Expected number of `interrupts` + `after` + `before` references
    /// listed by each service (0: none, and no `interrupts all`).
    pub density: f64,
    /// Every task periodic, and a WCET side file ([`Genom3Component::wcet`](super::Genom3Component::wcet)).
    pub timed: bool,
    /// The first task, and each other with probability 1/2, get permanent
    /// codels (`codel<start>` … `codel<stop>` in the task).
    pub permanent: bool,
    /// Some codels (one in four, `start` and `stop` excepted) are `async`.
    /// On a periodic task of a timed component an `async` codel makes the
    /// task overrun (it has no upper bound).
    pub asyncs: bool,
    /// Probability that a yield to a later state is `pause::` (yields to
    /// the same or an earlier state are always paused unless
    /// [`Genom3Config::unpaused_cycles`]).
    pub pauses: f64,
    /// Let some yields back to the same or an earlier state go without
    /// `pause::` (cycles that give `livelock` or `unpaused-loop`). Off by
    /// default.
    pub unpaused_cycles: bool,
    /// Declare ports (`port out`, `port in`) that codels write and read.
    pub ports: bool,
    /// With `timed`: how heavy the WCETs are. Up to 1, the sum of all
    /// WCETs as a fraction of the shortest period: at most 0.5 keeps every
    /// task within its period (each codel runs at most twice in one
    /// wake-up). Above 1, the sum of each task's codels' WCETs as a
    /// multiple of its period, each codel shorter than the period: a
    /// wake-up that runs several codels overruns (`thread-overrun`).
    pub load: f64,
}

impl Genom3Config {
    /// Two tasks, four activities, one function and one attribute of three
    /// states, about one reference per service, untimed, no permanent or
    /// `async` codels, half the forward yields paused, ports, load 0.3.
    pub fn new(seed: u64) -> Self {
        Genom3Config {
            seed,
            tasks: 2,
            activities: 4,
            functions: 1,
            attributes: 1,
            states: 3,
            density: 1.0,
            timed: false,
            permanent: false,
            asyncs: false,
            pauses: 0.5,
            unpaused_cycles: false,
            ports: true,
            load: 0.3,
        }
    }

    /// A random small configuration derived from `seed` alone: 1–3 tasks,
    /// 1–5 activities, 0–2 functions and 0–2 attributes, 1–4 states,
    /// density 0–2, and timing, permanent codels, ports and pauses at
    /// random; `async` codels only when untimed; load 0.3 for most timed
    /// seeds and 2, 3 or 4 for about a third of them; never unpaused
    /// cycles.
    pub fn small(seed: u64) -> Self {
        let mut r = SplitMix::new(seed ^ 0x6E03_6E03_6E03_6E03);
        let timed = r.chance(0.5);
        let overload = r.chance(0.35);
        let load = [2.0, 3.0, 4.0][r.below(3)];
        Genom3Config {
            seed,
            tasks: 1 + r.below(3),
            activities: 1 + r.below(5),
            functions: r.below(3),
            attributes: r.below(3),
            states: 1 + r.below(4),
            #[allow(clippy::cast_precision_loss)]
            density: r.below(9) as f64 / 4.0,
            timed,
            permanent: r.chance(0.5),
            asyncs: !timed && r.chance(0.5),
            pauses: [0.0, 0.5, 1.0][r.below(3)],
            unpaused_cycles: false,
            ports: r.chance(0.5),
            load: if overload { load } else { 0.3 },
        }
    }
}
