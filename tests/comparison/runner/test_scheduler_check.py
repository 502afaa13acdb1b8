"""``--scheduler`` at something that is not a usable Dask scheduler: the message names the cause.

A transport Dask cannot use here (``ucx://``, ``tls://`` without TLS settings) and a peer that does not
speak Dask's protocol (an HTTP server, whose answer would be read as a frame length of exabytes) are each
worded by their cause, never by an exception's type alone.
"""

from __future__ import annotations

import contextlib
import socket
import threading
from collections.abc import Callable, Iterator

import pytest

pytest.importorskip("distributed")

from comparison.runner.executor.cluster import ClusterError, check_scheduler  # noqa: E402

#: An HTTP server's answer to bytes that are no request (nginx, a web UI on the wrong port).
BAD_REQUEST = b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\nConnection: close\r\n\r\n"
#: Eight bytes a Dask peer reads as the number of frames that follow (2**62), then nothing.
HUGE_FRAME = (2**62).to_bytes(8, "little")


def _server(answer: Callable[[socket.socket], None]) -> Iterator[int]:
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()

    def one(conn: socket.socket) -> None:
        with conn, contextlib.suppress(OSError):
            answer(conn)

    def serve() -> None:  # each connection in a thread of its own, as a real server: a client's connection
        while True:       # left open must not hold up the next (the HTTP probe waited behind Dask's, under load)
            try:
                conn = server.accept()[0]
            except OSError:
                return
            threading.Thread(target=one, args=(conn,), daemon=True).start()

    threading.Thread(target=serve, daemon=True).start()
    yield server.getsockname()[1]
    server.close()


@pytest.fixture()
def http_400() -> Iterator[int]:
    """A server that answers whatever it reads with an HTTP 400."""

    def answer(conn: socket.socket) -> None:
        conn.settimeout(2.0)
        conn.recv(65536)
        conn.sendall(BAD_REQUEST)

    yield from _server(answer)


@pytest.fixture()
def garbage() -> Iterator[int]:
    """A server that sends eight bytes of no protocol at once and nothing else, whatever it is asked."""

    def answer(conn: socket.socket) -> None:
        conn.sendall(HUGE_FRAME)
        conn.settimeout(2.0)
        conn.recv(65536)

    yield from _server(answer)


def _why(address: str) -> str:
    with pytest.raises(ClusterError) as info:
        check_scheduler(address)
    message = str(info.value)
    assert message.startswith(f"no Dask scheduler at {address} (") and "\n" not in message, message
    return message


def test_ucx_without_its_transport_says_which_package_is_missing() -> None:
    assert "needs Dask's UCX transport, the distributed-ucxx package" in _why("ucx://127.0.0.1:8786")


@pytest.mark.parametrize("scheme", ["tls", "wss"])
def test_tls_without_settings_says_so(scheme: str) -> None:
    assert f"{scheme}:// needs Dask's TLS settings (distributed.comm.tls.ca-file" in _why(f"{scheme}://127.0.0.1:1")


@pytest.mark.parametrize("scheme", ["tcp", "ws"])
def test_an_http_server_is_named_as_such(scheme: str, http_400: int) -> None:
    assert "an HTTP server answers there, not a Dask scheduler" in _why(f"{scheme}://127.0.0.1:{http_400}")


def test_a_peer_of_another_protocol_is_named_as_such(garbage: int) -> None:
    assert "its answer is not Dask's protocol" in _why(f"tcp://127.0.0.1:{garbage}")
