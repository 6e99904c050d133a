//! The server's end of standard input and output, bounded against hostile
//! clients. A reader thread reads the `Content-Length` framing itself
//! (lsp-server's reader allocates the announced length at once and ends
//! the connection on the first bad message): header lines of at most
//! [`MAX_LINE`] bytes, a body of at most [`MAX_BODY`] bytes, read as it
//! arrives (an announced length is never allocated in advance). A message
//! that cannot be taken is answered with a JSON-RPC error, and reading
//! goes on:
//!
//! - a body over the limit is skipped in small chunks (-32600);
//! - a header block that is not one, or has no `Content-Length`, gets
//!   -32700, and the framing is found again at the next `Content-Length`;
//! - a body that is not JSON, or not a JSON-RPC message: see [`decode`].
//!
//! An error whose request id is unknown has the id `null`, as JSON-RPC
//! says, and is also told in a `window/logMessage`. The input ending,
//! between messages or inside one, or after `exit`, ends the reader, which
//! drops its channel: the server then stops. A writer thread writes what
//! the server sends (lsp-server's [`Message::write`]) and these errors.

use std::io::{self, BufRead, Read as _, Write};
use std::thread::{self, JoinHandle};

use crossbeam_channel::{Receiver, Sender, bounded};
use lsp_server::{Connection, ErrorCode, Message};
use serde_json::{Value, json};

use super::decode::{self, Rejection};

/// The largest body taken (64 MiB).
pub const MAX_BODY: u64 = 64 << 20;

/// The longest header line kept (8 KiB); a longer one is not a header.
const MAX_LINE: usize = 8 << 10;

/// Header lines of one message taken before it is refused.
const MAX_HEADERS: usize = 32;

/// The writer thread of the connection.
pub struct IoThreads {
    writer: JoinHandle<io::Result<()>>,
}

impl IoThreads {
    /// Waits until what the server sent is written (once the connection
    /// is dropped). The reader is not waited for: it may be blocked on an
    /// input that never ends, and ends with the process.
    pub fn join(self) -> io::Result<()> {
        self.writer
            .join()
            .unwrap_or_else(|_| Err(io::Error::other("the writer thread panicked")))
    }
}

/// A connection over standard input and output.
pub fn stdio() -> io::Result<(Connection, IoThreads)> {
    let (sender, outgoing) = bounded::<Message>(0);
    let (errors, rejected) = bounded::<Value>(4);
    let (incoming, receiver) = bounded::<Message>(0);
    let writer = thread::Builder::new()
        .name("lsp-writer".to_owned())
        .spawn(move || write_all(io::stdout().lock(), &outgoing, rejected))?;
    thread::Builder::new()
        .name("lsp-reader".to_owned())
        .spawn(move || {
            let result = read_all(io::stdin().lock(), &incoming, errors);
            if let Err(e) = result {
                eprintln!("genom-check lsp: cannot read the input: {e}");
            }
        })?;
    Ok((Connection { sender, receiver }, IoThreads { writer }))
}

/// Writes the server's messages and the reader's errors until the server
/// drops its sender.
fn write_all(
    mut out: impl Write,
    outgoing: &Receiver<Message>,
    rejected: Receiver<Value>,
) -> io::Result<()> {
    let mut rejected = Some(rejected);
    loop {
        let never = crossbeam_channel::never();
        let errors = rejected.as_ref().unwrap_or(&never);
        crossbeam_channel::select! {
            recv(outgoing) -> message => match message {
                Ok(message) => message.write(&mut out)?,
                Err(_) => return Ok(()),
            },
            recv(errors) -> value => match value {
                Ok(value) => write_frame(&mut out, &value)?,
                Err(_) => rejected = None,
            },
        }
    }
}

/// Writes one framed JSON value.
fn write_frame(out: &mut impl Write, value: &Value) -> io::Result<()> {
    let text = value.to_string();
    write!(out, "Content-Length: {}\r\n\r\n{text}", text.len())?;
    out.flush()
}

/// Reads messages until the input ends or `exit` came, sending each to
/// the server and answering those that cannot be taken.
fn read_all(
    input: impl BufRead,
    incoming: &Sender<Message>,
    errors: Sender<Value>,
) -> io::Result<()> {
    let mut reader = Reader {
        input,
        errors,
        lost_body: false,
    };
    while let Some(body) = reader.body()? {
        let decoded = decode::message(&body);
        drop(body);
        match decoded {
            Ok(Some(message)) => {
                let exit = matches!(&message, Message::Notification(n) if n.method == "exit");
                incoming.send(message).map_err(io::Error::other)?;
                if exit {
                    break;
                }
            }
            Ok(None) => {}
            Err(rejection) => reader.reject(rejection)?,
        }
    }
    Ok(())
}

/// What a header block announced.
enum Header {
    /// A body of this many bytes follows.
    Length(u64),
    /// The block is not valid (why), with the length of the body that
    /// follows when it said one.
    Bad(String, Option<u64>),
    /// The input ended.
    End,
}

/// One line of the input, without its line end.
struct Line {
    /// Its bytes, or its last [`MAX_LINE`] bytes when it is longer.
    text: Vec<u8>,
    /// It was longer than [`MAX_LINE`].
    long: bool,
}

/// What one header line says.
enum Field {
    /// `Content-Length: N` (a length past `u64` is `u64::MAX`).
    Length(u64),
    /// Another header (`Content-Type`), ignored.
    Other,
    /// A `Content-Length` whose value is no length.
    Invalid(String),
    /// Bytes that are no header, then `Content-Length: N` (a body sent
    /// without its `Content-Length`, then the next message).
    AfterJunk(u64),
    /// No header.
    Junk,
}

/// The framing reader.
struct Reader<R> {
    input: R,
    /// The errors to write.
    errors: Sender<Value>,
    /// The last header block had no `Content-Length`: its body follows,
    /// and is skipped up to the next header without another error.
    lost_body: bool,
}

impl<R: BufRead> Reader<R> {
    /// The next body of at most [`MAX_BODY`] bytes (the others are
    /// answered and skipped); `None` when the input ends.
    fn body(&mut self) -> io::Result<Option<Vec<u8>>> {
        loop {
            let length = match self.header()? {
                Header::End => return Ok(None),
                Header::Length(length) if length <= MAX_BODY => {
                    let mut body = Vec::new();
                    (&mut self.input).take(length).read_to_end(&mut body)?;
                    if (body.len() as u64) < length {
                        eprintln!("genom-check lsp: the input ended inside a message");
                        return Ok(None);
                    }
                    return Ok(Some(body));
                }
                Header::Length(length) => {
                    self.reject(Rejection::new(
                        Value::Null,
                        ErrorCode::InvalidRequest,
                        format!(
                            "message of {length} bytes exceeds the {} MiB limit: skipped",
                            MAX_BODY >> 20
                        ),
                    ))?;
                    length
                }
                Header::Bad(why, length) => {
                    self.reject(Rejection::new(Value::Null, ErrorCode::ParseError, why))?;
                    match length {
                        Some(length) => length,
                        None => continue,
                    }
                }
            };
            // Skipped through a small buffer: nothing of it is kept.
            let skipped = io::copy(&mut (&mut self.input).take(length), &mut io::sink())?;
            if skipped < length {
                eprintln!("genom-check lsp: the input ended inside a skipped message");
                return Ok(None);
            }
        }
    }

    /// Reads one header block, up to its empty line.
    fn header(&mut self) -> io::Result<Header> {
        let mut length = None;
        let mut problem = None;
        let mut lines = 0;
        loop {
            let Some(line) = self.line()? else {
                if lines > 0 {
                    eprintln!("genom-check lsp: the input ended inside a header");
                }
                return Ok(Header::End);
            };
            if line.text.is_empty() && !line.long {
                if lines == 0 {
                    // Empty lines between messages.
                    continue;
                }
                break;
            }
            match field(&line) {
                // The rest of a body sent without its length.
                Field::Junk if self.lost_body => continue,
                Field::Junk if line.long => {
                    let why = format!("a header line longer than {} KiB", MAX_LINE >> 10);
                    problem.get_or_insert(why);
                }
                Field::Junk => {
                    problem.get_or_insert_with(|| "a header line is not `Name: value`".to_owned());
                }
                Field::AfterJunk(n) => {
                    if !std::mem::take(&mut self.lost_body) {
                        self.reject(Rejection::new(
                            Value::Null,
                            ErrorCode::ParseError,
                            "bytes that are no message before a header: skipped".to_owned(),
                        ))?;
                    }
                    length = Some(n);
                }
                Field::Length(n) => length = Some(n),
                Field::Invalid(why) => {
                    problem.get_or_insert(why);
                }
                Field::Other => {}
            }
            self.lost_body = false;
            lines += 1;
            if lines > MAX_HEADERS {
                problem.get_or_insert_with(|| format!("more than {MAX_HEADERS} header lines"));
            }
        }
        // Without a length, the body is read as the next header lines.
        self.lost_body = length.is_none();
        Ok(match (problem, length) {
            (None, Some(length)) => Header::Length(length),
            (Some(why), length) => Header::Bad(format!("malformed header: {why}"), length),
            (None, None) => Header::Bad("malformed header: no Content-Length".to_owned(), None),
        })
    }

    /// The next line; `None` when the input ends before a line end.
    fn line(&mut self) -> io::Result<Option<Line>> {
        let mut text = Vec::new();
        let mut long = false;
        loop {
            let available = match self.input.fill_buf() {
                Ok(available) => available,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            if available.is_empty() {
                return Ok(None);
            }
            let end = available.iter().position(|&b| b == b'\n');
            let taken = end.map_or(available.len(), |i| i + 1);
            text.extend_from_slice(available.get(..end.unwrap_or(taken)).unwrap_or_default());
            self.input.consume(taken);
            if text.len() > 2 * MAX_LINE {
                text.drain(..text.len() - MAX_LINE);
                long = true;
            }
            if end.is_some() {
                break;
            }
        }
        if text.last() == Some(&b'\r') {
            text.pop();
        }
        if text.len() > MAX_LINE {
            text.drain(..text.len() - MAX_LINE);
            long = true;
        }
        Ok(Some(Line { text, long }))
    }

    /// Answers a message that cannot be taken: an error response, and a
    /// `window/logMessage` when the request it answers is unknown.
    fn reject(&self, rejection: Rejection) -> io::Result<()> {
        let Rejection { id, code, message } = rejection;
        if id.is_null() {
            let log = json!({
                "jsonrpc": "2.0",
                "method": "window/logMessage",
                "params": { "type": 1, "message": format!("genom-check lsp: {message}") },
            });
            self.errors.send(log).map_err(io::Error::other)?;
        }
        let response = json!({
            "jsonrpc": "2.0",
            "id": id,
            "error": { "code": code, "message": message },
        });
        self.errors.send(response).map_err(io::Error::other)
    }
}

/// Reads one header line.
fn field(line: &Line) -> Field {
    // A body sent without its length runs into the next message's header.
    let lower = line.text.to_ascii_lowercase();
    let found = lower
        .windows(b"content-length:".len())
        .rposition(|w| w == b"content-length:");
    match found {
        Some(0) if !line.long => header_field(&line.text).unwrap_or(Field::Junk),
        Some(at) => match line.text.get(at..).and_then(header_field) {
            Some(Field::Length(n)) => Field::AfterJunk(n),
            _ => Field::Junk,
        },
        None if line.long => Field::Junk,
        None => header_field(&line.text).unwrap_or(Field::Junk),
    }
}

/// A `Name: value` header line, or `None` when the line is not one.
fn header_field(line: &[u8]) -> Option<Field> {
    let colon = line.iter().position(|&b| b == b':')?;
    let (name, value) = (line.get(..colon)?, line.get(colon + 1..)?);
    let token = |b: &u8| b.is_ascii_alphanumeric() || *b == b'-' || *b == b'_';
    if name.is_empty() || !name.iter().all(token) {
        return None;
    }
    if !name.eq_ignore_ascii_case(b"content-length") {
        return Some(Field::Other);
    }
    let value = value.trim_ascii();
    if value.is_empty() || !value.iter().all(u8::is_ascii_digit) {
        let shown = String::from_utf8_lossy(value.get(..40).unwrap_or(value));
        return Some(Field::Invalid(format!("invalid Content-Length `{shown}`")));
    }
    let length = value.iter().try_fold(0_u64, |n, d| {
        n.checked_mul(10)?.checked_add(u64::from(d - b'0'))
    });
    Some(Field::Length(length.unwrap_or(u64::MAX)))
}
