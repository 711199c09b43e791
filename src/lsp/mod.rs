//! `rtlang lsp`: a language server over stdio on `lsp-server` and
//! `lsp-types` (rust-analyzer's crates). This module holds the open
//! documents and routes messages; each feature has a file of its own.
//!
//! Documents sync whole (every change sends the full text): scene files are
//! small and a full re-check is what gives `rtlang check`'s diagnostics.

mod complete;
mod diagnostics;
mod document;
mod hover;
mod index;
mod navigate;
mod position;
pub mod reference;
mod symbols;

use std::collections::HashMap;
use std::error::Error;
use std::sync::Arc;

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::Notification as _;
use lsp_types::request::Request as _;
use lsp_types::{notification, request, *};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::lang::cache::AssetCache;

use document::Document;
use position::{uri_to_path, Lines};

type Failure = Box<dyn Error + Send + Sync>;

/// Serves one client on stdin and stdout until it shuts down.
pub fn serve_stdio() -> Result<(), Failure> {
    let (connection, threads) = Connection::stdio();
    serve(&connection)?;
    // The writer thread ends when the last sender is gone.
    drop(connection);
    threads.join()?;
    Ok(())
}

/// The initialize handshake, then messages until `shutdown` and `exit`.
pub fn serve(connection: &Connection) -> Result<(), Failure> {
    connection.initialize(serde_json::to_value(capabilities())?)?;
    let mut server = Server::default();
    for message in &connection.receiver {
        match message {
            Message::Request(req) => {
                if connection.handle_shutdown(&req)? {
                    return Ok(());
                }
                connection
                    .sender
                    .send(Message::Response(server.request(req)))?;
            }
            Message::Notification(n) => {
                for out in server.notification(n) {
                    connection.sender.send(Message::Notification(out))?;
                }
            }
            Message::Response(_) => {}
        }
    }
    Ok(())
}

fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(TextDocumentSyncKind::FULL)),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        rename_provider: Some(OneOf::Left(true)),
        completion_provider: Some(CompletionOptions::default()),
        document_symbol_provider: Some(OneOf::Left(true)),
        document_formatting_provider: Some(OneOf::Left(true)),
        semantic_tokens_provider: Some(
            SemanticTokensOptions {
                legend: SemanticTokensLegend {
                    token_types: symbols::TOKEN_TYPES.to_vec(),
                    token_modifiers: Vec::new(),
                },
                full: Some(SemanticTokensFullOptions::Bool(true)),
                ..SemanticTokensOptions::default()
            }
            .into(),
        ),
        ..ServerCapabilities::default()
    }
}

/// The open documents and the assets their checks share.
#[derive(Default)]
struct Server {
    documents: HashMap<Uri, Document>,
    assets: Arc<AssetCache>,
}

/// A request's parameters, or the response that rejects them.
fn params<P: DeserializeOwned>(req: &Request) -> Result<P, Response> {
    serde_json::from_value(req.params.clone()).map_err(|e| {
        Response::new_err(
            req.id.clone(),
            ErrorCode::InvalidParams as i32,
            e.to_string(),
        )
    })
}

fn reply<R: Serialize>(req: &Request, result: R) -> Response {
    Response::new_ok(req.id.clone(), result)
}

impl Server {
    /// The document and byte offset a positional request points at.
    fn at(&self, pos: &TextDocumentPositionParams) -> Option<(&Document, usize)> {
        let doc = self.documents.get(&pos.text_document.uri)?;
        let at = Lines::new(&doc.text).offset(pos.position);
        Some((doc, at))
    }

    fn request(&mut self, req: Request) -> Response {
        match self.answer(&req) {
            Ok(response) | Err(response) => response,
        }
    }

    fn answer(&mut self, req: &Request) -> Result<Response, Response> {
        Ok(match req.method.as_str() {
            request::HoverRequest::METHOD => {
                let p: HoverParams = params(req)?;
                let found = self.at(&p.text_document_position_params);
                reply(req, found.and_then(|(doc, at)| hover::hover(doc, at)))
            }
            request::GotoDefinition::METHOD => {
                let p: GotoDefinitionParams = params(req)?;
                let pos = &p.text_document_position_params;
                let found = self
                    .at(pos)
                    .and_then(|(doc, at)| navigate::definition(&pos.text_document.uri, doc, at));
                reply(req, found.map(GotoDefinitionResponse::Scalar))
            }
            request::References::METHOD => {
                let p: ReferenceParams = params(req)?;
                let pos = &p.text_document_position;
                let found = self.at(pos).map(|(doc, at)| {
                    let decl = p.context.include_declaration;
                    navigate::references(&pos.text_document.uri, doc, at, decl)
                });
                reply(req, found)
            }
            request::Rename::METHOD => {
                let p: RenameParams = params(req)?;
                if !valid_name(&p.new_name) {
                    return Err(Response::new_err(
                        req.id.clone(),
                        ErrorCode::InvalidParams as i32,
                        format!("`{}` is not a name a definition can have", p.new_name),
                    ));
                }
                let pos = &p.text_document_position;
                let found = self.at(pos).and_then(|(doc, at)| {
                    navigate::rename(&pos.text_document.uri, doc, at, &p.new_name)
                });
                reply(req, found)
            }
            request::Completion::METHOD => {
                let p: CompletionParams = params(req)?;
                let found = self.at(&p.text_document_position);
                reply(req, found.map(|(doc, at)| complete::complete(doc, at)))
            }
            request::DocumentSymbolRequest::METHOD => {
                let p: DocumentSymbolParams = params(req)?;
                let found = self.documents.get(&p.text_document.uri);
                reply(
                    req,
                    found.map(|doc| DocumentSymbolResponse::Nested(symbols::outline(doc))),
                )
            }
            request::SemanticTokensFullRequest::METHOD => {
                let p: SemanticTokensParams = params(req)?;
                let found = self
                    .documents
                    .get(&p.text_document.uri)
                    .map(|doc| SemanticTokens {
                        result_id: None,
                        data: symbols::tokens(doc),
                    });
                reply(req, found)
            }
            request::Formatting::METHOD => {
                let p: DocumentFormattingParams = params(req)?;
                let found = self.documents.get(&p.text_document.uri).and_then(|doc| {
                    let formatted = crate::lang::format::format(&doc.text, 0).ok()?;
                    let lines = Lines::new(&doc.text);
                    let whole = lines.range(0, doc.text.len());
                    Some(vec![TextEdit::new(whole, formatted)])
                });
                reply(req, found)
            }
            _ => Response::new_err(
                req.id.clone(),
                ErrorCode::MethodNotFound as i32,
                format!("`{}` is not supported", req.method),
            ),
        })
    }

    /// Handles a notification; returns the diagnostics to publish.
    fn notification(&mut self, n: Notification) -> Vec<Notification> {
        let changed = match n.method.as_str() {
            notification::DidOpenTextDocument::METHOD => {
                serde_json::from_value::<DidOpenTextDocumentParams>(n.params)
                    .ok()
                    .map(|p| (p.text_document.uri, p.text_document.text))
            }
            notification::DidChangeTextDocument::METHOD => {
                serde_json::from_value::<DidChangeTextDocumentParams>(n.params)
                    .ok()
                    .and_then(|p| {
                        Some((
                            p.text_document.uri,
                            p.content_changes.into_iter().last()?.text,
                        ))
                    })
            }
            notification::DidCloseTextDocument::METHOD => {
                if let Ok(p) = serde_json::from_value::<DidCloseTextDocumentParams>(n.params) {
                    self.documents.remove(&p.text_document.uri);
                }
                None
            }
            _ => None,
        };
        let Some((uri, text)) = changed else {
            return Vec::new();
        };
        let Some(path) = uri_to_path(&uri) else {
            return Vec::new();
        };
        let doc = self
            .documents
            .entry(uri.clone())
            .or_insert_with(|| Document::new(path));
        let outcome = doc.update(&text, &self.assets);
        diagnostics::publish(&uri, &outcome)
            .into_iter()
            .map(|p| Notification::new(notification::PublishDiagnostics::METHOD.to_string(), p))
            .collect()
    }
}

/// Whether `name` can name a definition.
fn valid_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !crate::lang::names::is_keyword(name)
}
