"""``fresnel-lut``: build the eigen-basis, the split-sum LUTs, and material coefficients.

Usage::

    fresnel-lut build  [--size N] [--out DIR] [--half] [--order N] [--visibility FORM] [--format exr,png16,header]
                       [--basis FILE | --model NAME ...]
    fresnel-lut basis  --out FILE [--count N] [--seed S] [--grid-size M] [--terms K] [--fit-angles auto|talk|notebook]
                       [--weighting normalised|span]
    fresnel-lut coeffs (--eta R G B --kappa R G B | --reflectivity R G B --edge-tint R G B | --material NAME [--space S]
                        | --model NAME --PARAMETER ... [--fit four-point|least-squares|minimax]) [--json] [--basis FILE]
    fresnel-lut materials --presets FILE [--from-database]
    fresnel-lut scene FILE --out DIR
    fresnel-lut render [--out DIR] [--quick]
    fresnel-lut report [--out DIR] [--quick | --materials | --fidelity [--quick]]

Errors print one line ``fresnel-lut: error: …`` and exit with status 2; Ctrl-C exits with 130 and
leaves every previously written file untouched. This module is the only one that knows about both
:mod:`basis` and :mod:`preintegrate` and about files.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from basis.coefficients import MODEL_FITS, coefficients_from_model
from basis.eigenbasis import TERMS_RANGE, Basis, default_basis, shipped_basis_path
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.materials import material_from_mapping
from basis.models import FRESNEL_MODELS, fresnel_model
from basis.presets import (
    PRESET_SPACES,
    material_preset,
    material_presets,
    shipped_presets_path,
    write_presets,
)
from basis.training import FIT_ANGLE_CHOICES, build_basis
from basis.training.builder import MAX_GRID
from basis.training.svd import WEIGHTINGS
from basis.validation import ParameterError, check_choice, check_positive_int
from handoff.formats import FORMATS, MAX_HEADER_VALUES, check_formats
from handoff.shipped import SCHLICK_LUT, model_lut_name
from handoff.tables import write_default_build, write_model_build
from preintegrate.ggx import VISIBILITIES
from preintegrate.ltc import ltc_grid
from preintegrate.lut import LutGrid
from preintegrate.quadrature import DEFAULT_ORDER, QuadratureOrder

from .interrupts import INTERRUPTED, caused_by_interrupt
from .progress import Progress, peak_rss_mib


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


def _output_folder(option: str, folder) -> Path:
    """Check an output folder before any work (nothing is created until the files are written).

    It must be named, and its nearest existing ancestor must be a writable folder.
    """
    if str(folder).strip() == "":
        raise ParameterError(f"{option} must name a folder, got an empty string")
    folder = Path(folder)
    existing = folder
    while not existing.exists() and existing != existing.parent:
        if existing.is_symlink():
            raise ParameterError(f"{option} {folder}: {existing} is a symbolic link to nothing (dangling)")
        existing = existing.parent
    if not existing.is_dir():
        raise ParameterError(f"{option} {folder}: {existing} exists and is not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ParameterError(f"{option} {folder}: {existing} is not writable")
    return folder


def _output_file(option: str, path) -> Path:
    """Check an output file before any work: named, not a folder or a device, in a writable folder."""
    if str(path).strip() == "":
        raise ParameterError(f"{option} must name a file, got an empty string")
    path = Path(path)
    if path.exists() and not path.is_file():
        raise ParameterError(f"{option} {path} exists and is not a regular file (a folder or a device); name a file")
    _output_folder(f"{option}'s folder", path.parent)
    return path


def _load_basis(path) -> Basis:
    return default_basis() if path is None else Basis.read(path)


def _size_text(path: Path) -> str:
    size = path.stat().st_size
    return f"{size / 1024:.1f} KiB" if size < 1024**2 else f"{size / 1024**2:.2f} MiB"


def _after(first: Progress, second: Progress | None):
    """A progress callback that closes ``first`` (the integration's line) before ``second`` starts reporting."""
    if second is None:
        return None

    def report(done: int, total: int) -> None:
        first.close()
        second(done, total)

    return report


def command_build(arguments) -> int:
    size = check_positive_int("--size", arguments.size, low=2, high=8192)
    formats = check_formats(arguments.format)  # refused before the work
    if "header" in formats and size * size * 4 > MAX_HEADER_VALUES:
        raise ParameterError(
            f"--format header holds at most {MAX_HEADER_VALUES:,} values per table (about "
            f"{int((MAX_HEADER_VALUES / 4) ** 0.5)} x {int((MAX_HEADER_VALUES / 4) ** 0.5)}); "
            f"--size {size} needs {size * size * 4:,}: use ktx2 or exr"
        )
    out = _output_folder("--out", arguments.out)
    order = (
        DEFAULT_ORDER
        if arguments.order is None
        else QuadratureOrder.uniform(check_positive_int("--order", arguments.order, low=2, high=512))
    )
    grid = LutGrid(size, size, visibility=arguments.visibility)
    shape = {name: getattr(arguments, name) for name in _SHAPE_OPTIONS if getattr(arguments, name, None) is not None}
    if arguments.model is None and shape:
        raise ParameterError(f"{', '.join(map(_option, shape))} go{'es' if len(shape) == 1 else ''} with --model NAME")
    if arguments.model in ("basis", "schlick"):
        raise ParameterError(
            f"--model {arguments.model}: the default build (no --model) writes the basis and Schlick tables"
        )
    if arguments.model is not None and arguments.basis is not None:
        raise ParameterError("--basis goes with the basis table, not with --model")
    if arguments.model is not None and arguments.ltc:
        raise ParameterError("--ltc goes with the default build, not with --model")
    if arguments.ltc_size is not None and not arguments.ltc:
        raise ParameterError("--ltc-size goes with --ltc")
    ltc = (
        ltc_grid(
            check_positive_int(
                "--ltc-size", 64 if arguments.ltc_size is None else arguments.ltc_size, low=2, high=1024
            ),
            arguments.visibility,
        )
        if arguments.ltc
        else None
    )
    if arguments.model is not None:
        model = fresnel_model(arguments.model)
        unused = sorted(set(shape) - set(model.shape))
        if unused:
            raise ParameterError(
                f"--model {model.name} takes {[_option(n) for n in model.shape] or 'no shape options'}, "
                f"not {[_option(n) for n in unused]}"
            )
    basis = None if arguments.model is not None else _load_basis(arguments.basis)
    started = time.perf_counter()
    progress = Progress(f"integrating {size}x{size} texels", "texels")
    if arguments.model is None:
        ltc_progress = Progress(f"fitting {ltc.width}x{ltc.height} LTC texels", "rows") if ltc is not None else None
        paths = write_default_build(
            out, basis, grid, order, formats, arguments.half, progress, ltc, _after(progress, ltc_progress)
        )
        if ltc_progress is not None:
            ltc_progress.close()
    else:
        paths, channels = write_model_build(out, arguments.model, shape, grid, order, formats, arguments.half, progress)
    progress.close()
    kind = "LUTs" if arguments.model is None else f"{arguments.model} LUT ({channels.n_channels} channels)"
    print(
        f"built {size}x{size} {kind} ({'half' if arguments.half else 'float32'}) in {time.perf_counter() - started:.2f} s"
        + (f", basis {basis.content_hash}:" if basis is not None else ":")
    )
    for path in paths:
        print(f"  {path}  {_size_text(path)}")
    if arguments.model is not None:
        print(f"  {channels.combination}")
    return 0


def _option(name: str) -> str:
    """The command-line option of a parameter name: ``eta_prime`` → ``--eta-prime``."""
    return "--" + name.replace("_", "-")


def command_basis(arguments) -> int:
    count = check_positive_int("--count", arguments.count, low=100, high=100_000_000)
    seed = check_positive_int("--seed", arguments.seed, low=0, high=2**63 - 1)
    _output_file("--out", arguments.out)
    started = time.perf_counter()
    progress = Progress("training curves", "curves")
    fit_angles = check_choice("--fit-angles", arguments.fit_angles, FIT_ANGLE_CHOICES)
    basis = build_basis(
        count=count,
        seed=seed,
        grid_size=check_positive_int("--grid-size", arguments.grid_size, low=16, high=MAX_GRID),
        n_terms=check_positive_int("--terms", arguments.terms, low=TERMS_RANGE[0], high=TERMS_RANGE[1]),
        fit_angles=fit_angles,
        progress=lambda done: progress(done, count),
        weighting=arguments.weighting,
    )
    progress.close()
    path = basis.write(arguments.out)
    elapsed = time.perf_counter() - started
    replaced_shipped = path.resolve() == shipped_basis_path().resolve()
    peak = peak_rss_mib()
    print(
        f"built basis {basis.content_hash} from {count} curves x {basis.theta.size} angles in {elapsed:.2f} s "
        f"(peak RSS {peak:.0f} MiB)"
    )
    print(f"fit angles: {', '.join(f'{angle:.4f}' for angle in basis.fit_angles)} rad")
    print("held-out max |dF| over theta of the four-point fit:")
    errors = basis.training["holdout_max_abs_error"]
    groups = [key for key in next(iter(errors.values())) if key != "angles"]
    print(f"  {'angles':28s}" + "".join(f"{group:>13s}" for group in groups))
    for name, row in errors.items():
        label = f"{name} ({', '.join(f'{angle:.4f}' for angle in row['angles'])})"
        print(f"  {label:28s}" + "".join(f"{row[group]:13.4f}" for group in groups))
    print(f"  {path}  {_size_text(path)}")
    if replaced_shipped:
        print(
            f"note: the shipped presets {shipped_presets_path()} belong to the previous basis until "
            "`make materials` refits them"
        )
    return 0


def command_coeffs(arguments) -> int:
    if arguments.list_materials:
        return _list_materials(arguments.space, arguments.json)
    basis = _load_basis(arguments.basis)
    if arguments.model is not None:
        return _coeffs_of_model(arguments, basis)
    material = material_from_mapping(_material_mapping(arguments), arguments.space or "ACEScg")
    coefficients = material.coefficients(basis)
    described = dict(material.description)
    if material.kind == "preset":
        preset = material_preset(material.description["preset"], material.space)
        described.update(
            space=material.space,
            f0=preset["f0"].tolist(),
            source=preset["source"],
            rms_delta_e2000=_preset_errors(preset, material, coefficients, basis),
        )
    elif material.kind == "gulbrandsen":
        eta, kappa = gulbrandsen_to_nk(np.array(described["reflectivity"]), np.array(described["edge_tint"]))
        described.update(eta=eta.tolist(), kappa=kappa.tolist())
    if arguments.json:
        print(
            json.dumps(
                {
                    "basis_hash": basis.content_hash,
                    "material": described,
                    "coefficients": coefficients.tolist(),
                    "layout": f"[channel R,G,B][term c0..c{basis.n_terms - 1}]",
                }
            )
        )
        return 0
    if material.kind == "preset":
        errors = described["rms_delta_e2000"]
        print(
            f"{described['preset']} ({described['space']}, linear): F0 = "
            + ", ".join(f"{v:.4f}" for v in described["f0"])
            + f"; RMS dE2000 basis {errors['basis']:.3f}, Schlick {errors['schlick']:.3f}"
        )
    _print_coefficients(basis, coefficients)
    return 0


def _material_mapping(arguments) -> dict:
    """The material the options name, as a mapping of :mod:`basis.materials`; mixtures and strays are refused."""
    given = {
        key: getattr(arguments, key)
        for key in ("eta", "kappa", "reflectivity", "edge_tint")
        if getattr(arguments, key) is not None
    }
    if arguments.material is not None:
        given["preset"] = arguments.material
    groups = [
        name
        for name, keys in (
            ("--eta and --kappa", ("eta", "kappa")),
            ("--reflectivity and --edge-tint", ("reflectivity", "edge_tint")),
            ("--material NAME", ("preset",)),
        )
        if set(keys) & set(given)
    ]
    if len(groups) != 1:
        raise ParameterError(
            "give one of: --eta and --kappa, --reflectivity and --edge-tint, --material NAME "
            "or --model NAME with its parameters"
        )
    for first, second in (("eta", "kappa"), ("reflectivity", "edge_tint")):
        if (first in given) != (second in given):
            raise ParameterError(f"{_option(first)} and {_option(second)} go together")
    ignored = [
        _option(name)
        for name in _MODEL_PARAMETERS
        if name not in ("eta", "kappa", "reflectivity", "edge_tint") and getattr(arguments, name, None) is not None
    ]
    if arguments.fit is not None:
        ignored.append("--fit")
    if ignored:
        raise ParameterError(
            f"{', '.join(ignored)} go{'es' if len(ignored) == 1 else ''} with --model NAME; "
            "a material given by --eta/--kappa, --reflectivity/--edge-tint or --material takes none"
        )
    if arguments.space is not None and "preset" not in given:
        raise ParameterError("--space goes with --material (an (eta, kappa) or (r, g) material has no colour space)")
    return given


def _preset_errors(preset: dict, material, coefficients, basis: Basis) -> dict:
    """RMS ΔE2000 of the coefficients against the spectral truth: the shipped file's, or measured afresh for another
    basis (the shipped numbers belong to the shipped basis' coefficients)."""
    if basis.content_hash == default_basis().content_hash:
        return preset["rms_delta_e2000"]
    from basis.material_fits import ANGLES_DEGREES, rms_delta_E_2000

    theta = np.deg2rad(ANGLES_DEGREES)
    truth = material.curve(np.cos(theta))
    return {
        "basis": float(rms_delta_E_2000(truth, (coefficients @ basis.evaluate(theta).T).T, material.space)),
        "schlick": preset["rms_delta_e2000"]["schlick"],
    }


def _print_coefficients(basis, coefficients) -> None:
    """The combination rule (terms 4-7 of a basis of more than four are the second table, LUT2) and the rows."""
    terms = " + ".join(f"c{k}*{'LUT' if k < 4 else 'LUT2'}.{'rgba'[k % 4]}" for k in range(basis.n_terms))
    print(f"basis {basis.content_hash}; Fbar = {terms} per colour channel")
    for name, row in zip("RGB", coefficients):
        print(f"  {name}: " + "  ".join(f"c{k}={value: .6f}" for k, value in enumerate(row)))


def command_materials(arguments) -> int:
    from basis.presets import build_presets
    from basis.spectral import shipped_spectra_path, spectra_from_database, write_spectra

    presets_path = _output_file("--presets", arguments.presets)
    if arguments.from_database:
        print(f"re-sampling {shipped_spectra_path()} from the refractiveindex.info database")
        write_spectra(spectra_from_database())
    started = time.perf_counter()
    progress = Progress("fitting presets", "materials")
    document = build_presets(default_basis(), progress=progress)
    progress.close()
    write_presets(document, presets_path)  # only once every fit is done: an interrupted run leaves the file as it was
    for space in PRESET_SPACES:
        entries = {name: entry[space] for name, entry in document["materials"].items()}
        metals = {
            name: entry["rms_delta_e2000"]["basis"]
            for name, entry in entries.items()
            if document["materials"][name]["kind"] == "metal"
        }
        worst = max(metals, key=metals.get)
        unconverged = sorted(name for name, entry in entries.items() if not entry.get("fit", {}).get("converged", True))
        evaluations = [entry["fit"]["evaluations"] for entry in entries.values() if "fit" in entry]
        print(
            f"  {space}: worst metal {worst} {metals[worst]:.3f} RMS dE2000 (basis); fits converged: "
            f"{len(entries) - len(unconverged)} of {len(entries)}, {max(evaluations, default=0)} evaluations at most"
            + (f"; NOT converged: {', '.join(unconverged)}" if unconverged else "")
        )
    print(f"presets fitted in {time.perf_counter() - started:.1f} s:")
    print(f"  {presets_path}  {_size_text(presets_path)}")
    return 0


#: Every model parameter of the registry, by name: RGB triples (``colour``) and scalars become ``coeffs``
#: options; the shape parameters (which fix a model's channels) are ``build --model`` options too.
_MODEL_PARAMETERS = {parameter.name: parameter for model in FRESNEL_MODELS.values() for parameter in model.parameters}
_SHAPE_OPTIONS = tuple(sorted({name for model in FRESNEL_MODELS.values() for name in model.shape}))


def _list_materials(space: str | None, as_json: bool = False) -> int:
    space = space or "ACEScg"
    document = material_presets()
    if as_json:
        print(
            json.dumps(
                {
                    "basis_hash": document["basis_hash"],
                    "space": space,
                    "materials": {
                        name: {
                            "kind": material["kind"],
                            "f0": material[space]["f0"],
                            "rms_delta_e2000": material[space]["rms_delta_e2000"],
                        }
                        for name, material in document["materials"].items()
                    },
                }
            )
        )
        return 0
    print(f"measured materials of --material ({space}; luts/materials.json, basis {document['basis_hash']}):")
    print(f"  {'name':16s} {'kind':10s} {'F0 (R, G, B)':24s} RMS dE2000 basis / Schlick")
    for name, material in document["materials"].items():
        entry = material[space]
        f0 = ", ".join(f"{value:.3f}" for value in entry["f0"])
        errors = entry["rms_delta_e2000"]
        print(f"  {name:16s} {material['kind']:10s} {f0:24s} {errors['basis']:.3f} / {errors['schlick']:.2f}")
    return 0


def _coeffs_of_model(arguments, basis: Basis) -> int:
    model = fresnel_model(arguments.model)
    given = {name: getattr(arguments, name) for name in _MODEL_PARAMETERS if getattr(arguments, name, None) is not None}
    if arguments.material is not None or arguments.space is not None:
        raise ParameterError("--model takes its own parameters, not --material or --space")
    parameters = model.check(**{name: np.array(value, dtype=np.float64) for name, value in given.items()})
    fit = arguments.fit or "four-point"
    coefficients, error = coefficients_from_model(model.name, fit, basis, **parameters)
    own = None
    if model.linear:
        weights = model.channel_weights(**parameters)
        own = {
            "lut": _own_table_text(model, parameters),
            "weights": np.broadcast_to(weights, (3, weights.shape[-1])).tolist(),
            "exact": bool(np.all(model.clamp_is_inactive(**parameters))),
        }
    material = {"model": model.name, **{name: np.asarray(value).tolist() for name, value in parameters.items()}}
    if arguments.json:
        print(
            json.dumps(
                {
                    "basis_hash": basis.content_hash,
                    "material": material,
                    "fit": fit,
                    "coefficients": coefficients.tolist(),
                    "layout": f"[channel R,G,B][term c0..c{basis.n_terms - 1}]",
                    "max_abs_error_over_theta": error.tolist(),
                    "own_split_sum": own,
                }
            )
        )
        return 0
    print(
        f"{model.name} ({model.reference}); {fit} projection, max |dF| over theta per channel: "
        + ", ".join(f"{value:.4f}" for value in error)
    )
    _print_coefficients(basis, coefficients)
    if own is not None:
        print(f"own exact split sum ({'exact' if own['exact'] else 'approximate: the curve is clamped'}): {own['lut']}")
        for name, row in zip("RGB", own["weights"]):
            print(f"  {name}: " + "  ".join(f"w{k}={value: .6f}" for k, value in enumerate(row)))
    return 0


def _own_table_text(model, parameters) -> str:
    """The table that holds a linear model's split sum exactly, and the command that writes it."""
    if model.name == "schlick":  # the default build's Schlick table (R = scale, G = bias)
        return f"{SCHLICK_LUT} (fresnel-lut build)"
    shape = model.shape_values(**parameters)
    options = "".join(f" --{name.replace('_', '-')} {value:g}" for name, value in shape.items())
    return f"{model_lut_name(model.name, shape)} (fresnel-lut build --model {model.name}{options})"


def command_scene(arguments) -> int:
    from .scene import build_scene

    out = _output_folder("--out", arguments.out)
    started = time.perf_counter()
    result = build_scene(
        arguments.file,
        out,
        arguments.format,
        arguments.half,
        arguments.visibility,
        progress=lambda text: print(text, flush=True),
    )
    print(result["text"])
    print(f"scene built in {time.perf_counter() - started:.1f} s:")
    for path in [
        *result["tables"],
        *result["scene_basis"],
        *result["shader_includes"],
        result["coefficients"],
        result["report"],
    ]:
        print(f"  {path}  {_size_text(path)}")
    return 0


def command_render(arguments) -> int:
    from .report.renders import render_markdown, write_renders

    out = _output_folder("--out", arguments.out)
    progress = Progress("rendering", "images")
    result = write_renders(out, quick=arguments.quick, progress=progress)
    progress.close()
    print(render_markdown(result))
    print(f"rendered in {result['seconds']:.1f} s:")
    for path in [*result["pngs"], result["markdown"]]:
        print(f"  {path}  {_size_text(path)}")
    print(f"  {len(result['exrs'])} linear EXRs beside them")
    return 0


def command_view(arguments) -> int:
    import webbrowser

    from .view import serve

    def ready(url: str) -> None:
        print(f"fresnel-lut view: serving {url} (Ctrl-C stops)", flush=True)
        if arguments.open:
            webbrowser.open(url)

    try:
        serve(
            arguments.port, arguments.host, arguments.environment, ready=ready, progress=lambda text: print(f"  {text}")
        )
    except KeyboardInterrupt:
        print("\nfresnel-lut view: stopped", file=sys.stderr)
    return 0


def command_report(arguments) -> int:
    if arguments.materials and (arguments.quick or arguments.fidelity):
        raise ParameterError("--materials is a report of its own: give it without --quick or --fidelity")
    folder = _output_folder("--out", arguments.out)
    if arguments.materials:
        return _materials_report(folder)
    if arguments.fidelity:
        return _fidelity_report(folder, arguments.quick)
    from .report import write_report  # imports the studies only when asked

    result = write_report(folder, quick=arguments.quick)
    print(f"report written in {result['seconds']:.1f} s:")
    for path in [result["readme"], *result["pngs"]]:
        print(f"  {path}  {_size_text(path)}")
    for target, measured, reached in result["targets"]:
        print(f"  target: {target}: {measured} -> {reached}")
    return 0


def _fidelity_report(folder: Path, quick: bool) -> int:
    from .report.basis_fidelity import write_fidelity_report

    result = write_fidelity_report(folder, quick, progress=lambda text: print(f"  {text}", flush=True))
    for line in result["summary"]:
        print(f"  {line}")
    for path in result["paths"]:
        print(f"  {path}  {_size_text(path)}")
    return 0


def _materials_report(folder: Path) -> int:
    from .report.material_error import write_materials_report

    progress = Progress("dE2000 tables", "tables")
    result = write_materials_report(folder, progress=progress)
    progress.close()
    for line in result["summary"]:
        print(f"  {line}")
    print(f"  {result['path']}  {_size_text(result['path'])}")
    return 0


def _add_shape_options(parser) -> None:
    for name in _SHAPE_OPTIONS:
        users = sorted(model.name for model in FRESNEL_MODELS.values() if name in model.shape)
        parser.add_argument(
            f"--{name.replace('_', '-')}",
            type=float,
            default=None,
            help=f"{_MODEL_PARAMETERS[name].description} ({', '.join(users)})",
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
        help="also fit the area lights' LTC table ggx_ltc (64 x 64 by default, about 30 s; make luts does)",
    )
    build.add_argument("--ltc-size", type=int, default=None, help="the LTC table's size (default 64; with --ltc)")
    build.add_argument(
        "--model",
        default=None,
        help="instead: the exact split-sum table of one linear model "
        f"({', '.join(sorted(n for n, m in FRESNEL_MODELS.items() if m.linear))})",
    )
    _add_shape_options(build)
    build.set_defaults(run=command_build)

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
    basis.set_defaults(run=command_basis)

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
    for name, parameter in _MODEL_PARAMETERS.items():
        if name in ("eta", "kappa", "reflectivity", "edge_tint") or name in _SHAPE_OPTIONS:
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
    coeffs.set_defaults(run=command_coeffs)

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
    materials.set_defaults(run=command_materials)

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
    scene.set_defaults(run=command_scene)

    render = commands.add_parser("render", help="pictures: curves, strips, spheres three ways, dE2000 heat maps")
    render.add_argument(
        "--out",
        default="build/render",
        help="output folder (default: build/render; the committed pictures are report/render: make render)",
    )
    render.add_argument(
        "--quick", action="store_true", help="128x128 spheres, 128-spp lattice references, 2 roughnesses per scene"
    )
    render.set_defaults(run=command_render)

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
    report.set_defaults(run=command_report)

    view = commands.add_parser("view", help="the look-development page: a local server for your browser (WebGL 2)")
    view.add_argument("--port", type=int, default=8000, help="port to listen on (default 8000; 0: any free port)")
    view.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1: this machine only)")
    view.add_argument("--environment", default=None, help="an equirectangular EXR (2:1) instead of the studio")
    view.add_argument("--open", action="store_true", help="open the page in the default browser")
    view.set_defaults(run=command_view)
    return parser


def main(argv=None) -> int:
    parser = make_parser()
    arguments = parser.parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return arguments.run(arguments)
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader of standard output went away (`… | head`): the console command ends quietly
        raise
    except (ValueError, OSError) as error:
        if caused_by_interrupt(error):  # a library turned Ctrl-C into its own error
            print(INTERRUPTED, file=sys.stderr)
            return 130
        print(f"fresnel-lut: error: {_message(error)}", file=sys.stderr)
        return 2


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning of the library (a folder's odd file left alone) as one line, as errors are."""
    print(f"fresnel-lut: warning: {message}", file=sys.stderr)


def _message(error: BaseException) -> str:
    """One line for an error: an OSError by its reason and the file it names, without Python's "[Errno N]"."""
    if isinstance(error, OSError) and error.strerror:
        return error.strerror + (f": {error.filename}" if error.filename else "")
    return str(error)


if __name__ == "__main__":
    sys.exit(main())
