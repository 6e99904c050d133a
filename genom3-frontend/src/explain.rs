//! Long explanations (Markdown, as `genom-check explain CODE` prints them
//! after the code's one-line meaning) of the diagnostic codes the GenoM3
//! front end adds; [`crate::Genom3Frontend`] gives them to
//! `genom-check explain`.

use genom_model::Code;

/// The explanation of a code added by the GenoM3 front end (`None` for
/// other codes).
pub fn explanation(code: Code) -> Option<&'static str> {
    Some(match code {
        Code::IgnoredDirective => IGNORED_DIRECTIVE,
        Code::UnknownState => UNKNOWN_STATE,
        Code::UnreachableState => UNREACHABLE_STATE,
        Code::StopNoEther => STOP_NO_ETHER,
        Code::AsyncSharedData => ASYNC_SHARED_DATA,
        Code::UnknownInterface => UNKNOWN_INTERFACE,
        Code::MissingSource => MISSING_SOURCE,
        Code::BadWcet => BAD_WCET,
        _ => return None,
    })
}

const IGNORED_DIRECTIVE: &str = "\
GenoM3 files go through a C preprocessor. genom-check preprocesses them
itself and interprets `#include`, include guards (`#ifndef`, `#define`,
`#endif`, `#if defined(X)`, `#elif`, `#else`) and the pragmas `require`,
`provides` and `masquerade`. Any other directive (for example `#line`,
`#warning` or `#pragma once`) is skipped; this advice says so, because a
macro the file relies on is not expanded.

```
#warning \"experimental\"   // advice: `#warning` is ignored
```
";

const UNKNOWN_STATE: &str = "\
Each GenoM3 codel runs in the states listed between `<` and `>` and yields
the states that may run next; `ether` ends the activity (or the task's
state machine). A yield (or a `pause::` yield) must name a state that some
codel of the same activity or task runs in.

```
codel<start> go_start() yield exec;      // error: no codel<exec>
codel<main> go_main() yield ether;
```

Fix the name, or add `codel<exec> ...`.
";

const UNREACHABLE_STATE: &str = "\
Every codel of a state machine must be reachable by yields from
`codel<start>` (or, for cleanup, from `codel<stop>`). A codel no path reaches
never runs: usually a typo in a yield. GenoM3 rejects such a component.

```
codel<start> s() yield ether;
codel<spin> p() yield spin, ether;       // error: never reached
```
";

const STOP_NO_ETHER: &str = "\
`codel<stop>` runs when an activity is interrupted (or the component stops
a task). Some path of yields from it must end in `ether`, otherwise the
interrupted activity could never finish. GenoM3 rejects such a component.

```
codel<stop> halt() yield halt;           // error: loops forever
```

Make the cleanup end: `yield ether` (or `yield pause::halt, ether`).
";

const ASYNC_SHARED_DATA: &str = "\
An `async` codel runs outside its task's execution: it must not share ids
data with a codel that can run at the same time in another task, or with a
control codel (`validate`, a function's codel, an attribute), when one of
them writes it. (A task's `codel<start>` and codels only reached from
`codel<stop>` are exempt: they never overlap.) GenoM3 rejects such a
component.

```
task io { async codel<start> poll(out buf) yield ether; };
activity read() { task main; codel<start> r(in buf) yield ether; };  // error
```

Pass the data through a port, or give each task its own ids member.
";

const UNKNOWN_INTERFACE: &str = "\
`provides I` copies interface `I`'s ids, ports, attributes and services
into the component; `uses I` connects to a component that provides it (its
ports flip direction and its services become remotes). `I` must be
declared, usually by including its `.gen` file: check the `#include` and
the `-I` folders.

```
#include \"or/pose/pose_estimator.gen\"
component c { provides or_pose_estimator; };
```
";

const MISSING_SOURCE: &str = "\
A codel parameter without a source (`ids`, `local`, `port` or `remote`)
is looked up among the service's parameters and locals, the ids members,
the ports and the remotes. When the name is found in more than one of
them, GenoM3 refuses to guess: write the source.

```
ids { double x; };
activity a(in double x) {
  codel<start> f(in x) yield ether;         // error: parameter or ids member?
  codel<start> f(local in x) yield ether;   // the service parameter
};
```
";

const BAD_WCET: &str = "\
A WCET side file gives the worst-case execution time of GenoM3 codels, one
per line: `OWNER.STATE DURATION`. OWNER is a service (STATE one of its
codel states, or `validate` / `codel` for the control codels of a function
or attribute) or a task (STATE a state of its permanent codels). `#`
starts a comment. A malformed line, an unknown owner or an unknown state
is an error in the WCET file.

```
# demo.wcet
servo.start   200us
main.control  1.2ms
servo.strat   1ms     # error: service `servo` has no codel state `strat`
```
";

#[cfg(test)]
mod tests {
    use super::explanation;
    use genom_model::Code;

    #[test]
    fn every_new_code_is_explained() {
        for code in [
            Code::IgnoredDirective,
            Code::UnknownState,
            Code::UnreachableState,
            Code::StopNoEther,
            Code::AsyncSharedData,
            Code::UnknownInterface,
            Code::MissingSource,
            Code::BadWcet,
        ] {
            assert!(
                explanation(code).is_some_and(|t| t.contains("```")),
                "{code}"
            );
        }
        assert!(explanation(Code::Syntax).is_none());
    }
}
