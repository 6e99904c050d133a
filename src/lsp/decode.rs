//! A message body read into a JSON-RPC message, or the error that answers
//! it: a body that is not JSON gets -32700 (parse error); JSON that is not
//! a request, notification or response gets -32600 (invalid request), with
//! the request's id when it has a usable one. A response of the client
//! that cannot be read is dropped (JSON-RPC never answers a response).
//!
//! The body is first scanned without building anything, counting its
//! values: a body of at most 64 MiB could still cost gigabytes as a
//! `serde_json::Value` (`[0,0,0,…]` is some 80 bytes per two bytes of
//! text), so one of more than [`MAX_VALUES`] values is refused (-32600)
//! before it is built.

use std::fmt;

use lsp_server::{ErrorCode, Message, Notification, Request, RequestId, Response};
use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::Value;

/// The most JSON values (map keys included) a message may have.
pub const MAX_VALUES: usize = 1 << 20;

/// An error answering a message that was not taken.
#[derive(Debug)]
pub struct Rejection {
    /// The id of the request it answers, `null` when unknown.
    pub id: Value,
    pub code: i32,
    pub message: String,
}

impl Rejection {
    pub fn new(id: Value, code: ErrorCode, message: String) -> Self {
        Self {
            id,
            code: code as i32,
            message,
        }
    }
}

/// The message a body holds; `None` for a response that cannot be read.
pub fn message(body: &[u8]) -> Result<Option<Message>, Rejection> {
    let mut tally = Tally::default();
    let mut scanner = serde_json::Deserializer::from_slice(body);
    let scanned = Scan {
        tally: &mut tally,
        top: true,
        capture: false,
    }
    .deserialize(&mut scanner)
    .and_then(|_| scanner.end());
    if let Err(e) = scanned {
        return Err(if tally.values > MAX_VALUES {
            Rejection::new(
                tally.id.unwrap_or(Value::Null),
                ErrorCode::InvalidRequest,
                format!("message of more than {MAX_VALUES} JSON values: not read"),
            )
        } else {
            Rejection::new(
                Value::Null,
                ErrorCode::ParseError,
                format!("message is not JSON: {e}"),
            )
        });
    }
    let value: Value = serde_json::from_slice(body).map_err(|e| {
        Rejection::new(
            Value::Null,
            ErrorCode::ParseError,
            format!("message is not JSON: {e}"),
        )
    })?;
    classify(value)
}

/// A JSON value as a request, notification or response.
fn classify(value: Value) -> Result<Option<Message>, Rejection> {
    let Value::Object(mut fields) = value else {
        return Err(invalid(
            Value::Null,
            "a message is a JSON object (batches are not part of the protocol)",
        ));
    };
    let id = fields.remove("id");
    // The id to answer with: a request's, when it is one.
    let echo = match &id {
        Some(id @ (Value::Number(_) | Value::String(_))) => id.clone(),
        _ => Value::Null,
    };
    match fields.remove("method") {
        Some(Value::String(method)) => {
            let params = fields.remove("params").unwrap_or(Value::Null);
            let Some(id) = id else {
                return Ok(Some(Notification { method, params }.into()));
            };
            match request_id(&id) {
                Some(id) => Ok(Some(Request { id, method, params }.into())),
                None => Err(invalid(
                    echo,
                    "a request id is a string or an integer of 32 bits",
                )),
            }
        }
        Some(_) => Err(invalid(echo, "`method` is not a string")),
        None if id.is_some() && (fields.contains_key("result") || fields.contains_key("error")) => {
            if let Some(id) = id {
                fields.insert("id".to_owned(), id);
            }
            Ok(serde_json::from_value::<Response>(Value::Object(fields))
                .ok()
                .map(Message::Response))
        }
        None => Err(invalid(
            echo,
            "a message without `method` and no response (no `result` or `error`)",
        )),
    }
}

fn invalid(id: Value, message: &str) -> Rejection {
    Rejection::new(id, ErrorCode::InvalidRequest, message.to_owned())
}

/// A request id lsp-server can hold.
fn request_id(id: &Value) -> Option<RequestId> {
    match id {
        Value::Number(n) => n
            .as_i64()
            .and_then(|n| i32::try_from(n).ok())
            .map(RequestId::from),
        Value::String(s) => Some(RequestId::from(s.clone())),
        _ => None,
    }
}

/// What the scan found.
#[derive(Debug, Default)]
struct Tally {
    /// Values seen so far (map keys included).
    values: usize,
    /// The top-level `id`, when it is a number or a string.
    id: Option<Value>,
}

/// Scans one value, counting it and what it holds (and stopping with an
/// error past [`MAX_VALUES`]); builds nothing but a top-level `id`.
struct Scan<'a> {
    tally: &'a mut Tally,
    /// The value is the message itself (its `id` is kept).
    top: bool,
    /// The value is the top-level `id`: a number or string is returned.
    capture: bool,
}

impl Scan<'_> {
    fn count<E: de::Error>(&mut self) -> Result<(), E> {
        self.tally.values += 1;
        if self.tally.values > MAX_VALUES {
            return Err(E::custom("too many JSON values"));
        }
        Ok(())
    }

    fn inner(&mut self, capture: bool) -> Scan<'_> {
        Scan {
            tally: &mut *self.tally,
            top: false,
            capture,
        }
    }
}

impl<'de> DeserializeSeed<'de> for Scan<'_> {
    type Value = Option<Value>;

    fn deserialize<D: Deserializer<'de>>(mut self, d: D) -> Result<Self::Value, D::Error> {
        self.count()?;
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Scan<'_> {
    type Value = Option<Value>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<Self::Value, E> {
        Ok(None)
    }

    fn visit_i64<E>(self, v: i64) -> Result<Self::Value, E> {
        Ok(self.capture.then(|| Value::from(v)))
    }

    fn visit_u64<E>(self, v: u64) -> Result<Self::Value, E> {
        Ok(self.capture.then(|| Value::from(v)))
    }

    fn visit_f64<E>(self, v: f64) -> Result<Self::Value, E> {
        Ok(self.capture.then(|| Value::from(v)))
    }

    fn visit_str<E>(self, v: &str) -> Result<Self::Value, E> {
        Ok(self.capture.then(|| Value::from(v)))
    }

    fn visit_unit<E>(self) -> Result<Self::Value, E> {
        Ok(None)
    }

    fn visit_seq<A: SeqAccess<'de>>(mut self, mut seq: A) -> Result<Self::Value, A::Error> {
        while seq.next_element_seed(self.inner(false))?.is_some() {}
        Ok(None)
    }

    fn visit_map<A: MapAccess<'de>>(mut self, mut map: A) -> Result<Self::Value, A::Error> {
        while let Some(IsId(is_id)) = map.next_key()? {
            self.count()?;
            let id = self.top && is_id;
            let value = map.next_value_seed(self.inner(id))?;
            if id {
                self.tally.id = value;
            }
        }
        Ok(None)
    }
}

/// A map key: whether it is `id`.
struct IsId(bool);

impl<'de> de::Deserialize<'de> for IsId {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_str(IsIdVisitor)
    }
}

struct IsIdVisitor;

impl Visitor<'_> for IsIdVisitor {
    type Value = IsId;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a key")
    }

    fn visit_str<E>(self, v: &str) -> Result<IsId, E> {
        Ok(IsId(v == "id"))
    }
}
