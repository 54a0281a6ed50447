"""MaterialX from PyPI (``materialx``), generated to GLSL and run on Mesa's llvmpipe (headless EGL, moderngl): the
tests' and ``benchmarks.materialx_library``'s harness.

Public objects: ``MaterialXMissing``, ``standard_library``, ``document``, ``conductor``, ``standard_surface``,
``open_pbr_surface``, ``generate``, ``furnace``, ``furnace_cosines``, ``COMPARED``, ``f82_tint_curve``,
``exact_environment_light``.

A furnace: MaterialX's own pixel shader with a vertex shader of ours that feeds its ``VertexData`` block (world
position 0, view position on +z: V = (0, 0, 1)), a one-row framebuffer whose normals sweep from grazing to the view
direction (:func:`furnace_cosines` gives each pixel's N·V as float32 interpolation and normalisation leave it), a
white environment (a 1 × 1 radiance and irradiance map of 1) and no lights: a pixel shows what MaterialX's
image-based light makes of the material's directional albedo.
"""

from __future__ import annotations

import functools
import re

import numpy as np

from basis.models.formulas import adobe_dip_weight

__all__ = [
    "COMPARED",
    "MaterialXMissing",
    "conductor",
    "document",
    "exact_environment_light",
    "f82_tint_curve",
    "furnace",
    "furnace_cosines",
    "generate",
    "open_pbr_surface",
    "standard_library",
    "standard_surface",
]

#: Pixels of the furnace's row.
WIDTH = 64
#: The normal at the row's left end, (1, 0, ε): N·V from about 1e-3 at the left to 1 at the right.
LEFT_NORMAL = (1.0, 0.0, 1e-3)

#: What the vertex shader writes into each member of the pixel shader's ``VertexData`` it knows (others: zero).
_MEMBERS = {
    "normalWorld": "mix(vec3(%r, %r, %r), vec3(0.0, 0.0, 1.0), 0.5 * (position.x + 1.0))" % LEFT_NORMAL,
    "tangentWorld": "vec3(0.0, 1.0, 0.0)",
    "bitangentWorld": "vec3(-1.0, 0.0, 0.0)",
    "positionWorld": "vec3(0.0)",
}


def _vertex(pixel: str) -> str:
    """The furnace's vertex shader for ``pixel``: its ``VertexData`` block member for member."""
    found = re.search(r"\bin VertexData\s*\{([^}]*)\}\s*vd;", pixel)
    members = re.findall(r"(\w+)\s+(\w+);", found.group(1)) if found else []
    block = "".join(f" {kind} {name};" for kind, name in members)
    writes = "".join(f"    vd.{name} = {_MEMBERS.get(name, f'{kind}(0.0)')};\n" for kind, name in members)
    interface = f"out VertexData {{{block} }} vd;\n" if members else ""
    return f"#version 400\nin vec2 position;\n{interface}void main()\n{{\n{writes}    gl_Position = vec4(position, 0.0, 1.0);\n}}\n"


class MaterialXMissing(RuntimeError):
    """PyPI's materialx, moderngl or Mesa's EGL is not installed."""


def _materialx():
    try:
        import MaterialX
        from MaterialX import PyMaterialXGenGlsl, PyMaterialXGenShader
    except ImportError as error:
        raise MaterialXMissing(f"MaterialX (PyPI materialx, the 'materialx' extra) is missing: {error}") from None
    return MaterialX, PyMaterialXGenShader, PyMaterialXGenGlsl


@functools.cache
def standard_library(extra_folder: str | None = None):
    """MaterialX's libraries (and the node library in ``extra_folder``), loaded once."""
    mx, _, _ = _materialx()
    library = mx.createDocument()
    search = mx.getDefaultDataSearchPath()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search, library)
    if extra_folder is not None:
        for name in ("fresnel_basis_defs.mtlx", "fresnel_basis_genglsl_impl.mtlx"):
            mx.readFromXmlFile(library, f"{extra_folder}/{name}")
    return library


def document(extra_folder: str | None = None):
    """A new MaterialX document with the standard library (and ``extra_folder``'s nodes) imported."""
    mx, _, _ = _materialx()
    doc = mx.createDocument()
    doc.importLibrary(standard_library(extra_folder))
    return doc


def conductor(eta, kappa, alpha: float):
    """(document, surface shader node): ``conductor_bsdf`` (η, κ, GGX α) under a ``surface``."""
    mx, _, _ = _materialx()
    doc = document()
    bsdf = doc.addNode("conductor_bsdf", "metal", "BSDF")
    bsdf.setInputValue("ior", mx.Color3(*map(float, eta)))
    bsdf.setInputValue("extinction", mx.Color3(*map(float, kappa)))
    bsdf.setInputValue("roughness", mx.Vector2(alpha, alpha))
    surface = doc.addNode("surface", "surface", "surfaceshader")
    surface.setConnectedNode("bsdf", bsdf)
    doc.addMaterialNode("fresnel_material", surface)
    return doc, surface


def _metal_surface(category: str, metalness: str, colour, specular_colour, roughness: float):
    """(document, node): a metal of the surface shader ``category`` (``metalness`` its metalness input's name)."""
    mx, _, _ = _materialx()
    doc = document()
    node = doc.addNode(category, "surface", "surfaceshader")
    node.setInputValue(metalness, 1.0)
    node.setInputValue("base_color", mx.Color3(*map(float, colour)))
    node.setInputValue("specular_color", mx.Color3(*map(float, specular_colour)))
    node.setInputValue("specular_roughness", float(roughness))
    doc.addMaterialNode("fresnel_material", node)
    return doc, node


def standard_surface(reflectivity, edge, roughness: float):
    """(document, node): Autodesk Standard Surface, metalness 1: base_color = Gulbrandsen's r, specular_color = his
    edge colour g (MaterialX's ``artistic_ior``), specular_roughness r (α = r²)."""
    return _metal_surface("standard_surface", "metalness", reflectivity, edge, roughness)


def open_pbr_surface(f0, tint, roughness: float):
    """(document, node): OpenPBR, base_metalness 1: base_color = F0, specular_color = the F82 tint, specular_roughness
    r (α = r²)."""
    return _metal_surface("open_pbr_surface", "base_metalness", f0, tint, roughness)


def generate(doc, node, environment: str = "prefilter", extra_folder: str | None = None) -> str:
    """The pixel shader MaterialX's GLSL generator writes for ``node`` of ``doc``, its environment light
    ``prefilter`` (the default: a prefiltered map × mx_ggx_dir_albedo) or ``fis`` (filtered importance sampling, the
    exact Fresnel per sample)."""
    mx, gen_shader, gen_glsl = _materialx()
    generator = gen_glsl.GlslShaderGenerator.create()
    context = gen_shader.GenContext(generator)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    if extra_folder is not None:
        context.registerSourceCodeSearchPath(mx.FileSearchPath(extra_folder))
    methods = gen_shader.HwSpecularEnvironmentMethod
    context.getOptions().hwSpecularEnvironmentMethod = {
        "prefilter": methods.SPECULAR_ENVIRONMENT_PREFILTER,
        "fis": methods.SPECULAR_ENVIRONMENT_FIS,
    }[environment]
    valid, message = doc.validate()
    if not valid:
        raise ValueError(f"the MaterialX document is not valid: {message}")
    return generator.generate(node.getName(), node, context).getSourceCode(gen_shader.PIXEL_STAGE)


def furnace_cosines(width: int = WIDTH) -> np.ndarray:
    """N·V at each pixel centre of the furnace's row (the vertex shader's linear interpolation, normalised)."""
    t = (np.arange(width) + 0.5) / width
    normal = (1.0 - t)[:, None] * np.array(LEFT_NORMAL) + t[:, None] * np.array([0.0, 0.0, 1.0])
    return normal[:, 2] / np.linalg.norm(normal, axis=1)


def furnace(pixel: str, uniforms: dict | None = None, textures: dict | None = None, width: int = WIDTH) -> np.ndarray:
    """(width, 3): ``pixel`` (a MaterialX pixel shader) in the white furnace on llvmpipe; ``uniforms`` name → value
    (``u_envRadianceSamples`` for FIS), ``textures`` uniform name → float array (H, W, 4), bilinear, clamped."""
    try:
        import moderngl
    except ImportError:
        raise MaterialXMissing("moderngl (the 'gpu' extra) is missing") from None
    try:
        context = moderngl.create_standalone_context(backend="egl")
    except Exception as error:  # noqa: BLE001 - no EGL/Mesa: a missing system library
        raise MaterialXMissing(f"a headless OpenGL context (Mesa's EGL) is missing: {error}") from None
    try:
        program = context.program(vertex_shader=_vertex(pixel), fragment_shader=pixel)
        white = context.texture((1, 1), 4, np.ones(4, dtype="f4").tobytes(), dtype="f4")
        white.use(0)
        bound = {"u_envRadiance": 0, "u_envIrradiance": 0}
        for unit, (name, values) in enumerate((textures or {}).items(), start=1):
            values = np.ascontiguousarray(values, dtype="f4")
            texture = context.texture(values.shape[1::-1], values.shape[2], values.tobytes(), dtype="f4")
            texture.filter = (moderngl.LINEAR, moderngl.LINEAR)
            texture.repeat_x = texture.repeat_y = False
            texture.use(unit)
            bound[name] = unit
        settings = {"u_viewPosition": (0.0, 0.0, 100.0), "u_envRadianceMips": 1, "u_numActiveLightSources": 0}
        for name, value in {**bound, **settings, **(uniforms or {})}.items():
            if name in program:
                program[name] = value
        target = context.texture((width, 1), 4, dtype="f4")
        framebuffer = context.framebuffer(color_attachments=[target])
        framebuffer.use()
        quad = context.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], dtype="f4").tobytes())
        context.vertex_array(program, [(quad, "2f", "position")]).render(moderngl.TRIANGLE_STRIP)
        return np.frombuffer(framebuffer.read(components=4, dtype="f4"), "f4").reshape(width, 4)[:, :3].astype(float)
    finally:
        context.release()


#: The furnace pixels the exact model is evaluated at (N·V 0.05 … 0.99; every sixth).
COMPARED = slice(2, None, 6)


def f82_tint_curve(f0, tint):
    """μ (N,) → (N, 3): OpenPBR's metal Fresnel, Hoffman 2023 eq. 3 (F82 tint, exponent 5, F90 = 1), unclamped as
    MaterialX's ``mx_fresnel_hoffman_schlick`` evaluates it."""
    f0, tint = np.asarray(f0, dtype=float), np.asarray(tint, dtype=float)

    def curve(mu):
        mu = np.asarray(mu, dtype=float)[:, None]
        return f0 + (1 - f0) * (1 - mu) ** 5 - adobe_dip_weight(f0, tint) * mu * (1 - mu) ** 6

    return curve


def exact_environment_light(curve, alpha: float) -> np.ndarray:
    """(len(furnace_cosines()[COMPARED]), C): MaterialX's environment light made exact at the compared pixels, F̄ of
    ``curve`` × (1 + F(N·V) (1 − E) / E) (Turquin 2019 eq. 16), F̄ and E by the independent quadrature of
    tests/references."""
    from tests.references.integration import reference_albedo_grid

    mu = furnace_cosines()[COMPARED]
    single = reference_albedo_grid(curve, mu, np.full_like(mu, alpha))
    albedo = reference_albedo_grid(lambda x: np.ones((x.size, 1)), mu, np.full_like(mu, alpha))
    return single * (1.0 + curve(mu) * (1.0 - albedo) / albedo)
