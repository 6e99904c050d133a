//! `genom-check lsp`: a Language Server over standard input and output.
//! Open and edited documents get the static checks, saved ones the whole
//! check (behaviour, bounded by a timeout, reported as `$/progress`);
//! their diagnostics are pushed. Checks run on a worker thread, newest
//! text first (a check of an outdated text is dropped). It answers
//! document symbols, go-to-definition and hover from the component model
//! of the last check.
//!
//! Nothing a client sends ends the server but `exit` and the end of its
//! input (the framing and what cannot be decoded: [`transport`]): a
//! request it cannot take gets a JSON-RPC error, a notification whose
//! params are not what the protocol says is dropped and logged
//! (`window/logMessage`). After `shutdown`, requests get -32600 and
//! notifications other than `exit` are dropped.

mod check;
mod decode;
mod navigate;
mod position;
mod publish;
mod transport;
mod worker;

use std::collections::{BTreeMap, BTreeSet};
use std::error::Error;

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, RequestId, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument, Exit,
    LogMessage, Notification as _, Progress, PublishDiagnostics,
};
use lsp_types::request::{
    DocumentSymbolRequest, GotoDefinition, HoverRequest, Initialize, Request as _, Shutdown,
    WorkDoneProgressCreate,
};
use lsp_types::{
    HoverProviderCapability, InitializeResult, MessageType, OneOf, ProgressParams,
    ProgressParamsValue, ProgressToken, PublishDiagnosticsParams, SaveOptions, ServerCapabilities,
    ServerInfo, TextDocumentSyncCapability, TextDocumentSyncKind, TextDocumentSyncOptions,
    TextDocumentSyncSaveOptions, Uri, WorkDoneProgress, WorkDoneProgressBegin,
    WorkDoneProgressCreateParams, WorkDoneProgressEnd,
};

use self::check::{Document, Done, Job, Settings};
use crate::cli::LspArgs;
use crate::exit::{EXIT_ERRORS, EXIT_OK, EXIT_USAGE};

type Fallible<T> = Result<T, Box<dyn Error + Send + Sync>>;

/// Serves one client on standard input and output until it exits.
pub fn run(args: &LspArgs) -> u8 {
    let (connection, io_threads) = match transport::stdio() {
        Ok(started) => started,
        Err(e) => {
            eprintln!("genom-check lsp: cannot start: {e}");
            return EXIT_USAGE;
        }
    };
    let status = match serve(&connection, args) {
        Ok(status) => status,
        Err(e) => {
            eprintln!("genom-check lsp: {e}");
            EXIT_USAGE
        }
    };
    drop(connection);
    match io_threads.join() {
        Ok(()) => status,
        Err(e) => {
            eprintln!("genom-check lsp: {e}");
            EXIT_USAGE
        }
    }
}

/// What the server offers.
fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Options(
            TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(TextDocumentSyncKind::FULL),
                save: Some(TextDocumentSyncSaveOptions::SaveOptions(SaveOptions {
                    include_text: Some(false),
                })),
                ..TextDocumentSyncOptions::default()
            },
        )),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        ..ServerCapabilities::default()
    }
}

/// Serves until `exit`, or the end of the input: 0 after a `shutdown`, 1
/// without (as the protocol says). An error ends it only when the
/// output or the check thread is gone.
fn serve(connection: &Connection, args: &LspArgs) -> Fallible<u8> {
    let Some(params) = initialize(connection)? else {
        return Ok(EXIT_ERRORS);
    };
    let code_url = params
        .get("initializationOptions")
        .and_then(|o| o.get("codeUrl"))
        .and_then(serde_json::Value::as_str)
        .map(str::to_owned);
    let progress = params
        .pointer("/capabilities/window/workDoneProgress")
        .and_then(serde_json::Value::as_bool)
        .unwrap_or(false);
    let settings = Settings {
        timeout: args.timeout,
        max_memory: args.max_memory,
        code_url,
    };
    let worker = worker::start(settings)?;
    let mut server = Server {
        connection,
        jobs: worker.jobs,
        running: std::sync::Arc::clone(&worker.running),
        progress,
        requests: 0,
        shut_down: false,
        documents: BTreeMap::new(),
    };
    loop {
        crossbeam_channel::select! {
            recv(connection.receiver) -> message => {
                // The input ended (or cannot be read) without `exit`.
                let Ok(message) = message else {
                    return Ok(server.exit_status());
                };
                if let Some(status) = server.message(message)? {
                    return Ok(status);
                }
            }
            recv(worker.done) -> done => server.finished(done?)?,
        }
    }
}

/// Waits for `initialize` and answers it: requests before it get -32002
/// (server not initialized), notifications are dropped. Its params, or
/// `None` when the client exits or leaves first.
fn initialize(connection: &Connection) -> Fallible<Option<serde_json::Value>> {
    let (id, params) = loop {
        let Ok(message) = connection.receiver.recv() else {
            return Ok(None);
        };
        match message {
            Message::Request(r) if r.method == Initialize::METHOD => break (r.id, r.params),
            Message::Request(r) => {
                let refused = Response::new_err(
                    r.id,
                    ErrorCode::ServerNotInitialized as i32,
                    format!("`{}` before `initialize`", r.method),
                );
                connection.sender.send(Message::Response(refused))?;
            }
            Message::Notification(n) if n.method == Exit::METHOD => return Ok(None),
            Message::Notification(_) | Message::Response(_) => {}
        }
    };
    let result = InitializeResult {
        capabilities: capabilities(),
        server_info: Some(ServerInfo {
            name: "genom-check".to_owned(),
            version: Some(env!("CARGO_PKG_VERSION").to_owned()),
        }),
    };
    let answer = Response::new_ok(id, serde_json::to_value(result)?);
    connection.sender.send(Message::Response(answer))?;
    Ok(Some(params))
}

/// The params of a request or notification, as the protocol types them.
fn typed<P: serde::de::DeserializeOwned>(params: serde_json::Value) -> Result<P, String> {
    serde_json::from_value(params).map_err(|e| e.to_string())
}

/// The server's state: the open documents by URI.
struct Server<'a> {
    connection: &'a Connection,
    /// Checks to run.
    jobs: crossbeam_channel::Sender<Job>,
    /// The check running now (to cancel it when its text changes).
    running: std::sync::Arc<worker::Running>,
    /// Whether the client shows `$/progress`.
    progress: bool,
    /// Requests sent to the client so far (for their ids).
    requests: u64,
    /// `shutdown` came: only `exit` is taken now.
    shut_down: bool,
    documents: BTreeMap<String, Document>,
}

impl Server<'_> {
    /// What `exit` (or the end of the input) ends with.
    fn exit_status(&self) -> u8 {
        if self.shut_down { EXIT_OK } else { EXIT_ERRORS }
    }

    /// Takes one message from the client; the exit status when it is
    /// `exit`.
    fn message(&mut self, message: Message) -> Fallible<Option<u8>> {
        match message {
            Message::Request(r) if self.shut_down => {
                let refused = Response::new_err(
                    r.id,
                    ErrorCode::InvalidRequest as i32,
                    format!("`{}`: the server is shutting down", r.method),
                );
                self.reply(refused)?;
            }
            Message::Request(r) if r.method == Shutdown::METHOD => {
                self.shut_down = true;
                self.reply(Response::new_ok(r.id, ()))?;
            }
            Message::Request(r) => self.request(r)?,
            Message::Notification(n) if n.method == Exit::METHOD => {
                return Ok(Some(self.exit_status()));
            }
            Message::Notification(_) if self.shut_down => {}
            Message::Notification(n) => self.notification(n)?,
            Message::Response(_) => {}
        }
        Ok(None)
    }

    /// The params of notification `method`, or `None` (logged) when they
    /// are not what the protocol says.
    fn params<P: serde::de::DeserializeOwned>(
        &self,
        method: &str,
        params: serde_json::Value,
    ) -> Fallible<Option<P>> {
        match typed(params) {
            Ok(p) => Ok(Some(p)),
            Err(e) => {
                let message = format!("ignored `{method}`: invalid params: {e}");
                self.log(MessageType::ERROR, &message)?;
                Ok(None)
            }
        }
    }

    fn notification(&mut self, n: Notification) -> Fallible<()> {
        let Notification { method, params } = n;
        match method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Some(p) =
                    self.params::<lsp_types::DidOpenTextDocumentParams>(&method, params)?
                else {
                    return Ok(());
                };
                let doc = Document::new(p.text_document.uri, p.text_document.text);
                self.recheck(doc, false)
            }
            DidChangeTextDocument::METHOD => {
                let Some(p) =
                    self.params::<lsp_types::DidChangeTextDocumentParams>(&method, params)?
                else {
                    return Ok(());
                };
                let key = p.text_document.uri.as_str().to_owned();
                let (Some(mut doc), Some(change)) = (
                    self.documents.remove(&key),
                    p.content_changes.into_iter().last(),
                ) else {
                    return Ok(());
                };
                doc.text = change.text;
                self.recheck(doc, false)
            }
            DidSaveTextDocument::METHOD => {
                let Some(p) =
                    self.params::<lsp_types::DidSaveTextDocumentParams>(&method, params)?
                else {
                    return Ok(());
                };
                match self.documents.remove(p.text_document.uri.as_str()) {
                    Some(doc) => self.recheck(doc, true),
                    None => Ok(()),
                }
            }
            DidCloseTextDocument::METHOD => {
                let Some(p) =
                    self.params::<lsp_types::DidCloseTextDocumentParams>(&method, params)?
                else {
                    return Ok(());
                };
                let Some(mut doc) = self.documents.remove(p.text_document.uri.as_str()) else {
                    return Ok(());
                };
                if let Some((token, _)) = doc.progress.take() {
                    self.end_progress(token)?;
                }
                self.clear(&doc)
            }
            _ => Ok(()),
        }
    }

    /// Asks for a check of `doc` (statically, or fully when `full`) and
    /// keeps it.
    fn recheck(&mut self, mut doc: Document, full: bool) -> Fallible<()> {
        let job = doc.job(full);
        if full && self.progress && doc.progress.is_none() {
            doc.progress = Some((self.begin_progress(&doc)?, job.generation));
        }
        if self.running.supersede(job.uri.as_str(), job.generation) {
            self.log(
                MessageType::INFO,
                &format!(
                    "cancelled the running check of {}: its text changed",
                    job.uri.as_str()
                ),
            )?;
        }
        self.jobs.send(job)?;
        self.documents.insert(doc.uri.as_str().to_owned(), doc);
        Ok(())
    }

    /// A check ended: unless its document changed since, its diagnostics
    /// are published and its result kept.
    fn finished(&mut self, done: Done) -> Fallible<()> {
        let key = done.job.uri.as_str().to_owned();
        let Some(mut doc) = self.documents.remove(&key) else {
            return Ok(());
        };
        if done.job.generation == doc.generation {
            let now: BTreeSet<String> = done.files.keys().cloned().collect();
            for (uri, diagnostics) in done.files.into_values() {
                self.publish(uri, diagnostics)?;
            }
            // Includes whose diagnostics are gone are cleared.
            for stale in doc.published.difference(&now) {
                if let Ok(uri) = stale.parse::<Uri>() {
                    self.publish(uri, Vec::new())?;
                }
            }
            doc.published = now;
            doc.checked = done.result.map(|r| (done.job.text, r));
        }
        // A save's progress ends with its check, or with a newer one.
        if let Some((token, _)) = doc.progress.take_if(|(_, g)| *g <= done.job.generation) {
            self.end_progress(token)?;
        }
        self.documents.insert(key, doc);
        Ok(())
    }

    /// Creates a progress token and begins it: "checking NAME".
    fn begin_progress(&mut self, doc: &Document) -> Fallible<ProgressToken> {
        self.requests += 1;
        let token = ProgressToken::String(format!("genom-check/{}", self.requests));
        let create = Request::new(
            RequestId::from(format!("genom-check/{}", self.requests)),
            WorkDoneProgressCreate::METHOD.to_owned(),
            WorkDoneProgressCreateParams {
                token: token.clone(),
            },
        );
        self.connection.sender.send(Message::Request(create))?;
        let name = doc
            .path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let begin = WorkDoneProgress::Begin(WorkDoneProgressBegin {
            title: format!("genom-check: checking {name}"),
            cancellable: Some(false),
            message: Some("whole check (behaviour and timing)".to_owned()),
            percentage: None,
        });
        self.send_progress(token.clone(), begin)?;
        Ok(token)
    }

    fn end_progress(&self, token: ProgressToken) -> Fallible<()> {
        let end = WorkDoneProgress::End(WorkDoneProgressEnd { message: None });
        self.send_progress(token, end)
    }

    fn send_progress(&self, token: ProgressToken, value: WorkDoneProgress) -> Fallible<()> {
        let params = ProgressParams {
            token,
            value: ProgressParamsValue::WorkDone(value),
        };
        let n = Notification::new(Progress::METHOD.to_owned(), params);
        self.connection.sender.send(Message::Notification(n))?;
        Ok(())
    }

    /// Clears every diagnostic a closed document published.
    fn clear(&self, doc: &Document) -> Fallible<()> {
        for uri in &doc.published {
            if let Ok(uri) = uri.parse::<Uri>() {
                self.publish(uri, Vec::new())?;
            }
        }
        Ok(())
    }

    /// A `window/logMessage` to the client.
    fn log(&self, typ: MessageType, message: &str) -> Fallible<()> {
        let params = lsp_types::LogMessageParams {
            typ,
            message: message.to_owned(),
        };
        let n = Notification::new(LogMessage::METHOD.to_owned(), params);
        self.connection.sender.send(Message::Notification(n))?;
        Ok(())
    }

    fn reply(&self, response: Response) -> Fallible<()> {
        self.connection.sender.send(Message::Response(response))?;
        Ok(())
    }

    fn publish(&self, uri: Uri, diagnostics: Vec<lsp_types::Diagnostic>) -> Fallible<()> {
        let params = PublishDiagnosticsParams::new(uri, diagnostics, None);
        let n = Notification::new(PublishDiagnostics::METHOD.to_owned(), params);
        self.connection.sender.send(Message::Notification(n))?;
        Ok(())
    }

    /// What `look` finds at the position a request names (go-to-definition
    /// and hover both carry a document and a position, and nothing else
    /// they need): `Err` when the params are not that.
    fn at_position<T>(
        &self,
        params: serde_json::Value,
        look: fn(&Document, lsp_types::Position) -> Option<T>,
    ) -> Result<Option<T>, String> {
        let at = typed::<lsp_types::TextDocumentPositionParams>(params)?;
        Ok(self
            .documents
            .get(at.text_document.uri.as_str())
            .and_then(|d| look(d, at.position)))
    }

    /// Answers a request: params that are not what the protocol says get
    /// -32602, a second `initialize` -32600, other methods -32601.
    fn request(&self, request: Request) -> Fallible<()> {
        let Request { id, method, params } = request;
        let invalid = |id, e: String| {
            let message = format!("`{method}`: invalid params: {e}");
            Response::new_err(id, ErrorCode::InvalidParams as i32, message)
        };
        let response = match method.as_str() {
            DocumentSymbolRequest::METHOD => match typed::<lsp_types::DocumentSymbolParams>(params)
            {
                Ok(p) => {
                    let symbols = self
                        .documents
                        .get(p.text_document.uri.as_str())
                        .map(navigate::symbols);
                    Response::new_ok(id, symbols)
                }
                Err(e) => invalid(id, e),
            },
            GotoDefinition::METHOD => match self.at_position(params, navigate::definition) {
                Ok(found) => Response::new_ok(id, found),
                Err(e) => invalid(id, e),
            },
            HoverRequest::METHOD => match self.at_position(params, navigate::hover) {
                Ok(found) => Response::new_ok(id, found),
                Err(e) => invalid(id, e),
            },
            Initialize::METHOD => Response::new_err(
                id,
                ErrorCode::InvalidRequest as i32,
                "`initialize`: the server is already initialized".to_owned(),
            ),
            _ => Response::new_err(
                id,
                ErrorCode::MethodNotFound as i32,
                format!("genom-check lsp does not handle `{method}`"),
            ),
        };
        self.reply(response)
    }
}
