//! `ncgear serve`: the interactive designer, a local web application. A shell over the library,
//! as the CLI is: the page (HTML, JS and CSS committed under `page/` and embedded in the binary)
//! draws what the JSON API answers, and the API calls the library's design, teeth, loads and file
//! writers — the same calls `ncgear design` makes, so an export is the CLI's file.
//!
//! Safety: it listens on loopback unless `--host` says otherwise (printed as a warning); a body
//! over [`MAX_BODY_BYTES`] is refused unread; uploads are parsed in memory (no path from the client
//! ever reaches the file system); every error is a JSON answer; a panic in a handler is caught and
//! answered 500, and the server goes on.

mod api;
mod loads;
mod page;
mod routes;
mod view;

use std::io::Read;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Largest request body accepted, bytes (a trajectory of 100 000 points is ~4 MB of JSON).
pub const MAX_BODY_BYTES: usize = 8 << 20;

/// Requests handled at once; more are answered 503 (each design already uses every core).
pub const MAX_CONCURRENT: usize = 8;

/// Where to listen.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// Interface to bind (`127.0.0.1` by default).
    pub host: String,
    /// TCP port (0: any free port).
    pub port: u16,
}

/// An answer: status, content type, body.
pub struct Reply {
    /// HTTP status.
    pub status: u16,
    /// `Content-Type`.
    pub content_type: &'static str,
    /// Body bytes.
    pub body: Vec<u8>,
    /// `Content-Disposition` file name for a download.
    pub download: Option<String>,
}

impl Reply {
    /// A 200 JSON answer.
    pub fn json(body: String) -> Self {
        Self {
            status: 200,
            content_type: "application/json",
            body: body.into_bytes(),
            download: None,
        }
    }

    /// The JSON error answer.
    pub fn error(e: &api::ApiError) -> Self {
        Self {
            status: e.status,
            content_type: "application/json",
            body: e.body().into_bytes(),
            download: None,
        }
    }
}

/// Binds the server; `ready` is called with its URL once it listens, then requests are served
/// until the process ends.
pub fn run(opts: &ServeOptions, ready: impl FnOnce(&str)) -> Result<(), String> {
    let server = tiny_http::Server::http((opts.host.as_str(), opts.port))
        .map_err(|e| format!("cannot listen on {}:{}: {e}", opts.host, opts.port))?;
    let port = server.server_addr().to_ip().map_or(opts.port, |a| a.port());
    let host = if opts.host.contains(':') {
        format!("[{}]", opts.host)
    } else {
        opts.host.clone()
    };
    ready(&format!("http://{host}:{port}/"));
    let server = Arc::new(server);
    let busy = Arc::new(AtomicUsize::new(0));
    for request in server.incoming_requests() {
        if busy.fetch_add(1, Ordering::SeqCst) >= MAX_CONCURRENT {
            busy.fetch_sub(1, Ordering::SeqCst);
            let e = api::ApiError {
                status: 503,
                error: format!("{MAX_CONCURRENT} requests are being served; try again"),
                field: None,
            };
            respond(request, Reply::error(&e));
            continue;
        }
        let busy = Arc::clone(&busy);
        std::thread::spawn(move || {
            handle(request);
            busy.fetch_sub(1, Ordering::SeqCst);
        });
    }
    Ok(())
}

/// Reads the body (bounded), routes, answers; a panic becomes a 500.
fn handle(mut request: tiny_http::Request) {
    let method = request.method().as_str().to_ascii_uppercase();
    let url = request.url().to_string();
    let reply = match read_body(&mut request) {
        Err(e) => Reply::error(&e),
        Ok(body) => std::panic::catch_unwind(|| routes::route(&method, &url, &body))
            .unwrap_or_else(|_| {
                Reply::error(&api::ApiError {
                    status: 500,
                    error: "internal error while answering this request (the server goes on)"
                        .into(),
                    field: None,
                })
            }),
    };
    respond(request, reply);
}

/// The body as UTF-8, refused above [`MAX_BODY_BYTES`] (declared or read).
fn read_body(request: &mut tiny_http::Request) -> Result<String, api::ApiError> {
    let too_big = || api::ApiError {
        status: 413,
        error: format!(
            "the request body is larger than {} MB: send fewer points",
            MAX_BODY_BYTES >> 20
        ),
        field: Some("body".into()),
    };
    if request.body_length().is_some_and(|n| n > MAX_BODY_BYTES) {
        return Err(too_big());
    }
    let mut bytes = Vec::new();
    request
        .as_reader()
        .take(MAX_BODY_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| api::ApiError::bad("body", format!("cannot read the request body: {e}")))?;
    if bytes.len() > MAX_BODY_BYTES {
        return Err(too_big());
    }
    String::from_utf8(bytes)
        .map_err(|_| api::ApiError::bad("body", "the request body is not UTF-8 text"))
}

fn respond(request: tiny_http::Request, reply: Reply) {
    let mut response = tiny_http::Response::from_data(reply.body).with_status_code(reply.status);
    let mut header = |k: &str, v: &str| {
        if let Ok(h) = tiny_http::Header::from_bytes(k.as_bytes(), v.as_bytes()) {
            response.add_header(h);
        }
    };
    header("Content-Type", reply.content_type);
    header("Cache-Control", "no-store");
    header("X-Content-Type-Options", "nosniff");
    if let Some(name) = &reply.download {
        header(
            "Content-Disposition",
            &format!("attachment; filename=\"{name}\""),
        );
    }
    // A client that went away (a cancelled request) is not an error of the server.
    let _ = request.respond(response);
}
