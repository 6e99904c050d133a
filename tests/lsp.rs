//! `genom-check lsp` driven over standard input and output by a small
//! scripted client: diagnostics pushed on open, change and save, document
//! symbols, go-to-definition, hover, and a clean shutdown; hostile
//! clients in `lsp/hostile_clients.rs`.

#![allow(
    clippy::expect_used,
    clippy::unwrap_used,
    clippy::needless_pass_by_value
)]

use std::io::{BufReader, Write as _};
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, channel};
use std::time::Duration;

use serde_json::{Value, json};

mod common;
#[path = "lsp/hostile_clients.rs"]
mod hostile_clients;

/// How long any answer may take (the debug binary on a busy machine).
const WAIT: Duration = Duration::from_secs(120);

/// A LANGUAGE.md component with an unknown thread (line 8, after
/// characters that take 1 and 2 UTF-16 units), and an advice whose
/// secondary label is in `halt`.
const BROKEN: &str = "component demo { lang: C; }

ids demoIds { double x; }

thread motion { period: 10ms; }

service move {
  /* é😀 */ thread: motoin;
  start codel { exec: go(demoIds.x); max-time: 1ms; }
}

service halt {
  thread: motion;
  stops: move;
  start codel { exec: stopit(); max-time: 1ms; }
}
";

struct Client {
    child: Child,
    stdin: ChildStdin,
    incoming: Receiver<Value>,
    next_id: i64,
}

impl Client {
    fn start() -> Self {
        Self::start_with(json!({}), Value::Null)
    }

    fn start_with(capabilities: Value, options: Value) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_genom-check"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .unwrap();
        let stdin = child.stdin.take().unwrap();
        let stdout = child.stdout.take().unwrap();
        let (send, incoming) = channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            while let Some(message) = read_frame(&mut reader) {
                if send.send(message).is_err() {
                    break;
                }
            }
        });
        let mut client = Self {
            child,
            stdin,
            incoming,
            next_id: 0,
        };
        let init = client.request(
            "initialize",
            json!({ "processId": null, "rootUri": null, "capabilities": capabilities,
                    "initializationOptions": options }),
        );
        let caps = &init["capabilities"];
        assert_eq!(caps["textDocumentSync"]["change"], 1, "full sync: {caps}");
        assert_eq!(caps["hoverProvider"], true);
        assert_eq!(caps["definitionProvider"], true);
        assert_eq!(caps["documentSymbolProvider"], true);
        client.notify("initialized", json!({}));
        client
    }

    fn send(&mut self, message: &Value) {
        let body = message.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
        self.stdin.flush().unwrap();
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({ "jsonrpc": "2.0", "method": method, "params": params }));
    }

    /// Sends a request and returns its result (notifications before the
    /// answer are dropped).
    fn request(&mut self, method: &str, params: Value) -> Value {
        self.next_id += 1;
        let id = self.next_id;
        self.send(&json!({ "jsonrpc": "2.0", "id": id, "method": method, "params": params }));
        loop {
            let message = self.incoming.recv_timeout(WAIT).unwrap();
            if message["id"] == id {
                assert!(message.get("error").is_none(), "{message}");
                return message["result"].clone();
            }
        }
    }

    /// The next diagnostics published for `uri`.
    fn diagnostics(&mut self, uri: &str) -> Vec<Value> {
        loop {
            let message = self.incoming.recv_timeout(WAIT).unwrap();
            if message["method"] == "textDocument/publishDiagnostics"
                && message["params"]["uri"] == uri
            {
                return message["params"]["diagnostics"].as_array().unwrap().clone();
            }
        }
    }

    /// The next message from the server.
    fn next(&mut self) -> Value {
        self.incoming.recv_timeout(WAIT).unwrap()
    }

    fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({ "textDocument": {
                "uri": uri, "languageId": "genom", "version": 1, "text": text } }),
        );
    }

    fn shutdown(mut self) {
        let result = self.request("shutdown", Value::Null);
        assert_eq!(result, Value::Null);
        self.notify("exit", Value::Null);
        let status = self.child.wait().unwrap();
        assert!(status.success(), "{status:?}");
    }
}

fn read_frame(reader: &mut impl std::io::BufRead) -> Option<Value> {
    let mut length = None;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line).ok()? == 0 {
            return None;
        }
        let line = line.trim_end();
        if line.is_empty() {
            break;
        }
        if let Some(n) = line.strip_prefix("Content-Length: ") {
            length = n.parse::<usize>().ok();
        }
    }
    let mut body = vec![0; length?];
    reader.read_exact(&mut body).ok()?;
    serde_json::from_slice(&body).ok()
}

fn uri_of(path: &Path) -> String {
    format!("file://{}", path.display())
}

fn codes(diagnostics: &[Value]) -> Vec<&str> {
    diagnostics
        .iter()
        .map(|d| d["code"].as_str().unwrap())
        .collect()
}

#[test]
fn diagnostics_follow_edits_and_navigation_answers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("demo.gen");
    let uri = uri_of(&path);
    let mut client = Client::start();
    client.open(&uri, BROKEN);

    let found = client.diagnostics(&uri);
    assert_eq!(codes(&found), ["unknown-thread", "missing-on-inter"]);
    let unknown = &found[0];
    // `motoin` is on line 8; before it, `é` counts 1 UTF-16 unit, `😀` 2.
    assert_eq!(
        unknown["range"],
        json!({ "start": { "line": 7, "character": 20 },
                "end": { "line": 7, "character": 26 } })
    );
    assert_eq!(unknown["severity"], 1);
    assert_eq!(unknown["source"], "genom-check");
    let message = unknown["message"].as_str().unwrap();
    assert!(message.contains("unknown thread `motoin`"), "{message}");
    assert!(
        message.contains("help: did you mean `motion`?"),
        "{message}"
    );
    let advice = &found[1];
    assert_eq!(advice["severity"], 3);
    let related = &advice["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], uri.as_str());
    assert_eq!(related["location"]["range"]["start"]["line"], 13);

    let fixed = BROKEN
        .replace("motoin", "motion")
        .replace("  stops: move;\n", "");
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 },
                "contentChanges": [{ "text": fixed }] }),
    );
    assert_eq!(client.diagnostics(&uri), Vec::<Value>::new());

    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": uri } }),
    );
    let component = &symbols[0];
    assert_eq!(component["name"], "demo");
    let names: Vec<&str> = component["children"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["move", "halt", "motion", "demoIds"]);
    assert_eq!(component["children"][0]["children"][0]["name"], "start");

    // `thread: motion;` in `halt` (line 13) names the thread of line 5.
    let definition = client.request(
        "textDocument/definition",
        json!({ "textDocument": { "uri": uri },
                "position": { "line": 12, "character": 12 } }),
    );
    assert_eq!(definition["uri"], uri.as_str());
    assert_eq!(
        definition["range"],
        json!({ "start": { "line": 4, "character": 7 },
                "end": { "line": 4, "character": 13 } })
    );
    let hover = client.request(
        "textDocument/hover",
        json!({ "textDocument": { "uri": uri },
                "position": { "line": 6, "character": 10 } }),
    );
    let text = hover["contents"]["value"].as_str().unwrap();
    assert!(text.contains("`move`"), "{text}");
    assert!(text.contains("thread: `motion`"), "{text}");
    assert!(text.contains("codels: `start` (1ms)"), "{text}");
    client.shutdown();
}

#[test]
fn a_save_runs_the_behavioural_checks() {
    let text =
        std::fs::read_to_string("tests/fixtures/invalid/dead-service.delayed-by-auto.gen").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("board.gen");
    std::fs::write(&path, &text).unwrap();
    let uri = uri_of(&path);
    let mut client = Client::start();
    client.open(&uri, &text);
    let opened = client.diagnostics(&uri);
    assert!(!codes(&opened).contains(&"dead-service"), "{opened:?}");
    client.notify(
        "textDocument/didSave",
        json!({ "textDocument": { "uri": uri } }),
    );
    let saved = client.diagnostics(&uri);
    let dead = saved
        .iter()
        .find(|d| d["code"] == "dead-service")
        .unwrap_or_else(|| panic!("{saved:?}"));
    assert!(
        dead["message"].as_str().unwrap().contains("Update"),
        "{dead}"
    );
    // The trace's steps that point at the text are related information.
    let steps: Vec<&str> = dead["relatedInformation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["message"].as_str().unwrap())
        .collect();
    assert!(
        steps
            .iter()
            .any(|s| s.starts_with("trace step ") && s.contains("requests `Update`")),
        "{steps:?}"
    );
    client.shutdown();
}

#[test]
fn a_genom3_document_is_recognised() {
    let text =
        std::fs::read_to_string("tests/fixtures/genom3/semantics/f6_interrupt_stop.gen").unwrap();
    // An unknown task: only GenoM3 has `task`, so the dialect is detected.
    let broken = text.replacen("task t;", "task nowhere;", 1);
    let dir = tempfile::tempdir().unwrap();
    let uri = uri_of(&dir.path().join("f6.gen"));
    let mut client = Client::start();
    client.open(&uri, &broken);
    // `servo` never ends by itself (by design of the fixture): a warning
    // in GenoM3's words.
    let found = client.diagnostics(&uri);
    assert_eq!(
        codes(&found),
        ["unknown-thread", "no-termination"],
        "{found:?}"
    );
    let message = found[0]["message"].as_str().unwrap();
    assert!(message.starts_with("unknown task `nowhere`"), "{message}");
    let line = broken
        .lines()
        .position(|l| l.contains("task nowhere;"))
        .unwrap();
    assert_eq!(found[0]["range"]["start"]["line"], line);
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 },
                "contentChanges": [{ "text": text }] }),
    );
    assert_eq!(
        codes(&client.diagnostics(&uri)),
        ["no-termination", "missing-wcet"]
    );
    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": uri } }),
    );
    let kinds: Vec<(&str, &str)> = symbols[0]["children"]
        .as_array()
        .unwrap_or_else(|| panic!("{symbols}"))
        .iter()
        .map(|s| {
            (
                s["name"].as_str().unwrap(),
                s["detail"].as_str().unwrap_or(""),
            )
        })
        .collect();
    assert_eq!(
        kinds,
        [
            ("servo", "activity"),
            ("halt", "activity"),
            ("next", "activity"),
            ("t", "task"),
            ("ids", "ids")
        ]
    );
    client.shutdown();
}

#[test]
fn unknown_requests_get_an_error_and_the_server_still_answers() {
    let mut client = Client::start();
    client.next_id += 1;
    let id = client.next_id;
    client.send(
        &json!({ "jsonrpc": "2.0", "id": id, "method": "textDocument/rename",
                         "params": {} }),
    );
    let answer = loop {
        let message = client.incoming.recv_timeout(WAIT).unwrap();
        if message["id"] == id {
            break message;
        }
    };
    assert_eq!(answer["error"]["code"], -32601);
    client.shutdown();
}

#[test]
fn an_exit_without_shutdown_fails() {
    let mut client = Client::start();
    client.notify("exit", Value::Null);
    let status = client.child.wait().unwrap();
    assert_eq!(status.code(), Some(1));
}

#[test]
fn a_newer_text_supersedes_the_check_of_an_older_one() {
    let dir = tempfile::tempdir().unwrap();
    let uri = uri_of(&dir.path().join("demo.gen"));
    let mut client = Client::start();
    client.open(&uri, BROKEN);
    let fixed = BROKEN
        .replace("motoin", "motion")
        .replace("  stops: move;\n", "");
    // No waiting for the first check: the fix is queued behind it or
    // replaces it, and only its diagnostics may be the last ones.
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 },
                "contentChanges": [{ "text": fixed }] }),
    );
    while !client.diagnostics(&uri).is_empty() {}
    client.next_id += 1;
    let id = client.next_id;
    client.send(
        &json!({ "jsonrpc": "2.0", "id": id, "method": "textDocument/documentSymbol",
                         "params": { "textDocument": { "uri": uri } } }),
    );
    let answer = loop {
        let message = client.next();
        assert_ne!(
            message["method"], "textDocument/publishDiagnostics",
            "published after the newest check: {message}"
        );
        if message["id"] == id {
            break message;
        }
    };
    // The symbols are those of the fixed text: `move` has its thread.
    assert_eq!(answer["result"][0]["children"][0]["name"], "move");
    let hover = client.request(
        "textDocument/hover",
        json!({ "textDocument": { "uri": uri },
                "position": { "line": 6, "character": 10 } }),
    );
    let text = hover["contents"]["value"].as_str().unwrap();
    assert!(text.contains("thread: `motion`"), "{text}");
    client.shutdown();
}

#[test]
fn a_save_check_reports_progress_when_the_client_shows_it() {
    let text =
        std::fs::read_to_string("tests/fixtures/invalid/dead-service.delayed-by-auto.gen").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("board.gen");
    std::fs::write(&path, &text).unwrap();
    let uri = uri_of(&path);
    let mut client = Client::start_with(
        json!({ "window": { "workDoneProgress": true } }),
        Value::Null,
    );
    client.open(&uri, &text);
    client.diagnostics(&uri);
    client.notify(
        "textDocument/didSave",
        json!({ "textDocument": { "uri": uri } }),
    );
    let create = client.next();
    assert_eq!(
        create["method"], "window/workDoneProgress/create",
        "{create}"
    );
    let token = create["params"]["token"].clone();
    client.send(&json!({ "jsonrpc": "2.0", "id": create["id"], "result": null }));
    let mut events = Vec::new();
    loop {
        let message = client.next();
        if message["method"] == "$/progress" {
            assert_eq!(message["params"]["token"], token);
            events.push(
                message["params"]["value"]["kind"]
                    .as_str()
                    .unwrap()
                    .to_owned(),
            );
        } else if message["method"] == "textDocument/publishDiagnostics" {
            events.push("diagnostics".to_owned());
            let codes = codes(message["params"]["diagnostics"].as_array().unwrap()).join(" ");
            assert!(codes.contains("dead-service"), "{codes}");
        }
        if events.len() == 3 {
            break;
        }
    }
    assert_eq!(events, ["begin", "diagnostics", "end"]);
    client.shutdown();
}

/// A GenoM3 interface included by the component: `pos` is in both ids.
const IFACE: &str = "/* shared */
interface shared {
  ids { long pos; };
  function reset() {
    codel reset_it(out pos);
  };
};
";

const MAIN: &str = "#include \"iface.gen\"
component main {
  ids { long pos; };
  provides shared;
  task t { period 10 ms; };
  activity move() { task t; interrupts reset; codel<start> go(inout pos) yield ether; };
};
";

#[test]
fn includes_get_their_own_diagnostics_and_definitions() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("iface.gen"), IFACE).unwrap();
    let main = uri_of(&dir.path().join("main.gen"));
    let iface = uri_of(&dir.path().join("iface.gen"));
    let mut client = Client::start_with(
        json!({}),
        json!({ "codeUrl": "https://example.org/codes#{code}" }),
    );
    client.open(&main, MAIN);
    // Files are published in the order of their URIs: `iface` first.
    let found = client.diagnostics(&iface);
    assert_eq!(codes(&found), ["duplicate-definition"]);
    assert_eq!(
        found[0]["range"]["start"],
        json!({ "line": 2, "character": 13 })
    );
    assert_eq!(
        found[0]["codeDescription"]["href"],
        "https://example.org/codes#duplicate-definition"
    );
    let related: Vec<(&str, &Value)> = found[0]["relatedInformation"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            (
                r["location"]["uri"].as_str().unwrap(),
                &r["location"]["range"]["start"],
            )
        })
        .collect();
    assert_eq!(
        related,
        [
            (main.as_str(), &json!({ "line": 2, "character": 13 })),
            (main.as_str(), &json!({ "line": 0, "character": 0 }))
        ]
    );
    assert_eq!(client.diagnostics(&main), Vec::<Value>::new());

    let fixed = MAIN.replace("long pos;", "long speed;");
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": main, "version": 2 },
                "contentChanges": [{ "text": fixed }] }),
    );
    // The include's diagnostics are cleared (after the document's).
    assert_eq!(codes(&client.diagnostics(&main)), ["missing-wcet"]);
    assert_eq!(client.diagnostics(&iface), Vec::<Value>::new());
    // `interrupts reset` names the function declared in the include.
    let definition = client.request(
        "textDocument/definition",
        json!({ "textDocument": { "uri": main },
                "position": { "line": 5, "character": 41 } }),
    );
    assert_eq!(definition["uri"], iface.as_str());
    assert_eq!(
        definition["range"],
        json!({ "start": { "line": 3, "character": 11 },
                "end": { "line": 3, "character": 16 } })
    );
    // The outline lists only what the document itself declares.
    let symbols = client.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": main } }),
    );
    let names: Vec<&str> = symbols[0]["children"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"move") && !names.contains(&"reset"),
        "{names:?}"
    );
    client.shutdown();
}

#[test]
fn a_codel_name_in_next_leads_to_its_codel() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("specs/pilot.gen");
    let text = std::fs::read_to_string(&path).unwrap();
    let uri = uri_of(&path);
    let mut client = Client::start();
    client.open(&uri, &text);
    client.diagnostics(&uri);
    // `next: goto, stop;` of the start codel.
    let (line, column) = text
        .lines()
        .enumerate()
        .find_map(|(i, l)| Some((i, l.find("next: goto")? + "next: ".len())))
        .unwrap();
    let at = json!({ "textDocument": { "uri": uri },
                     "position": { "line": line, "character": column + 1 } });
    let definition = client.request("textDocument/definition", at.clone());
    let declared = text
        .lines()
        .position(|l| l.contains("exec codel goto"))
        .unwrap();
    assert_eq!(definition["range"]["start"]["line"], declared);
    let hover = client.request("textDocument/hover", at);
    let facts = hover["contents"]["value"].as_str().unwrap();
    assert!(
        facts.starts_with("**exec codel** `moveDistance::goto`"),
        "{facts}"
    );
    assert!(facts.contains("on-inter: `stop`"), "{facts}");
    client.shutdown();
}

#[test]
fn a_type_name_leads_to_its_idl_declaration() {
    // pilot.gen's export block uses `DEMO_STATE_STR`, declared in the
    // included demoStruct.idl.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("specs/pilot.gen");
    let idl = Path::new(env!("CARGO_MANIFEST_DIR")).join("specs/demoStruct.idl");
    let text = std::fs::read_to_string(&path).unwrap();
    let uri = uri_of(&path);
    let mut client = Client::start();
    client.open(&uri, &text);
    client.diagnostics(&uri);
    let (line, column) = text
        .lines()
        .enumerate()
        .find_map(|(i, l)| Some((i, l.find("  DEMO_STATE_STR state")? + 3)))
        .unwrap();
    let at = json!({ "textDocument": { "uri": uri },
                     "position": { "line": line, "character": column } });
    let definition = client.request("textDocument/definition", at.clone());
    assert_eq!(definition["uri"], uri_of(&idl), "{definition:#}");
    let hover = client.request("textDocument/hover", at);
    let facts = hover["contents"]["value"].as_str().unwrap();
    assert!(facts.contains("type `DEMO_STATE_STR`"), "{facts}");
    client.shutdown();
}

/// A save check still running when the text changes is cancelled (the
/// server says so in a log message) and the new text is checked. The
/// component is issue 14's largest generated one (30 services, 5 codels,
/// 4 threads, density 3): its full check (about 10 s) takes far longer
/// than the pause before the change.
#[test]
fn a_change_cancels_the_running_save_check() {
    let mut cfg = genom_generate::GeneratorConfig::new(1, 30);
    cfg.codels_per_service = 5;
    cfg.threads = 4;
    cfg.rule_density = 3.0;
    cfg.init = true;
    cfg.autos = 1;
    let text = genom_generate::generate(&cfg);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.gen");
    std::fs::write(&path, &text).unwrap();
    let uri = uri_of(&path);
    let mut client = Client::start();
    client.open(&uri, &text);
    client.diagnostics(&uri);
    client.notify(
        "textDocument/didSave",
        json!({ "textDocument": { "uri": uri } }),
    );
    // Let the worker take the save check before the text changes.
    std::thread::sleep(Duration::from_millis(500));
    let changed = format!("{text}\n");
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 },
                "contentChanges": [ { "text": changed } ] }),
    );
    let mut cancelled = false;
    let mut published = false;
    while !(cancelled && published) {
        let message = client.next();
        if message["method"] == "window/logMessage" {
            let said = message["params"]["message"].as_str().unwrap_or_default();
            cancelled |= said.contains("cancelled the running check");
        }
        if message["method"] == "textDocument/publishDiagnostics" {
            // The changed text's static check: no `incomplete` from the
            // cancelled exploration is ever published.
            let d = message["params"]["diagnostics"].as_array().unwrap();
            assert!(!codes(d).contains(&"incomplete"), "{message}");
            published = true;
        }
    }
    client.shutdown();
}

/// With WCETs (here from the project's `genom-check.toml`), a save check
/// computes the response times and hover on a service shows its worst
/// case (`r1_paused_chain`: 23 ms, tests/genom3/genom3_response.rs).
#[test]
fn hover_shows_the_worst_response_time_after_a_save() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/genom3/response");
    let text = std::fs::read_to_string(root.join("r1_paused_chain.gen")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("r1.gen");
    std::fs::write(&path, &text).unwrap();
    std::fs::copy(
        root.join("r1_paused_chain.wcet"),
        dir.path().join("r1.wcet"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("genom-check.toml"),
        "[wcet]\n\"r1.gen\" = \"r1.wcet\"\n",
    )
    .unwrap();
    let uri = uri_of(&path);
    let mut client = Client::start();
    client.open(&uri, &text);
    client.diagnostics(&uri);
    let (line, column) = text
        .lines()
        .enumerate()
        .find_map(|(i, l)| Some((i, l.find("activity go")? + "activity ".len())))
        .unwrap();
    let at = json!({ "textDocument": { "uri": uri },
                     "position": { "line": line, "character": column } });
    let before = client.request("textDocument/hover", at.clone());
    let before = before["contents"]["value"].as_str().unwrap().to_owned();
    assert!(!before.contains("response time"), "{before}");
    client.notify(
        "textDocument/didSave",
        json!({ "textDocument": { "uri": uri } }),
    );
    // The verdicts say what they rest on: an information at the
    // component's name.
    let saved = client.diagnostics(&uri);
    let note = saved
        .iter()
        .find(|d| d["severity"] == 3)
        .unwrap_or_else(|| panic!("{saved:?}"));
    let message = note["message"].as_str().unwrap();
    assert!(
        message.starts_with("the verdicts assume every codel takes at most its WCET from"),
        "{message}"
    );
    assert!(message.contains("r1.wcet"), "{message}");
    assert!(
        message.contains("at most 1 concurrent request"),
        "{message}"
    );
    assert_eq!(
        note["range"]["start"]["line"],
        text.lines()
            .position(|l| l.starts_with("component"))
            .unwrap()
    );
    let after = client.request("textDocument/hover", at);
    let after = after["contents"]["value"].as_str().unwrap();
    assert!(after.contains("worst-case response time: 23ms"), "{after}");
    client.shutdown();
}
