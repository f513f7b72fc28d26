#!/usr/bin/env python3
"""Relays TCP connections on 127.0.0.1:<port> of this host into the same port of a private
network namespace (that of process <pid>), so a browser on this host reaches dt_view running in
tests/run_in_netns.sh. A byte relay only: HTTP and WebSocket are dt_view's (civetweb).

  netns_relay.py <pid> <port>
Needs the right to enter the namespace (root, as tests/run_in_netns.sh uses for it).
"""
import ctypes
import os
import socket
import sys
import threading

CLONE_NEWNET = 0x40000000
libc = ctypes.CDLL(None, use_errno=True)


def setns(fd):
    if libc.setns(fd, CLONE_NEWNET) != 0:
        raise OSError(ctypes.get_errno(), "setns")


def pump(src, dst):
    try:
        while data := src.recv(65536):
            dst.sendall(data)
    except OSError:
        pass
    finally:
        for s in (src, dst):
            try:
                s.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass


def main():
    pid, port = int(sys.argv[1]), int(sys.argv[2])
    here = os.open("/proc/self/ns/net", os.O_RDONLY)
    there = os.open(f"/proc/{pid}/ns/net", os.O_RDONLY)
    listener = socket.create_server(("127.0.0.1", port))
    while True:
        client, _ = listener.accept()
        setns(there)  # a socket belongs to the namespace it was made in
        try:
            inner = socket.socket()
        finally:
            setns(here)
        try:
            inner.connect(("127.0.0.1", port))
        except OSError:
            client.close()
            continue
        threading.Thread(target=pump, args=(client, inner), daemon=True).start()
        threading.Thread(target=pump, args=(inner, client), daemon=True).start()


if __name__ == "__main__":
    main()
