"""A server on 127.0.0.1 that answers generateContent in the Gemini API's wire format, for nanobanana's tests.

It records each request (path, headers, JSON body) and answers with `reply(request)`: a JSON-able dict
(sent with 200) or a (status, dict) pair. `image_reply` paints the input image's mirror image at twice its
size, so a test can tell the answer was used and resized back.
"""

from __future__ import annotations

import base64
import json
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import cv2
import numpy as np


def input_image(request: dict) -> np.ndarray:
    """The RGB image a request carries."""
    for part in request["body"]["contents"][0]["parts"]:
        if "inlineData" in part:
            data = base64.b64decode(part["inlineData"]["data"], altchars=b"-_")  # the SDK sends URL-safe
            return cv2.cvtColor(cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
    raise AssertionError("request has no image")


def prompt_of(request: dict) -> str:
    return " ".join(p["text"] for p in request["body"]["contents"][0]["parts"] if "text" in p)


def image_reply(request: dict) -> dict:
    rgb = input_image(request)[:, ::-1]
    big = cv2.resize(rgb, (rgb.shape[1] * 2, rgb.shape[0] * 2), interpolation=cv2.INTER_NEAREST)
    png = cv2.imencode(".png", cv2.cvtColor(big, cv2.COLOR_RGB2BGR))[1].tobytes()
    return {"candidates": [{"content": {"role": "model", "parts": [
        {"text": "Here is the image with the object removed."},
        {"inlineData": {"mimeType": "image/png", "data": base64.b64encode(png).decode()}}]},
        "finishReason": "STOP"}]}


@contextmanager
def gemini_server(reply: Callable[[dict], dict | tuple[int, dict]] = image_reply) -> Iterator[tuple[str, list]]:
    """(base URL, list of recorded requests) while the server runs."""
    requests: list[dict] = []

    class Handler(BaseHTTPRequestHandler):
        def do_POST(self) -> None:
            body = json.loads(self.rfile.read(int(self.headers["Content-Length"])))
            request = {"path": self.path, "headers": dict(self.headers), "body": body}
            requests.append(request)
            answer = reply(request)
            status, payload = answer if isinstance(answer, tuple) else (200, answer)
            data = json.dumps(payload).encode()
            self.send_response(status)
            self.send_header("Content-Type", "application/json")
            self.send_header("Content-Length", str(len(data)))
            self.end_headers()
            self.wfile.write(data)

        def log_message(self, *args) -> None:
            pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_port}", requests
    finally:
        server.shutdown()
        server.server_close()
