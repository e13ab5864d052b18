//! Whether the client of a request is still connected. A request whose client has closed its
//! connection — the page cancels a design when the pointer moves again, a tab is closed — is not
//! computed, or not finished: nobody would read the answer, and the cores it would take are those
//! the next edit waits for.
//!
//! tiny_http does not hand out a request's socket, so on Linux the socket is found among the
//! process's descriptors (`/proc/self/fd`) by its peer address (unique among live TCP
//! connections) and peeked without blocking and without consuming anything: end of stream, or a
//! reset, means the client has closed it (Go's `net/http` cancels a request's context on the same
//! event). While a request is being answered its connection is read by nobody else (tiny_http
//! reads the next request only after the answer), so the peek sees exactly what the client did
//! since. Elsewhere the client always counts as present: the request is computed, as before.

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

/// Whether the peer of socket `fd` has closed it: end of stream or a reset, seen by peeking one
/// byte without blocking and without consuming it (what the client sent after its request, if
/// anything, stays for tiny_http).
#[cfg(target_os = "linux")]
fn closed(fd: libc::c_int) -> bool {
    let mut byte = 0u8;
    // SAFETY: `byte` is a writable buffer of one byte. MSG_PEEK leaves the byte in the socket,
    // MSG_DONTWAIT never blocks; on a descriptor closed meanwhile the call fails (EBADF).
    let n = unsafe {
        libc::recv(
            fd,
            (&raw mut byte).cast(),
            1,
            libc::MSG_PEEK | libc::MSG_DONTWAIT,
        )
    };
    match n {
        0 => true,
        n if n > 0 => false,
        _ => matches!(
            std::io::Error::last_os_error().kind(),
            std::io::ErrorKind::ConnectionReset
                | std::io::ErrorKind::ConnectionAborted
                | std::io::ErrorKind::BrokenPipe
                | std::io::ErrorKind::NotConnected
        ),
    }
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

    #[test]
    fn a_closed_client_is_gone_a_waiting_one_is_not() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let mut client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (mut server, peer) = listener.accept().unwrap();
        client.write_all(b"request").unwrap();
        let mut buf = [0u8; 7];
        server.read_exact(&mut buf).unwrap();
        // Read to the end of what was sent, the client waiting for its answer.
        assert!(!gone(peer));
        drop(client);
        // The end of stream reaches the server's socket at once on loopback; allow a moment.
        let closed = (0..100).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(5));
            gone(peer)
        });
        assert!(closed, "the closed client is still seen as connected");
        drop(server);
        // No socket of this peer any more: nothing to tell.
        assert!(!gone(peer));
    }

    #[test]
    fn a_reset_client_is_gone() {
        use std::os::fd::AsRawFd;
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let mut client = TcpStream::connect(listener.local_addr().unwrap()).unwrap();
        let (mut server, peer) = listener.accept().unwrap();
        client.write_all(b"request").unwrap();
        let mut buf = [0u8; 7];
        server.read_exact(&mut buf).unwrap();
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
        let reset = (0..100).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(5));
            gone(peer)
        });
        assert!(reset, "the reset client is still seen as connected");
    }
}
