"""Babylon.js's OpenPBR environment BRDF table, read as Babylon.js reads it (issue 39: the report compares the F82-tint
family's split sum through it with this project's exact table).

Babylon.js ships, in ``Misc/brdfTextureTools.js`` of the npm package ``@babylonjs/core``, a 128 × 128 8-bit RGBD PNG
(base64) that its OpenPBR material expands on the GPU to half floats (``RGBDTextureTools.ExpandRGBDTexture``: the
``rgbdDecode`` pass, ``fromRGBD`` = ``toLinearSpace(rgb) / a``, ``toLinearSpace`` = ``pow(c, 2.2)`` unless the
engine sets ``useExactSrgbConversions``) and samples bilinearly with clamp at UV = (NdotV, perceptualRoughness)
(``getBRDFLookup``), α = perceptualRoughness². Its channels are x = ∫ (1 − μ)⁵ (the F90 − F0 weight), y = E and
z = 16 ∫ μ (1 − μ)⁶ (``BRDF_Z_SCALE``), so that ``getF82DirectionalAlbedo`` = (F90 − F0) x + F0 y − b z / 16, with
``getF82B``'s b = (F0 + (1 − F0)(6/7)⁵)(1 − tint) / ((1/7)(6/7)⁶) (Hoffman 2023 eq. 3, Adobe's F82 tint).

The package is fetched by name and pinned (``npm pack``, into the ignored ``build/npm/``); every piece of its shader
code the decoding relies on is checked verbatim, so a release that changes them fails here instead of being misread.
The project never imports this module: it is the benchmark's.
"""

from __future__ import annotations

import base64
import io
import re
import tarfile
from pathlib import Path

import numpy as np

from .npm import NpmError, npm_tarball

PACKAGE = "@babylonjs/core"
VERSION = "9.35.0"

#: Shader text the decoding below transcribes, per file of the package: if Babylon.js changes one, this fails.
ANCHORS = {
    "Shaders/ShadersInclude/pbrBRDFFunctions.js": (
        "vec2 UV=vec2(NdotV,perceptualRoughness);vec4 brdfLookup=texture2D(environmentBrdfSampler,UV);",
        "brdfLookup.rgb=fromRGBD(brdfLookup.rgba);",
        "vec3 getF82B(vec3 F0,vec3 edgeTint) {return (F0+(vec3(1.0)-F0)*F82_ONE_MINUS_CTM_POW5)*(vec3(1.0)-edgeTint)"
        "*F82_B_DENOMINATOR_RECIP;}",
        "vec3 getF82DirectionalAlbedo(vec3 F0,vec3 F90,vec3 b,vec3 environmentBrdf) {return (F90-F0)*environmentBrdf.x"
        "+F0*environmentBrdf.y-b*environmentBrdf.z;}",
    ),
    "Shaders/ShadersInclude/openpbrIblFunctions.js": (
        "vec3 openPBRBrdf=vec3(environmentBrdf.xy,environmentBrdf.z/BRDF_Z_SCALE);vec3 b =getF82B(reflectance.coloredF0,"
        "reflectance.coloredF90);vec3 E_F82=getF82DirectionalAlbedo(reflectance.coloredF0,vec3(1.0),b,openPBRBrdf);",
    ),
    "Shaders/ShadersInclude/helperFunctions.js": (
        "vec3 fromRGBD(vec4 rgbd) {rgbd.rgb=toLinearSpace(rgbd.rgb);return rgbd.rgb/rgbd.a;}",
        "vec3 toLinearSpace(vec3 color)\n{\n#if USE_EXACT_SRGB_CONVERSIONS\nreturn toLinearSpaceExact(color);\n#else\n"
        "return pow(color,vec3(LinearEncodePowerApprox));",
    ),
    "Misc/rgbdTextureTools.js": ("internalTexture.type = 2;",),  # expanded to half floats
    "Misc/brdfTextureTools.js": (
        "Texture.CreateFromBase64String(textureData, textureName + InstanceNumber++, scene, "
        "true, false, Texture.BILINEAR_SAMPLINGMODE)",
    ),  # invertY false: row 0 is v = 0
}


class BabylonError(RuntimeError):
    """The package could not be fetched, or its shaders no longer decode the table as :data:`ANCHORS` say."""


def package_tarball() -> Path:
    """The pinned package's tarball (:func:`benchmarks.npm.npm_tarball`)."""
    try:
        return npm_tarball(PACKAGE, VERSION)
    except NpmError as error:
        raise BabylonError(str(error)) from None


def _members(tarball: Path) -> dict[str, str]:
    with tarfile.open(tarball) as archive:
        return {name: archive.extractfile(f"package/{name}").read().decode("utf-8") for name in ANCHORS}


def _define(text: str, name: str) -> float:
    """A constant of the shaders: ``#define NAME value`` or ``const float NAME=value;``."""
    found = re.search(rf"(?:#define {name} |const float {name}=)([0-9.]+)", text)
    if found is None:
        raise BabylonError(f"{name} is no longer defined in Babylon.js {VERSION}'s shaders")
    return float(found.group(1))


def openpbr_table() -> dict:
    """The OpenPBR table as its shader reads it: ``texels`` (128, 128, 3) float64 of the half floats the RGBD pass
    writes (x, y, z / BRDF_Z_SCALE; row j ↔ perceptual roughness, column i ↔ NdotV, texel centres at (i + ½)/128),
    and the F82 constants ``one_minus_ctm_pow5`` and ``b_denominator_recip`` of its shaders."""
    import png  # pypng: the test extra's independent PNG reader

    files = _members(package_tarball())
    for name, anchors in ANCHORS.items():
        for anchor in anchors:
            if anchor not in files[name]:
                raise BabylonError(f"Babylon.js {VERSION}: {name} no longer contains {anchor[:60]!r}…")
    functions = files["Shaders/ShadersInclude/pbrBRDFFunctions.js"]
    found = re.search(
        r'_openPBREnvironmentBRDFBase64Texture = "data:image/png;base64,([^"]+)"', files["Misc/brdfTextureTools.js"]
    )
    if found is None:
        raise BabylonError(f"Babylon.js {VERSION} ships no OpenPBR BRDF table")
    width, height, rows, info = png.Reader(file=io.BytesIO(base64.b64decode(found.group(1)))).read()
    if info["bitdepth"] != 8 or info["planes"] != 4:
        raise BabylonError(f"the OpenPBR table is no longer 8-bit RGBD: {info}")
    rgbd = np.array([np.asarray(row, dtype=np.float64) for row in rows]).reshape(height, width, 4) / 255.0
    power = _define(files["Shaders/ShadersInclude/helperFunctions.js"], "LinearEncodePowerApprox")
    with np.errstate(divide="ignore", invalid="ignore"):
        decoded = np.where(rgbd[..., 3:] > 0, rgbd[..., :3] ** power / rgbd[..., 3:], 0.0)
    decoded = decoded.astype(np.float16).astype(np.float64)  # the half-float render target
    decoded[..., 2] /= _define(functions, "BRDF_Z_SCALE")
    return {
        "texels": decoded,
        "one_minus_ctm_pow5": _define(functions, "F82_ONE_MINUS_CTM_POW5"),
        "b_denominator_recip": _define(functions, "F82_B_DENOMINATOR_RECIP"),
    }


def bilinear(texels: np.ndarray, u, v) -> np.ndarray:
    """(…, C) of an (H, W, C) texture sampled at (u, v) ∈ [0, 1]² as a GPU does with bilinear filtering and clamp to
    edge: texel centres at (i + ½)/W, (j + ½)/H (exact weights; GPUs round them to 8 bits)."""
    height, width = texels.shape[:2]
    x = np.clip(np.asarray(u, dtype=np.float64) * width - 0.5, 0.0, width - 1.0)
    y = np.clip(np.asarray(v, dtype=np.float64) * height - 0.5, 0.0, height - 1.0)
    i, j = np.minimum(np.floor(x).astype(int), width - 2), np.minimum(np.floor(y).astype(int), height - 2)
    fx, fy = (x - i)[..., None], (y - j)[..., None]
    return (1 - fy) * ((1 - fx) * texels[j, i] + fx * texels[j, i + 1]) + fy * (
        (1 - fx) * texels[j + 1, i] + fx * texels[j + 1, i + 1]
    )


def f82_tint_albedo(table: dict, f0, tint, n_dot_v, perceptual_roughness) -> np.ndarray:
    """(P, M) ``E_F82`` of Babylon.js's ``computeConductorIblFresnel`` before its energy compensation (F90 = 1) for
    materials (f0, tint) (M,) at points (n_dot_v, perceptual_roughness) (P,)."""
    x, y, z = np.moveaxis(bilinear(table["texels"], n_dot_v, perceptual_roughness), -1, 0)
    f0, tint = np.asarray(f0, dtype=np.float64), np.asarray(tint, dtype=np.float64)
    b = (f0 + (1.0 - f0) * table["one_minus_ctm_pow5"]) * (1.0 - tint) * table["b_denominator_recip"]
    return (1.0 - f0) * x[:, None] + f0 * y[:, None] - b * z[:, None]
