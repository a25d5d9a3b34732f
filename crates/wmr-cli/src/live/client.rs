//! One client of the live server: its outgoing queue, bounded in bytes (the oldest data
//! dropped and counted when the client reads slower than the stream), its subscriptions,
//! and the thread that does its handshake, writes its queue and reads its requests without
//! ever blocking on it (a client that never reads cannot hold the server).

use std::collections::{BTreeMap, VecDeque};
use std::io;
use std::net::{SocketAddr, TcpStream};
use std::sync::atomic::Ordering;
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use tungstenite::protocol::WebSocketConfig;
use tungstenite::{Error as WsError, Message, WebSocket};

use super::handshake::negotiate;
use super::protocol::{self, Level, Request};
use super::server::Shared;

/// Longest one read or write of the handshake may block (the whole handshake is bounded
/// by [`super::server::Limits::handshake`], enforced by the server's accept thread).
const HANDSHAKE_TIMEOUT: Duration = Duration::from_secs(5);

/// Longest the client thread waits before looking at its socket again (for requests, or
/// for room to write when the client reads slowly) when nothing new is queued.
const CLIENT_POLL: Duration = Duration::from_millis(10);

/// Messages written between two looks at the client's requests.
const WRITE_BATCH: usize = 256;

/// Bytes a queued message costs beyond its payload (the queue entry, the allocation), so
/// that a queue of small messages is bounded by what it really holds.
const OVERHEAD_BYTES: usize = 64;

/// What `message` costs in a queue, bytes.
fn cost(message: &Message) -> usize {
    message.len() + OVERHEAD_BYTES
}

/// Largest text message a client may send (a subscribe to every channel of 256 runs takes
/// about 60 kB).
const MAX_REQUEST_BYTES: usize = 1 << 20;

/// A queued message: droppable ones (data, clock, replies) go first when the queue is over
/// its bound; the greeting (serverInfo, advertise) is kept.
struct Out {
    message: Message,
    droppable: bool,
}

/// What the server and the client thread share of a client, under one lock.
#[derive(Default)]
struct State {
    queue: VecDeque<Out>,
    /// Bytes of the queued messages.
    bytes: usize,
    /// Messages dropped from the queue, oldest first.
    dropped: u64,
    /// Channel id -> the client's subscription id on it.
    subscriptions: BTreeMap<u64, u32>,
    /// The thread holds written data the socket has not taken yet.
    busy: bool,
    /// The WebSocket is open (handshake done, not closed).
    open: bool,
    /// The handshake is over (done or failed).
    handshaken: bool,
    /// The client has subscribed to some channel (once is enough).
    subscribed: bool,
    /// The server asked this client to go (past a deadline, or its slot given to a new
    /// connection): it no longer counts against the client limit.
    leaving: bool,
}

/// A connected client.
pub struct Client {
    /// The peer address.
    pub peer: SocketAddr,
    /// A handle on the socket, to shut it down when the server closes.
    socket: TcpStream,
    state: Mutex<State>,
    wake: Condvar,
    /// Bound of the queue, bytes.
    queue_bytes: usize,
    /// When the connection was accepted.
    connected: Instant,
}

/// Where a client stands, for the server's deadlines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standing {
    /// Still in the WebSocket handshake.
    Handshaking,
    /// Open, never subscribed to anything.
    Idle,
    /// Subscribed at least once (a viewer): never sent away.
    Viewer,
    /// Asked to go, or gone.
    Leaving,
}

impl Client {
    /// A client on `socket` (a clone of the stream its thread serves).
    pub fn new(peer: SocketAddr, socket: TcpStream, queue_bytes: usize) -> Self {
        Self { peer, socket, state: Mutex::default(), wake: Condvar::new(), queue_bytes, connected: Instant::now() }
    }

    /// Time since the connection was accepted.
    pub fn age(&self) -> Duration {
        self.connected.elapsed()
    }

    /// Where the client stands.
    pub fn standing(&self) -> Standing {
        let s = self.lock();
        if s.leaving {
            Standing::Leaving
        } else if !s.handshaken {
            Standing::Handshaking
        } else if s.subscribed {
            Standing::Viewer
        } else if s.open {
            Standing::Idle
        } else {
            Standing::Leaving
        }
    }

    /// Sends the client away: a handshake still going is cut (its socket shut down), an
    /// open client is closed with a close frame by its thread. It stops counting against
    /// the client limit at once.
    pub fn send_away(&self) {
        let mut s = self.lock();
        s.leaving = true;
        let handshaking = !s.handshaken;
        drop(s);
        if handshaking {
            self.shutdown();
        }
        self.wake.notify_all();
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Queues `message`; over the bound, the oldest droppable messages go.
    fn push(&self, message: Message, droppable: bool) {
        let mut s = self.lock();
        s.bytes += cost(&message);
        s.queue.push_back(Out { message, droppable });
        while s.bytes > self.queue_bytes {
            // The greeting and replies sit at the front: the first droppable is close by.
            let Some(at) = s.queue.iter().position(|o| o.droppable) else { break };
            if at + 1 == s.queue.len() {
                break; // the message just queued: keep it (a message larger than the bound)
            }
            if let Some(old) = s.queue.remove(at) {
                s.bytes -= cost(&old.message);
                s.dropped += 1;
            }
        }
        drop(s);
        self.wake.notify_one();
    }

    /// Queues the message of `channel` at `log_time_ns` if the client subscribed to it.
    pub fn send_on(&self, channel: u64, log_time_ns: u64, payload: &[u8]) {
        let sub = self.lock().subscriptions.get(&channel).copied();
        if let Some(sub) = sub {
            self.push(Message::binary(protocol::message_data(sub, log_time_ns, payload)), true);
        }
    }

    /// Queues the server clock at `time_ns` (to an open client).
    pub fn send_time(&self, time_ns: u64) {
        if self.lock().open {
            self.push(Message::binary(protocol::time(time_ns)), true);
        }
    }

    /// Nothing left to write: the queue is empty and the socket has taken everything.
    pub fn idle(&self) -> bool {
        let s = self.lock();
        !s.open || (s.queue.is_empty() && !s.busy)
    }

    /// Messages dropped so far.
    pub fn dropped(&self) -> u64 {
        self.lock().dropped
    }

    /// Wakes the client thread (the server is closing).
    pub fn wake(&self) {
        self.wake.notify_all();
    }

    /// Writes an HTTP 400 reply with `text` straight to the socket (before any WebSocket).
    fn reply(&self, text: &str) {
        use std::io::Write as _;
        let body = format!("{text}\n");
        let head = format!(
            "HTTP/1.1 400 Bad Request\r\ncontent-type: text/plain; charset=utf-8\r\nconnection: close\r\n\
             content-length: {}\r\n\r\n",
            body.len()
        );
        let mut socket = &self.socket;
        let _ = socket.write_all(head.as_bytes()).and_then(|()| socket.write_all(body.as_bytes()));
        let _ = socket.shutdown(std::net::Shutdown::Write);
    }

    /// Shuts the socket down: a thread blocked in the handshake returns at once.
    pub fn shutdown(&self) {
        let _ = self.socket.shutdown(std::net::Shutdown::Both);
    }
}

fn would_block(e: &WsError) -> bool {
    matches!(e, WsError::Io(io) if matches!(io.kind(), io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut))
}

/// The client thread: handshake, greeting, then writes and reads until the client goes or
/// the server closes.
pub fn serve(client: &Client, stream: TcpStream, shared: &Shared) {
    if stream.set_read_timeout(Some(HANDSHAKE_TIMEOUT)).is_err()
        || stream.set_write_timeout(Some(HANDSHAKE_TIMEOUT)).is_err()
    {
        return;
    }
    let config = WebSocketConfig::default()
        .max_message_size(Some(MAX_REQUEST_BYTES))
        .max_frame_size(Some(MAX_REQUEST_BYTES))
        .max_write_buffer_size(shared.limits.queue_bytes.max(1 << 20) * 2);
    let handshake = tungstenite::accept_hdr_with_config(stream, negotiate, Some(config));
    client.lock().handshaken = true;
    let mut ws = match handshake {
        Ok(ws) => ws,
        Err(e) => {
            shared.failed_handshakes.fetch_add(1, Ordering::Relaxed);
            // A request that is not a WebSocket upgrade gets a reply saying so (a refused
            // subprotocol has had its reply already).
            if let tungstenite::HandshakeError::Failure(e) = e
                && !matches!(e, WsError::Http(_) | WsError::Io(_))
            {
                client.reply(&format!(
                    "wmr-cli live view: not a WebSocket upgrade request ({e}); connect with a WebSocket client \
                     offering {}",
                    protocol::SUBPROTOCOLS.join(" or ")
                ));
            }
            return;
        }
    };
    if ws.get_ref().set_nonblocking(true).is_err() || shared.stopping() || client.lock().leaving {
        return;
    }
    client.lock().open = true;
    client.push(Message::text(shared.server_info.clone()), false);
    client.push(Message::text(shared.advertise.clone()), false);
    let _ = run(client, &mut ws, shared);
    // Best effort: a close frame, if the socket takes it now.
    let _ = ws.close(None);
    let _ = ws.flush();
    client.lock().open = false;
}

/// Writes the queue and answers requests until an error, the client's close or the
/// server's stop; never blocks on the socket.
fn run(client: &Client, ws: &mut WebSocket<TcpStream>, shared: &Shared) -> Result<(), WsError> {
    loop {
        if shared.stopping() || client.lock().leaving {
            return Ok(());
        }
        // Write what is queued, as far as the socket takes it.
        if client.lock().busy {
            match ws.flush() {
                Ok(()) => client.lock().busy = false,
                Err(e) if would_block(&e) => {}
                Err(e) => return Err(e),
            }
        }
        let mut wrote = false;
        for _ in 0..WRITE_BATCH {
            let mut s = client.lock();
            if s.busy {
                break;
            }
            let Some(out) = s.queue.pop_front() else { break };
            s.bytes -= cost(&out.message);
            drop(s);
            wrote = true;
            match ws.write(out.message) {
                Ok(()) => {}
                // Buffered by the WebSocket: written on a later flush.
                Err(e) if would_block(&e) => client.lock().busy = true,
                Err(e) => return Err(e),
            }
        }
        if wrote && !client.lock().busy {
            match ws.flush() {
                Ok(()) => {}
                Err(e) if would_block(&e) => client.lock().busy = true,
                Err(e) => return Err(e),
            }
        }
        // Read the client's requests.
        loop {
            match ws.read() {
                Ok(Message::Text(text)) => answer(client, shared, text.as_str()),
                Ok(Message::Binary(_)) => client.push(
                    Message::text(protocol::status(
                        Level::Warning,
                        "this server does not take client messages (no clientPublish capability)",
                    )),
                    true,
                ),
                Ok(Message::Close(_)) => {}
                Ok(_) => {} // ping (answered by the WebSocket), pong, raw frame
                Err(e) if would_block(&e) => break,
                Err(WsError::ConnectionClosed | WsError::AlreadyClosed) => return Ok(()),
                Err(e) => return Err(e),
            }
        }
        let s = client.lock();
        if s.queue.is_empty() || s.busy {
            let _ = client.wake.wait_timeout(s, CLIENT_POLL);
        }
    }
}

/// Handles one text request; a bad one gets a status reply saying why.
fn answer(client: &Client, shared: &Shared, text: &str) {
    // Replies may be dropped too: a client that sends without reading cannot grow its queue.
    let reply = |level, msg: String| client.push(Message::text(protocol::status(level, &msg)), true);
    match protocol::parse_request(text) {
        Ok(Request::Subscribe(subs)) => {
            for (sub, channel) in subs {
                if !shared.has_channel(channel) {
                    reply(Level::Error, format!("subscribe: no channel {channel}"));
                    continue;
                }
                let mut s = client.lock();
                if s.subscriptions.values().any(|&v| v == sub) {
                    drop(s);
                    reply(Level::Error, format!("subscribe: subscription id {sub} is already in use"));
                    continue;
                }
                s.subscriptions.insert(channel, sub);
                s.subscribed = true;
                drop(s);
                shared.subscriptions.fetch_add(1, Ordering::SeqCst);
            }
        }
        Ok(Request::Unsubscribe(ids)) => client.lock().subscriptions.retain(|_, sub| !ids.contains(sub)),
        Ok(Request::Unsupported(op)) => reply(Level::Warning, format!("operation {op:?} is not supported here")),
        Err(why) => reply(Level::Error, format!("bad request: {why}")),
    }
}
