//! `rtlang lsp`: a language server over stdio on `lsp-server`'s message
//! types and `lsp-types` (rust-analyzer's crates), with a transport of its
//! own (`transport.rs` says why). This module holds the open documents and
//! routes messages; the lifecycle is `session.rs`'s, and each feature has a
//! file of its own.
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
mod scope;
mod session;
mod symbols;
pub mod transport;

use std::collections::HashMap;
use std::io::{self, Write};
use std::str::FromStr;
use std::sync::Arc;

use lsp_server::{ErrorCode, Notification, Request, Response};
use lsp_types::notification::Notification as _;
use lsp_types::request::Request as _;
use lsp_types::{notification, request, *};
use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::lang::cache::AssetCache;

use document::Document;
use position::{uri_to_path, Lines};

/// Serves one client on stdin and stdout until it sends `exit` or closes
/// stdin. Returns whether it shut down as the specification says
/// (`shutdown`, then `exit`): the exit code is 0 then and 1 otherwise.
pub fn serve_stdio() -> io::Result<bool> {
    let messages = transport::stdin_messages();
    session::run(&messages, &mut |message| {
        let mut out = io::stdout().lock();
        message.write(&mut out)?;
        out.flush()
    })
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
        // The document asked about is indexed as of its latest text (its
        // check may wait for a pause in the edits).
        let uri = req.params["textDocument"]["uri"].as_str();
        if let Some(doc) = uri
            .and_then(|u| Uri::from_str(u).ok())
            .and_then(|u| self.documents.get_mut(&u))
        {
            doc.refresh_index();
        }
        match self.answer(&req) {
            Ok(response) | Err(response) => response,
        }
    }

    fn answer(&mut self, req: &Request) -> Result<Response, Response> {
        Ok(match req.method.as_str() {
            request::HoverRequest::METHOD => {
                let p: HoverParams = params(req)?;
                let pos = &p.text_document_position_params;
                let found = self.at(pos);
                reply(
                    req,
                    found.and_then(|(doc, at)| hover::hover(&pos.text_document.uri, doc, at)),
                )
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

    /// Handles a notification: a document opened, changed or closed.
    fn notification(&mut self, n: Notification) {
        match n.method.as_str() {
            notification::DidOpenTextDocument::METHOD => {
                if let Ok(p) = serde_json::from_value::<DidOpenTextDocumentParams>(n.params) {
                    let doc = p.text_document;
                    self.set_text(doc.uri, doc.text, doc.version);
                }
            }
            notification::DidChangeTextDocument::METHOD => {
                if let Ok(p) = serde_json::from_value::<DidChangeTextDocumentParams>(n.params) {
                    if let Some(change) = p.content_changes.into_iter().last() {
                        let doc = p.text_document;
                        self.set_text(doc.uri, change.text, doc.version);
                    }
                }
            }
            notification::DidCloseTextDocument::METHOD => {
                if let Ok(p) = serde_json::from_value::<DidCloseTextDocumentParams>(n.params) {
                    if let Some(closed) = self.documents.remove(&p.text_document.uri) {
                        // Its includers read the file on disk again.
                        self.includers_stale(&closed.path);
                    }
                }
            }
            _ => {}
        }
    }

    fn set_text(&mut self, uri: Uri, text: String, version: i32) {
        let Some(path) = uri_to_path(&uri) else {
            return;
        };
        let doc = self
            .documents
            .entry(uri)
            .or_insert_with(|| Document::new(path));
        doc.set_text(text, version);
        let path = doc.path.clone();
        self.includers_stale(&path);
    }

    /// Marks for a new check every open document whose last check read the
    /// file at `path`, so an error made or fixed there shows at their
    /// `include` lines.
    fn includers_stale(&mut self, path: &std::path::Path) {
        for doc in self.documents.values_mut() {
            if doc.reads(path) {
                doc.stale_check = true;
            }
        }
    }

    /// Checks every document whose text (or an included open document's)
    /// changed since its last check; returns the diagnostics to publish.
    fn check_changed(&mut self) -> Vec<Notification> {
        let stale: Vec<Uri> = self
            .documents
            .iter()
            .filter(|(_, d)| d.stale_check)
            .map(|(u, _)| u.clone())
            .collect();
        let mut out = Vec::new();
        for uri in stale {
            let buffers = self
                .documents
                .iter()
                .filter(|(u, _)| **u != uri)
                .map(|(_, d)| (d.path.clone(), d.text.clone()))
                .collect();
            let Some(doc) = self.documents.get_mut(&uri) else {
                continue;
            };
            let outcome = doc.check(&self.assets, buffers);
            out.extend(
                diagnostics::publish(&uri, doc, &outcome)
                    .into_iter()
                    .map(|p| {
                        Notification::new(notification::PublishDiagnostics::METHOD.to_string(), p)
                    }),
            );
        }
        out
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
