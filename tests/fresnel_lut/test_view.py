"""The look-development page (``fresnel-lut view``, :mod:`fresnel_lut.view`, ``fresnel_lut/page/``) in a real browser:
Debian's Chromium headless (WebGL 2 on SwiftShader) driven by Playwright, the page set through its own controls and its
float render targets read back.

Against independent computations, each with its tolerance:

* the split sums (Schlick, basis, basis + multiple scattering), the point light and the rectangular light against the
  Python renderer (:mod:`fresnel_lut.render`) on the same tables rounded to half floats, as the page reads them:
  within 3e-3 of the value plus 1e-5 (measured 1.1e-3 for the split sums, 2.2e-3 for the point light's narrow peak:
  float32 and the GPU's 8-bit bilinear weights); the half rounding itself moves the Python split sum by at most 7e-4
  relative, which the page therefore carries against the float32 tables;
* the progressive reference against the Python Monte-Carlo reference (another sampler, another seed) and, for the
  rectangular light, against the Gauss-Legendre area integral of tests/references/area_light.py: differences within
  their combined standard errors (z-scores);
* the page's ΔE2000 numbers against colour-science's CIEDE2000 (:func:`basis.colorimetry.delta_E_2000`) of the
  page's own pictures: within 0.01;
* a user's environment map (the studio rasterised into an equirectangular EXR) prefiltered on the GPU against the
  studio's closed form.

And what a user must never meet: an error on the console, a page that fails without saying why (no WebGL 2, no float
targets, a table from another basis: one line in the page), a server that serves anything outside its page. Under
``CI=true`` a missing browser fails these tests (the set-up installs it).
"""

from __future__ import annotations

import http.client
import json
import signal
import socket
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import OpenEXR
import pytest

from basis.colorimetry import delta_E_2000
from basis.materials import material_from_mapping
from basis.storage import shipped_path
from basis.validation import ParameterError
from benchmarks.browser import browser_page, page_bytes
from benchmarks.three_page import gltf_document, uv_sphere
from fresnel_lut import render
from fresnel_lut.view import page_files, read_environment, serving
from handoff.exr import read_lut, stored_values
from handoff.formats import ktx2_bytes
from handoff.three import THREE_VERSION
from preintegrate.ggx import roughness_to_alpha
from tests.conftest import chromium
from tests.references.area_light import rect_light_reference

ROOT = Path(__file__).resolve().parents[2]
SIZE = 48  # the sphere's pixels in these tests (the page's default is 384)
RELATIVE, ABSOLUTE = 3e-3, 1e-5
MODES = ("schlick", "basis", "multiple")


@pytest.fixture(scope="module")
def files():
    return page_files()


@pytest.fixture(scope="module")
def server(files):
    with serving(files) as server:
        yield server


@pytest.fixture(scope="module")
def browser():
    with chromium() as browser:
        yield browser


def _url(server, **query) -> str:
    text = "&".join(f"{key}={value}" for key, value in {"size": SIZE, "spp": 32, **query}.items())
    return f"http://127.0.0.1:{server.server_address[1]}/?{text}"


def _open(browser, url):
    """A page at ``url``, ready (its pictures rendered once), and its console messages."""
    page, messages = browser_page(browser)
    page.goto(url)
    page.evaluate("() => fresnelView.ready.then(() => fresnelView.settle(1))")
    return page, messages


def _picture(page, name: str) -> np.ndarray:
    values = np.array(page.evaluate(f"() => fresnelView.readImage('{name}')"), dtype=np.float64)
    return values.reshape(SIZE, SIZE, 4)[::-1, :, :3]  # rows bottom first → the renderer's top first


def _reference(page, samples: int) -> tuple[np.ndarray, np.ndarray]:
    page.evaluate(f"() => fresnelView.settle({samples})")
    result = page.evaluate("() => fresnelView.readReference()")
    mean = np.array(result["mean"], dtype=np.float64).reshape(SIZE, SIZE, 4)[::-1, :, :3]
    spread = np.array(result["spread"], dtype=np.float64).reshape(SIZE, SIZE, 4)[::-1, :, :3]
    return mean, spread


def _set(page, selector: str, value) -> None:
    """Set a control as a user does: its value, then the input event the page listens to."""
    page.eval_on_selector(
        selector,
        "(element, value) => { element.value = value; element.dispatchEvent(new Event('input')); }",
        str(value),
    )


def _set_triple(page, name: str, values) -> None:
    for channel, value in zip("rgb", values):
        page.fill(f"#{name}-{channel}", str(value))


def _no_errors(messages) -> None:
    assert not [text for kind, text in messages if kind in ("error", "pageerror")], messages


def _close(picture, want, what: str) -> None:
    """``picture`` within RELATIVE of ``want`` plus ABSOLUTE."""
    assert np.all(np.isfinite(picture)), what
    excess = np.abs(picture - want) - (RELATIVE * np.abs(want) + ABSOLUTE)
    assert excess.max() <= 0.0, (
        f"{what}: {np.abs(picture - want).max():.3g} at {np.unravel_index(excess.argmax(), want.shape)}"
    )


@pytest.fixture(scope="module")
def half_tables():
    """The shipped tables as the page reads them: the half floats the server's KTX2 stores (``stored_values``, the
    writers' one rule: subnormal halves are written as 0)."""
    return {
        name: stored_values(read_lut(shipped_path(f"{name}.exr"))[0], half=True).astype(np.float64)
        for name in ("ggx_basis_rgba", "ggx_schlick_rgba", "ggx_ltc")
    }


def _material(mapping: dict) -> render.RenderMaterial:
    material = material_from_mapping(mapping, "sRGB")
    return render.RenderMaterial("test", material.curve, material.coefficients(), ())


# ---- the server ------------------------------------------------------------------------------------------------


def _get(server, path: str, method: str = "GET"):
    connection = http.client.HTTPConnection("127.0.0.1", server.server_address[1], timeout=10)
    connection.putrequest(method, path, skip_accept_encoding=True)  # the path as written: no client normalises it
    connection.endheaders()
    response = connection.getresponse()
    body = response.read()
    connection.close()
    return response, body


def test_the_server_serves_the_shipped_include_and_tables(server, files):
    assert server.server_address[0] == "127.0.0.1"
    response, body = _get(server, "/shaders/fresnel_basis.glsl")
    assert response.status == 200 and body == shipped_path("fresnel_basis.glsl").read_bytes()
    table, header = read_lut(shipped_path("ggx_basis_rgba.exr"))
    attributes = {key: value for key, value in header.items() if key not in ("content_hash", "pixel_type")}
    response, body = _get(server, "/tables/ggx_basis_rgba.ktx2")
    assert response.status == 200 and body == ktx2_bytes(table, attributes, half=True)
    response, _ = _get(server, "/")
    assert response.status == 200 and "default-src 'none'" in response.getheader("Content-Security-Policy")


@pytest.mark.parametrize(
    "path",
    [
        "/../pyproject.toml",
        "/%2e%2e/pyproject.toml",
        "/shaders/../../pyproject.toml",
        "/shaders/..%2f..%2fpyproject.toml",
        "//etc/passwd",
        "/etc/passwd",
        "/tables/ggx_basis_rgba.exr",
        "/index.html/",
        "/page/view.js",
        "/fresnel_lut/view.py",
    ],
)
def test_the_server_refuses_every_other_path(server, path):
    response, body = _get(server, path)
    assert response.status == 404 and b"[project]" not in body and b"root:" not in body


def test_the_server_only_reads(server):
    for method in ("POST", "PUT", "DELETE"):
        assert _get(server, "/", method)[0].status == 405


def _raw(server, request: bytes) -> bytes:
    """What the server answers to ``request`` sent as it is (no client library in between)."""
    with socket.create_connection(("127.0.0.1", server.server_address[1]), timeout=10) as connection:
        connection.sendall(request)
        answer = b""
        while chunk := connection.recv(65536):
            answer += chunk
    return answer


@pytest.mark.parametrize(
    "host, status",
    [
        ("evil.example:{port}", 403),  # a DNS-rebinding page: its own name, rebound to 127.0.0.1
        ("evil.example", 403),
        ("localhost:1", 403),  # another port
        ("localhost:{port}", 200),
        ("127.0.0.1:{port}", 200),
        ("LOCALHOST:{port}", 200),
    ],
)
def test_a_request_for_another_host_is_refused(server, host, status):
    """Issue 36 item 5: ``Host`` names this server, or the request is refused before any file is read."""
    port = server.server_address[1]
    answer = _raw(
        server, f"GET /config.json HTTP/1.1\r\nHost: {host.format(port=port)}\r\nConnection: close\r\n\r\n".encode()
    )
    assert answer.split(b"\r\n", 1)[0].split()[1] == str(status).encode()
    assert (b'"basis_hash"' in answer) == (status == 200)


@pytest.mark.parametrize(
    "request_line", [b"GET http://[/ HTTP/1.0", b"GET / HTTP/9.9", b"\x00\xff garbage", b"GET " + b"a" * 70000]
)
def test_a_malformed_request_gets_an_http_answer_and_no_traceback(server, request_line, capfd):
    """Item 10: every request is answered (400-class), and nothing reaches the terminal."""
    answer = _raw(server, request_line + b"\r\n\r\n")
    assert answer.startswith(b"HTTP/") and answer.split()[1] in (b"400", b"404", b"414", b"505")
    assert capfd.readouterr().err == ""


def test_clients_that_reset_or_idle_print_nothing_and_hold_no_thread(files, monkeypatch, capfd):
    """Items 5 and 10: connections reset mid-request print no traceback; idle ones are closed after the time-out,
    so 60 of them hold no thread for long."""
    import threading
    import time

    from fresnel_lut import view

    monkeypatch.setattr(view._Handler, "timeout", 0.5)
    with serving(files) as idle_server:
        port = idle_server.server_address[1]
        baseline = threading.active_count()
        for _ in range(5):
            connection = socket.create_connection(("127.0.0.1", port))
            connection.sendall(b"GET /config.json HTTP/1.1\r\nHost: 127.0.0.1\r\n")
            connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            connection.close()  # a reset
        idle = [socket.create_connection(("127.0.0.1", port)) for _ in range(60)]
        time.sleep(0.2)
        assert threading.active_count() > baseline + 30
        deadline = time.monotonic() + 10
        while threading.active_count() > baseline + 2 and time.monotonic() < deadline:
            time.sleep(0.1)
        assert threading.active_count() <= baseline + 2
        for connection in idle:
            assert connection.recv(1) == b""  # closed by the server
            connection.close()
    assert "Traceback" not in capfd.readouterr().err


def test_the_server_listens_on_ipv6_loopback(files):
    """Item 5: ``--host ::1``."""
    if not socket.has_ipv6:
        pytest.skip("no IPv6 on this machine")
    try:
        probe = socket.socket(socket.AF_INET6)
        probe.bind(("::1", 0))
        probe.close()
    except OSError:
        pytest.skip("no IPv6 loopback address here")
    with serving(files, host="::1") as server6:
        connection = http.client.HTTPConnection("::1", server6.server_address[1], timeout=10)
        connection.request("GET", "/config.json")
        assert connection.getresponse().status == 200
        connection.close()


def test_a_server_beyond_loopback_warns(monkeypatch):
    """Item 5: bound beyond the loopback addresses, the command says so before it serves."""
    from fresnel_lut import view

    def refused(*arguments, **keywords):
        raise KeyboardInterrupt

    monkeypatch.setattr(view, "page_files", lambda *arguments: {})
    monkeypatch.setattr(view, "make_server", refused)
    with pytest.warns(view.ServerWarning, match="other machines can open the page"), pytest.raises(KeyboardInterrupt):
        view.serve(port=0, host="0.0.0.0")
    assert view.is_loopback("127.0.0.2") and view.is_loopback("::1") and view.is_loopback("localhost")
    assert not view.is_loopback("0.0.0.0") and not view.is_loopback("example.org")


def test_a_missing_shipped_table_says_how_to_make_it(tmp_path, monkeypatch):
    """Item 7: ``view`` over a checkout whose LTC table is gone names the command that makes it."""
    from fresnel_lut import view

    monkeypatch.setattr(view, "shipped_path", lambda name: tmp_path / name)
    with pytest.raises(ValueError, match="does not exist.*make luts"):
        view.page_files()


def _write_exr(path: Path, rgb: np.ndarray) -> Path:
    channels = {name: np.ascontiguousarray(rgb[..., i], dtype=np.float32) for i, name in enumerate("RGB")}
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, channels) as file:
        file.write(str(path))
    return path


def test_an_environment_that_is_not_a_2_to_1_finite_positive_exr_is_refused(tmp_path):
    good = np.ones((8, 16, 3))
    assert read_environment(_write_exr(tmp_path / "good.exr", good)).shape == (8, 16, 4)
    cases = {
        "square.exr": np.ones((8, 8, 3)),
        "nan.exr": np.where(np.arange(16)[:, None] == 3, np.nan, good),
        "negative.exr": -good,
    }
    for name, pixels in cases.items():
        with pytest.raises(ValueError, match="equirectangular|NaN|negative"):
            read_environment(_write_exr(tmp_path / name, pixels))
    (tmp_path / "text.exr").write_text("not an EXR")
    with pytest.raises(ValueError, match="not a readable EXR"):
        read_environment(tmp_path / "text.exr")
    with pytest.raises(ValueError, match="does not exist"):
        read_environment(tmp_path / "missing.exr")


@pytest.mark.slow
def test_the_view_command_serves_until_interrupted(tmp_path):
    command = [sys.executable, "-m", "fresnel_lut.cli", "view", "--port", "0"]
    process = subprocess.Popen(  # Ctrl-C's default in the child: a shell's background job starts ignoring it
        command,
        cwd=ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        line = ""
        while "serving" not in line:
            line = process.stdout.readline()
            assert line, process.stderr.read()
        url = line.split("serving ")[1].split()[0]
        host, port = url.split("//")[1].rstrip("/").rsplit(":", 1)
        assert host == "127.0.0.1"
        connection = http.client.HTTPConnection(host, int(port), timeout=10)
        connection.request("GET", "/")
        assert connection.getresponse().status == 200
        connection.close()
    finally:
        process.send_signal(signal.SIGINT)
        _, errors = process.communicate(timeout=20)
    assert process.returncode == 0 and "stopped" in errors
    missing = subprocess.run(
        [*command, "--environment", str(tmp_path / "missing.exr")], cwd=ROOT, capture_output=True, text=True
    )
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1 and "does not exist" in missing.stderr


# ---- the page --------------------------------------------------------------------------------------------------


@pytest.mark.slow
def test_the_page_renders_figure_2_as_the_python_renderer(server, browser, half_tables):
    page, messages = _open(browser, _url(server))
    assert page.inner_text("#error") == ""
    figure2 = render.DEFAULT_SCENES["figure2"]("sRGB")
    roughness = render.FIGURE2_ROUGHNESS
    basis, schlick, ltc = (half_tables[name] for name in ("ggx_basis_rgba", "ggx_schlick_rgba", "ggx_ltc"))
    want = render.render_split_sum(figure2, roughness, SIZE, basis, schlick)
    for mode, key in (("schlick", "schlick"), ("basis", "basis"), ("multiple", "basis_multiple_scattering")):
        _close(_picture(page, mode), want[key], f"split sum {mode}")
    # what the half rounding does to the renderer's own split sum: the page's agreement with the float32 tables
    full = render.render_split_sum(figure2, roughness, SIZE, read_lut(shipped_path("ggx_basis_rgba.exr"))[0], schlick)[
        "basis"
    ]
    assert np.max(np.abs(full - want["basis"]) / np.maximum(np.abs(full), 1e-3)) <= 7e-4

    page.check("#light-point")
    page.uncheck("#light-environment")
    page.evaluate("() => fresnelView.settle(1)")
    point = render.render_point_light(figure2, roughness, SIZE)
    for mode in ("schlick", "basis"):
        _close(_picture(page, mode), point[mode], f"point light {mode}")

    page.uncheck("#light-point")
    page.check("#light-rect")
    page.evaluate("() => fresnelView.settle(1)")
    rect = render.render_rect_light(figure2, roughness, SIZE, ltc, basis, schlick)
    for mode in ("schlick", "basis"):
        _close(_picture(page, mode), rect[mode], f"rectangular light {mode}")
    _no_errors(messages)
    page.close()


@pytest.mark.slow
@pytest.mark.parametrize(
    "kind, controls, mapping",
    [
        (
            "nk",
            {"eta": [0.27, 0.68, 1.32], "kappa": [3.61, 2.64, 1.81]},
            {"eta": [0.27, 0.68, 1.32], "kappa": [3.61, 2.64, 1.81]},
        ),
        (
            "f82tint",
            {"f0": [0.95, 0.64, 0.54], "tint": [1.0, 0.9, 0.8]},
            {"model": "adobe", "f0": [0.95, 0.64, 0.54], "tint": [1.0, 0.9, 0.8]},
        ),
        ("preset", {"preset": "Gold"}, {"preset": "Gold"}),
        (
            "gulbrandsen",
            {"reflectivity": [0.9999, 0.5, 0.0], "edge-tint": [1.0, 0.0, 0.5]},
            {"reflectivity": [0.9999, 0.5, 0.0], "edge_tint": [1.0, 0.0, 0.5]},
        ),
    ],
    ids=["eta-kappa", "f82-tint", "gold-preset", "gulbrandsen-edges"],
)
def test_every_kind_of_material_through_the_page_controls(server, browser, half_tables, kind, controls, mapping):
    page, messages = _open(browser, _url(server))
    page.select_option("#kind", kind)
    for name, values in controls.items():
        if name == "preset":
            page.select_option("#preset", values)
        else:
            _set_triple(page, name, values)
    _set(page, "#roughness", 0.45)
    page.check("#light-point")
    page.evaluate("() => fresnelView.settle(1)")
    material = _material(mapping)
    basis, schlick = half_tables["ggx_basis_rgba"], half_tables["ggx_schlick_rgba"]
    want = render.render_split_sum(material, 0.45, SIZE, basis, schlick)
    point = render.render_point_light(material, 0.45, SIZE)
    for mode, key in (("schlick", "schlick"), ("basis", "basis"), ("multiple", "basis_multiple_scattering")):
        light = point["basis" if mode != "schlick" else "schlick"]
        _close(_picture(page, mode), want[key] + light, f"{kind} {mode}")
    _no_errors(messages)
    page.close()


def _canvas(page) -> np.ndarray:
    shown = page.evaluate("() => fresnelView.readCanvas()")
    return np.array(shown["pixels"], dtype=np.float64).reshape(shown["height"], shown["width"], 4)[::-1, :, :3]


@pytest.mark.slow
def test_the_views_show_the_pictures_as_the_renderer_would(server, browser):
    """Each view of the canvas against the float pictures read back: one picture and the split are the renderer's
    tone map and sRGB encoding (:func:`fresnel_lut.render.to_srgb8`) of them, within one 8-bit step; the gallery holds
    the four side by side; the difference views are black outside the sphere and where the pictures agree."""
    page, messages = _open(browser, _url(server))
    shown = {mode: render.to_srgb8(render.tone_map(_picture(page, mode))).astype(np.float64) for mode in MODES}
    gallery = _canvas(page)
    assert gallery.shape == (SIZE, 4 * SIZE, 3)
    for k, mode in enumerate(("schlick", "basis", "multiple")):
        assert np.abs(gallery[:, k * SIZE : (k + 1) * SIZE] - shown[mode]).max() <= 1.0, mode
    page.select_option("#view", "single")
    page.select_option("#main", "schlick")
    assert np.abs(_canvas(page) - shown["schlick"]).max() <= 1.0
    page.select_option("#view", "split")
    page.select_option("#compare", "basis")
    split = _canvas(page)
    half = SIZE // 2
    assert np.abs(split[:, :half] - shown["schlick"][:, :half]).max() <= 1.0
    assert np.abs(split[:, half + 1 :] - shown["basis"][:, half + 1 :]).max() <= 1.0
    assert np.all(split[:, half] == 255.0)  # the divider
    outside = ~render.sphere_geometry(SIZE)[1]
    for view in ("difference", "delta-e"):
        page.select_option("#view", view)
        page.select_option("#compare", "schlick")
        assert np.all(_canvas(page) == 0.0), f"{view} of a picture with itself"
        page.select_option("#compare", "basis")
        heat = _canvas(page)
        assert np.all(heat[outside] == 0.0) and heat[~outside].max() > 50.0, view
    _no_errors(messages)
    page.close()


@pytest.mark.slow
def test_the_progressive_reference_converges_to_the_python_monte_carlo(server, browser):
    page, messages = _open(browser, _url(server))
    page.check("#light-point")
    samples = 1024
    mean, spread = _reference(page, samples)
    figure2 = render.DEFAULT_SCENES["figure2"]("sRGB")
    roughness = render.FIGURE2_ROUGHNESS
    want, want_spread, _ = render.render_reference(figure2, roughness, SIZE, samples, seed=7)
    want = want + render.render_point_light(figure2, roughness, SIZE)["exact"]
    mask = render.sphere_geometry(SIZE)[1]
    z = (mean - want)[mask] / np.sqrt(spread[mask] ** 2 + want_spread[mask] ** 2 + 1e-30)
    assert np.all(np.isfinite(mean))
    assert np.mean(np.abs(z) > 4.0) <= 2e-3 and abs(z.mean()) <= 0.1, (np.abs(z).max(), z.mean())
    relative_bias = (mean - want)[mask].mean() / want[mask].mean()
    assert (
        abs(relative_bias)
        <= 3.0 * np.sqrt(np.mean(spread[mask] ** 2 + want_spread[mask] ** 2) / mask.sum()) / want[mask].mean() + 1e-4
    )

    # the page's ΔE2000 numbers are colour-science's CIEDE2000 of its own pictures
    numbers = page.evaluate("() => fresnelView.statistics()")
    assert numbers["samples"] == samples
    reference = _reference(page, samples)[0]
    for mode in ("schlick", "basis", "multiple"):
        picture = _picture(page, mode)
        delta = delta_E_2000(render.tone_map(picture), render.tone_map(reference), "sRGB")[mask]
        for name, value in (("max", delta.max()), ("mean", delta.mean())):
            assert abs(numbers[mode][name] - value) <= 0.01 + 1e-3 * value, (mode, name, numbers[mode][name], value)
    assert numbers["basis"]["mean"] < 0.5 * numbers["schlick"]["mean"]  # figure 2's edge tint: Schlick has none
    _no_errors(messages)
    page.close()


@pytest.mark.slow
def test_the_rectangular_light_reference_is_the_area_integral(server, browser):
    """The reference of the rectangular light (BRDF samples that meet the light) against tests/references/
    area_light.py (Gauss-Legendre over the light's area, the exact curve), at pixels spread over the sphere."""
    page, messages = _open(browser, _url(server))
    page.uncheck("#light-environment")
    page.check("#light-rect")
    _set(page, "#roughness", 0.5)
    mean, spread = _reference(page, 2048)
    figure2 = render.DEFAULT_SCENES["figure2"]("sRGB")
    normals, mask = render.sphere_geometry(SIZE)
    rows, columns = np.nonzero(mask)
    pick = np.arange(0, rows.size, 7)
    normal = normals[rows[pick], columns[pick]]
    view = np.broadcast_to([0.0, 0.0, 1.0], normal.shape)
    alpha = roughness_to_alpha(0.5)
    want = (
        4.0
        * np.concatenate(  # 16 pixels at a time: the reference holds (pixels, 96², 3) arrays
            [
                rect_light_reference(
                    normal[i : i + 16], view[i : i + 16], normal[i : i + 16], render.RECT_LIGHT, alpha, figure2.curve
                )
                for i in range(0, len(normal), 16)
            ]
        )
    )
    got, sigma = mean[rows[pick], columns[pick]], spread[rows[pick], columns[pick]]
    # where the light lies in the lobe's tail, 2048 samples may never meet it (the estimate 0, its spread 0): one
    # hit's worth, L / N, stands for the spread there
    z = (got - want) / np.maximum(sigma, render.RECT_LIGHT_RADIANCE / 2048)
    assert np.mean(np.abs(z) > 4.0) <= 5e-3 and abs(z.mean()) <= 0.15, (np.abs(z).max(), z.mean())
    _no_errors(messages)
    page.close()


@pytest.mark.slow
def test_a_users_environment_map_is_prefiltered_on_the_gpu(tmp_path, browser, half_tables):
    """The studio rasterised into a 512 × 256 equirectangular EXR and served as a user's map: the page's prefiltered
    split sum within 4 % of the studio's closed form at every pixel and 0.5 % on average (measured 2.6 % and 0.3 %:
    the mip levels that filtered importance sampling reads blur a bright light into its dim surroundings), and a
    constant map gives the split sum itself (the white furnace: prefiltering changes nothing)."""
    height = 256
    theta = (np.arange(height) + 0.5) / height * np.pi
    phi = ((np.arange(2 * height) + 0.5) / (2 * height) - 0.5) * 2.0 * np.pi
    t, p = np.meshgrid(theta, phi, indexing="ij")
    directions = np.stack([np.sin(t) * np.sin(p), np.cos(t), -np.sin(t) * np.cos(p)], axis=-1)
    cases = {
        "studio.exr": (render.STUDIO.radiance(directions), render.STUDIO, (4e-2, 5e-3)),
        "furnace.exr": (
            np.ones(directions.shape),
            render.Environment(np.array([[0.0, 1.0, 0.0]]), np.array([0.0]), np.array([[1.0, 1.0, 1.0]])),
            (RELATIVE, RELATIVE),
        ),
    }
    figure2 = render.DEFAULT_SCENES["figure2"]("sRGB")
    for name, (pixels, environment, tolerance) in cases.items():
        with serving(page_files(_write_exr(tmp_path / name, pixels))) as server:
            page, messages = _open(browser, _url(server))
            for roughness in (0.3, 0.6):
                _set(page, "#roughness", roughness)
                page.evaluate("() => fresnelView.settle(1)")
                want = render.render_split_sum(
                    figure2,
                    roughness,
                    SIZE,
                    half_tables["ggx_basis_rgba"],
                    half_tables["ggx_schlick_rgba"],
                    environment,
                )["basis"]
                got = _picture(page, "basis")
                error = np.abs(got - want) / np.maximum(want, 1e-2)
                inside = render.sphere_geometry(SIZE)[1]
                assert np.all(np.isfinite(got)), name
                assert error.max() <= tolerance[0] and error[inside].mean() <= tolerance[1], (
                    name,
                    roughness,
                    error.max(),
                )
            _no_errors(messages)
            page.close()


@pytest.mark.slow
@pytest.mark.parametrize(
    "script, message",
    [
        (
            "HTMLCanvasElement.prototype.getContext = function () { return null; };",
            "This page needs WebGL 2",
        ),
        (
            "const original = WebGL2RenderingContext.prototype.getExtension;"
            "WebGL2RenderingContext.prototype.getExtension = function (name) {"
            "  return name === 'EXT_color_buffer_float' ? null : original.call(this, name); };",
            "float render targets",
        ),
    ],
    ids=["no-webgl2", "no-float-targets"],
)
def test_a_browser_that_cannot_run_the_page_is_told_in_one_line(server, browser, script, message):
    page, _ = browser_page(browser)
    page.add_init_script(script)
    page.goto(_url(server))
    page.wait_for_selector("#error:not([hidden])")
    text = page.inner_text("#error")
    assert message in text and "\n" not in text
    page.close()


@pytest.mark.slow
def test_a_table_from_another_basis_is_refused_in_the_page(server, browser):
    table, header = read_lut(shipped_path("ggx_basis_rgba.exr"))
    attributes = {key: value for key, value in header.items() if key not in ("content_hash", "pixel_type")}
    other = ktx2_bytes(table, {**attributes, "basis_hash": "0123456789abcdef"}, half=True)
    page, _ = browser_page(browser)
    page.route("**/tables/ggx_basis_rgba.ktx2", lambda route: route.fulfill(body=other, content_type="image/ktx2"))
    page.goto(_url(server))
    page.wait_for_selector("#error:not([hidden])")
    text = page.inner_text("#error")
    assert "another basis" in text and "0123456789abcdef" in text
    page.close()


def test_the_page_loads_nothing_from_elsewhere():
    """Every file the page names is one of the server's (no CDN, no font, no analytics)."""
    page = Path(__file__).resolve().parents[2] / "fresnel_lut" / "page"
    text = "".join(
        (page / name).read_text(encoding="utf-8")
        for name in ("index.html", "view.js", "view.css", "asset.html", "asset.js")
    )
    assert "http://" not in text and "https://" not in text and "//cdn" not in text


@pytest.fixture(scope="module")
def three_js():
    from benchmarks.npm import NpmError, npm_unpacked
    from tests.conftest import gpu_missing

    try:
        return npm_unpacked("three", THREE_VERSION)
    except NpmError as error:
        gpu_missing(str(error))


def test_the_asset_page_shows_a_gltf_stock_and_with_the_basis(three_js, browser):
    """ "Your asset": a glTF chosen in the page's file field, in three.js 0.187.0 with and without the package (its
    GLTFLoader plugin), under the page's Content-Security-Policy (the import map admitted by its hash)."""
    sphere = uv_sphere()
    figure2 = {"pbrMetallicRoughness": {"baseColorFactor": [0.44, 0.44, 0.44, 1.0], "metallicFactor": 1.0,
                                        "roughnessFactor": 0.28},
               "extensions": {"KHR_materials_specular": {"specularColorFactor": [0.2, 1.0, 0.2]}}}  # fmt: skip
    document = json.dumps(gltf_document([sphere], [figure2])).encode("utf-8")
    with serving(page_files(three_js=three_js)) as asset_server:
        page, messages = browser_page(browser)
        page.goto(f"http://127.0.0.1:{asset_server.server_address[1]}/asset.html")
        page.wait_for_function("() => window.fresnelAsset !== undefined", timeout=60_000)
        page.set_input_files(
            "#file", files=[{"name": "sphere.gltf", "mimeType": "model/gltf+json", "buffer": document}]
        )
        page.wait_for_function("() => window.fresnelAsset.state.name === 'sphere.gltf'", timeout=60_000)
        assert page.evaluate("window.fresnelAsset.state.metals") == 1
        basis = np.frombuffer(page_bytes(page, "window.fresnelAsset.pixels()"), np.uint8).reshape(512, 768, 4) * 1.0
        page.select_option("#mode", "stock")
        stock = np.frombuffer(page_bytes(page, "window.fresnelAsset.pixels()"), np.uint8).reshape(512, 768, 4) * 1.0
        page.close()
    _no_errors(messages)
    background = np.array([basis[0, 0, :3], stock[0, 0, :3]])
    covered = np.any(basis[..., :3] != basis[0, 0, :3], axis=-1)
    assert np.ptp(background, axis=0).max() == 0 and covered.mean() > 0.1  # the sphere fills a part of the picture
    # F82 tint (0.2, 1, 0.2): the basis' sphere turns green towards its rim; stock three.js ignores a metal's tint
    assert basis[covered, 1].mean() - basis[covered, 0].mean() > 5
    assert abs(stock[covered, 1].mean() - stock[covered, 0].mean()) < 2


def test_the_asset_page_needs_three_js_of_the_packages_version(tmp_path):
    (tmp_path / "package.json").write_text('{"name": "three", "version": "0.180.0"}', encoding="utf-8")
    with pytest.raises(ParameterError, match=f"made for three {THREE_VERSION}"):
        page_files(three_js=tmp_path)
    with pytest.raises(ParameterError, match="not npm's three package"):
        page_files(three_js=tmp_path / "missing")
