//! The live server: a TCP listener bound before anything else is done, a bounded number of
//! clients (one thread each, [`super::client`]), each with a queue bounded in bytes; the
//! stream's messages fanned out to the clients subscribed to their channel. Closing never
//! waits on a client.

use std::collections::BTreeSet;
use std::io::{Read as _, Write as _};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context as _, Result};

use super::client::{self, Client, Standing};
use super::protocol::{self, ChannelInfo};

/// Clients connected at once at most (further connections get HTTP 503).
pub const MAX_CLIENTS: usize = 16;

/// Bytes queued per client at most; over it the oldest messages are dropped (and counted).
pub const CLIENT_QUEUE_BYTES: usize = 4 << 20;

/// Longest a connection may take, from its accept, to complete the WebSocket handshake
/// (the whole request and the reply, however slowly it trickles in).
pub const HANDSHAKE_DEADLINE: Duration = Duration::from_secs(5);

/// Longest a client may stay connected without ever subscribing to a channel (a viewer
/// subscribes as soon as it reads the channels).
pub const IDLE_LIMIT: Duration = Duration::from_secs(10);

/// At the client limit, a new connection takes the slot of the oldest client that has
/// not subscribed (or not finished its handshake) and has been connected this long.
pub const SLOT_GRACE: Duration = Duration::from_secs(1);

/// Longest the accept thread sleeps between two looks at the listener.
const ACCEPT_POLL: Duration = Duration::from_millis(10);

/// Longest a refused connection may take to send its request before the 503 reply.
const REFUSE_READ: Duration = Duration::from_millis(200);

/// After the server asks its clients to stop, how long they get to send a close frame
/// before their sockets are shut down.
const CLOSE_GRACE: Duration = Duration::from_millis(200);

/// The server's limits.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Clients at once.
    pub max_clients: usize,
    /// Queue bound per client, bytes.
    pub queue_bytes: usize,
    /// Deadline of the whole handshake, from the accept.
    pub handshake: Duration,
    /// Longest a client may stay without ever subscribing.
    pub idle: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_clients: MAX_CLIENTS,
            queue_bytes: CLIENT_QUEUE_BYTES,
            handshake: HANDSHAKE_DEADLINE,
            idle: IDLE_LIMIT,
        }
    }
}

/// What the server and its threads share.
pub struct Shared {
    stop: AtomicBool,
    clients: Mutex<Vec<Arc<Client>>>,
    threads: Mutex<Vec<JoinHandle<()>>>,
    channels: BTreeSet<u64>,
    /// The greeting: `serverInfo` and `advertise`.
    pub server_info: String,
    /// See `server_info`.
    pub advertise: String,
    /// The limits.
    pub limits: Limits,
    /// Subscriptions made so far (all clients).
    pub subscriptions: AtomicU64,
    /// Connections refused for the client limit.
    refused: AtomicU64,
    /// Connections that did not complete the WebSocket handshake.
    pub failed_handshakes: AtomicU64,
    /// Clients served (handshake done or not).
    connections: AtomicU64,
    /// Messages dropped by clients already gone.
    dropped_gone: AtomicU64,
    /// Clients sent away: past the handshake deadline or the idle limit, or for a new
    /// connection at the client limit.
    expired: AtomicU64,
}

impl Shared {
    /// The server is closing.
    pub fn stopping(&self) -> bool {
        self.stop.load(Ordering::SeqCst)
    }

    /// `channel` is one the server advertised.
    pub fn has_channel(&self, channel: u64) -> bool {
        self.channels.contains(&channel)
    }

    fn clients(&self) -> MutexGuard<'_, Vec<Arc<Client>>> {
        self.clients.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// What the server saw, for the final report.
#[derive(Debug, Default)]
pub struct Stats {
    /// Connections accepted.
    pub connections: u64,
    /// Connections refused (client limit).
    pub refused: u64,
    /// Messages dropped for clients that read slower than the stream.
    pub dropped: u64,
    /// Clients sent away (handshake deadline, idle limit, slot given to a new connection).
    pub expired: u64,
}

/// A running server.
pub struct Server {
    shared: Arc<Shared>,
    accept: Option<JoinHandle<()>>,
    addr: SocketAddr,
}

impl Server {
    /// Binds `addr` and starts accepting clients that get `name` and `channels`.
    pub fn bind(addr: SocketAddr, name: &str, channels: &[ChannelInfo], limits: Limits) -> Result<Self> {
        let listener = TcpListener::bind(addr)?;
        let addr = listener.local_addr()?;
        listener.set_nonblocking(true)?;
        let shared = Arc::new(Shared {
            stop: AtomicBool::new(false),
            clients: Mutex::default(),
            threads: Mutex::default(),
            channels: channels.iter().map(|c| c.id).collect(),
            server_info: protocol::server_info(name),
            advertise: protocol::advertise(channels),
            limits,
            subscriptions: AtomicU64::new(0),
            refused: AtomicU64::new(0),
            failed_handshakes: AtomicU64::new(0),
            connections: AtomicU64::new(0),
            dropped_gone: AtomicU64::new(0),
            expired: AtomicU64::new(0),
        });
        let accept = {
            let shared = shared.clone();
            std::thread::Builder::new()
                .name("live-accept".into())
                .spawn(move || accept_loop(&listener, &shared))
                .context("cannot start the server thread")?
        };
        Ok(Self { shared, accept: Some(accept), addr })
    }

    /// The address listened on (the port chosen for port 0).
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Some client has subscribed to some channel.
    pub fn subscribed(&self) -> bool {
        self.shared.subscriptions.load(Ordering::SeqCst) > 0
    }

    /// Hands the message of `channel` at `log_time_ns` to every client subscribed to it.
    pub fn log(&self, channel: u64, log_time_ns: u64, payload: &[u8]) {
        for c in self.shared.clients().iter() {
            c.send_on(channel, log_time_ns, payload);
        }
    }

    /// Sends the server clock to every client.
    pub fn broadcast_time(&self, time_ns: u64) {
        for c in self.shared.clients().iter() {
            c.send_time(time_ns);
        }
    }

    /// Every client's queue is written out (or the client gone).
    pub fn drained(&self) -> bool {
        self.shared.clients().iter().all(|c| c.idle())
    }

    /// Stops the server: no new client, each client asked to close, sockets shut down
    /// after [`CLOSE_GRACE`]; returns what it saw. Never waits on a client longer.
    pub fn close(mut self) -> Stats {
        self.stop_threads()
    }

    fn stop_threads(&mut self) -> Stats {
        let shared = &self.shared;
        shared.stop.store(true, Ordering::SeqCst);
        if let Some(a) = self.accept.take() {
            let _ = a.join();
        }
        for c in shared.clients().iter() {
            c.wake();
        }
        let threads = std::mem::take(&mut *shared.threads.lock().unwrap_or_else(|p| p.into_inner()));
        let t0 = Instant::now();
        while t0.elapsed() < CLOSE_GRACE && !threads.iter().all(JoinHandle::is_finished) {
            std::thread::sleep(Duration::from_millis(5));
        }
        for c in shared.clients().iter() {
            c.shutdown();
        }
        for t in threads {
            let _ = t.join();
        }
        let dropped =
            shared.dropped_gone.load(Ordering::SeqCst) + shared.clients().iter().map(|c| c.dropped()).sum::<u64>();
        Stats {
            connections: shared.connections.load(Ordering::SeqCst),
            refused: shared.refused.load(Ordering::SeqCst),
            dropped,
            expired: shared.expired.load(Ordering::SeqCst),
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        if self.accept.is_some() {
            self.stop_threads();
        }
    }
}

/// Sends away the clients past their deadline: a handshake longer than
/// [`Limits::handshake`], an open client that never subscribed within [`Limits::idle`].
fn enforce_deadlines(shared: &Shared) {
    for c in shared.clients().iter() {
        let late = match c.standing() {
            Standing::Handshaking => c.age() > shared.limits.handshake,
            Standing::Idle => c.age() > shared.limits.idle,
            Standing::Viewer | Standing::Leaving => false,
        };
        if late {
            shared.expired.fetch_add(1, Ordering::SeqCst);
            c.send_away();
        }
    }
}

/// Whether a new connection gets a slot: under the limit, or by sending away the oldest
/// client that has not subscribed (idle or still in its handshake) and is older than
/// [`SLOT_GRACE`]. Viewers keep theirs.
fn make_room(shared: &Shared) -> bool {
    let clients = shared.clients();
    let standing: Vec<Standing> = clients.iter().map(|c| c.standing()).collect();
    let present = standing.iter().filter(|s| **s != Standing::Leaving).count();
    if present < shared.limits.max_clients {
        return true;
    }
    let oldest = clients
        .iter()
        .zip(&standing)
        .filter(|(c, s)| matches!(s, Standing::Handshaking | Standing::Idle) && c.age() >= SLOT_GRACE)
        .max_by_key(|(c, _)| c.age());
    match oldest {
        Some((c, _)) => {
            shared.expired.fetch_add(1, Ordering::SeqCst);
            c.send_away();
            true
        }
        None => false,
    }
}

fn accept_loop(listener: &TcpListener, shared: &Arc<Shared>) {
    while !shared.stopping() {
        enforce_deadlines(shared);
        match listener.accept() {
            Ok((stream, peer)) => {
                if stream.set_nonblocking(false).is_err() {
                    continue;
                }
                if !make_room(shared) {
                    shared.refused.fetch_add(1, Ordering::SeqCst);
                    refuse(stream, shared.limits.max_clients);
                    continue;
                }
                let Ok(handle) = stream.try_clone() else { continue };
                let client = Arc::new(Client::new(peer, handle, shared.limits.queue_bytes));
                shared.clients().push(client.clone());
                shared.connections.fetch_add(1, Ordering::SeqCst);
                let s = shared.clone();
                let spawned = std::thread::Builder::new().name("live-client".into()).spawn(move || {
                    client::serve(&client, stream, &s);
                    // Gone: its drops are kept for the report.
                    s.dropped_gone.fetch_add(client.dropped(), Ordering::SeqCst);
                    s.clients().retain(|c| !Arc::ptr_eq(c, &client));
                });
                match spawned {
                    Ok(t) => {
                        let mut threads = shared.threads.lock().unwrap_or_else(|p| p.into_inner());
                        threads.retain(|t| !t.is_finished());
                        threads.push(t);
                    }
                    Err(_) => shared.clients().retain(|c| c.peer != peer),
                }
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => std::thread::sleep(ACCEPT_POLL),
            // Out of file descriptors, a connection reset before accept: try again shortly.
            Err(_) => std::thread::sleep(ACCEPT_POLL),
        }
    }
}

/// Answers a connection over the client limit with HTTP 503 saying so.
fn refuse(mut stream: TcpStream, max: usize) {
    let body = format!(
        "wmr-cli live view: too many connections: at most {max} clients at once; close one and connect again\n"
    );
    let reply = format!(
        "HTTP/1.1 503 Service Unavailable\r\ncontent-type: text/plain; charset=utf-8\r\nconnection: close\r\n\
         content-length: {}\r\n\r\n{body}",
        body.len()
    );
    // Read (some of) the request first, so closing does not reset the connection before
    // the reply is read.
    let _ = stream.set_read_timeout(Some(REFUSE_READ));
    let _ = stream.set_write_timeout(Some(REFUSE_READ));
    let mut buf = [0u8; 4096];
    let _ = stream.read(&mut buf);
    let _ = stream.write_all(reply.as_bytes());
    let _ = stream.shutdown(std::net::Shutdown::Write);
}
