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
leaves every previously written file untouched. Each command checks its options (:mod:`fresnel_lut.options` parses
them), calls one library function and prints what it returns.
"""

from __future__ import annotations

import json
import os
import sys
import time
import warnings
from pathlib import Path

from basis.eigenbasis import TERMS_RANGE, Basis, default_basis, shipped_basis_path
from basis.models import fresnel_model
from basis.presets import presets_summary_lines, shipped_presets_path, write_presets
from basis.training import FIT_ANGLE_CHOICES, build_basis, holdout_lines
from basis.training.builder import MAX_GRID
from basis.validation import ParameterError, check_choice, check_positive_int
from handoff.formats import MAX_HEADER_VALUES, check_formats
from handoff.records import coefficient_record, listing_lines, presets_listing, record_lines
from handoff.tables import write_default_build, write_model_build
from preintegrate.ltc import ltc_grid
from preintegrate.lut import LutGrid
from preintegrate.quadrature import DEFAULT_ORDER, QuadratureOrder

from .interrupts import INTERRUPTED, caused_by_interrupt
from .options import MODEL_PARAMETERS, SHAPE_OPTIONS, make_parser, option_name
from .progress import Progress, peak_rss_mib


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
    shape = {name: getattr(arguments, name) for name in SHAPE_OPTIONS if getattr(arguments, name, None) is not None}
    if arguments.model is None and shape:
        raise ParameterError(
            f"{', '.join(map(option_name, shape))} go{'es' if len(shape) == 1 else ''} with --model NAME"
        )
    if arguments.model in ("basis", "schlick"):
        raise ParameterError(
            f"--model {arguments.model}: the default build (no --model) writes the basis and Schlick tables"
        )
    if arguments.model is not None and arguments.basis is not None:
        raise ParameterError("--basis goes with the basis table, not with --model")
    if arguments.model is not None and arguments.ltc:
        raise ParameterError("--ltc goes with the default build, not with --model")
    if arguments.model is not None and arguments.atlas:
        raise ParameterError("--atlas goes with the default build, not with --model")
    if arguments.model is not None and arguments.materialx:
        raise ParameterError("--materialx goes with the default build, not with --model")
    if arguments.model is not None and arguments.three:
        raise ParameterError("--three goes with the default build, not with --model")
    if arguments.model is not None and arguments.pixel_tables:
        raise ParameterError("--pixel-tables goes with the default build, not with --model")
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
                f"--model {model.name} takes {[option_name(n) for n in model.shape] or 'no shape options'}, "
                f"not {[option_name(n) for n in unused]}"
            )
    basis = None if arguments.model is not None else _load_basis(arguments.basis)
    started = time.perf_counter()
    progress = Progress(f"integrating {size}x{size} texels", "texels")
    if arguments.model is None:
        ltc_progress = (
            Progress(f"fitting {ltc.width}x{ltc.height} LTC texels (two fits, then the choice)", "rows")
            if ltc is not None
            else None
        )
        paths = write_default_build(
            out,
            basis,
            grid,
            order,
            formats,
            arguments.half,
            progress,
            ltc,
            _after(progress, ltc_progress),
            arguments.pixel_tables,
            arguments.atlas,
            arguments.three,
            arguments.materialx,
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
    print("\n".join(holdout_lines(basis)))
    print(f"  {path}  {_size_text(path)}")
    if replaced_shipped:
        print(
            f"note: the shipped presets {shipped_presets_path()} belong to the previous basis until "
            "`make materials` refits them"
        )
    return 0


def command_coeffs(arguments) -> int:
    if arguments.list_materials:
        listing = presets_listing(arguments.space or "ACEScg")
        print(json.dumps(listing) if arguments.json else "\n".join(listing_lines(listing)))
        return 0
    record = coefficient_record(
        _material_mapping(arguments), arguments.space or "ACEScg", _load_basis(arguments.basis), arguments.fit
    )
    print(json.dumps(record) if arguments.json else "\n".join(record_lines(record)))
    return 0


def _material_mapping(arguments) -> dict:
    """The material the options name, in the vocabulary of :mod:`basis.materials`; mixtures and strays are refused."""
    parameters = {
        name: getattr(arguments, name) for name in MODEL_PARAMETERS if getattr(arguments, name, None) is not None
    }
    if arguments.model is not None:
        if arguments.material is not None or arguments.space is not None:
            raise ParameterError("--model takes its own parameters, not --material or --space")
        return {"model": arguments.model, **parameters}
    given = {key: parameters.pop(key) for key in ("eta", "kappa", "reflectivity", "edge_tint") if key in parameters}
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
            raise ParameterError(f"{option_name(first)} and {option_name(second)} go together")
    ignored = [option_name(name) for name in parameters] + (["--fit"] if arguments.fit is not None else [])
    if ignored:
        raise ParameterError(
            f"{', '.join(ignored)} go{'es' if len(ignored) == 1 else ''} with --model NAME; "
            "a material given by --eta/--kappa, --reflectivity/--edge-tint or --material takes none"
        )
    if arguments.space is not None and "preset" not in given:
        raise ParameterError("--space goes with --material (an (eta, kappa) or (r, g) material has no colour space)")
    return given


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
    print("\n".join(presets_summary_lines(document)))
    print(f"presets fitted in {time.perf_counter() - started:.1f} s:")
    print(f"  {presets_path}  {_size_text(presets_path)}")
    return 0


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
            arguments.port,
            arguments.host,
            arguments.environment,
            ready=ready,
            progress=lambda text: print(f"  {text}"),
            three_js=arguments.three_js,
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


#: Each subcommand's function (:func:`fresnel_lut.options.make_parser` names them).
COMMANDS = {
    "build": command_build,
    "basis": command_basis,
    "coeffs": command_coeffs,
    "materials": command_materials,
    "scene": command_scene,
    "render": command_render,
    "report": command_report,
    "view": command_view,
}


def main(argv=None) -> int:
    parser = make_parser()
    arguments = parser.parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _show_warning
            return COMMANDS[arguments.command](arguments)
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
