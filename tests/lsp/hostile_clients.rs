//! Issue 28 items 21 and 22: a hostile client never ends the server nor
//! makes it allocate what it announces. Each case is generated here: a
//! `Content-Length` of 2 GB with 17 bytes sent, a body over the 64 MiB
//! limit, framing without `Content-Length`, a body that is not JSON or
//! not a message, notifications and requests whose params are not the
//! protocol's, a request after `shutdown`, a second `initialize`, and
//! the input ending inside a body. After each, the server still answers
//! (or, when the input ended, exits with status 1, not 2).

use std::io::Write as _;

use serde_json::{Value, json};

use super::{BROKEN, Client, common, uri_of};

/// The peak resident size the server may reach on these inputs (it is
/// about 10 MiB; it was 1.9 GB on the 2 GB `Content-Length`).
const PEAK: u64 = 128 << 20;

fn send_raw(client: &mut Client, bytes: &[u8]) {
    client.stdin.write_all(bytes).unwrap();
    client.stdin.flush().unwrap();
}

fn frame(body: &str) -> Vec<u8> {
    format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
}

/// The answer (a result or an error) with id `id`, skipping the rest.
fn answer(client: &mut Client, id: &Value) -> Value {
    loop {
        let message = client.next();
        let answers = message.get("result").is_some() || message.get("error").is_some();
        if answers && message.get("id") == Some(id) {
            return message;
        }
    }
}

/// The error code and message of the answer with id `id`.
fn error(client: &mut Client, id: &Value) -> (i64, String) {
    let answer = answer(client, id);
    let error = &answer["error"];
    let code = error["code"].as_i64().unwrap_or_else(|| panic!("{answer}"));
    (code, error["message"].as_str().unwrap().to_owned())
}

/// The next `window/logMessage`.
fn log_message(client: &mut Client) -> String {
    loop {
        let message = client.next();
        if message["method"] == "window/logMessage" {
            return message["params"]["message"].as_str().unwrap().to_owned();
        }
    }
}

/// The server answers a request (outline of a document it does not have).
fn still_answers(client: &mut Client) {
    let outline = client.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": "file:///nowhere/none.gen" } }),
    );
    assert_eq!(outline, Value::Null);
}

/// The server's peak resident size so far, checked against [`PEAK`].
fn assert_small_peak(client: &Client) {
    if let Some(peak) = common::high_water_mark(client.child.id()) {
        assert!(peak < PEAK, "peak resident size {} MiB", peak >> 20);
    }
}

/// Closes the server's input; its exit status.
fn close(client: Client) -> Option<i32> {
    let Client {
        mut child, stdin, ..
    } = client;
    drop(stdin);
    child.wait().unwrap().code()
}

#[test]
fn a_two_gigabyte_content_length_is_refused_without_allocating_it() {
    let mut client = Client::start();
    let mut bytes = b"Content-Length: 2000000000\r\n\r\n{\"jsonrpc\":\"2.0\",".to_vec();
    bytes.extend(frame(
        r#"{"jsonrpc":"2.0","id":"after","method":"shutdown"}"#,
    ));
    send_raw(&mut client, &bytes);
    let (code, message) = error(&mut client, &Value::Null);
    assert_eq!(code, -32600);
    assert!(
        message.contains("2000000000 bytes exceeds the 64 MiB limit"),
        "{message}"
    );
    // The request after the 17 bytes is inside the announced body: the
    // server is skipping it, waiting for the rest.
    assert_small_peak(&client);
    // The input ends inside the skipped body: a clean end, without
    // `shutdown` (status 1).
    assert_eq!(close(client), Some(1));
}

#[test]
fn a_body_over_the_limit_is_skipped_and_the_next_message_answered() {
    let mut client = Client::start();
    let length = (64 << 20) + 1;
    send_raw(
        &mut client,
        format!("Content-Length: {length}\r\n\r\n").as_bytes(),
    );
    let chunk = vec![b' '; 1 << 20];
    for _ in 0..64 {
        send_raw(&mut client, &chunk);
    }
    send_raw(&mut client, b"}");
    let (code, message) = error(&mut client, &Value::Null);
    assert_eq!(code, -32600);
    assert!(message.contains(&format!("{length} bytes")), "{message}");
    still_answers(&mut client);
    assert_small_peak(&client);
    client.shutdown();
}

#[test]
fn a_body_that_is_not_json_gets_a_parse_error() {
    let mut client = Client::start();
    send_raw(&mut client, &frame(r#"{"jsonrpc": "2.0", "id": 5,"#));
    // Its id is unknown: the error is told in the log too, first.
    assert!(log_message(&mut client).contains("not JSON"));
    assert_eq!(error(&mut client, &Value::Null).0, -32700);
    still_answers(&mut client);
    client.shutdown();
}

#[test]
fn json_that_is_no_message_gets_invalid_request() {
    let mut client = Client::start();
    // No `method`, no `result`: an invalid request, answered with its id.
    send_raw(&mut client, &frame(r#"{"jsonrpc":"2.0","id":"no-method"}"#));
    assert_eq!(error(&mut client, &json!("no-method")).0, -32600);
    // Not an object: no id to answer with.
    send_raw(&mut client, &frame("[1, 2, 3]"));
    assert_eq!(error(&mut client, &Value::Null).0, -32600);
    // An id lsp-server cannot hold (past 32 bits).
    send_raw(
        &mut client,
        &frame(r#"{"jsonrpc":"2.0","id":1099511627776,"method":"shutdown"}"#),
    );
    assert_eq!(error(&mut client, &json!(1_099_511_627_776_u64)).0, -32600);
    still_answers(&mut client);
    client.shutdown();
}

#[test]
fn framing_without_content_length_is_refused_and_found_again() {
    let mut client = Client::start();
    // A body announced by `Content-Type` only, then a valid message right
    // after it: the framing is found again at its `Content-Length`.
    let mut bytes = b"Content-Type: application/vscode-jsonrpc\r\n\r\n".to_vec();
    bytes.extend(br#"{"jsonrpc":"2.0","id":"lost","method":"shutdown"}"#);
    bytes.extend(frame(
        r#"{"jsonrpc":"2.0","id":"found","method":"nothing"}"#,
    ));
    send_raw(&mut client, &bytes);
    let (code, message) = error(&mut client, &Value::Null);
    assert_eq!(code, -32700);
    assert!(message.contains("no Content-Length"), "{message}");
    assert_eq!(error(&mut client, &json!("found")).0, -32601);
    // A header line of 100 KB: refused, with the message it belongs to.
    let mut bytes = format!("X-Padding: {}\r\n", "a".repeat(100_000)).into_bytes();
    bytes.extend(frame(
        r#"{"jsonrpc":"2.0","id":"padded","method":"nothing"}"#,
    ));
    send_raw(&mut client, &bytes);
    let (code, message) = error(&mut client, &Value::Null);
    assert_eq!(code, -32700);
    assert!(message.contains("longer than 8 KiB"), "{message}");
    still_answers(&mut client);
    client.shutdown();
}

#[test]
fn a_change_with_a_negative_line_is_logged_and_the_document_kept() {
    let dir = tempfile::tempdir().unwrap();
    let uri = uri_of(&dir.path().join("demo.gen"));
    let mut client = Client::start();
    client.open(&uri, BROKEN);
    assert!(!client.diagnostics(&uri).is_empty());
    client.notify(
        "textDocument/didChange",
        json!({ "textDocument": { "uri": uri, "version": 2 },
                "contentChanges": [{ "range": { "start": { "line": -1, "character": 0 },
                                                "end": { "line": 0, "character": 0 } },
                                     "text": "" }] }),
    );
    let logged = log_message(&mut client);
    assert!(logged.contains("textDocument/didChange"), "{logged}");
    // The document is still there, with its text before the change.
    let outline = client.request(
        "textDocument/documentSymbol",
        json!({ "textDocument": { "uri": uri } }),
    );
    assert!(!outline.as_array().unwrap().is_empty(), "{outline}");
    client.shutdown();
}

#[test]
fn an_open_whose_uri_is_no_uri_is_logged() {
    let mut client = Client::start();
    client.open("not a uri at all", BROKEN);
    let logged = log_message(&mut client);
    assert!(logged.contains("textDocument/didOpen"), "{logged}");
    // Missing fields: logged too.
    client.notify("textDocument/didOpen", json!({}));
    let logged = log_message(&mut client);
    assert!(logged.contains("missing field"), "{logged}");
    still_answers(&mut client);
    client.shutdown();
}

#[test]
fn a_request_with_invalid_params_gets_invalid_params() {
    let mut client = Client::start();
    client.send(
        &json!({ "jsonrpc": "2.0", "id": "hover", "method": "textDocument/hover",
                         "params": { "textDocument": { "uri": "file:///a.gen" },
                                     "position": { "line": -1, "character": 0 } } }),
    );
    assert_eq!(error(&mut client, &json!("hover")).0, -32602);
    still_answers(&mut client);
    client.shutdown();
}

#[test]
fn requests_after_shutdown_are_refused_until_exit() {
    let mut client = Client::start();
    let result = client.request("shutdown", Value::Null);
    assert_eq!(result, Value::Null);
    client.send(
        &json!({ "jsonrpc": "2.0", "id": "late", "method": "textDocument/hover",
                         "params": {} }),
    );
    let (code, message) = error(&mut client, &json!("late"));
    assert_eq!(code, -32600);
    assert!(message.contains("shutting down"), "{message}");
    client.send(&json!({ "jsonrpc": "2.0", "id": "again", "method": "shutdown" }));
    assert_eq!(error(&mut client, &json!("again")).0, -32600);
    client.notify("exit", Value::Null);
    assert_eq!(client.child.wait().unwrap().code(), Some(0));
}

#[test]
fn a_second_initialize_is_an_invalid_request() {
    let mut client = Client::start();
    client.send(
        &json!({ "jsonrpc": "2.0", "id": "init", "method": "initialize",
                         "params": { "capabilities": {} } }),
    );
    assert_eq!(error(&mut client, &json!("init")).0, -32600);
    still_answers(&mut client);
    client.shutdown();
}

#[test]
fn the_input_ending_inside_a_body_ends_the_server_cleanly() {
    let mut client = Client::start();
    send_raw(&mut client, b"Content-Length: 100\r\n\r\n{\"jsonrpc\"");
    assert_eq!(close(client), Some(1));
}
