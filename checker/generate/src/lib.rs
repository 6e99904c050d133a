//! A random generator of valid component descriptions, for benchmarks,
//! property tests and differential testing of the engines.
//!
//! [`generate`] turns a [`GeneratorConfig`] into the *text* of a `.gen`
//! file that parses, resolves and passes every static check without an
//! error or a warning (advice may remain, e.g. `missing-on-inter` for a
//! one-codel interruptible service). Behavioural verdicts (starvation,
//! dead services, ...) are not excluded: finding them is the engine's job.
//!
//! The output depends on the configuration only: the random numbers come
//! from a splitmix64 generator written here (no `rand`, no hashing, no
//! floating-point function other than `+ - * /` and comparisons), so a
//! seed gives the same component on every platform and with every version
//! of the dependencies.
//!
//! What a component holds:
//!
//! - `ids` blocks (`d0`, `d1`, ...) whose members cycle through `double`,
//!   `long` and `boolean`, and an `export` block of `double` items;
//! - threads `t0`, `t1`, ... (periodic, with random periods; when not
//!   `timed`, some are aperiodic);
//! - services `S00`, `S01`, ...: first the `init` service if asked, then
//!   the `auto` services, then ordinary ones, some of which may be
//!   attribute setters (control codel only, no thread);
//! - `stops`/`delays`/`forbids`: every ordered pair of services (a service
//!   and itself included, for `stops` only) gets a rule with probability
//!   `rule_density / services`, so each service lists `rule_density`
//!   references on average; half are `stops`, a quarter `delays`, a quarter
//!   `forbids`. Unless [`GeneratorConfig::auto_rules`] is set, an `auto`
//!   service only lists `stops` (an `auto` instance never ends, so its
//!   `delays` or `forbids` would make their targets dead);
//! - codels: a threaded service has `codels_per_service` start, exec and
//!   inter codels. Inter codels exist only when something can interrupt the
//!   service (a `stops` naming it, or its own `max-time`); then every start
//!   and exec codel has an `on-inter`. The `next` graph of the start and
//!   exec codels is a random tree rooted at `start` (so every codel is
//!   reachable) plus random back edges (loops) and forward edges; in a
//!   non-`auto` service every leaf of the tree has an exit outcome (`end`
//!   or a report) and the first leaf has `end`, so every codel can end the
//!   service and the `init` service can succeed; in an `auto` service every
//!   leaf loops back instead and no outcome ends it. Inter codels form a
//!   forward-only tree (no loop, so interrupts are bounded) that ends;
//! - codel functions: a pool of functions whose prototypes are fixed at
//!   their first use; a later codel may call the same function again with
//!   other data of the same types and the same `const` flags. Arguments are
//!   `ids` members, export items and the service's own parameters;
//!   non-`const` `ids`/export arguments may be listed in `update`;
//! - with `timed`: every thread is periodic, every codel has a WCET
//!   (`max-time`) well below its thread's period divided among the services
//!   of the thread, and about half of the services have a generous
//!   `max-time` (several periods per codel).
//!
//! For property tests, [`strategy`] (only under `#[cfg(test)]`, since
//! proptest is a dev-dependency of this crate) yields configurations of
//! small components; outside this crate's tests, [`GeneratorConfig::small`]
//! derives such a configuration from a single seed, which any proptest
//! `any::<u64>()` can feed.

use std::fmt::Write as _;

/// What to generate. Build with [`GeneratorConfig::new`] and adjust the
/// public fields.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratorConfig {
    /// The seed of the random choices.
    pub seed: u64,
    /// Number of services, `init`, `auto` and attribute setters included
    /// (at least 1).
    pub services: usize,
    /// Start, exec and inter codels of each threaded service (at least 1;
    /// an `auto` service gets at least 2 so that it can loop).
    pub codels_per_service: usize,
    /// Number of threads (at least 1).
    pub threads: usize,
    /// Expected number of `stops` + `delays` + `forbids` references listed
    /// by each service.
    pub rule_density: f64,
    /// Make the first service an `init` service.
    pub init: bool,
    /// Number of `auto` services (after the init service).
    pub autos: usize,
    /// Thread periods, codel WCETs and service `max-time`s.
    pub timed: bool,
    /// Let `auto` services list `delays` and `forbids` too (their targets
    /// may then be dead).
    pub auto_rules: bool,
    /// Probability that an ordinary service is an attribute setter
    /// (control codel only, no thread).
    pub setters: f64,
    /// Probability that a start or exec codel gets an extra back edge (a
    /// loop) in its `next`.
    pub loops: f64,
    /// Number of `ids` blocks (0: one per five services).
    pub ids_blocks: usize,
    /// Number of export items (0: none).
    pub exports: usize,
    /// Probability that an ordinary or `init` service also lists itself in
    /// `stops` (a new request replaces the running one, as in most motion
    /// services), on top of `rule_density`.
    pub self_stops: f64,
}

impl GeneratorConfig {
    /// `services` ordinary services of 3 codels on 1 thread, about one rule
    /// reference per service, untimed, no init, no autos.
    pub fn new(seed: u64, services: usize) -> Self {
        GeneratorConfig {
            seed,
            services,
            codels_per_service: 3,
            threads: 1,
            rule_density: 1.0,
            init: false,
            autos: 0,
            timed: false,
            auto_rules: false,
            setters: 0.0,
            loops: 0.3,
            ids_blocks: 0,
            exports: 1,
            self_stops: 0.0,
        }
    }

    /// A random small configuration derived from `seed` alone (1–6
    /// services, 1–4 codels, 1–3 threads, density 0–3, init, autos,
    /// setters, self-stops and timing at random): the same space as [`strategy`], for
    /// users outside this crate's tests.
    pub fn small(seed: u64) -> Self {
        let mut r = SplitMix::new(seed ^ 0x5EED_5EED_5EED_5EED);
        GeneratorConfig {
            seed,
            services: 1 + r.below(6),
            codels_per_service: 1 + r.below(4),
            threads: 1 + r.below(3),
            #[allow(clippy::cast_precision_loss)]
            rule_density: r.below(13) as f64 / 4.0,
            init: r.chance(0.5),
            autos: r.below(3),
            timed: r.chance(0.5),
            auto_rules: r.chance(0.2),
            setters: if r.chance(0.5) { 0.3 } else { 0.0 },
            loops: if r.chance(0.5) { 0.3 } else { 0.0 },
            ids_blocks: r.below(3),
            exports: r.below(3),
            self_stops: if r.chance(0.5) { 0.5 } else { 0.0 },
        }
    }
}

/// The splitmix64 generator (Steele, Lea and Flood 2014): tiny, fast,
/// and its output is fixed by its definition.
#[derive(Debug, Clone)]
struct SplitMix(u64);

impl SplitMix {
    fn new(seed: u64) -> Self {
        SplitMix(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (0 when `n` is 0), by multiply-shift.
    fn below(&mut self, n: usize) -> usize {
        let wide = u128::from(self.next_u64()) * n as u128;
        usize::try_from(wide >> 64).unwrap_or(0)
    }

    /// Uniform in `lo..=hi`.
    fn range(&mut self, lo: u64, hi: u64) -> u64 {
        let span = usize::try_from(hi.saturating_sub(lo)).unwrap_or(usize::MAX - 1) + 1;
        lo + self.below(span) as u64
    }

    /// True with probability `p` (exact for every platform: a 53-bit
    /// integer scaled by a power of two).
    fn chance(&mut self, p: f64) -> bool {
        #[allow(clippy::cast_precision_loss)]
        let x = (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0);
        x < p
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> Option<&'a T> {
        let i = self.below(items.len());
        items.get(i)
    }
}

/// A data type of the generated data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ty {
    Double,
    Long,
    Boolean,
}

impl Ty {
    const ALL: [Ty; 3] = [Ty::Double, Ty::Long, Ty::Boolean];

    fn name(self) -> &'static str {
        match self {
            Ty::Double => "double",
            Ty::Long => "long",
            Ty::Boolean => "boolean",
        }
    }

    fn default_value(self, r: &mut SplitMix) -> String {
        match self {
            Ty::Double => format!("{}.{}", r.below(10), r.below(10)),
            Ty::Long => r.below(100).to_string(),
            Ty::Boolean => if r.chance(0.5) { "TRUE" } else { "FALSE" }.to_owned(),
        }
    }
}

/// A piece of data a codel can name: its text, type, and whether it is a
/// lockable structure that `update` may list (`ids` member, export item)
/// rather than a service parameter.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Data {
    text: String,
    ty: Ty,
    structure: bool,
}

/// A codel function: its name and fixed prototype.
#[derive(Debug, Clone)]
struct Function {
    name: String,
    args: Vec<(bool, Ty)>,
}

/// Kinds of service.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Init,
    Auto,
    Plain,
    Setter,
}

/// A `next` outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Out {
    Codel(usize),
    End,
    Report(usize),
}

/// One generated codel (index 0 is `start`).
#[derive(Debug, Clone, Default)]
struct CodelPlan {
    name: String,
    inter: bool,
    next: Vec<Out>,
    on_inter: Option<usize>,
}

/// One generated service.
#[derive(Debug, Clone)]
struct ServicePlan {
    name: String,
    kind: Kind,
    thread: Option<usize>,
    stops: Vec<usize>,
    delays: Vec<usize>,
    forbids: Vec<usize>,
    max_time: bool,
}

/// Generates the text of a component. Deterministic: the same
/// configuration always gives the same text.
pub fn generate(config: &GeneratorConfig) -> String {
    Generator::new(config).run()
}

struct Generator<'c> {
    cfg: &'c GeneratorConfig,
    r: SplitMix,
    data: Vec<Data>,
    functions: Vec<Function>,
    periods_us: Vec<Option<u64>>,
    services: Vec<ServicePlan>,
    out: String,
}

/// Thread periods to choose from, in microseconds.
const PERIODS_US: [u64; 7] = [1_000, 2_000, 5_000, 10_000, 20_000, 50_000, 100_000];

impl<'c> Generator<'c> {
    fn new(cfg: &'c GeneratorConfig) -> Self {
        Generator {
            cfg,
            r: SplitMix::new(cfg.seed),
            data: Vec::new(),
            functions: Vec::new(),
            periods_us: Vec::new(),
            services: Vec::new(),
            out: String::new(),
        }
    }

    fn run(mut self) -> String {
        let cfg = self.cfg;
        let n = cfg.services.max(1);
        let threads = cfg.threads.max(1);
        let _ = writeln!(
            self.out,
            "/* generated by genom-check generate: seed {}, {} services, {} codels, {} threads, \
             density {}, init {}, autos {}, timed {}, auto-rules {}, setters {}, loops {}, \
             self-stops {}, ids {}, exports {} */",
            cfg.seed,
            n,
            cfg.codels_per_service,
            threads,
            cfg.rule_density,
            cfg.init,
            cfg.autos,
            cfg.timed,
            cfg.auto_rules,
            cfg.setters,
            cfg.loops,
            cfg.self_stops,
            cfg.ids_blocks,
            cfg.exports
        );
        let _ = writeln!(
            self.out,
            "component gen{} {{ category: default; lang: C; }}\n",
            cfg.seed
        );
        self.data_blocks(n);
        self.threads(threads);
        self.plan_services(n, threads);
        self.plan_rules(n);
        for i in 0..n {
            self.service(i);
        }
        self.out
    }

    fn data_blocks(&mut self, n: usize) {
        let blocks = if self.cfg.ids_blocks == 0 {
            n.div_ceil(5)
        } else {
            self.cfg.ids_blocks
        };
        for b in 0..blocks {
            let members = 3 + self.r.below(3);
            let _ = write!(self.out, "ids d{b} {{");
            for m in 0..members {
                let ty = Ty::ALL[m % 3];
                let name = format!("m{m}");
                if self.r.chance(0.5) {
                    let v = ty.default_value(&mut self.r);
                    let _ = write!(self.out, " {} {name} := {v};", ty.name());
                } else {
                    let _ = write!(self.out, " {} {name};", ty.name());
                }
                self.data.push(Data {
                    text: format!("d{b}.{name}"),
                    ty,
                    structure: true,
                });
            }
            let _ = writeln!(self.out, " }}");
        }
        if self.cfg.exports > 0 {
            let _ = write!(self.out, "export port {{");
            for e in 0..self.cfg.exports {
                let _ = write!(self.out, " double out{e} := 0.0;");
                self.data.push(Data {
                    text: format!("port.out{e}"),
                    ty: Ty::Double,
                    structure: true,
                });
            }
            let _ = writeln!(self.out, " }}");
        }
        self.out.push('\n');
    }

    fn threads(&mut self, threads: usize) {
        for t in 0..threads {
            let periodic = self.cfg.timed || self.r.chance(0.5);
            let period = periodic.then(|| *self.r.pick(&PERIODS_US).unwrap_or(&10_000));
            let priority = self.r.below(100);
            match period {
                Some(p) => {
                    let _ = writeln!(
                        self.out,
                        "thread t{t} {{ priority: {priority}; period: {}; }}",
                        duration(p)
                    );
                }
                None => {
                    let _ = writeln!(self.out, "thread t{t} {{ priority: {priority}; }}");
                }
            }
            self.periods_us.push(period);
        }
        self.out.push('\n');
    }

    fn plan_services(&mut self, n: usize, threads: usize) {
        let mut next_thread = 0;
        for i in 0..n {
            let autos_from = usize::from(self.cfg.init);
            let kind = if self.cfg.init && i == 0 {
                Kind::Init
            } else if i < autos_from + self.cfg.autos {
                Kind::Auto
            } else if self.r.chance(self.cfg.setters) {
                Kind::Setter
            } else {
                Kind::Plain
            };
            // Every thread gets a service before threads are drawn at random.
            let thread = (kind != Kind::Setter).then(|| {
                if next_thread < threads {
                    next_thread += 1;
                    next_thread - 1
                } else {
                    self.r.below(threads)
                }
            });
            let max_time = self.cfg.timed && kind != Kind::Setter && self.r.chance(0.5);
            self.services.push(ServicePlan {
                name: format!("S{i:02}"),
                kind,
                thread,
                stops: Vec::new(),
                delays: Vec::new(),
                forbids: Vec::new(),
                max_time,
            });
        }
    }

    fn plan_rules(&mut self, n: usize) {
        #[allow(clippy::cast_precision_loss)]
        let p = self.cfg.rule_density / n as f64;
        for s in 0..n {
            for t in 0..n {
                if !self.r.chance(p) {
                    continue;
                }
                let mut kind = self.r.below(4);
                let auto_source = self.services[s].kind == Kind::Auto && !self.cfg.auto_rules;
                if s == t || auto_source {
                    kind = 0;
                }
                let plan = &mut self.services[s];
                match kind {
                    0 | 1 => plan.stops.push(t),
                    2 => plan.delays.push(t),
                    _ => plan.forbids.push(t),
                }
            }
        }
        // Drawn only when asked, so that other configurations keep their text.
        if self.cfg.self_stops > 0.0 {
            for s in 0..n {
                let eligible = matches!(self.services[s].kind, Kind::Init | Kind::Plain);
                if eligible
                    && self.r.chance(self.cfg.self_stops)
                    && !self.services[s].stops.contains(&s)
                {
                    self.services[s].stops.insert(0, s);
                }
            }
        }
    }

    /// Whether something can interrupt service `i`.
    fn interruptible(&self, i: usize) -> bool {
        self.services[i].max_time || self.services.iter().any(|s| s.stops.contains(&i))
    }

    fn service(&mut self, i: usize) {
        let plan = self.services[i].clone();
        let keyword = match plan.kind {
            Kind::Init => "init ",
            Kind::Auto => "auto ",
            Kind::Plain | Kind::Setter => "",
        };
        let _ = writeln!(self.out, "{keyword}service {} {{", plan.name);
        let threaded = plan.kind != Kind::Setter;
        let has_control = match plan.kind {
            Kind::Auto => false,
            Kind::Setter => self.r.chance(0.7),
            Kind::Init | Kind::Plain => self.r.chance(0.3),
        };
        // A service without control codel must produce each report in a `next`.
        let reports = match plan.kind {
            Kind::Auto => 0,
            Kind::Setter if !has_control => 0,
            _ => self.r.below(3),
        };
        let codels = if threaded {
            self.plan_codels(i, plan.kind, reports)
        } else {
            Vec::new()
        };
        if let Some(t) = plan.thread {
            let _ = writeln!(self.out, "  thread: t{t};");
        }
        if reports > 0 {
            let names: Vec<String> = (0..reports).map(report_name).collect();
            let _ = writeln!(self.out, "  report: {};", names.join(", "));
        }
        if plan.max_time {
            let period = plan
                .thread
                .and_then(|t| self.periods_us[t])
                .unwrap_or(10_000);
            let factor = (codels.len() as u64 + 2) * self.r.range(2, 9);
            let _ = writeln!(self.out, "  max-time: {};", duration(period * factor));
        }
        for (attr, list) in [
            ("stops", &plan.stops),
            ("delays", &plan.delays),
            ("forbids", &plan.forbids),
        ] {
            if !list.is_empty() {
                let names: Vec<&str> = list
                    .iter()
                    .map(|&t| self.services[t].name.as_str())
                    .collect();
                let _ = writeln!(self.out, "  {attr}: {};", names.join(", "));
            }
        }
        let params = self.params(plan.kind);
        if has_control {
            let call = self.call(&params, false);
            let wcet = self.cfg.timed.then(|| self.r.range(1, 50));
            let mut body = format!("exec: {};", call.0);
            if let Some(w) = wcet {
                let _ = write!(body, " max-time: {};", duration(w));
            }
            let _ = writeln!(self.out, "  control codel {{ {body} }}");
        }
        let wcet_max = plan.thread.and_then(|t| self.periods_us[t]).map(|p| {
            let sharing = self
                .services
                .iter()
                .filter(|s| s.thread == plan.thread)
                .count() as u64;
            (p / (8 * sharing.max(1))).max(1)
        });
        for k in 0..codels.len() {
            self.codel(&codels, k, &params, wcet_max);
        }
        let _ = writeln!(self.out, "}}\n");
    }

    /// Writes the service's parameters; returns the data they add for its
    /// codels.
    fn params(&mut self, kind: Kind) -> Vec<Data> {
        let mut local = Vec::new();
        let mut inputs = Vec::new();
        let defaults = kind == Kind::Auto || self.r.chance(0.5);
        if self.r.chance(0.4) {
            let ty = Ty::ALL[self.r.below(3)];
            let mut text = format!("{} a", ty.name());
            if defaults {
                let _ = write!(text, " := {}", ty.default_value(&mut self.r));
            }
            inputs.push(text);
            local.push(Data {
                text: "a".to_owned(),
                ty,
                structure: false,
            });
        }
        if self.r.chance(0.3) {
            if let Some(d) = self
                .r
                .pick(&self.data)
                .filter(|d| d.text.starts_with('d'))
                .cloned()
            {
                let mut text = d.text.clone();
                if defaults {
                    let _ = write!(text, " := {}", d.ty.default_value(&mut self.r));
                }
                inputs.push(text);
            }
        }
        if !inputs.is_empty() {
            let _ = writeln!(self.out, "  input: {};", inputs.join(", "));
        }
        if kind != Kind::Auto && self.r.chance(0.3) {
            if self.r.chance(0.5) {
                let ty = Ty::ALL[self.r.below(3)];
                let _ = writeln!(self.out, "  output: {} r;", ty.name());
                local.push(Data {
                    text: "r".to_owned(),
                    ty,
                    structure: false,
                });
            } else if let Some(d) = self
                .r
                .pick(&self.data)
                .filter(|d| d.text.starts_with('d'))
                .cloned()
            {
                let _ = writeln!(self.out, "  output: {};", d.text);
            }
        }
        local
    }

    /// Plans the start, exec and inter codels of threaded service `i`.
    fn plan_codels(&mut self, i: usize, kind: Kind, reports: usize) -> Vec<CodelPlan> {
        let auto = kind == Kind::Auto;
        let total = if auto {
            self.cfg.codels_per_service.max(2)
        } else {
            self.cfg.codels_per_service.max(1)
        };
        let interruptible = self.interruptible(i);
        let inters = if interruptible && total >= 2 {
            (total / 3).max(1)
        } else {
            0
        };
        let main = total - inters;
        let mut codels: Vec<CodelPlan> = (0..total)
            .map(|k| CodelPlan {
                name: if k == 0 {
                    "start".to_owned()
                } else if k < main {
                    format!("e{k}")
                } else {
                    format!("i{}", k - main + 1)
                },
                inter: k >= main,
                ..CodelPlan::default()
            })
            .collect();
        // The tree: every codel has an earlier parent.
        for k in 1..main {
            let parent = self.r.below(k);
            codels[parent].next.push(Out::Codel(k));
        }
        // Extra back edges (loops, never to `start`) and forward edges.
        for (k, codel) in codels.iter_mut().enumerate().take(main) {
            if main > 1 && self.r.chance(self.cfg.loops) {
                let target = 1 + self.r.below(k.max(1));
                push_unique(&mut codel.next, Out::Codel(target));
            }
            if k + 1 < main && self.r.chance(0.2) {
                let target = k + 1 + self.r.below(main - k - 1);
                push_unique(&mut codel.next, Out::Codel(target));
            }
        }
        let leaves: Vec<usize> = (0..main)
            .filter(|&k| !is_tree_parent(&codels, k, main))
            .collect();
        if auto {
            // Leaves loop back: no outcome ever ends an auto service.
            for &k in &leaves {
                let target = if main > 1 {
                    1 + self.r.below(main - 1)
                } else {
                    0
                };
                push_unique(&mut codels[k].next, Out::Codel(target));
            }
        } else {
            for (n, &k) in leaves.iter().enumerate() {
                let out = if n > 0 && reports > 0 && self.r.chance(0.3) {
                    Out::Report(self.r.below(reports))
                } else {
                    Out::End
                };
                push_unique(&mut codels[k].next, out);
            }
            for codel in codels.iter_mut().take(main) {
                if self.r.chance(0.2) {
                    let out = if reports > 0 && self.r.chance(0.5) {
                        Out::Report(self.r.below(reports))
                    } else {
                        Out::End
                    };
                    push_unique(&mut codel.next, out);
                }
            }
        }
        // Inter codels: a forward tree reached through `on-inter`.
        if inters > 0 {
            for k in main + 1..total {
                let parent = main + self.r.below(k - main);
                codels[parent].next.push(Out::Codel(k));
            }
            for (k, codel) in codels.iter_mut().enumerate().skip(main) {
                let leaf = !codel.next.iter().any(|o| matches!(o, Out::Codel(_)));
                if leaf || self.r.chance(0.3) {
                    let out = if !auto && reports > 0 && self.r.chance(0.2) {
                        Out::Report(self.r.below(reports))
                    } else {
                        Out::End
                    };
                    push_unique(&mut codel.next, out);
                }
                if k + 1 < total && self.r.chance(0.2) {
                    let target = k + 1 + self.r.below(total - k - 1);
                    push_unique(&mut codel.next, Out::Codel(target));
                }
            }
            codels[0].on_inter = Some(main);
            for codel in codels.iter_mut().take(main).skip(1) {
                codel.on_inter = Some(main + self.r.below(inters));
            }
        }
        // Every report must be produced by some `next` (no control codel
        // needed for that).
        if !auto {
            for rep in 0..reports {
                if !codels.iter().any(|c| c.next.contains(&Out::Report(rep))) {
                    let k = self.r.below(main);
                    codels[k].next.push(Out::Report(rep));
                }
            }
        }
        codels
    }

    fn codel(&mut self, codels: &[CodelPlan], k: usize, params: &[Data], wcet_max: Option<u64>) {
        let codel = &codels[k];
        let kind = if codel.name == "start" {
            "start codel".to_owned()
        } else if codel.inter {
            format!("inter codel {}", codel.name)
        } else {
            format!("exec codel {}", codel.name)
        };
        let (call, writable) = self.call(params, true);
        let mut body = format!("exec: {call};");
        let updates: Vec<&str> = writable
            .iter()
            .filter(|_| self.r.chance(0.5))
            .map(String::as_str)
            .collect();
        if !updates.is_empty() {
            let _ = write!(body, " update: {};", updates.join(", "));
        }
        if self.cfg.timed {
            let w = self.r.range(1, wcet_max.unwrap_or(1000));
            let _ = write!(body, " max-time: {};", duration(w));
        }
        if let Some(i) = codel.on_inter {
            let _ = write!(body, " on-inter: {};", codels[i].name);
        }
        let next: Vec<String> = codel
            .next
            .iter()
            .map(|o| match *o {
                Out::Codel(t) => codels[t].name.clone(),
                Out::End => "end".to_owned(),
                Out::Report(r) => report_name(r),
            })
            .collect();
        if !next.is_empty() {
            let _ = write!(body, " next: {};", next.join(", "));
        }
        let _ = writeln!(self.out, "  {kind} {{ {body} }}");
    }

    /// A codel function call: a new function or, sometimes, an existing one
    /// with other data of the same types. Returns the text and the
    /// non-`const` structure arguments (which `update` may list).
    fn call(&mut self, params: &[Data], may_reuse: bool) -> (String, Vec<String>) {
        let pool: Vec<Data> = self.data.iter().chain(params).cloned().collect();
        if may_reuse && !self.functions.is_empty() && self.r.chance(0.3) {
            let f = self.functions[self.r.below(self.functions.len())].clone();
            if let Some(args) = self.args_for(&f, &pool) {
                return render_call(&f, &args);
            }
        }
        let arity = self.r.below(4).min(pool.len());
        let mut args: Vec<Data> = Vec::new();
        let mut flags = Vec::new();
        while args.len() < arity {
            let Some(d) = self.r.pick(&pool).cloned() else {
                break;
            };
            if args.contains(&d) {
                continue;
            }
            flags.push((self.r.chance(0.5), d.ty));
            args.push(d);
        }
        let f = Function {
            name: format!("f{}", self.functions.len()),
            args: flags,
        };
        self.functions.push(f.clone());
        render_call(&f, &args)
    }

    /// Distinct data of the prototype's types, if there are enough.
    fn args_for(&mut self, f: &Function, pool: &[Data]) -> Option<Vec<Data>> {
        let mut args: Vec<Data> = Vec::new();
        for &(_, ty) in &f.args {
            let candidates: Vec<&Data> = pool
                .iter()
                .filter(|d| d.ty == ty && !args.contains(d))
                .collect();
            let d = (*self.r.pick(&candidates)?).clone();
            args.push(d);
        }
        Some(args)
    }
}

/// Whether codel `k` has a forward (tree or extra) codel successor among
/// the main codels.
fn is_tree_parent(codels: &[CodelPlan], k: usize, main: usize) -> bool {
    codels[k]
        .next
        .iter()
        .any(|o| matches!(*o, Out::Codel(t) if t > k && t < main))
}

fn push_unique(list: &mut Vec<Out>, o: Out) {
    if !list.contains(&o) {
        list.push(o);
    }
}

fn report_name(r: usize) -> String {
    format!(
        "FAIL_{}",
        char::from(b'A' + u8::try_from(r % 26).unwrap_or(0))
    )
}

fn render_call(f: &Function, args: &[Data]) -> (String, Vec<String>) {
    let mut writable = Vec::new();
    let texts: Vec<String> = f
        .args
        .iter()
        .zip(args)
        .map(|(&(is_const, _), d)| {
            if is_const {
                format!("const {}", d.text)
            } else {
                if d.structure {
                    writable.push(d.text.clone());
                }
                d.text.clone()
            }
        })
        .collect();
    (format!("{}({})", f.name, texts.join(", ")), writable)
}

/// A duration in microseconds as the language writes it.
fn duration(us: u64) -> String {
    if us % 1_000_000 == 0 {
        format!("{}s", us / 1_000_000)
    } else if us % 1_000 == 0 {
        format!("{}ms", us / 1_000)
    } else {
        format!("{us}us")
    }
}

/// Configurations of small components for property tests: 1–6 services,
/// 1–4 codels, 1–3 threads, density 0–3, and every option at random.
/// Only in this crate's tests (proptest is a dev-dependency); elsewhere use
/// `any::<u64>().prop_map(GeneratorConfig::small)`.
#[cfg(test)]
pub fn strategy() -> impl proptest::strategy::Strategy<Value = GeneratorConfig> {
    use proptest::prelude::*;
    (
        any::<u64>(),
        1usize..=6,
        1usize..=4,
        1usize..=3,
        0u32..=12,
        any::<bool>(),
        0usize..=2,
        any::<bool>(),
        prop::bool::weighted(0.2),
        prop_oneof![Just(0.0), Just(0.3)],
        prop_oneof![Just(0.0), Just(0.3), Just(0.6)],
        (0usize..=2, 0usize..=2, prop_oneof![Just(0.0), Just(0.5)]),
    )
        .prop_map(
            |(
                seed,
                services,
                codels,
                threads,
                quarter,
                init,
                autos,
                timed,
                auto_rules,
                setters,
                loops,
                (ids, exports, self_stops),
            )| {
                GeneratorConfig {
                    seed,
                    services,
                    codels_per_service: codels,
                    threads,
                    rule_density: f64::from(quarter) / 4.0,
                    init,
                    autos,
                    timed,
                    auto_rules,
                    setters,
                    loops,
                    ids_blocks: ids,
                    exports,
                    self_stops,
                }
            },
        )
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use genom_model::Severity;
    use genom_parser::MemoryLoader;
    use proptest::prelude::*;

    use super::*;
    use genom_check::{CheckOptions, CheckResult, check_source};

    fn check(text: &str, behaviour: bool) -> CheckResult {
        let options = CheckOptions::new()
            .behaviour(behaviour)
            .max_states(20_000)
            .timeout(Some(std::time::Duration::from_secs(2)));
        check_source(
            Path::new("gen.gen"),
            text.to_owned(),
            &MemoryLoader::new(),
            &options,
        )
    }

    /// Errors and warnings of the static checks, rendered for a failure
    /// message (empty when clean).
    fn problems(text: &str) -> String {
        let result = check(text, false);
        assert!(result.component.is_some(), "no component:\n{text}");
        result
            .diagnostics
            .iter()
            .filter(|d| d.severity >= Severity::Warning)
            .map(|d| format!("{:?} {}\n", d.code, d.message))
            .collect()
    }

    fn assert_clean(cfg: &GeneratorConfig) {
        let text = generate(cfg);
        let p = problems(&text);
        assert!(p.is_empty(), "{cfg:?}\n{p}\n{text}");
    }

    #[test]
    fn small_components_of_200_seeds_check_clean() {
        for seed in 0..200 {
            assert_clean(&GeneratorConfig::small(seed));
        }
    }

    #[test]
    fn benchmark_sizes_check_clean() {
        for seed in 0..10 {
            for (services, codels, threads, density) in [
                (5, 3, 1, 1.0),
                (10, 5, 2, 1.0),
                (30, 5, 4, 1.0),
                (30, 5, 4, 3.0),
                (40, 8, 6, 0.5),
            ] {
                let mut cfg = GeneratorConfig::new(seed, services);
                (cfg.codels_per_service, cfg.threads, cfg.rule_density) =
                    (codels, threads, density);
                (cfg.init, cfg.autos, cfg.timed, cfg.setters) =
                    (seed % 2 == 0, usize::from(seed % 3 == 0), seed % 4 < 2, 0.1);
                assert_clean(&cfg);
            }
        }
    }

    #[test]
    fn generation_is_deterministic() {
        for seed in [0, 1, 42, u64::MAX] {
            let mut cfg = GeneratorConfig::small(seed);
            assert_eq!(generate(&cfg), generate(&cfg.clone()));
            cfg.services = 12;
            assert_eq!(generate(&cfg), generate(&cfg));
        }
        assert_ne!(
            generate(&GeneratorConfig::new(1, 5)),
            generate(&GeneratorConfig::new(2, 5))
        );
    }

    /// The generator's output is fixed by its definition: this digest
    /// changes only when the generator itself changes.
    #[test]
    fn output_is_stable() {
        let mut cfg = GeneratorConfig::new(7, 4);
        (cfg.init, cfg.autos, cfg.timed) = (true, 1, true);
        let text = generate(&cfg);
        let digest = text.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
        assert_eq!(digest, STABLE_DIGEST, "{text}");
    }

    const STABLE_DIGEST: u64 = 12_496_380_282_404_570_434;

    #[test]
    fn the_prng_is_splitmix64() {
        // Reference values of splitmix64 seeded with 1234567.
        let mut r = SplitMix::new(1_234_567);
        assert_eq!(r.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(r.next_u64(), 3_203_168_211_198_807_973);
    }

    #[test]
    fn the_requested_structure_is_there() {
        let mut cfg = GeneratorConfig::new(3, 8);
        (cfg.init, cfg.autos, cfg.threads, cfg.codels_per_service) = (true, 2, 3, 4);
        let result = check(&generate(&cfg), false);
        let c = result.component.expect("a component");
        assert_eq!(c.services.len(), 8);
        assert_eq!(c.threads.len(), 3);
        assert!(c.init_service().is_some());
        let autos = c
            .services
            .values()
            .filter(|s| s.kind == genom_model::kinds::ServiceKind::Auto)
            .count();
        assert_eq!(autos, 2);
        for s in c.services.values() {
            let threaded = s
                .codels
                .iter()
                .filter(|&&k| c.codels[k].kind != genom_model::kinds::CodelKind::Control);
            assert_eq!(threaded.count(), 4, "{}", s.name.name);
        }
    }

    #[test]
    fn timed_components_have_wcets_below_the_period() {
        for seed in 0..20 {
            let mut cfg = GeneratorConfig::new(seed, 10);
            (cfg.timed, cfg.threads, cfg.codels_per_service) = (true, 3, 4);
            let c = check(&generate(&cfg), false)
                .component
                .expect("a component");
            for s in c.services.values() {
                let Some(t) = s.thread else { continue };
                let period = c.threads[t.id].period.map(|p| p.ns).expect("periodic");
                for &k in &s.codels {
                    let wcet = c.codels[k].wcet.map(|m| m.ns).expect("a WCET");
                    assert!(wcet <= period, "{} {wcet} > {period}", s.name.name);
                }
            }
        }
    }

    /// The engine runs on generated components without panicking.
    #[test]
    fn the_engine_runs_on_small_components() {
        for seed in 0..40 {
            let result = check(&generate(&GeneratorConfig::small(seed)), true);
            assert!(result.statistics.is_some(), "seed {seed}");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn generated_components_check_clean(cfg in strategy()) {
            let text = generate(&cfg);
            prop_assert_eq!(problems(&text), "");
        }
    }
}
