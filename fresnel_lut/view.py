"""The look-development page: a local server for a WebGL 2 page that runs the shipped includes on the shipped tables.

Public objects: ``page_files``, ``make_server``, ``serving``, ``serve``, ``read_environment``, ``is_loopback``,
``ServerWarning``, ``PAGE_SIZE``, ``THREE_FILES``, ``IDLE_TIMEOUT``, ``MAX_CONNECTIONS``.

The server (Python's standard library, bound to 127.0.0.1 unless told otherwise) answers GET and HEAD for a fixed set
of names built once at start, in memory, and nothing else: no path of a request is ever joined to a folder, so no file
outside that set can be read (``..``, encoded or not, is simply not one of the names). What it serves:

* ``/`` — ``fresnel_lut/page/index.html`` with ``view.js``, ``view.css`` and ``view.glsl`` (the page's own shaders:
  the sphere, the studio, the reference, ΔE2000 and the tone map);
* ``/shaders/fresnel_basis.glsl`` — the shipped include, verbatim;
* ``/tables/NAME.ktx2`` — the shipped tables as half-float KTX2 (:func:`handoff.formats.ktx2_bytes`, the bytes
  ``fresnel-lut build --format ktx2 --half`` writes), which WebGL 2 filters without any extension;
* ``/config.json`` — what the page needs from Python: the presets (sRGB coefficients and their exact curves sampled
  at 1024 values of μ, since a preset's curve is spectral), the studio's spherical Gaussians, the lights of
  :mod:`fresnel_lut.render`, the colorimetry of ΔE2000 and the basis hash;
* ``/environment.f32`` — with ``environment``: the user's equirectangular EXR as float32 RGBA, rows top first,
  which the page prefilters on the GPU;
* ``/asset.html`` — with ``three_js`` (npm's ``three`` at :data:`handoff.three.THREE_VERSION`): "your asset", a
  dropped glTF in three.js, stock or through the three.js package, whose files (``/fresnel-basis-three/``, from
  ``luts/three``) and three.js's (``/three/``, :data:`THREE_FILES`) it serves; the Content-Security-Policy admits its
  inline import map by hash, and ``data:`` and ``blob:`` reads (a glTF's embedded buffers and images: nothing leaves
  the machine).

The Content-Security-Policy header allows nothing but these names: the page loads nothing from the internet. A
request whose ``Host`` is not this server's (a name other than ``localhost``, an address, or this machine's own name)
is refused, so that a page elsewhere cannot read ``/config.json`` or the user's environment through a DNS name
rebound to 127.0.0.1. Connections idle for :data:`IDLE_TIMEOUT` seconds are closed and at most
:data:`MAX_CONNECTIONS` are served at once; every request gets an HTTP answer (400 for a malformed one) and none
prints a traceback. Bound beyond the loopback addresses, the server warns (:class:`ServerWarning`).
"""

from __future__ import annotations

import base64
import contextlib
import hashlib
import http.server
import ipaddress
import json
import re
import socket
import threading
import warnings
from collections.abc import Callable
from pathlib import Path
from urllib.parse import unquote, urlsplit

import numpy as np
import OpenEXR

from basis.colorimetry import working_space
from basis.eigenbasis import default_basis
from basis.materials import material_from_mapping
from basis.presets import material_presets
from basis.storage import MAX_DOCUMENT_BYTES, MAX_TABLE_BYTES, check_regular_file, read_regular_file, shipped_path
from basis.validation import ParameterError, check_positive_int
from handoff.exr import LutFileError, read_lut
from handoff.formats import ktx2_bytes
from handoff.shipped import BASIS_LUT, LTC_LUT, SCHLICK_LUT
from handoff.tables import THREE_FOLDER
from handoff.three import THREE_VERSION

from .render import (
    FIGURE2,
    FIGURE2_ROUGHNESS,
    POINT_LIGHT_DIRECTION,
    POINT_LIGHT_RADIANCE,
    RECT_LIGHT,
    RECT_LIGHT_RADIANCE,
    STUDIO,
)

__all__ = [
    "IDLE_TIMEOUT",
    "MAX_CONNECTIONS",
    "PAGE_SIZE",
    "THREE_FILES",
    "ServerWarning",
    "is_loopback",
    "make_server",
    "page_files",
    "read_environment",
    "serve",
    "serving",
]

PAGE = Path(__file__).resolve().parent / "page"
#: The page's files and their types.
_PAGE_FILES = {
    "index.html": "text/html; charset=utf-8",
    "view.js": "text/javascript; charset=utf-8",
    "view.css": "text/css; charset=utf-8",
    "view.glsl": "text/plain; charset=utf-8",
}
#: The "your asset" page (with ``three_js``): three.js as an application runs it, with the three.js package.
_ASSET_FILES = {"asset.html": "text/html; charset=utf-8", "asset.js": "text/javascript; charset=utf-8"}
#: The files of npm's ``three`` the asset page imports (three.js's build and the add-ons it uses).
THREE_FILES = (
    "build/three.module.js",
    "build/three.core.js",
    "examples/jsm/loaders/GLTFLoader.js",
    "examples/jsm/utils/BufferGeometryUtils.js",
    "examples/jsm/utils/SkeletonUtils.js",
    "examples/jsm/environments/RoomEnvironment.js",
    "examples/jsm/controls/OrbitControls.js",
)
_THREE_PACKAGE_FILES = ("index.js", "data.js")
#: The largest module the asset page serves (three.core.js is 1.5 MB).
MAX_MODULE_BYTES = 1 << 24
#: The shipped include the page compiles, verbatim.
_INCLUDES = ("fresnel_basis.glsl",)
#: Samples of each preset's exact curve over μ = cos θ in [0, 1] (linear interpolation: < 2e-5 from the curve).
CURVE_SAMPLES = 1024
#: The sphere's size in pixels (the canvas shows four of them side by side in the gallery view).
PAGE_SIZE = 384
#: An environment is stored at most this wide (larger files are halved by 2 × 2 averages until they fit).
ENVIRONMENT_WIDTH = 2048


def _import_map_hash() -> str:
    """CSP's hash source of the asset page's inline import map (import maps cannot be external files)."""
    found = re.search(r'<script type="importmap">(.*?)</script>', (PAGE / "asset.html").read_text(encoding="utf-8"))
    return "'sha256-" + base64.b64encode(hashlib.sha256(found.group(1).encode("utf-8")).digest()).decode("ascii") + "'"


_CONTENT_SECURITY_POLICY = (
    f"default-src 'none'; script-src 'self' {_import_map_hash()}; style-src 'self'; connect-src 'self' data: blob:; "
    "img-src 'self' data: blob:; base-uri 'none'; form-action 'none'; frame-ancestors 'none'"
)


#: What makes the shipped files the page serves, for the error that says one is missing.
_REBUILD = (
    "`make luts` (fresnel-lut build --ltc --out luts, from the project's root) makes the shipped tables and includes"
)


def _ktx2_of(name: str) -> bytes:
    try:
        table, header = read_lut(shipped_path(name))
    except LutFileError as error:
        raise LutFileError(f"{error}; {_REBUILD}") from None
    attributes = {key: value for key, value in header.items() if key not in ("content_hash", "pixel_type")}
    return ktx2_bytes(table, attributes, half=True)


def _presets() -> list[dict]:
    """Each preset's sRGB coefficients (3, 4) and exact curve (1024, 3) over μ (the page's reference)."""
    mu = np.linspace(0.0, 1.0, CURVE_SAMPLES)
    presets = []
    for name, entry in material_presets()["materials"].items():
        material = material_from_mapping({"preset": name}, "sRGB")
        curve = material.curve(mu)  # as it is: sRGB gold's red F0 is 1.038, out of the gamut (README, Known limits)
        presets.append(
            {
                "name": name,
                "kind": entry["kind"],
                "coefficients": np.round(material.coefficients(), 9).tolist(),
                "curve": np.round(curve, 7).ravel().tolist(),
            }
        )
    return presets


def _colorimetry() -> dict:
    """sRGB → XYZ and the white of ΔE2000 as :func:`basis.colorimetry.rgb_to_Lab` takes them (the published matrix,
    white = its rows' sums), so that the page's ΔE is the report's."""
    matrix = working_space("sRGB").rgb_colourspace.matrix_RGB_to_XYZ
    return {"rgb_to_xyz": np.asarray(matrix).tolist(), "white": np.asarray(matrix).sum(axis=1).tolist()}


def read_environment(path) -> np.ndarray:
    """(H, W, 4) float32 RGBA of an equirectangular EXR (rows top first; R, G, B or Y; A = 1), at most
    :data:`ENVIRONMENT_WIDTH` wide, or an error naming what is wrong (not 2:1, not finite, negative)."""
    path = check_regular_file(path, "environment", MAX_TABLE_BYTES)
    try:
        with OpenEXR.File(str(path)) as file:
            channels = {name: np.asarray(channel.pixels) for name, channel in file.parts[0].channels.items()}
    except Exception as error:  # OpenEXR raises bare exceptions for anything that is not an EXR
        raise ParameterError(f"environment {path} is not a readable EXR ({error})") from error
    if "RGB" in channels:
        rgb = channels["RGB"][..., :3]
    elif {"R", "G", "B"} <= set(channels):
        rgb = np.stack([channels[name] for name in ("R", "G", "B")], axis=-1)
    elif "Y" in channels:
        rgb = np.repeat(channels["Y"][..., None], 3, axis=-1)
    else:
        raise ParameterError(f"environment {path} has no R, G, B or Y channels (it has {sorted(channels)})")
    rgb = np.asarray(rgb, dtype=np.float64)
    height, width = rgb.shape[:2]
    if width != 2 * height or height < 2:
        raise ParameterError(f"environment {path} must be equirectangular, 2:1, got {width} x {height}")
    bad = ~np.isfinite(rgb)
    if bad.any():
        raise ParameterError(f"environment {path} holds {int(bad.sum())} NaN or infinite values")
    if (rgb < 0.0).any():
        raise ParameterError(f"environment {path} holds {int((rgb < 0.0).sum())} negative values")
    while rgb.shape[1] > ENVIRONMENT_WIDTH and rgb.shape[0] % 2 == 0 and rgb.shape[1] % 2 == 0:
        rgb = 0.25 * (rgb[0::2, 0::2] + rgb[1::2, 0::2] + rgb[0::2, 1::2] + rgb[1::2, 1::2])
    if rgb.shape[1] > ENVIRONMENT_WIDTH:
        raise ParameterError(f"environment {path} is {width} wide; at most {ENVIRONMENT_WIDTH} (or an even size)")
    rgba = np.concatenate([rgb, np.ones(rgb.shape[:2] + (1,))], axis=-1)
    return np.ascontiguousarray(rgba, dtype="<f4")


def _asset_files(three_js) -> dict[str, tuple[bytes, str]]:
    """The asset page, npm's ``three`` of the package's version from the folder ``three_js``, and the package."""
    folder = Path(three_js)
    try:
        manifest = json.loads(read_regular_file(folder / "package.json", "three.js package.json", MAX_DOCUMENT_BYTES))
    except (ParameterError, ValueError) as error:
        raise ParameterError(f"--three-js {three_js}: not npm's three package ({error})") from None
    if manifest.get("name") != "three" or manifest.get("version") != THREE_VERSION:
        raise ParameterError(
            f"--three-js {three_js}: three {manifest.get('version')!r}, but the package is made for three "
            f"{THREE_VERSION} (npm pack three@{THREE_VERSION}; make view fetches it)"
        )
    files = {f"/{name}": ((PAGE / name).read_bytes(), kind) for name, kind in _ASSET_FILES.items()}
    script = "text/javascript; charset=utf-8"
    for name in THREE_FILES:
        files[f"/three/{name}"] = (read_regular_file(folder / name, "three.js module", MAX_MODULE_BYTES), script)
    package = shipped_path(THREE_FOLDER)
    for name in _THREE_PACKAGE_FILES:
        try:
            data = read_regular_file(Path(package) / name, "three.js package", MAX_MODULE_BYTES)
        except ParameterError as error:
            raise ParameterError(f"{error}; `make luts` (fresnel-lut build --three) makes the package") from None
        files[f"/fresnel-basis-three/{name}"] = (data, script)
    return files


def page_files(
    environment=None, progress: Callable[[str], None] | None = None, three_js=None
) -> dict[str, tuple[bytes, str]]:
    """Every name the server answers (a path such as ``/tables/ggx_basis_rgba.ktx2``) → (bytes, content type); with
    ``three_js`` (the folder of npm's ``three`` at the package's version), the "your asset" page too."""
    say = progress or (lambda text: None)
    files = {}
    for name, kind in _PAGE_FILES.items():
        files[f"/{name}"] = ((PAGE / name).read_bytes(), kind)
    files["/"] = files["/index.html"]
    if three_js is not None:
        files.update(_asset_files(three_js))
    for include in _INCLUDES:
        try:
            data = read_regular_file(shipped_path(include), "shader include", MAX_DOCUMENT_BYTES)
        except ParameterError as error:
            raise ParameterError(f"{error}; {_REBUILD}") from None
        files[f"/shaders/{Path(include).name}"] = (data, "text/plain; charset=utf-8")
    for table in (BASIS_LUT, SCHLICK_LUT, LTC_LUT):
        files[f"/tables/{Path(table).stem}.ktx2"] = (_ktx2_of(table), "image/ktx2")
    say("sampling the presets' spectral curves")
    config = {
        "basis_hash": default_basis().content_hash,
        "size": PAGE_SIZE,
        "presets": _presets(),
        "figure2": {
            "reflectivity": np.broadcast_to(FIGURE2["reflectivity"], 3).tolist(),
            "edge_tint": np.broadcast_to(FIGURE2["edge_tint"], 3).tolist(),
            "roughness": FIGURE2_ROUGHNESS,
        },
        "studio": {
            "axes": STUDIO.axes.tolist(),
            "sharpness": STUDIO.sharpness.tolist(),
            "amplitudes": STUDIO.amplitudes.tolist(),
        },
        "point_light": {"direction": list(POINT_LIGHT_DIRECTION), "radiance": POINT_LIGHT_RADIANCE},
        "rect_light": {"corners": RECT_LIGHT.tolist(), "radiance": RECT_LIGHT_RADIANCE},
        "colorimetry": _colorimetry(),
        "environment": None,
        "three": three_js is not None,
    }
    if environment is not None:
        say(f"reading {environment}")
        pixels = read_environment(environment)
        files["/environment.f32"] = (pixels.tobytes(), "application/octet-stream")
        config["environment"] = {"name": Path(environment).name, "width": pixels.shape[1], "height": pixels.shape[0]}
    files["/config.json"] = (json.dumps(config, separators=(",", ":")).encode("utf-8"), "application/json")
    return files


#: Seconds a connection may stay silent (before or between requests) before the server closes it.
IDLE_TIMEOUT = 10.0
#: Connections served at once; one more is closed unanswered until a place frees (each holds a thread).
MAX_CONNECTIONS = 128


class ServerWarning(UserWarning):
    """The page's server is reachable from other machines."""


def is_loopback(host: str) -> bool:
    """Whether ``host`` (a name or an address, as ``--host`` takes it) reaches this machine only."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def _host_names(host: str) -> set[str]:
    """The names a browser may put in ``Host`` for a server bound to ``host`` (lower case, without the port)."""
    names = {"localhost", host.strip("[]").lower()}
    if not is_loopback(host):  # reachable from elsewhere: this machine's own names too
        names |= {socket.gethostname().lower(), socket.getfqdn().lower()}
    return names


def _split_host(value: str) -> tuple[str, str | None]:
    """(name or address, port or None) of a ``Host`` header value (``[::1]:8000`` → ``::1``, ``8000``)."""
    value = value.strip().lower()
    if value.startswith("["):
        address, _, rest = value[1:].partition("]")
        return address, rest[1:] if rest.startswith(":") else None
    name, colon, port = value.rpartition(":")
    return (name, port) if colon and ":" not in name else (value, None)


class _Handler(http.server.BaseHTTPRequestHandler):
    """GET and HEAD of the server's names; 404 for every other path, 405 for every other method, 400 for a request
    that cannot be read, 403 for another site's ``Host``."""

    files: dict[str, tuple[bytes, str]] = {}
    names: set[str] = set()
    server_version = "fresnel-lut-view"
    sys_version = ""
    timeout = IDLE_TIMEOUT  # socket time-out of every read (StreamRequestHandler applies it)
    default_request_version = (
        "HTTP/1.0"  # an unreadable request line is answered with a status line, not HTTP/0.9's body
    )

    def _host_allowed(self) -> bool:
        value = self.headers.get("Host")
        if value is None:  # HTTP/1.0 without Host: no browser, hence no rebound name
            return True
        name, port = _split_host(value)
        if port is not None and port != str(self.server.server_address[1]):
            return False
        if name in self.names:
            return True
        try:
            ipaddress.ip_address(name)  # an address literal names no site another page could rebind
            return True
        except ValueError:
            return False

    def _answer(self, body: bool) -> None:
        if not self._host_allowed():
            self.send_error(403, "not this server's host name")
            return
        try:
            path = unquote(urlsplit(self.path).path)
        except ValueError:  # e.g. "http://[/": not a URL
            self.send_error(400, "the request's path is not a URL")
            return
        found = self.files.get(path)
        if found is None:
            self.send_error(404, "not one of the page's files")
            return
        data, kind = found
        self.send_response(200)
        self.send_header("Content-Type", kind)
        self.send_header("Content-Length", str(len(data)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("Content-Security-Policy", _CONTENT_SECURITY_POLICY)
        self.end_headers()
        if body:
            self.wfile.write(data)

    def do_GET(self) -> None:  # noqa: N802 (the standard library's name)
        self._answer(True)

    def do_HEAD(self) -> None:  # noqa: N802
        self._answer(False)

    def _refuse(self) -> None:
        self.send_error(405, "the page's server only reads")

    do_POST = do_PUT = do_DELETE = do_PATCH = _refuse  # noqa: N815

    def log_message(self, format, *args) -> None:  # noqa: A002 (the standard library's signature)
        pass  # one line per request would bury the URL; errors reach the page's console


class _Server(http.server.ThreadingHTTPServer):
    """A thread per connection, at most :data:`MAX_CONNECTIONS` at once; errors of a connection (a client that reset
    it, a time-out) end that connection quietly instead of printing a traceback."""

    daemon_threads = True
    request_queue_size = MAX_CONNECTIONS  # the listen backlog: a page's burst of requests is not refused by the kernel

    def __init__(self, address, handler):
        self._places = threading.BoundedSemaphore(MAX_CONNECTIONS)
        super().__init__(address, handler)

    def process_request(self, request, client_address):
        if not self._places.acquire(blocking=False):
            self.shutdown_request(request)  # full: closed unanswered, as a busy server would
            return
        try:
            super().process_request(request, client_address)
        except BaseException:
            self._places.release()
            raise

    def process_request_thread(self, request, client_address):
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._places.release()

    def handle_error(self, request, client_address) -> None:
        pass  # a connection's own failure (reset, time-out, a broken pipe) concerns that connection only


def make_server(
    files: dict[str, tuple[bytes, str]], port: int = 8000, host: str = "127.0.0.1"
) -> http.server.ThreadingHTTPServer:
    """A server of ``files`` (:func:`page_files`) on ``host``:``port`` (0: any free port; an IPv6 address such as
    ``::1`` too), not yet serving."""
    port = check_positive_int("port", port, low=0, high=65535)
    if not isinstance(host, str) or not host or any(character.isspace() for character in host):
        raise ParameterError(f"host must be a host name or address, got {host!r}")
    handler = type("Handler", (_Handler,), {"files": dict(files), "names": _host_names(host)})
    try:
        family = socket.getaddrinfo(host.strip("[]"), port, type=socket.SOCK_STREAM)[0][0]
    except (OSError, UnicodeError) as error:
        raise ParameterError(f"host {host!r} is no address or name of this machine ({error})") from None
    server_class = type("Server", (_Server,), {"address_family": family})
    try:
        return server_class((host.strip("[]"), port), handler)
    except OSError as error:
        raise OSError(error.errno, f"cannot listen on {host}:{port}: {error.strerror}") from error


@contextlib.contextmanager
def serving(files: dict[str, tuple[bytes, str]], port: int = 0, host: str = "127.0.0.1"):
    """:func:`make_server` answering in a background thread for the ``with`` block, then shut down and closed."""
    server = make_server(files, port, host)
    threading.Thread(target=server.serve_forever, kwargs={"poll_interval": 0.05}, daemon=True).start()
    try:
        yield server
    finally:
        server.shutdown()
        server.server_close()


def serve(
    port: int = 8000,
    host: str = "127.0.0.1",
    environment=None,
    ready: Callable[[str], None] | None = None,
    progress: Callable[[str], None] | None = None,
    three_js=None,
) -> None:
    """Serve the page until interrupted; ``ready`` gets its URL once it listens."""
    if not is_loopback(host):
        warnings.warn(
            f"listening on {host}: other machines can open the page (and the environment map); --host 127.0.0.1 "
            "keeps it to this one",
            ServerWarning,
            stacklevel=2,
        )
    server = make_server(page_files(environment, progress, three_js), port, host)
    try:
        address, bound = server.server_address[:2]
        shown = f"[{address}]" if ":" in str(address) else address
        if ready is not None:
            ready(f"http://{shown}:{bound}/")
        server.serve_forever(poll_interval=0.2)
    finally:
        server.server_close()
