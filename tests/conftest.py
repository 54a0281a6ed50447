"""Shared test helpers: running the CLI in-process or as a subprocess, checking its one-line errors, and
making the n-th call of a function fail. Test modules import them from here (``tests.conftest``) and never
from one another; the deliberately independent references are ``tests.references``."""

from __future__ import annotations

import re
import subprocess
import sys

from fresnel_lut import cli


def run(argv):
    """cli.main in-process; argparse errors raise SystemExit, converted to its status."""
    try:
        return cli.main([str(a) for a in argv])
    except SystemExit as exit_:
        return exit_.code


def run_subprocess(argv, cwd, timeout=120, env=None):
    """The ``fresnel-lut`` command (its entry point, which pins the numeric kernels before numpy loads) in a fresh
    process."""
    return subprocess.run(
        [sys.executable, "-m", "fresnel_lut.entry", *map(str, argv)],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=timeout,
        env=env,
    )


def read_png16(path):
    """(texels (H, W, K) in [0, 1], the tEXt chunks) of a png16 table: a 16-bit greyscale image, the K channels
    stacked top to bottom, read by pypng (a reader that shares no code with the writer)."""
    import json

    import numpy as np
    import png

    width, height, rows, info = png.Reader(filename=str(path)).read()
    samples = np.array([np.asarray(row, dtype=np.float64) for row in rows])
    text = {}
    for kind, data in png.Reader(filename=str(path)).chunks():
        if kind == b"tEXt":
            key, value = data.split(b"\x00", 1)
            text[key.decode("latin-1")] = value.decode("latin-1")
    assert info["bitdepth"] == 16 and info["planes"] == 1 and not info["alpha"]
    rows_per_channel = json.loads(text["fresnel:encoding"])["rows_per_channel"]
    texels = samples.reshape(height // rows_per_channel, rows_per_channel, width).transpose(1, 2, 0)
    return texels / 65535.0, text


#: A progress report (fresnel_lut.progress.Progress: ``label: 42.0% (done/total unit) 12.0s, about 16 s left``), which
#: a command prints on standard error for work that runs past a second, as a loaded machine makes a small build do: not
#: part of the error message whose lines :func:`assert_one_line_error` counts.
PROGRESS_LINE = re.compile(r"^.+: (?:\s*\d+\.\d% )?\(\d+(?:/\d+)? [^)]*\) \d+\.\ds(?:, about .+ left)?$")


def assert_one_line_error(stderr):
    """``stderr`` is one line, ``fresnel-lut…error…``, and no traceback (progress reports aside: :data:`PROGRESS_LINE`)."""
    lines = [line for line in stderr.splitlines() if not PROGRESS_LINE.match(line)]
    assert len(lines) == 1, stderr
    assert lines[0].startswith("fresnel-lut"), stderr
    assert "error" in lines[0]
    assert "Traceback" not in stderr


def fail_on_call(monkeypatch, owner, name, call, failure):
    """Patch ``owner.name`` so that its ``call``-th call runs ``failure(*arguments)`` (which raises) instead."""
    original, calls = getattr(owner, name), []

    def patched(*arguments):
        calls.append(arguments)
        if len(calls) == call:
            failure(*arguments)
        return original(*arguments)

    monkeypatch.setattr(owner, name, patched)


def gpu_missing(what: str):
    """Skip a GPU test whose tool is not installed here; under ``CI=true`` fail instead (the set-up installs it)."""
    import os

    import pytest

    if os.environ.get("CI") == "true":
        pytest.fail(f"{what} is missing: the project's set-up installs it (make test, as root on Debian)")
    pytest.skip(f"{what} is not installed here (the set-up installs it as root)")


def chromium(viewport=(1280, 900)):
    """Debian's Chromium driven by Playwright for Python (:func:`benchmarks.browser.chromium`); a missing browser or
    Playwright skips, or fails under ``CI=true`` (:func:`gpu_missing`)."""
    from benchmarks.browser import chromium as launch

    return launch(viewport, missing=gpu_missing)


GL_VERTEX = """#version 330
in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }
"""


def gl_draw(fragment: str, textures, uniforms: dict, outputs: int, size: int = 32, mipmaps: bool = False):
    """Run ``fragment`` on Mesa's llvmpipe (headless EGL, moderngl) over a ``size`` × ``size`` framebuffer of
    ``outputs`` RGBA32F colour attachments; ``textures`` (float arrays (H, W, C)) are bound to units 0, 1, … with
    bilinear filtering and clamp to edge (and mipmaps if asked). Returns each attachment as (size², 4)."""
    import numpy as np

    try:
        import moderngl
    except ImportError:
        gpu_missing("moderngl (the 'gpu' extra)")
    try:
        context = moderngl.create_standalone_context(backend="egl")
    except Exception as error:  # noqa: BLE001 - no EGL/Mesa: a missing system library
        gpu_missing(f"a headless OpenGL context (Mesa's EGL: {error})")
    try:
        for unit, table in enumerate(textures):
            table = np.asarray(table, dtype="f4")
            texture = context.texture(table.shape[1::-1], table.shape[2], table.tobytes(), dtype="f4")
            texture.repeat_x = texture.repeat_y = False  # clamp to edge
            if mipmaps:
                texture.build_mipmaps()
                texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
            else:
                texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.use(unit)
        program = context.program(vertex_shader=GL_VERTEX, fragment_shader=fragment)
        for name, value in uniforms.items():
            program[name] = value
        targets = [context.texture((size, size), 4, dtype="f4") for _ in range(outputs)]
        framebuffer = context.framebuffer(color_attachments=targets)
        framebuffer.use()
        quad = context.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], dtype="f4").tobytes())
        context.vertex_array(program, [(quad, "2f", "position")]).render(moderngl.TRIANGLE_STRIP)
        return [
            np.frombuffer(framebuffer.read(attachment=k, components=4, dtype="f4"), "f4").reshape(size * size, 4)
            for k in range(outputs)
        ]
    finally:
        context.release()


def per_pixel_inputs():
    """(1024, 4) texels (η, κ, a, b) of the per-pixel shader tests: the documented ranges, their edges (η → 1,
    η < 1, κ → 10⁴, r → 1, g at 0 and 1) and bad values (NaN, ±inf, negative, beyond the range)."""
    import numpy as np

    rng = np.random.default_rng(23)
    eta_special = [1.0, 1.0 + 1e-6, 1.0 - 1e-6, 0.5, 0.67, 1e-4, 1e4, 1e6, 0.0, -1.0, np.nan, np.inf, -np.inf]
    kappa_special = [0.0, 1e-6, 1e4, 1e6, -1.0, np.nan, np.inf]
    unit_special = [0.0, 1.0, 0.9999, 0.99999, 1e-7, -0.5, 1.5, np.nan, np.inf, -np.inf]
    count = 1024
    eta = np.exp(rng.uniform(np.log(1e-2), np.log(50.0), count))
    kappa = np.where(rng.random(count) < 0.3, 0.0, np.exp(rng.uniform(np.log(1e-3), np.log(20.0), count)))
    a, b = rng.uniform(0.0, 1.0, count), rng.uniform(0.0, 1.0, count)
    eta[: len(eta_special) * len(kappa_special)] = np.repeat(eta_special, len(kappa_special))
    kappa[: len(eta_special) * len(kappa_special)] = np.tile(kappa_special, len(eta_special))
    a[200 : 200 + len(unit_special) ** 2] = np.repeat(unit_special, len(unit_special))
    b[200 : 200 + len(unit_special) ** 2] = np.tile(unit_special, len(unit_special))
    return np.stack([eta, kappa, a, b], axis=-1)


#: The per-pixel shader tests' outputs, in order: the call each makes of the generated include on texel q.
PER_PIXEL_CALLS = (
    "fresnelCoefficientsNK(q.x, q.y)",
    "fresnelCoefficientsGulbrandsen(q.z, q.w)",
    "fresnelCoefficientsSchlick(q.z, q.w)",
    "fresnelCoefficientsF82(q.z, q.w)",
    "fresnelCoefficientsF82Tint(q.z, q.w)",
    "fresnelCoefficientsGeneralizedAdobe(q.z, 1.0, q.w)",
    "fresnelBasisCurves(q.z)",
    "fresnelBasisLutUV(q.z, q.w).xyxy",
)


def glsl_main(calls) -> str:
    """The GLSL main of the per-pixel tests (after an include): each fragment reads its texel q and writes every
    call of ``calls`` to its own RGBA32F attachment."""
    return (
        "\nuniform sampler2D inputs;\n"
        + "".join(f"layout(location = {k}) out vec4 out{k};\n" for k in range(len(calls)))
        + "void main() {\n    vec4 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);\n"
        + "".join(f"    out{k} = {call};\n" for k, call in enumerate(calls))
        + "}\n"
    )


#: The GLSL main of :data:`PER_PIXEL_CALLS`.
PER_PIXEL_GLSL_MAIN = glsl_main(PER_PIXEL_CALLS)


def per_pixel_expected(inputs, constants=None):
    """The Python mirrors (handoff.shaders) of every call of :data:`PER_PIXEL_CALLS` for the texels as float32
    holds them, (1024, L) each: the K terms zero-padded to the L = 4 (K ≤ 4) or 8 lanes the shaders return, the
    table coordinates (u, v, u, v)."""
    import numpy as np

    from handoff.shaders import (
        coefficients_per_pixel_gulbrandsen,
        coefficients_per_pixel_model,
        coefficients_per_pixel_nk,
        direct_fresnel,
        lut_coordinates,
        shader_constants,
    )

    constants = shader_constants() if constants is None else constants
    k = constants.n_terms
    eta, kappa, a, b = np.asarray(inputs, dtype=np.float32).astype(np.float64).T

    def lanes(values):
        padded = np.zeros((values.shape[0], 8 if k > 4 else 4))
        padded[:, :k] = values
        return padded

    return [
        lanes(coefficients_per_pixel_nk(eta, kappa, constants)),
        lanes(coefficients_per_pixel_gulbrandsen(a, b, constants)),
        lanes(coefficients_per_pixel_model("schlick", constants, f0=a, f90=b)),
        lanes(coefficients_per_pixel_model("f82", constants, f0=a, f82=b)),
        lanes(coefficients_per_pixel_model("f82-tint", constants, f0=a, tint=b)),
        lanes(coefficients_per_pixel_model("generalized-adobe", constants, r0=a, r90=np.ones_like(a), tint=b)),
        lanes(direct_fresnel(np.eye(k)[:, None, :], a[None, :], constants).T),
        np.tile(lut_coordinates(a, b, constants), 2),
    ]


def assert_per_pixel_outputs(outputs, inputs, where: str, constants=None) -> dict:
    """Each output finite and within what float32 allows of its mirror: the coefficients within the constants'
    ``float32_tolerance`` (1e-5 for the shipped basis) and the Fresnel curve they give within
    ``float32_curve_tolerance`` (max over μ of |Σ_k (c_GPU − c_mirror)_k b_k(μ)|), the direct-light curves within
    1e-4, the coordinates within 1e-6; the errors."""
    import numpy as np

    from handoff.shaders import direct_fresnel, shader_constants

    constants = shader_constants() if constants is None else constants
    k, mu = constants.n_terms, np.linspace(0.0, 1.0, 257)
    errors, bounds = {}, {}
    for call, got, want in zip(PER_PIXEL_CALLS, outputs, per_pixel_expected(inputs, constants)):
        got = np.asarray(got, dtype=np.float64)[:, : want.shape[1]]
        assert np.all(np.isfinite(got)), f"{call}: NaN or inf on {where}"
        errors[call] = float(np.max(np.abs(got - want)))
        bounds[call] = 1e-4 if "Curves" in call else (1e-6 if "LutUV" in call else constants.float32_tolerance)
        if "Coefficients" in call:
            difference = direct_fresnel((got - want)[:, None, :k], mu[None, :], constants)
            errors[f"F of {call}"] = float(np.max(np.abs(difference)))
            bounds[f"F of {call}"] = constants.float32_curve_tolerance
    for call, error in errors.items():
        assert error <= bounds[call], (where, call, error, errors)
    return errors


#: The linear models' per-pixel calls on texel q (weights of fresnelLinear<Model>, then a punctual light's F from three
#: of them at V.H = q.w): they need no table, so they run on llvmpipe, lavapipe and WebGL 2 alike.
LINEAR_CALLS = (
    "vec4(fresnelLinearSchlick(q.z, q.w), 0.0)",
    "vec4(fresnelLinearF82(q.z, q.w), 0.0)",
    "vec4(fresnelLinearF82Tint(q.z, q.w), 0.0)",
    "vec4(fresnelLinearGeneralizedAdobe(q.z, q.w, 0.5), 0.0)",
    "vec4(fresnelLinearDirect(q.w, fresnelLinearF82Tint(q.z, q.w), fresnelLinearF82(q.z, q.w), "
    "fresnelLinearGeneralizedAdobe(q.z, 1.0, q.w)), 0.0)",
)


def assert_linear_outputs(outputs, inputs, where: str) -> dict:
    """Each of :data:`LINEAR_CALLS` finite and within float32 of its mirror (handoff.shaders ``linear_weights``,
    ``linear_direct``) for the texels as float32 holds them: weights within 2e-6 of max(1, |w|) (the dip weight is a
    difference of terms near 1 times 1/FRESNEL_F82_DIP = 17.6: float32's 6e-8 on each, 9.4e-7 measured on llvmpipe),
    F within 5e-6 (three products of weights up to 17.6 with the functions); the errors."""
    import numpy as np

    from handoff.shaders import linear_direct, linear_weights

    _, _, a, b = np.asarray(inputs, dtype=np.float32).astype(np.float64).T
    weights = [
        linear_weights("schlick", f0=a, f90=b),
        linear_weights("f82", f0=a, f82=b),
        linear_weights("f82-tint", f0=a, tint=b),
        linear_weights("generalized-adobe", r0=a, r90=b, tint=0.5),
    ]
    light = np.stack([weights[2], weights[1], linear_weights("generalized-adobe", r0=a, r90=1.0, tint=b)], axis=-2)
    expected = [*weights, linear_direct(light, b)]
    errors = {}
    for call, got, want in zip(LINEAR_CALLS, outputs, expected):
        got = np.asarray(got, dtype=np.float64)[:, :3]
        assert np.all(np.isfinite(got)), f"{call}: NaN or inf on {where}"
        scale = np.maximum(1.0, np.abs(want)) if "Direct" not in call else 1.0
        errors[call] = float(np.max(np.abs(got - want) / scale))
        assert errors[call] <= (5e-6 if "Direct" in call else 2e-6), (where, call, errors)
    return errors


def wgpu_device(monkeypatch, features=()):
    """A WebGPU device on Mesa's lavapipe (wgpu), with ``features``; skipped (failed under CI) where there is none."""
    import os

    try:
        import wgpu
    except ImportError:
        gpu_missing("wgpu (the 'gpu' extra)")
    monkeypatch.setenv("XDG_RUNTIME_DIR", os.environ.get("XDG_RUNTIME_DIR") or "/tmp")
    adapter = wgpu.gpu.request_adapter_sync(power_preference="high-performance")
    if adapter is None or any(feature not in adapter.features for feature in features):
        gpu_missing(
            f"a WebGPU adapter{' with ' + ', '.join(features) if features else ''} (Mesa's lavapipe: Debian "
            "mesa-vulkan-drivers)"
        )
    return adapter.request_device_sync(required_features=list(features))


def wgpu_compute(device, code: str, resources: list, output_buffer, count: int, constants: dict | None = None) -> bytes:
    """Run the compute shader ``code`` (entry ``main``, workgroups of 64) over ``count`` invocations with
    ``resources`` bound to bindings 0, 1, … of group 0 and ``constants`` for its ``override`` declarations; the bytes
    of ``output_buffer`` afterwards."""
    module = device.create_shader_module(code=code)
    stage = {"module": module, "entry_point": "main"}
    if constants:
        stage["constants"] = constants
    pipeline = device.create_compute_pipeline(layout="auto", compute=stage)
    group = device.create_bind_group(
        layout=pipeline.get_bind_group_layout(0),
        entries=[{"binding": k, "resource": resource} for k, resource in enumerate(resources)],
    )
    encoder = device.create_command_encoder()
    compute = encoder.begin_compute_pass()
    compute.set_pipeline(pipeline)
    compute.set_bind_group(0, group)
    compute.dispatch_workgroups((count + 63) // 64)
    compute.end()
    device.queue.submit([encoder.finish()])
    return device.queue.read_buffer(output_buffer)


def wgpu_texture_views(device, tables) -> list:
    """Views of ``tables`` ((H, W, C ≤ 4) arrays) uploaded to ``device`` as rgba32float textures (channels beyond C
    zero), as the include's tables are bound: bilinear filtering needs the float32-filterable feature."""
    import numpy as np
    import wgpu

    views = []
    for table in tables:
        rgba = np.zeros(table.shape[:2] + (4,), np.float32)
        rgba[..., : table.shape[2]] = table
        texture = device.create_texture(
            size=(table.shape[1], table.shape[0], 1),
            format=wgpu.TextureFormat.rgba32float,
            usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
        )
        device.queue.write_texture(
            {"texture": texture},
            rgba.tobytes(),
            {"bytes_per_row": table.shape[1] * 16, "rows_per_image": table.shape[0]},
            (table.shape[1], table.shape[0], 1),
        )
        views.append(texture.create_view())
    return views


def linear_model_materials(rng, count: int, oversample: int = 4) -> list:
    """(model, parameters (count,) each) of random materials of the four models the Schlick table holds exactly
    (Schlick F0/F90, F82, Adobe F82 tint, generalised Adobe with p = 5) whose curves stay in [0, 1] (the models' clamp
    inactive, where the linear form is the model); ``oversample`` × ``count`` draws per model to choose from."""
    import numpy as np

    from basis.models import fresnel_model

    unit = lambda: rng.uniform(0.0, 1.0, oversample * count)  # noqa: E731
    drawn = {
        "generalized-schlick": {"r0": unit(), "r90": unit(), "exponent": 5.0},
        "f82": {"f0": unit(), "f82": unit()},
        "adobe": {"f0": unit(), "tint": unit()},
        "generalized-adobe": {"r0": unit(), "r90": unit(), "tint": unit(), "exponent": 5.0},
    }
    chosen = []
    for model, parameters in drawn.items():
        inside = np.flatnonzero(fresnel_model(model).clamp_is_inactive(**parameters))[:count]
        assert inside.size == count, model
        chosen.append((model, {k: (v[inside] if np.ndim(v) else v) for k, v in parameters.items()}))
    return chosen
