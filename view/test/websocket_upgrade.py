"""The server side of a WebSocket for the view's test servers (synthetic_feed.py, scene3d.py):
the upgrade of an HTTP request and unmasked text or binary frames from the server (RFC 6455)."""
import base64
import hashlib


def accept(handler):
    """Answers the upgrade request `handler` (an http.server.BaseHTTPRequestHandler) holds."""
    key = handler.headers["Sec-WebSocket-Key"]
    digest = hashlib.sha1((key + "258EAFA5-E914-47DA-95CA-C5AB0DC85B11").encode()).digest()
    handler.send_response(101)
    handler.send_header("Upgrade", "websocket")
    handler.send_header("Connection", "Upgrade")
    handler.send_header("Sec-WebSocket-Accept", base64.b64encode(digest).decode())
    handler.end_headers()
    handler.wfile.flush()


def frame(message):
    """One final frame holding `message`: text for a str, binary for bytes."""
    binary = isinstance(message, (bytes, bytearray))
    data = bytes(message) if binary else message.encode()
    op = 0x82 if binary else 0x81
    n = len(data)
    if n < 126:
        head = bytes([op, n])
    elif n < 1 << 16:
        head = bytes([op, 126]) + n.to_bytes(2, "big")
    else:
        head = bytes([op, 127]) + n.to_bytes(8, "big")
    return head + data
