//! The `genom-check explain` texts of the system file's codes.

use genom_model::Code;

/// The explanation of `code`, when it is one of the system file's.
pub fn explanation(code: Code) -> Option<&'static str> {
    Some(match code {
        Code::BadSystem => {
            "A system file (`genom-check check --system FILE`) is TOML: `[component.NAME]` tables \
with `file`, `wcet` and `steady`, `[external.NAME]` tables with `period` and `feeds`, \
`[[connect]]` entries with `from` and `to`, `[[chain]]` entries with `to`, `from` and \
`deadline`. This code reports text that is not TOML, a key the file does not know, or a \
value of the wrong form, at the place in the file.\n\n```toml\n[external.pose]\nperiod = \"fast\"   # bad-system: not a duration such as `1ms`\n```\n\nSee docs/functional-layer.md."
        }
        Code::UnknownSystemName => {
            "A system file names a component that no `[component.NAME]` declares, a port that \
the component does not have (ports of provided and used interfaces included, with `uses` \
flipping their direction), a service that the component does not have (in `steady`), or an \
external source that no `[external.NAME]` declares (in a chain's `from`).\n\n```toml\n[[connect]]\nfrom = \"maneuver.desire\"   # unknown-system-name: did you mean `desired`?\nto = \"uavpos.reference\"\n```"
        }
        Code::PortTypeMismatch => {
            "A connection joins an out port to an in port whose IDL types differ. Types are \
compared structurally across the two components: base types, string and sequence bounds, \
array lengths, and structs and enums by their qualified names and members, aliases \
resolved. An external source's in ports must all have one type.\n\n```toml\n[[connect]]\nfrom = \"maneuver.desired\"      # or_rigid_body::state\nto = \"uavatt.uav_input\"       # or_uav::input: port-type-mismatch\n```"
        }
        Code::DuplicateConnection => {
            "An in port reads one out port (GenoM3's `connect_port`). The system file connects \
this in port twice: twice from the same out port, from two out ports, or from a connection \
and an external source. Keep one.\n\n```toml\n[[connect]]\nfrom = \"a.out\"\nto = \"b.in\"\n[[connect]]\nfrom = \"a.out\"\nto = \"b.in\"   # duplicate-connection\n```"
        }
        Code::BadConnection => {
            "A connection goes from an out port to an in port; an external source feeds in \
ports; a chain starts at an out port or an external source and ends at an in port (or a \
component, for its every in port). This code reports one of these written the wrong way.\n\n```toml\n[[connect]]\nfrom = \"uavpos.reference\"   # bad-connection: an in port\nto = \"uavatt.uav_input\"\n```"
        }
        Code::UnconnectedInput => {
            "An in port of a component of the system that no connection and no external \
source feeds: the component would read nothing there. Connect it, or declare where its data \
comes from with an `[external.NAME]` table that `feeds` it (the warning goes away).\n\n```toml\n[external.pose]\nperiod = \"1ms\"\nfeeds = [\"uavatt.state\"]\n```"
        }
        Code::ChainDeadlineMiss => {
            "A cause-effect chain (`[[chain]]` with `deadline`, or `--chain FROM->TO<=DURATION`) \
whose worst-case data age or reaction time, composed from each component's timing, is \
longer than its deadline; or that has no bound at all (a task on it can overrun, is \
aperiodic, or lacks WCETs). The diagnostic carries the timeline that reaches the bound: \
which codel of which task read and wrote what, when. The bound rests on the WCET files, \
the steady state the file declares (`steady`), one request at a time, and the platform of \
docs/functional-layer.md (each component a process, each task on its own core).\n\n```toml\n[[chain]]\nfrom = \"maneuver.desired\"\nto = \"rotorcraft.rotor_input\"\ndeadline = \"5ms\"   # chain-deadline-miss when the data age can reach more\n```"
        }
        Code::ChainUnbounded => {
            "A chain the system file or the command line asks for gets no number: a task on \
it has no period (nothing bounds when it runs), can overrun its period (the timed engine \
shows a trace with `genom-check check` on the component), its exploration stopped, or a \
codel on it has no WCET; or no data path goes from the source to the sink. The message \
says which. Listing the services clients call in flight (`steady = [...]`) often removes an \
overrun caused by a service that is not called then (a log function).\n\n```toml\n[component.uavatt]\nfile = \"uavatt.gen\"\nwcet = \"uavatt.wcet\"\nsteady = [\"servo\"]\n```"
        }
        _ => return None,
    })
}
