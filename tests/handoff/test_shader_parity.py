"""Issue 37 item 3: the GLSL, HLSL and WGSL includes offer the same functions with the same signatures, for bases of
four terms (one vec4 per channel) and of more (a FresnelTerms8 and two tables), with these reasoned exceptions:

* WGSL has no out parameters: ``fresnelCoefficientsNK3``, ``fresnelCoefficientsGulbrandsen3`` and
  ``fresnelCoefficientsGulbrandsenTable3`` (which fill three
  channels' coefficients through them) are GLSL and HLSL only; WGSL calls ``fresnelCoefficientsNK`` (or
  ``…Gulbrandsen``) per channel;
* HLSL and WGSL sample a texture through a separate sampler: a function that reads textures takes one,
  ``linearClamp``, after its last texture (GLSL's ``sampler2D`` carries its own).

And no function body is written twice: the include is printed from one GLSL source (handoff/shaders/source and the
generated statements), so its GLSL is that source.
"""

from __future__ import annotations

import re

import pytest

from basis.training import build_basis
from handoff.shaders import LANGUAGES, shader_includes, shader_source, translate
from handoff.shaders.constants import shader_constants

#: The functions each language lacks, with the reason (module docstring).
EXCEPTIONS = {
    "wgsl": {
        "fresnelCoefficientsNK3": "no out parameters",
        "fresnelCoefficientsGulbrandsen3": "no out parameters",
        "fresnelCoefficientsGulbrandsenTable3": "no out parameters",
    }
}
#: Each language's types in one vocabulary.
_TYPES = {
    "float": "float", "f32": "float", "int": "int", "i32": "int", "uint": "uint", "u32": "uint", "bool": "bool",
    "vec2": "vec2", "float2": "vec2", "vec2f": "vec2", "vec3": "vec3", "float3": "vec3", "vec3f": "vec3",
    "vec4": "vec4", "float4": "vec4", "vec4f": "vec4", "sampler2D": "texture", "Texture2D<float4>": "texture",
    "texture_2d<f32>": "texture", "FresnelTerms8": "FresnelTerms8", "FresnelLtcLight": "FresnelLtcLight",
    "void": "void",
}  # fmt: skip


def _kind(text: str) -> str:
    array = re.fullmatch(r"array<(.+), (\d+)>", text.strip())
    if array:
        return f"{_TYPES[array.group(1)]}[{array.group(2)}]"
    return _TYPES[text.strip()]


def signatures(text: str, language: str) -> dict[str, tuple]:
    """name → (return kind, ((parameter name, kind, out?), …)) of every function of an include, samplers left out."""
    found = {}
    for line in text.splitlines():
        if language == "wgsl":
            match = re.match(r"^fn (\w+)\((.*)\)(?:\s*->\s*(.+?))?\s*$", line)
            if not match:
                continue
            name, parameters, returned = match.group(1), match.group(2), match.group(3) or "void"
            items = []
            for part in re.split(r",\s*(?![^<]*>)", parameters) if parameters else []:
                pname, ptype = (piece.strip() for piece in part.split(":", 1))
                if ptype != "sampler":
                    items.append((pname.removesuffix("In"), _kind(ptype), False))
        else:
            match = re.match(r"^([\w<>]+)\s+(\w+)\((.*)\)\s*$", line)
            if not match or match.group(1) in ("return", "struct"):
                continue
            returned, name, parameters = match.groups()
            items = []
            for part in (piece.strip() for piece in parameters.split(",") if piece.strip()):
                out = part.startswith("out ")
                ptype, pname = part.removeprefix("out ").rsplit(" ", 1)
                size = re.search(r"\[(\d+)\]$", pname)
                if ptype == "SamplerState":
                    continue
                kind = _kind(ptype) + (f"[{size.group(1)}]" if size else "")
                items.append((pname.split("[")[0], kind, out))
        found[name] = (_kind(returned), tuple(items))
    return found


@pytest.fixture(scope="module", params=[4, 6], ids=["4 terms", "6 terms"])
def includes(request):
    basis = None if request.param == 4 else build_basis(count=3000, n_terms=request.param, grid_size=96)
    return {name.rsplit(".", 1)[1]: text for name, text in shader_includes(basis)}


def test_every_language_offers_the_same_functions_and_signatures(includes):
    found = {language: signatures(includes[language], language) for language in LANGUAGES}
    reference = found["glsl"]
    assert len(reference) >= 30
    for language in ("hlsl", "wgsl"):
        missing = set(reference) - set(found[language])
        assert missing == set(EXCEPTIONS.get(language, {})), (language, missing)
        assert set(found[language]) <= set(reference), (language, set(found[language]) - set(reference))
        for name, signature in found[language].items():
            assert signature == reference[name], (language, name, signature, reference[name])


def test_the_glsl_is_the_one_source_and_the_others_are_printed_from_it(includes):
    """The GLSL include is the assembled source itself; HLSL and WGSL are its translations (no second body)."""
    constants = shader_constants()
    source = shader_source(constants)
    shipped = dict(shader_includes())
    body = source[source.index("\nconst uint FRESNEL_BASIS_HASH") :]
    assert shipped["fresnel_basis.glsl"].endswith(body)
    for language in ("hlsl", "wgsl"):
        assert shipped[f"fresnel_basis.{language}"].endswith(translate(body, language))


def test_the_textures_come_with_one_sampler_in_hlsl_and_wgsl(includes):
    for language, spelled in (("hlsl", "SamplerState linearClamp"), ("wgsl", "linearClamp: sampler")):
        for line in includes[language].splitlines():
            textures = line.count("Texture2D<float4>") + line.count("texture_2d<f32>")
            if textures and re.match(r"^(fn |[\w<>]+ \w+\()", line):
                assert line.count(spelled) == 1, line


@pytest.mark.parametrize("power", [12.0, 1.0, 2.5])
def test_a_rect_light_power_the_shaders_cannot_square_to_is_refused(monkeypatch, power):
    """The shaders raise the Fresnel blend's I^n and the horizon share's min(I/H, 1)^m by squaring
    (``fresnelLtcSquared``, ``FRESNEL_LTC_*_SQUARINGS`` = log2 of the power): a power that is not 2, 4, 8, … is refused
    when the include is generated, not rounded to another."""
    from basis.validation import ParameterError
    from handoff.shaders import include

    monkeypatch.setattr(include, "SPLIT_SUM_WEIGHT_POWER", power)
    with pytest.raises(ParameterError, match="power of two"):
        shader_includes()


def test_the_rect_light_squarings_are_the_shipped_powers(includes):
    """``FRESNEL_LTC_UPPER_SHARE_SQUARINGS`` and ``FRESNEL_LTC_SPLIT_SUM_WEIGHT_SQUARINGS`` are log2 of
    preintegrate.ltc's UPPER_SHARE_POWER and SPLIT_SUM_WEIGHT_POWER in every language."""
    from preintegrate.ltc import SPLIT_SUM_WEIGHT_POWER, UPPER_SHARE_POWER

    for name, text in includes.items():
        for constant, power in (
            ("FRESNEL_LTC_UPPER_SHARE_SQUARINGS", UPPER_SHARE_POWER),
            ("FRESNEL_LTC_SPLIT_SUM_WEIGHT_SQUARINGS", SPLIT_SUM_WEIGHT_POWER),
        ):
            found = re.findall(rf"{constant}\b[^=]*= (\d+);", text)
            assert found and all(2 ** int(times) == power for times in found), (name, constant, found)
