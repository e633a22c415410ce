"""Scene.show (issue 47): the viewer served by this process follows the Scene and the Scene
follows the page, as a notebook uses it. The page's side is played by a WebSocket client speaking
the viewer's protocol (docs/viewer.md), as the browser does."""

import io
import json
import os
import re
import signal
import time
import urllib.error
import urllib.request

import numpy as np
import pytest

import intermix

websocket = pytest.importorskip("websocket")
PIL = pytest.importorskip("PIL.Image")


def small_scene():
    return intermix.Scene.from_dict({
        "image": {"width": 96, "height": 64},
        "render": {"method": "mdvr", "spp": 1},
        "objects": [{"name": "ct", "type": "volume", "source": {"phantom": "ct-head", "size": 40},
                     "transfer_function": {"preset": "ct-bone"}}]})


class Page:
    """A page of the view: its WebSocket, and the messages it has been sent."""

    def __init__(self, view):
        m = re.search(r"http://([^/]+)/\?token=(\w+)", view.url)
        assert m, view.url
        self.ws = websocket.create_connection(f"ws://{m.group(1)}/ws?token={m.group(2)}",
                                              timeout=60)

    def next(self, kind, accept=lambda msg: True):
        while True:
            text = self.ws.recv()
            if isinstance(text, bytes):
                continue
            msg = json.loads(text)
            assert msg.get("type") != "error", msg
            if msg.get("type") == kind and accept(msg):
                if kind == "frame":
                    return msg, self.ws.recv()  # its image follows as one binary message
                return msg

    def send(self, **message):
        self.ws.send(json.dumps(message))


def test_the_page_and_the_scene_follow_each_other():
    scene = small_scene()
    view = scene.show(width=320, height=240)
    try:
        assert view.open and view.url.startswith("http://127.0.0.1:")
        page = Page(view)
        hello = page.next("hello")
        assert "ct" in json.dumps(hello)
        # The page's edit is in the scene when Python reads it next.
        page.send(type="edit", seq=2, object="ct", visible=False)
        page.next("state")
        assert scene.to_dict()["objects"][0]["visible"] is False
        # Python's edit reaches the page.
        scene.set("objects[0].visible", True)
        state = page.next("state", lambda m: "visible" in json.dumps(m))
        ct = [o for o in state["objects"] if o["name"] == "ct"][0]
        assert ct["visible"] is True
    finally:
        view.close()
    assert not view.open
    with pytest.raises(urllib.error.URLError):
        urllib.request.urlopen(view.url, timeout=5)


def test_a_converged_frame_is_the_scenes_render():
    scene = small_scene()
    view = scene.show(width=200, height=120)
    try:
        page = Page(view)
        page.send(type="settings", seq=1, moving=False, viewport=[200, 120])
        msg, png = page.next("frame", lambda m: m.get("final") and m.get("width") == 200
                             and m.get("seq", 0) >= 1)
        shown = np.asarray(PIL.open(io.BytesIO(png)).convert("RGBA"))
        rendered = scene.render(width=200, height=120).to_uint8()
        assert shown.shape == rendered.shape
        assert np.abs(shown.astype(int) - rendered.astype(int)).max() <= 1
    finally:
        view.close()


def test_interrupting_python_stays_pythons_and_the_cell_has_a_frame():
    scene = small_scene()
    view = scene.show(width=160, height=120)
    try:
        # The view's server leaves SIGINT to Python: a notebook's "interrupt kernel".
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(1)
        assert urllib.request.urlopen(view.url, timeout=5).status == 200
        html = view._repr_html_()
        assert f'src="{view.url}"' in html and 'width="160"' in html
        assert "data:image/png;base64," in html  # for a saved notebook without its kernel
    finally:
        view.close()
    with pytest.raises(ValueError, match="Scene.show: width 10 is not in"):
        scene.show(width=10)
