//! Whether the client of a request is still connected. A request whose client has closed its
//! connection — the page cancels a design when the pointer moves again, a tab is closed — is not
//! computed, or not finished: nobody would read the answer, and the cores it would take are those
//! the next edit waits for.
//!
//! tiny_http does not hand out a request's socket, so on Linux the socket is found among the
//! process's descriptors (`/proc/self/fd`) by its peer address (unique among live TCP
//! connections), and its TCP state read: CLOSE_WAIT (the client's end of stream) or CLOSE (a
//! reset) means the client has closed it (Go's `net/http` cancels a request's context on the
//! same event). Elsewhere the client always counts as present: the request is computed, as before.

use std::net::SocketAddr;

/// Whether the client at `peer` has closed its connection to this process (Linux; `false` when
/// it cannot be told). Every descriptor of that peer must say so (tiny_http holds two, a reading
/// and a writing one, of the same socket; a second socket of the same peer address, a new
/// connection from a port just freed, keeps the request computed: a false "gone" would drop a
/// wanted answer, a false "present" only computes one nobody reads).
#[cfg(target_os = "linux")]
pub fn gone(peer: SocketAddr) -> bool {
    let Ok(dir) = std::fs::read_dir("/proc/self/fd") else {
        return false;
    };
    let mut found = false;
    for entry in dir.flatten() {
        let Some(fd) = entry
            .file_name()
            .to_str()
            .and_then(|s| s.parse::<libc::c_int>().ok())
        else {
            continue;
        };
        if !peer_of(fd).is_some_and(|p| p.ip() == peer.ip() && p.port() == peer.port()) {
            continue;
        }
        if !closed(fd) {
            return false;
        }
        found = true;
    }
    found
}

/// Whether the peer of socket `fd` has closed it: the connection's TCP state (`TCP_INFO`) is
/// CLOSE_WAIT (the client sent its end of stream) or CLOSE (a reset). The state, not a peek at
/// the stream: tiny_http shuts the reading side of a `Connection: close` request's socket once
/// it has read it, and a peek there sees an end of stream the client never sent.
#[cfg(target_os = "linux")]
fn closed(fd: libc::c_int) -> bool {
    /// `TCP_CLOSE` and `TCP_CLOSE_WAIT` of linux/tcp_states.h.
    const CLOSE: u8 = 7;
    const CLOSE_WAIT: u8 = 8;
    // SAFETY: all-zero bytes are a valid `tcp_info` (plain integers).
    let mut info: libc::tcp_info = unsafe { std::mem::zeroed() };
    let mut len = std::mem::size_of::<libc::tcp_info>() as libc::socklen_t;
    // SAFETY: `info` is writable for `len` bytes; a descriptor closed meanwhile only makes the
    // call fail.
    let r = unsafe {
        libc::getsockopt(
            fd,
            libc::IPPROTO_TCP,
            libc::TCP_INFO,
            (&raw mut info).cast(),
            &mut len,
        )
    };
    r == 0 && matches!(info.tcpi_state, CLOSE | CLOSE_WAIT)
}

/// Elsewhere the client cannot be told gone: every request is computed.
#[cfg(not(target_os = "linux"))]
pub fn gone(_peer: SocketAddr) -> bool {
    false
}

/// The peer address of descriptor `fd`, if it is an IP socket that was connected. Asked by
/// `SO_PEERNAME`, not `getpeername`: the latter fails once the connection is reset (the socket
/// is closed), the former still gives the address the socket was connected to.
#[cfg(target_os = "linux")]
fn peer_of(fd: libc::c_int) -> Option<SocketAddr> {
    use std::net::{Ipv4Addr, Ipv6Addr, SocketAddrV6};
    // SAFETY: all-zero bytes are a valid `sockaddr_storage` (plain integers).
    let mut ss: libc::sockaddr_storage = unsafe { std::mem::zeroed() };
    // The kernel refuses (EINVAL) a buffer longer than the address: an IPv6 one's length first,
    // then an IPv4 one's.
    let sizes = [
        std::mem::size_of::<libc::sockaddr_in6>(),
        std::mem::size_of::<libc::sockaddr_in>(),
    ];
    let read = sizes.iter().any(|&size| {
        let mut len = size as libc::socklen_t;
        // SAFETY: `ss` is writable for `len` bytes (≤ its size); a descriptor that is not a
        // socket, or a socket never connected (the listener), only makes the call fail.
        let r = unsafe {
            libc::getsockopt(
                fd,
                libc::SOL_SOCKET,
                libc::SO_PEERNAME,
                (&raw mut ss).cast(),
                &mut len,
            )
        };
        r == 0 && len as usize == size
    });
    if !read {
        return None;
    }
    match libc::c_int::from(ss.ss_family) {
        libc::AF_INET => {
            // SAFETY: the family says the storage holds a `sockaddr_in`.
            let a: libc::sockaddr_in = unsafe { *(&raw const ss).cast() };
            Some(SocketAddr::from((
                Ipv4Addr::from(u32::from_be(a.sin_addr.s_addr)),
                u16::from_be(a.sin_port),
            )))
        }
        libc::AF_INET6 => {
            // SAFETY: the family says the storage holds a `sockaddr_in6`.
            let a: libc::sockaddr_in6 = unsafe { *(&raw const ss).cast() };
            Some(SocketAddr::V6(SocketAddrV6::new(
                Ipv6Addr::from(a.sin6_addr.s6_addr),
                u16::from_be(a.sin6_port),
                a.sin6_flowinfo,
                a.sin6_scope_id,
            )))
        }
        _ => None,
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::gone;
    use std::io::{Read, Write};
    use std::net::{TcpListener, TcpStream};

    /// A loopback connection whose server side has read the client's request: `(client,
    /// server, the client's address)`.
    fn connected() -> (TcpStream, TcpStream, std::net::SocketAddr) {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let mut client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (mut server, peer) = listener.accept().unwrap();
        client.write_all(b"request").unwrap();
        let mut buf = [0u8; 7];
        server.read_exact(&mut buf).unwrap();
        (client, server, peer)
    }

    /// Whether `peer` is seen gone within half a second (the close reaches the server's socket
    /// at once on loopback; a moment is allowed).
    fn soon_gone(peer: std::net::SocketAddr) -> bool {
        (0..100).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(5));
            gone(peer)
        })
    }

    #[test]
    fn a_closed_client_is_gone_a_waiting_one_is_not() {
        let (client, server, peer) = connected();
        // Read to the end of what was sent, the client waiting for its answer.
        assert!(!gone(peer));
        drop(client);
        let closed = soon_gone(peer);
        assert!(closed, "the closed client is still seen as connected");
        drop(server);
        // No socket of this peer any more: nothing to tell.
        assert!(!gone(peer));
    }

    #[test]
    fn a_reset_client_is_gone() {
        use std::os::fd::AsRawFd;
        let (client, _server, peer) = connected();
        assert!(!gone(peer));
        // A linger of zero: the close sends a reset instead of the end of stream (an aborted
        // connection, as a browser's cancelled fetch may).
        let linger = libc::linger {
            l_onoff: 1,
            l_linger: 0,
        };
        // SAFETY: a valid socket and a `linger` of the size given.
        let r = unsafe {
            libc::setsockopt(
                client.as_raw_fd(),
                libc::SOL_SOCKET,
                libc::SO_LINGER,
                (&raw const linger).cast(),
                std::mem::size_of::<libc::linger>() as libc::socklen_t,
            )
        };
        assert_eq!(r, 0);
        drop(client);
        let reset = soon_gone(peer);
        assert!(reset, "the reset client is still seen as connected");
    }
}
