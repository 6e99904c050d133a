//! From a [`Genom3Config`] to a [`Plan`]: data, tasks, services and the
//! `interrupts`/`after`/`before` relations, every choice drawn from one
//! splitmix64 stream in a fixed order.

use super::config::Genom3Config;
use super::fsm::{Pool, Shape, machine};
use super::plan::{
    ControlCodel, DataPath, DataTy, Dir, Kind, Param, Plan, PortPlan, ServiceParam, ServicePlan,
    Source, TaskPlan,
};
use crate::rng::SplitMix;

/// The component's name (the prefix of every codel function).
const NAME: &str = "rnd";

/// Periods and delays to draw from, in milliseconds.
const PERIODS: [u64; 3] = [10, 20, 50];
const DELAYS: [u64; 3] = [1, 2, 5];

/// Plans the whole component.
pub(crate) fn plan(cfg: &Genom3Config) -> Plan {
    let mut r = SplitMix::new(cfg.seed);
    let (members, paths) = data(&mut r);
    let ports = if cfg.ports {
        let mut ports = vec![PortPlan {
            name: "p_out".into(),
            out: true,
        }];
        if r.chance(0.5) {
            ports.push(PortPlan {
                name: "p_in".into(),
                out: false,
            });
        }
        ports
    } else {
        Vec::new()
    };
    let mut plan = Plan {
        name: NAME.into(),
        exceptions: vec!["e_fail".into(), "e_busy".into()],
        members,
        paths,
        ports,
        tasks: Vec::new(),
        services: Vec::new(),
    };
    plan.tasks = (0..cfg.tasks.max(1))
        .map(|t| task(&mut r, cfg, &plan, t))
        .collect();
    for i in 0..cfg.activities {
        let s = activity(&mut r, cfg, &plan, i);
        plan.services.push(s);
    }
    for i in 0..cfg.functions {
        let s = function(&mut r, &plan, i);
        plan.services.push(s);
    }
    for i in 0..cfg.attributes {
        let s = attribute(&mut r, &plan, i);
        plan.services.push(s);
    }
    relations(&mut r, cfg, &mut plan.services);
    plan
}

/// The ids members `m0`, `m1`, ... (2 to 4, of cycling types) and every
/// path a codel may name in them.
fn data(r: &mut SplitMix) -> (Vec<(String, DataTy)>, Vec<DataPath>) {
    const TYPES: [DataTy; 4] = [DataTy::Long, DataTy::Pose, DataTy::Double, DataTy::Cmd];
    let count = 2 + r.below(3);
    let first = r.below(TYPES.len());
    let members: Vec<(String, DataTy)> = (0..count)
        .map(|i| (format!("m{i}"), TYPES[(first + i) % TYPES.len()]))
        .collect();
    let mut paths = Vec::new();
    for (name, ty) in &members {
        paths.push(DataPath {
            path: name.clone(),
            ty: *ty,
        });
        for (sub, t) in ty.members() {
            paths.push(DataPath {
                path: format!("{name}.{sub}"),
                ty: t,
            });
        }
    }
    (members, paths)
}

fn task(r: &mut SplitMix, cfg: &Genom3Config, plan: &Plan, t: usize) -> TaskPlan {
    let periodic = cfg.timed || r.chance(0.7);
    let period_ms = periodic.then(|| PERIODS[r.below(PERIODS.len())]);
    let delay_ms = (periodic && r.chance(0.25)).then(|| DELAYS[r.below(DELAYS.len())]);
    let fsm = (cfg.permanent && (t == 0 || r.chance(0.5))).then(|| {
        let pool = Pool {
            paths: &plan.paths,
            locals: &[],
            ports: &plan.ports,
        };
        let shape = Shape {
            endless: 0.6,
            stop: 0.6,
            ..shape(cfg)
        };
        machine(r, &format!("{NAME}_t{t}"), &shape, &pool)
    });
    TaskPlan {
        name: format!("t{t}"),
        period_ms,
        delay_ms,
        fsm,
    }
}

fn shape(cfg: &Genom3Config) -> Shape {
    Shape {
        states: cfg.states,
        pauses: cfg.pauses,
        unpaused_cycles: cfg.unpaused_cycles,
        asyncs: cfg.asyncs,
        endless: 0.15,
        stop: 0.5,
    }
}

/// An empty service of `kind`.
fn service(name: String, kind: Kind) -> ServicePlan {
    ServicePlan {
        name,
        kind,
        task: None,
        params: Vec::new(),
        interrupts: Vec::new(),
        interrupts_all: false,
        after: Vec::new(),
        before: Vec::new(),
        throws: Vec::new(),
        validate: None,
        codels: Vec::new(),
        fsm: None,
    }
}

/// Typed service parameters: `in` ones from `ins` (each with probability
/// 1/2, with a default sometimes), an `out` one sometimes.
fn typed_params(
    r: &mut SplitMix,
    ins: &[(&str, &'static str)],
    out: (&str, &'static str),
) -> Vec<ServiceParam> {
    let mut params = Vec::new();
    for (k, &(name, ty)) in ins.iter().enumerate() {
        if r.chance(0.5) {
            let default = r.chance(0.3).then(|| {
                if ty == "long" {
                    format!("{}", k + 2)
                } else {
                    format!("{k}.5")
                }
            });
            params.push(ServiceParam {
                dir: Dir::In,
                ty,
                name: name.to_owned(),
                default,
            });
        }
    }
    if r.chance(0.3) {
        params.push(ServiceParam {
            dir: Dir::Out,
            ty: out.1,
            name: out.0.to_owned(),
            default: None,
        });
    }
    params
}

/// A control codel reading the service's `in` parameters and ids data.
fn control(
    r: &mut SplitMix,
    plan: &Plan,
    function: String,
    locals: &[ServiceParam],
) -> ControlCodel {
    let pool = Pool {
        paths: &plan.paths,
        locals,
        ports: &[],
    };
    let count = r.below(3);
    ControlCodel {
        function,
        params: pool.pick(r, count),
    }
}

fn throws(r: &mut SplitMix, plan: &Plan) -> Vec<usize> {
    if !r.chance(0.3) {
        return Vec::new();
    }
    let first = r.below(plan.exceptions.len());
    if r.chance(0.3) {
        (0..plan.exceptions.len()).collect()
    } else {
        vec![first]
    }
}

fn activity(r: &mut SplitMix, cfg: &Genom3Config, plan: &Plan, i: usize) -> ServicePlan {
    let name = format!("a{i}");
    let mut s = service(name.clone(), Kind::Activity);
    s.task = Some(r.below(plan.tasks.len()));
    s.params = typed_params(
        r,
        &[("a_goal", "long"), ("a_gain", "double")],
        ("a_res", "double"),
    );
    s.throws = throws(r, plan);
    let ins = inputs(&s.params);
    if r.chance(0.2) {
        s.validate = Some(control(r, plan, format!("{NAME}_{name}_validate"), &ins));
    }
    let pool = Pool {
        paths: &plan.paths,
        locals: &s.params,
        ports: &plan.ports,
    };
    s.fsm = Some(machine(r, &format!("{NAME}_{name}"), &shape(cfg), &pool));
    s
}

/// The `in` parameters of a service (what its `validate` may read).
fn inputs(params: &[ServiceParam]) -> Vec<ServiceParam> {
    params
        .iter()
        .filter(|p| p.dir == Dir::In)
        .cloned()
        .collect()
}

fn function(r: &mut SplitMix, plan: &Plan, i: usize) -> ServicePlan {
    let name = format!("f{i}");
    let mut s = service(name.clone(), Kind::Function);
    s.params = typed_params(r, &[("f_x", "long"), ("f_k", "double")], ("f_y", "double"));
    s.throws = throws(r, plan);
    let ins = inputs(&s.params);
    if r.chance(0.3) {
        s.validate = Some(control(r, plan, format!("{NAME}_{name}_validate"), &ins));
    }
    let codels = match r.below(10) {
        0 | 1 => 0,
        2 | 3 => 2,
        _ => 1,
    };
    for k in 0..codels {
        let suffix = if k == 0 {
            String::new()
        } else {
            (k + 1).to_string()
        };
        let c = control(r, plan, format!("{NAME}_{name}_codel{suffix}"), &s.params);
        s.codels.push(c);
    }
    s
}

/// An attribute of one or two ids paths, each set (`in`) or read
/// (`out`), maybe with a `validate` codel reading the new values.
fn attribute(r: &mut SplitMix, plan: &Plan, i: usize) -> ServicePlan {
    let name = format!("attr{i}");
    let mut s = service(name.clone(), Kind::Attribute);
    let mut taken: Vec<&DataPath> = Vec::new();
    for _ in 0..1 + r.below(2) {
        let Some(p) = r.pick(&plan.paths) else { break };
        if taken
            .iter()
            .any(|t| t.overlaps(&p.path) || t.last() == p.last())
        {
            continue;
        }
        taken.push(p);
        let dir = if r.chance(0.6) { Dir::In } else { Dir::Out };
        let default = if dir == Dir::In && r.chance(0.4) {
            p.ty.default_value(1 + r.below(9))
        } else {
            None
        };
        s.params.push(ServiceParam {
            dir,
            ty: "",
            name: p.path.clone(),
            default,
        });
    }
    if r.chance(0.4) {
        let locals: Vec<ServiceParam> = taken
            .iter()
            .zip(&s.params)
            .filter(|(_, sp)| sp.dir == Dir::In)
            .map(|(p, _)| ServiceParam {
                dir: Dir::In,
                ty: "",
                name: p.last().to_owned(),
                default: None,
            })
            .collect();
        let mut v = control(r, plan, format!("{NAME}_{name}_validate"), &[]);
        // The attribute's own names are locals too: ids paths say `ids`.
        for p in &mut v.params {
            if p.path != "::ids" {
                p.source = Source::Ids;
            }
        }
        // The new values, as `local in NAME` (attributes name their
        // parameters after the path's last component).
        for l in &locals {
            let clash = v
                .params
                .iter()
                .any(|p| p.path.rsplit('.').next() == Some(l.name.as_str()));
            if !clash {
                v.params.push(Param {
                    source: Source::Local,
                    dir: Dir::In,
                    path: l.name.clone(),
                });
            }
        }
        s.validate = Some(v);
    }
    s
}

/// `interrupts`, `after` and `before`: every ordered pair of services gets
/// a reference with probability `density / services` (half `interrupts`,
/// a quarter each `after` and `before`; only `interrupts` may name the
/// service itself); `interrupts all` now and then when density > 0.
fn relations(r: &mut SplitMix, cfg: &Genom3Config, services: &mut [ServicePlan]) {
    let n = services.len();
    if n == 0 || cfg.density <= 0.0 {
        return;
    }
    #[allow(clippy::cast_precision_loss)]
    let p = cfg.density / n as f64;
    for (s, service) in services.iter_mut().enumerate() {
        for t in 0..n {
            if !r.chance(p) {
                continue;
            }
            match r.below(4) {
                0 | 1 => service.interrupts.push(t),
                2 if t != s => service.after.push(t),
                3 if t != s => service.before.push(t),
                _ => {}
            }
        }
        service.interrupts_all = r.chance(0.03);
    }
}
