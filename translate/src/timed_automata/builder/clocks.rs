//! The declarations: clocks (periods, executions, control, watchdogs) and
//! integer variables (services' positions, pending flags and wait bits,
//! threads' eligible sets and orders, locks) with their descriptions.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use genom_model::behaviour::{IDLE, PosId};
use genom_model::component::{ServiceId, StructureId, ThreadId};
use genom_model::kinds::ServiceKind;
use genom_model::timed_automata::{ClockRole, ServiceVars};

use super::units::{cluster_of, unit_ns, units};
use super::{Builder, Svc, Thr, position_class};

impl<'a> Builder<'a> {
    /// Declares the clocks and variables.
    pub(super) fn declare(&mut self) {
        let c = self.c;
        let all: Vec<ServiceId> = c.services.ids().collect();
        let unit = self.net.unit_ns;
        let cspan = c.name.span;
        let has_init = c.init_service().is_some();
        self.init_done = self.int(
            "init_done",
            None,
            0,
            1,
            i64::from(!has_init),
            cspan,
            "1 once the init service has completed successfully".to_owned(),
        );
        self.net.frozen = self.int(
            "frozen",
            None,
            0,
            1,
            0,
            cspan,
            "1 while a watchdog probes whether time can pass its max-time (every other step waits)"
                .to_owned(),
        );
        // Threads (those running some service), in thread order.
        let mut thread_members: BTreeMap<ThreadId, Vec<ServiceId>> = BTreeMap::new();
        for &s in &all {
            if let Some(t) = c.services[s].thread.map(|t| t.id) {
                thread_members.entry(t).or_default().push(s);
            }
        }
        let clusters = cluster_of(c);
        let mut max_const = 0i64;
        // Thread clocks first (the engine's order), then control, then
        // watchdogs.
        let mut thrs = Vec::new();
        for (&t, members) in &thread_members {
            let th = &c.threads[t];
            let period = th.period.map(|p| units(p.ns, unit));
            let period_clock = period.map(|p| {
                max_const = max_const.max(p);
                self.clock(
                    &format!("{}_period", th.name.name),
                    ClockRole::Period(t),
                    th.name.span,
                    format!(
                        "time since the last wake-up of thread {} (period {p})",
                        th.name.name
                    ),
                )
            });
            let exec_clock = self.clock(
                &format!("{}_exec", th.name.name),
                ClockRole::Exec(t),
                th.name.span,
                format!("time since thread {} began its running codel", th.name.name),
            );
            thrs.push((t, period, members.clone(), period_clock, exec_clock));
        }
        if c.services.values().any(|s| s.control.is_some()) {
            self.ctl_clock = Some(self.clock(
                "control_exec",
                ClockRole::Control,
                cspan,
                "time since the control thread began the running control codel".to_owned(),
            ));
        }
        // Services.
        let n = c.services.len();
        let index = |s: ServiceId| s.0 as usize;
        for &s in &all {
            let svc = &c.services[s];
            let m = self.machine(s);
            let mut order: Vec<PosId> = (1..m.positions.len())
                .filter_map(|i| PosId::try_from(i).ok())
                .collect();
            order.sort_by_key(|&p| (position_class(m.positions[usize::from(p)]), p));
            order.insert(0, IDLE);
            let mut value = vec![0i64; m.positions.len()];
            for (v, &p) in order.iter().enumerate() {
                value[usize::from(p)] = v as i64;
            }
            let mut bounds = [0i64; 5];
            for (k, slot) in bounds.iter_mut().enumerate() {
                let class = u8::try_from(k + 1).unwrap_or(0);
                *slot = order
                    .iter()
                    .position(|&p| position_class(m.positions[usize::from(p)]) >= class)
                    .unwrap_or(order.len()) as i64;
            }
            let mut desc = format!("position of {}'s main instance:", svc.name.name);
            for (v, &p) in order.iter().enumerate() {
                let _ = write!(
                    desc,
                    " {v} {};",
                    self.position_text(m.positions[usize::from(p)])
                );
            }
            desc.pop();
            let pos = self.int(
                &format!("{}_pos", svc.name.name),
                None,
                0,
                order.len() as i64 - 1,
                0,
                svc.name.span,
                desc,
            );
            let pend = self.int(
                &format!("{}_pend", svc.name.name),
                None,
                0,
                1,
                0,
                svc.name.span,
                format!("1 when {} has a pending instance", svc.name.name),
            );
            let mut stops: Vec<ServiceId> = Vec::new();
            for r in &svc.stops {
                if !stops.contains(&r.id) {
                    stops.push(r.id);
                }
            }
            let wait = (!stops.is_empty()).then(|| {
                let names: Vec<&str> = stops.iter().map(|&t| self.sname(t)).collect();
                self.int(
                    &format!("{}_wait", svc.name.name),
                    Some(u32::try_from(stops.len()).unwrap_or(u32::MAX)),
                    0,
                    1,
                    0,
                    svc.name.span,
                    format!(
                        "wait bits of {}'s pending instance, one per stops target ({})",
                        svc.name.name,
                        names.join(", ")
                    ),
                )
            });
            let tmo = svc.max_time.map(|mt| {
                self.int(
                    &format!("{}_timed_out", svc.name.name),
                    None,
                    0,
                    1,
                    0,
                    mt.span,
                    format!(
                        "1 when {}'s main instance was interrupted by its watchdog",
                        svc.name.name
                    ),
                )
            });
            let others = |rule: fn(
                &genom_model::component::Service,
            ) -> &Vec<genom_model::component::Ref<ServiceId>>| {
                c.services
                    .iter()
                    .filter(|&(t, ts)| t != s && rule(ts).iter().any(|r| r.id == s))
                    .map(|(t, _)| t)
                    .collect::<Vec<ServiceId>>()
            };
            let ctl_wcet = svc
                .control
                .map(|k| c.codels[k].wcet.map_or(0, |w| units(w.ns, unit)));
            if let Some(w) = ctl_wcet {
                max_const = max_const.max(w);
            }
            self.svcs.push(Svc {
                id: s,
                name: svc.name.name.clone(),
                pos,
                pend,
                wait,
                tmo,
                order,
                value,
                bounds,
                self_stop: svc.stops.iter().any(|r| r.id == s),
                stops,
                delayers: others(|t| &t.delays),
                forbidders: others(|t| &t.forbids),
                auto: svc.kind == ServiceKind::Auto,
                control_uses: svc
                    .control
                    .map(|k| c.codels[k].structures())
                    .unwrap_or_default(),
                placement: None,
                watch: None,
                watch_exact: true,
                armed: None,
                watchdog: svc.max_time.is_some(),
                ctl_wcet,
            });
        }
        let _ = n;
        // Threads' variables.
        for (t, period, members, period_clock, exec_clock) in thrs {
            let th = &c.threads[t];
            let k = members.len();
            let kk = k as i64;
            let names: Vec<&str> = members.iter().map(|&s| self.sname(s)).collect();
            let slots = names
                .iter()
                .enumerate()
                .map(|(i, n)| format!("{i} {n}"))
                .collect::<Vec<_>>()
                .join(", ");
            let elig = self.int(
                &format!("{}_eligible", th.name.name),
                Some(u32::try_from(k + 1).unwrap_or(u32::MAX)),
                0,
                1,
                0,
                th.name.span,
                format!(
                    "slots of thread {} that still run a codel this {} (slots: {slots}; the last element is always 0)",
                    th.name.name,
                    if period.is_some() { "period" } else { "round" }
                ),
            );
            let ord = self.int(
                &format!("{}_order", th.name.name),
                Some(u32::try_from(k).unwrap_or(u32::MAX)),
                0,
                kk,
                kk,
                th.name.span,
                format!(
                    "slots of thread {} with an instance, in acknowledgment order ({kk}: empty)",
                    th.name.name
                ),
            );
            let turn = self.int(
                &format!("{}_turn", th.name.name),
                None,
                0,
                kk,
                kk,
                th.name.span,
                format!(
                    "first eligible slot of thread {} in acknowledgment order ({kk}: none)",
                    th.name.name
                ),
            );
            let busy = self.int(
                &format!("{}_busy", th.name.name),
                None,
                0,
                1,
                0,
                th.name.span,
                format!("1 while thread {} runs a codel", th.name.name),
            );
            let idx = self.thrs.len();
            for (slot, &s) in members.iter().enumerate() {
                self.svcs[index(s)].placement = Some((idx, slot));
            }
            for &s in &members {
                for &k in &c.services[s].codels {
                    if Some(k) != c.services[s].control {
                        max_const = max_const.max(self.wcet[k.0 as usize]);
                    }
                }
            }
            self.thrs.push(Thr {
                id: t,
                name: th.name.name.clone(),
                period,
                members,
                period_clock,
                exec_clock,
                elig,
                ord,
                turn,
                busy,
            });
        }
        // Locks: structures used by codels that run on a thread.
        let nthreads = self.thrs.len() as i64;
        let mut used: BTreeSet<StructureId> = BTreeSet::new();
        for s in &self.svcs {
            if s.placement.is_none() {
                continue;
            }
            for k in self.running_codels(s.id) {
                used.extend(c.codels[k].structures().into_iter().map(|(d, _)| d));
            }
        }
        for d in used {
            let st = &c.structures[d];
            let path = st.path();
            let r = self.int(
                &format!("lock_{}_r", path),
                None,
                0,
                nthreads,
                0,
                st.span,
                format!("running thread codels that read {path} (const)"),
            );
            let w = self.int(
                &format!("lock_{}_w", path),
                None,
                0,
                nthreads,
                0,
                st.span,
                format!("running thread codels that may write {path}"),
            );
            self.locks.insert(d, (r, w));
        }
        if self.ctl_clock.is_some() {
            let n = c.services.len() as i64;
            let names = self
                .svcs
                .iter()
                .filter(|s| s.ctl_wcet.is_some())
                .map(|s| format!("{} {}", s.id.0, s.name))
                .collect::<Vec<_>>()
                .join(", ");
            self.ctl = Some(self.int(
                "control_running",
                None,
                0,
                n,
                n,
                cspan,
                format!("the service whose control codel runs ({names}; {n}: none)"),
            ));
        }
        // Watchdog clocks.
        for &s in &all {
            let svc = &c.services[s];
            let Some(mt) = svc.max_time else { continue };
            // The engine computes the max-time in its cluster's unit
            // (exact for services with a start codel; truncated otherwise).
            let cl = &clusters[s.0 as usize];
            let cu = unit_ns(c, cl);
            // As the engine: exact, or from the horizon on for a looping
            // service whose max-time is beyond it.
            let (ns, exact) = c.watchdog_instant_ns(s, self.machine(s).active_loop, cl);
            let max = units(ns, cu).saturating_mul(i64::try_from(cu / unit.max(1)).unwrap_or(1));
            self.svcs[index(s)].watch_exact = exact;
            max_const = max_const.max(max);
            let clock = self.clock(
                &format!("{}_watch", svc.name.name),
                ClockRole::Watchdog(s),
                mt.span,
                format!(
                    "time since {}'s instance was acknowledged (max-time {max})",
                    svc.name.name
                ),
            );
            self.svcs[index(s)].watch = Some((clock, max));
            let armed = self.int(
                &format!("{}_armed", svc.name.name),
                None,
                0,
                1,
                0,
                mt.span,
                format!(
                    "1 while {}'s watchdog follows an instance (its location `on`)",
                    svc.name.name
                ),
            );
            self.svcs[index(s)].armed = Some(armed);
        }
        self.net.horizon = max_const + 1;
        self.net.services = self
            .svcs
            .iter()
            .map(|s| ServiceVars {
                service: s.id,
                name: s.name.clone(),
                pos: s.pos,
                pend: s.pend,
                wait: s.wait,
                timed_out: s.tmo,
                positions: s.order.clone(),
                watchdog: s.watchdog,
                delayers: s.delayers.clone(),
            })
            .collect();
    }
}
