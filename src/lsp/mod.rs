//! `genom-check lsp`: a Language Server over standard input and output.
//! Open and edited documents get the static checks, saved ones the whole
//! check (behaviour, bounded by a timeout); their diagnostics are pushed.
//! It answers document symbols, go-to-definition and hover from the
//! component model of the last check.

mod check;
mod navigate;
mod position;
mod publish;

use std::collections::{BTreeMap, BTreeSet};
use std::error::Error;

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::{
    DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument,
    Notification as _, PublishDiagnostics,
};
use lsp_types::request::{DocumentSymbolRequest, GotoDefinition, HoverRequest, Request as _};
use lsp_types::{
    HoverProviderCapability, InitializeResult, OneOf, PublishDiagnosticsParams, SaveOptions,
    ServerCapabilities, ServerInfo, TextDocumentSyncCapability, TextDocumentSyncKind,
    TextDocumentSyncOptions, TextDocumentSyncSaveOptions, Uri,
};

use self::check::{Document, Settings};
use crate::cli::LspArgs;
use crate::commands::{EXIT_OK, EXIT_USAGE};

type Fallible<T> = Result<T, Box<dyn Error + Send + Sync>>;

/// Serves one client on standard input and output until it exits.
pub fn run(args: &LspArgs) -> u8 {
    let (connection, io_threads) = Connection::stdio();
    let status = match serve(&connection, args) {
        Ok(()) => EXIT_OK,
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

fn serve(connection: &Connection, args: &LspArgs) -> Fallible<()> {
    let (id, params) = connection.initialize_start()?;
    let result = InitializeResult {
        capabilities: capabilities(),
        server_info: Some(ServerInfo {
            name: "genom-check".to_owned(),
            version: Some(env!("CARGO_PKG_VERSION").to_owned()),
        }),
    };
    connection.initialize_finish(id, serde_json::to_value(result)?)?;
    let code_url = params
        .get("initializationOptions")
        .and_then(|o| o.get("codeUrl"))
        .and_then(serde_json::Value::as_str)
        .map(str::to_owned);
    let mut server = Server {
        connection,
        settings: Settings {
            timeout: args.timeout,
            code_url,
        },
        documents: BTreeMap::new(),
    };
    for message in &connection.receiver {
        match message {
            Message::Request(request) => {
                if connection.handle_shutdown(&request)? {
                    return Ok(());
                }
                server.request(request)?;
            }
            Message::Notification(n) if n.method == "exit" => return Ok(()),
            Message::Notification(n) => server.notification(n)?,
            Message::Response(_) => {}
        }
    }
    Ok(())
}

/// The server's state: the open documents by URI.
struct Server<'a> {
    connection: &'a Connection,
    settings: Settings,
    documents: BTreeMap<String, Document>,
}

impl Server<'_> {
    fn notification(&mut self, n: Notification) -> Fallible<()> {
        match n.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let p: lsp_types::DidOpenTextDocumentParams = serde_json::from_value(n.params)?;
                let doc = Document::new(p.text_document.uri, p.text_document.text);
                self.recheck(doc, false)
            }
            DidChangeTextDocument::METHOD => {
                let p: lsp_types::DidChangeTextDocumentParams = serde_json::from_value(n.params)?;
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
                let p: lsp_types::DidSaveTextDocumentParams = serde_json::from_value(n.params)?;
                match self.documents.remove(p.text_document.uri.as_str()) {
                    Some(doc) => self.recheck(doc, true),
                    None => Ok(()),
                }
            }
            DidCloseTextDocument::METHOD => {
                let p: lsp_types::DidCloseTextDocumentParams = serde_json::from_value(n.params)?;
                match self.documents.remove(p.text_document.uri.as_str()) {
                    Some(doc) => self.clear(&doc),
                    None => Ok(()),
                }
            }
            _ => Ok(()),
        }
    }

    /// Checks `doc` (statically, or fully when `full`), publishes its
    /// diagnostics and keeps it.
    fn recheck(&mut self, mut doc: Document, full: bool) -> Fallible<()> {
        let files = doc.check(&self.settings, full);
        let now: BTreeSet<String> = files.keys().cloned().collect();
        for (uri, diagnostics) in files.into_values() {
            self.publish(uri, diagnostics)?;
        }
        // Includes whose diagnostics are gone are cleared.
        for stale in doc.published.difference(&now) {
            if let Ok(uri) = stale.parse::<Uri>() {
                self.publish(uri, Vec::new())?;
            }
        }
        doc.published = now;
        self.documents.insert(doc.uri.as_str().to_owned(), doc);
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

    fn publish(&self, uri: Uri, diagnostics: Vec<lsp_types::Diagnostic>) -> Fallible<()> {
        let params = PublishDiagnosticsParams::new(uri, diagnostics, None);
        let n = Notification::new(PublishDiagnostics::METHOD.to_owned(), params);
        self.connection.sender.send(Message::Notification(n))?;
        Ok(())
    }

    fn request(&self, request: Request) -> Fallible<()> {
        let Request { id, method, params } = request;
        let response = match method.as_str() {
            DocumentSymbolRequest::METHOD => {
                let p: lsp_types::DocumentSymbolParams = serde_json::from_value(params)?;
                let symbols = self
                    .documents
                    .get(p.text_document.uri.as_str())
                    .map(navigate::symbols);
                Response::new_ok(id, symbols)
            }
            GotoDefinition::METHOD => {
                let p: lsp_types::GotoDefinitionParams = serde_json::from_value(params)?;
                let at = p.text_document_position_params;
                let found = self
                    .documents
                    .get(at.text_document.uri.as_str())
                    .and_then(|d| navigate::definition(d, at.position));
                Response::new_ok(id, found)
            }
            HoverRequest::METHOD => {
                let p: lsp_types::HoverParams = serde_json::from_value(params)?;
                let at = p.text_document_position_params;
                let found = self
                    .documents
                    .get(at.text_document.uri.as_str())
                    .and_then(|d| navigate::hover(d, at.position));
                Response::new_ok(id, found)
            }
            _ => Response::new_err(
                id,
                ErrorCode::MethodNotFound as i32,
                format!("genom-check lsp does not handle `{method}`"),
            ),
        };
        self.connection.sender.send(Message::Response(response))?;
        Ok(())
    }
}
