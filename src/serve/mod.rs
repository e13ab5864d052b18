//! `ncgear serve`: the interactive designer, a local web application. A shell over the library,
//! as the CLI is: the page (HTML, JS and CSS committed under `page/` and embedded in the binary)
//! draws what the JSON API answers, and the API calls the library's design, teeth, loads and file
//! writers — the same calls `ncgear design` makes, so an export is the CLI's file.
//!
//! Serving: each request is read and answered on a thread of its own (at most [`MAX_IN_FLIGHT`]
//! at once; more are answered 503), but its computation waits for one of `--workers` permits
//! (the number of cores by default, [`default_workers`]),
//! taken in arrival order: a design already runs on every core for part of its time, and more
//! designs at once than cores only share the cores, each answering later, and hold more memory.
//! A request whose client has closed its connection (the page cancels a design when the pointer
//! moves again) is not computed, or not finished ([`client::gone`]): it leaves the queue, or
//! stops after the design, before drawing and writing the answer.
//!
//! Safety: it listens on loopback unless `--host` says otherwise (printed as a warning); a body
//! over [`MAX_BODY_BYTES`] is refused unread; uploads are parsed in memory (no path from the client
//! ever reaches the file system); every error is a JSON answer; a panic in a handler is caught and
//! answered 500, and the server goes on.

mod api;
mod client;
mod dispatch;
mod loads;
mod page;
mod view;

use std::collections::VecDeque;
use std::io::Read;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::time::Duration;

/// Largest request body accepted, bytes (a trajectory of 100 000 points is ~4 MB of JSON).
pub const MAX_BODY_BYTES: usize = 8 << 20;

/// Requests in the server at once (being read, waiting for a core, computed or answered); more
/// are answered 503.
pub const MAX_IN_FLIGHT: usize = 64;

/// How often a request waiting for a core looks whether its client is still there.
const WAIT_POLL: Duration = Duration::from_millis(20);

/// Status of the answer to a request whose client has gone (nginx's "client closed request";
/// nobody reads it).
pub const CLIENT_GONE: u16 = 499;

/// Requests computed at once by default: the number of cores.
pub fn default_workers() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get())
}

/// Where to listen.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// Interface to bind (`127.0.0.1` by default).
    pub host: String,
    /// TCP port (0: any free port).
    pub port: u16,
    /// Requests computed at once (the others wait in arrival order); `None`: the number of
    /// cores ([`default_workers`]).
    pub workers: Option<usize>,
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
    let gate = Arc::new(Gate::new(opts.workers.unwrap_or_else(default_workers)));
    let in_flight = Arc::new(AtomicUsize::new(0));
    for request in server.incoming_requests() {
        if in_flight.fetch_add(1, Ordering::SeqCst) >= MAX_IN_FLIGHT {
            in_flight.fetch_sub(1, Ordering::SeqCst);
            let e = api::ApiError {
                status: 503,
                error: format!("{MAX_IN_FLIGHT} requests are being served; try again"),
                field: None,
            };
            STATS.refused_busy.fetch_add(1, Ordering::Relaxed);
            respond(request, Reply::error(&e));
            continue;
        }
        let (gate, in_flight) = (Arc::clone(&gate), Arc::clone(&in_flight));
        std::thread::spawn(move || {
            handle(request, &gate);
            in_flight.fetch_sub(1, Ordering::SeqCst);
        });
    }
    Ok(())
}

/// Reads the body (bounded), waits for a core, routes, answers; a panic becomes a 500. A request
/// whose client has gone is not computed.
fn handle(mut request: tiny_http::Request, gate: &Gate) {
    let method = request.method().as_str().to_ascii_uppercase();
    let url = request.url().to_string();
    let peer = request.remote_addr().copied();
    let gone = || peer.is_some_and(client::gone);
    let reply = match read_body(&mut request) {
        Err(e) => Reply::error(&e),
        // What the server says of itself, at once (not behind the computations).
        Ok(_) if method == "GET" && url == "/api/stats" => Reply::json(STATS.json(gate)),
        // Pages, examples, the scene: nothing to compute, no permit.
        Ok(body) if method != "POST" => answer(&method, &url, &body, &|| false),
        Ok(_) if gone() => STATS.left(Reply::error(&gone_error())),
        Ok(body) => match gate.enter(&gone) {
            None => STATS.left(Reply::error(&gone_error())),
            Some(_permit) => {
                let reply = answer(&method, &url, &body, &gone);
                STATS.computed(&reply);
                reply
            }
        },
    };
    respond(request, reply);
}

/// Routes; a panic becomes a 500.
fn answer(method: &str, url: &str, body: &str, gone: &dyn Fn() -> bool) -> Reply {
    // `gone` only reads the peer's socket: nothing a panic could leave half-changed.
    let route = std::panic::AssertUnwindSafe(|| dispatch::route(method, url, body, gone));
    std::panic::catch_unwind(route).unwrap_or_else(|_| {
        Reply::error(&api::ApiError {
            status: 500,
            error: "internal error while answering this request (the server goes on)".into(),
            field: None,
        })
    })
}

/// What became of the computing requests (`POST`) since the server started: `GET /api/stats`.
static STATS: Stats = Stats {
    computed: AtomicUsize::new(0),
    gone_before: AtomicUsize::new(0),
    gone_after_design: AtomicUsize::new(0),
    refused_busy: AtomicUsize::new(0),
};

struct Stats {
    /// Given a permit and computed (answered, or stopped after the design: `gone_after_design`).
    computed: AtomicUsize,
    /// Client gone before a permit: not computed at all.
    gone_before: AtomicUsize,
    /// Client gone during the design: designed, not drawn nor written.
    gone_after_design: AtomicUsize,
    /// Answered 503: [`MAX_IN_FLIGHT`] requests in the server.
    refused_busy: AtomicUsize,
}

impl Stats {
    fn left(&self, reply: Reply) -> Reply {
        self.gone_before.fetch_add(1, Ordering::Relaxed);
        reply
    }

    fn computed(&self, reply: &Reply) {
        self.computed.fetch_add(1, Ordering::Relaxed);
        if reply.status == CLIENT_GONE {
            self.gone_after_design.fetch_add(1, Ordering::Relaxed);
        }
    }

    fn json(&self, gate: &Gate) -> String {
        let n = |a: &AtomicUsize| a.load(Ordering::Relaxed);
        let (waiting, free) = {
            let s = gate.lock();
            (s.waiting.len(), s.free)
        };
        serde_json::json!({
            "workers": gate.permits,
            "computing": gate.permits - free,
            "waiting": waiting,
            "computed": n(&self.computed),
            "gone_before_computing": n(&self.gone_before),
            "gone_after_design": n(&self.gone_after_design),
            "refused_busy": n(&self.refused_busy),
        })
        .to_string()
    }
}

/// The answer to a request whose client closed its connection before it was answered.
pub fn gone_error() -> api::ApiError {
    api::ApiError {
        status: CLIENT_GONE,
        error: "the client closed its connection before the answer (nobody reads this)".into(),
        field: None,
    }
}

/// At most `permits` computations at once; the others wait in arrival order (a fair semaphore).
struct Gate {
    permits: usize,
    state: Mutex<GateState>,
    turn: Condvar,
}

struct GateState {
    free: usize,
    /// Tickets of the waiting requests, oldest first.
    waiting: VecDeque<u64>,
    next: u64,
}

/// A computation's permit, given back when dropped.
struct Permit<'a>(&'a Gate);

impl Gate {
    fn new(permits: usize) -> Self {
        Self {
            permits: permits.max(1),
            state: Mutex::new(GateState {
                free: permits.max(1),
                waiting: VecDeque::new(),
                next: 0,
            }),
            turn: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, GateState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Waits for a permit, in arrival order; `None` when `abandoned()` (asked every
    /// [`WAIT_POLL`] while waiting, never under the lock) says the request is no longer wanted.
    fn enter(&self, abandoned: &dyn Fn() -> bool) -> Option<Permit<'_>> {
        let mut s = self.lock();
        let ticket = s.next;
        s.next += 1;
        s.waiting.push_back(ticket);
        loop {
            if s.free > 0 && s.waiting.front() == Some(&ticket) {
                s.waiting.pop_front();
                s.free -= 1;
                drop(s);
                // The next in line may find a permit free too.
                self.turn.notify_all();
                return Some(Permit(self));
            }
            s = self
                .turn
                .wait_timeout(s, WAIT_POLL)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
            drop(s);
            let leave = abandoned();
            s = self.lock();
            if leave {
                s.waiting.retain(|&t| t != ticket);
                drop(s);
                self.turn.notify_all();
                return None;
            }
        }
    }
}

impl Drop for Permit<'_> {
    fn drop(&mut self) {
        self.0.lock().free += 1;
        self.0.turn.notify_all();
    }
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

#[cfg(test)]
mod tests {
    use super::Gate;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::{Arc, Mutex};
    use std::thread::{sleep, spawn};
    use std::time::{Duration, Instant};

    /// Waits until `n` requests wait at `gate` (10 s at most).
    fn until_waiting(gate: &Gate, n: usize) {
        let t = Instant::now();
        while gate.lock().waiting.len() != n {
            assert!(t.elapsed() < Duration::from_secs(10), "{n} never waiting");
            sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn permits_are_given_in_arrival_order() {
        let gate = Arc::new(Gate::new(1));
        let order = Arc::new(Mutex::new(Vec::new()));
        let first = gate.enter(&|| false).unwrap();
        let mut waiters = Vec::new();
        for k in 0..6 {
            let (gate2, order) = (Arc::clone(&gate), Arc::clone(&order));
            waiters.push(spawn(move || {
                let _permit = gate2.enter(&|| false).unwrap();
                order.lock().unwrap().push(k);
                sleep(Duration::from_millis(2));
            }));
            // The next arrives once this one waits: arrival order is k.
            until_waiting(&gate, k + 1);
        }
        drop(first);
        for w in waiters {
            w.join().unwrap();
        }
        assert_eq!(*order.lock().unwrap(), (0..6).collect::<Vec<_>>());
        assert_eq!(gate.lock().free, 1);
    }

    #[test]
    fn a_permit_given_back_lets_the_next_in_even_after_a_panic() {
        let gate = Arc::new(Gate::new(2));
        let a = gate.enter(&|| false).unwrap();
        let b = gate.enter(&|| false).unwrap();
        assert_eq!(gate.lock().free, 0);
        let entered = Arc::new(AtomicBool::new(false));
        let (gate2, entered2) = (Arc::clone(&gate), Arc::clone(&entered));
        let third = spawn(move || {
            let _permit = gate2.enter(&|| false).unwrap();
            entered2.store(true, Ordering::SeqCst);
        });
        until_waiting(&gate, 1);
        sleep(Duration::from_millis(60));
        assert!(
            !entered.load(Ordering::SeqCst),
            "a third entered with two permits taken"
        );
        drop(a);
        third.join().unwrap();
        assert!(entered.load(Ordering::SeqCst));
        drop(b);
        assert_eq!(gate.lock().free, 2);
        // A computation that panics gives its permit back while unwinding.
        let gate2 = Arc::clone(&gate);
        let panicked = spawn(move || {
            let _permit = gate2.enter(&|| false).unwrap();
            panic!("a handler's panic");
        });
        assert!(panicked.join().is_err());
        assert_eq!(gate.lock().free, 2);
        assert!(gate.lock().waiting.is_empty());
    }

    #[test]
    fn an_abandoned_request_leaves_the_queue_and_the_next_is_served() {
        let gate = Arc::new(Gate::new(1));
        let holder = gate.enter(&|| false).unwrap();
        let leave = Arc::new(AtomicBool::new(false));
        let (gate2, leave2) = (Arc::clone(&gate), Arc::clone(&leave));
        let quitter = spawn(move || gate2.enter(&|| leave2.load(Ordering::SeqCst)).is_none());
        until_waiting(&gate, 1);
        let gate2 = Arc::clone(&gate);
        let next = spawn(move || gate2.enter(&|| false).is_some());
        until_waiting(&gate, 2);
        // The first in line gives up while the permit is still held: it leaves without one.
        leave.store(true, Ordering::SeqCst);
        assert!(
            quitter.join().unwrap(),
            "the abandoned request was given a permit"
        );
        until_waiting(&gate, 1);
        drop(holder);
        assert!(next.join().unwrap());
        assert_eq!(gate.lock().free, 1);
        assert!(gate.lock().waiting.is_empty());
    }
}
