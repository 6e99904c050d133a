//! The built-in `genom` interface every GenoM3 component provides: the
//! generic exceptions and the services the middleware adds to each
//! component. A minimal reconstruction, written for genom-check from how
//! components and clients use it (not the text of `genom.gen`).

/// The virtual path it is loaded under (shown in diagnostics).
pub(crate) const PATH: &str = "<built-in>/genom.gen";

/// Its text.
pub(crate) const GENOM_GEN: &str = r#"/* built-in interface of genom-check's GenoM3 front end */
interface genom {
  exception bad_transition { string<128> from, to; };
  exception interrupted { string<128> by; };
  exception serialization, too_many_activities, disallowed;
  exception no_such_activity, no_such_inport, no_such_outport, port_io;
  exception no_such_remote, no_such_service, remote_io;
  exception mwerr { string<256> what; };
  throws bad_transition, interrupted, serialization, too_many_activities, disallowed, mwerr;

  function kill() {
    doc "Interrupts every activity, then stops the component";
    interrupts all;
  };
  function abort_activity(in unsigned long activity = : "id of the activity") {
    doc "Interrupts one activity";
    throws no_such_activity;
  };
  function connect_port(in string<128> local = : "input port", in string<128> remote = : "output port") {
    doc "Connects an input port to another component's output port";
    throws no_such_inport, no_such_outport, port_io;
  };
  function connect_service(in string<128> local = : "remote", in string<128> remote = : "service") {
    doc "Binds a remote to another component's service";
    throws no_such_remote, no_such_service, remote_io;
  };
};
"#;
