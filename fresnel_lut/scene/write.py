"""Write a planned scene: its tables, ``scene_coefficients.json``, ``scene_report.md``, when a table holds
the scene's own basis, ``scene_basis.json`` (its curves, fit angles and hash), and the shader include
``fresnel_basis_scene.*`` on the scene's grid (:mod:`handoff.shaders`; of the scene's own basis where a table holds
it, else of the generic one), as one transaction.

Public objects: ``write_scene``, ``build_scene``.
"""

from __future__ import annotations

import dataclasses
import json
import re
import tempfile
from collections.abc import Callable
from pathlib import Path

from basis.eigenbasis import Basis, resolve_basis
from basis.storage import MAX_DOCUMENT_BYTES, parse_json, read_regular_file, shipped_path
from basis.validation import check_choice, safe_line
from handoff.formats import FORMATS, check_formats
from handoff.shaders import INCLUDE_STEM, SHADER_INCLUDES, shader_includes
from handoff.shipped import BASIS_LUT, SCHLICK_LUT, lut_attributes
from handoff.tables import Table, rgba_tables, table_file_name, write_tables
from preintegrate.ggx import VISIBILITIES

from .files import SceneError, read_scene
from .layout import SCENE_TABLE_PREFIX
from .plan import ACCURACY_GOAL, ScenePlan, plan_scene

__all__ = ["build_scene", "write_scene"]


#: The scene basis beside its table: the coefficients of ``scene_coefficients.json`` are on these curves.
SCENE_BASIS_FILE = "scene_basis.json"
#: A scene's include is named apart from the default build's (``fresnel_basis.*``), so that a scene written into a
#: build's folder never replaces the include of that build's tables.
SCENE_INCLUDE_STEM = "fresnel_basis_scene"
#: The suffixes of every table format.
FORMAT_SUFFIXES = frozenset(fmt.suffix for fmt in FORMATS.values())
_INCLUDE_FILES = frozenset(name.replace(INCLUDE_STEM, SCENE_INCLUDE_STEM) for name, _ in SHADER_INCLUDES.values())


#: The scene tables of the builds before they were named apart (``scene_ggx_…``): names no build writes.
_LEGACY_SCENE_TABLES = re.compile(r"ggx_(?:scene_basis_rgba(?:_2)?|schlick_rg|basis_(?:r|rg|rgb))")


def _previous_files(coefficients_path: Path) -> set[str]:
    """The files a scene built earlier into the same folder wrote, as its ``scene_coefficients.json`` lists them:
    only names a scene writes (its ``scene_ggx_…`` tables, its scene basis and includes), so that a crafted list
    can remove nothing else (a build's ``ggx_…`` tables, a user's file)."""
    try:
        data = read_regular_file(coefficients_path, "scene coefficients", MAX_DOCUMENT_BYTES)
        document = parse_json(data.decode("utf-8"))
        names = {entry.get(key) for entry in document["materials"].values() for key in ("lut", "second_lut")}
        names.add((document.get("scene_basis") or {}).get("file"))
        includes = document.get("shader_includes") or []
        names.update(name for name in includes if isinstance(name, str))
    except (ValueError, KeyError, TypeError, AttributeError, RecursionError):  # ParameterError is a ValueError
        return set()
    return {
        name
        for name in names
        if isinstance(name, str)
        and Path(name).name == name
        and (
            (
                Path(name).suffix in FORMAT_SUFFIXES
                and (
                    re.fullmatch(rf"{SCENE_TABLE_PREFIX}ggx_[A-Za-z0-9_.=-]+", Path(name).stem)
                    or _LEGACY_SCENE_TABLES.fullmatch(Path(name).stem)
                )
            )
            or name == SCENE_BASIS_FILE
            or name in _INCLUDE_FILES
        )
    }


def _include_basis(plan: ScenePlan, basis: Basis) -> Basis:
    """The basis of the scene's include: the scene's own where a table holds it, else the generic one (whose first
    terms a basis table holds; a Schlick or model table is read through the include's coordinates alone)."""
    for table in plan.tables:
        layout = plan.candidates[table]
        if layout.kind == "scene":
            return layout.trained
    return basis


def write_scene(
    plan: ScenePlan, out, basis: Basis | None = None, reference_folder=None, formats=("exr",), half: bool = False
) -> dict:
    """Write the plan's tables (in every format of ``formats``, half floats with ``half``),
    ``scene_coefficients.json`` and ``scene_report.md`` into ``out``.

    ``reference_folder`` holds the full default build to compare sizes with (default: the shipped luts).
    """
    basis = resolve_basis(basis)
    formats = check_formats(formats)
    out = Path(out)
    low, high = plan.roughness_range
    grid = plan.grid
    convention = grid.convention
    tables, names, texts = [], {}, []
    command = f"fresnel-lut scene {safe_line(Path(plan.scene.source).name)}"  # a file name may hold any text
    trained = {
        table: plan.candidates[table].trained for table in plan.tables if plan.candidates[table].trained is not None
    }
    hashes = {table: trained[table].content_hash if table in trained else basis.content_hash for table in plan.tables}
    for table in plan.tables:
        layout = plan.candidates[table]
        channels = layout.channel_set(basis)
        header = lut_attributes(
            channels,
            plan.columns,
            plan.rows,
            command,
            convention,
            channel_set=table,
            roughness_range=f"{low:.9g},{high:.9g}",
            basis_hash=hashes[table],
        )
        stem, values = Path(layout.file_name()).stem, plan.table_values[table]
        parts = (
            rgba_tables(stem, values, header)
            if layout.kind in ("basis", "scene")
            else [Table(stem, values, channels.channel_names, header)]
        )
        names[table] = [table_file_name(part.name, formats[0]) for part in parts]
        tables += parts
    scene_basis = next(iter(trained.values()), None)
    if scene_basis is not None:
        texts.append((SCENE_BASIS_FILE, json.dumps(scene_basis.to_dict(), indent=1) + "\n"))
    include_basis = _include_basis(plan, basis)
    includes = [
        (name.replace(INCLUDE_STEM, SCENE_INCLUDE_STEM), text)
        for name, text in shader_includes(include_basis, command, grid, pixel_tables=False)  # none for its basis
    ]
    texts += includes
    materials = {
        material.name: {
            "target": material.description,
            "roughness": list(material.roughness),
            "layout": plan.layouts[material.name],
            "lut": names[plan.layouts[material.name]][0],
            **(
                {"second_lut": names[plan.layouts[material.name]][1]}
                if len(names[plan.layouts[material.name]]) > 1
                else {}
            ),
            "basis_hash": hashes[plan.layouts[material.name]],
            "coefficients": plan.coefficients[material.name].tolist(),
            "max_abs_error_fbar": plan.errors[material.name],
            "max_abs_error_fbar_full_default_build": plan.default_build_errors[material.name],
            "path": plan.path(material.name),
        }
        for material in plan.scene.materials
    }
    document = {
        "scene": Path(plan.scene.source).name,
        "basis_hash": basis.content_hash,
        "tolerance": plan.scene.tolerance,
        "space": plan.scene.space,
        "visibility": plan.scene.visibility,
        "roughness_range": [low, high],
        "rows": plan.rows,
        "columns": plan.columns,
        "convention": convention,  # how to address the tables: the same text as their headers
        "formats": formats,
        "shader_includes": [name for name, _ in includes],
        "layout": (
            "coefficients[channel R,G,B][LUT channel]: Fbar = sum_k coefficients[c][k] * LUT_k; LUT channels "
            "4-7 of a basis of more than four terms are R, G, B, A of second_lut"
        ),
        "materials": materials,
    }
    if scene_basis is not None:
        document["scene_basis"] = {
            "file": SCENE_BASIS_FILE,
            "content_hash": scene_basis.content_hash,
            "fit_angles": scene_basis.fit_angles.tolist(),
        }
    # the tables, the coefficients and the report are renamed into place together (or not at all); the
    # report quotes the tables' sizes, so the tables are first encoded in a scratch folder of the system's
    # (nothing appears in ``out`` before the transaction, nothing is left there by a kill)
    with tempfile.TemporaryDirectory(prefix="fresnel-lut-scene-") as scratch:
        measured = write_tables(tables, scratch, formats, half)
        written = {path.name: path.stat().st_size for path in measured}
    exr_bytes = {name: size for name, size in written.items() if name.endswith(FORMATS["exr"].suffix)}
    reference_folder = shipped_path("") if reference_folder is None else Path(reference_folder)
    full = {
        name: (reference_folder / name).stat().st_size
        for name in (BASIS_LUT, SCHLICK_LUT)
        if (reference_folder / name).exists()
    }
    left_out = [name for name in ("schlick", "basis-4") if name not in plan.tables]
    scene_layouts = [name for name in plan.full_errors if name.startswith("scene-basis")]
    table_list = ", ".join(f"{' + '.join(names[table])} ({table})" for table in plan.tables)
    report = [
        f"# Scene build: {_cell(safe_line(Path(plan.scene.source).name))}",
        "",
        (
            f"Tolerance {plan.scene.tolerance:.4g} on Fbar (max over each material's roughness range and all view "
            f"angles, bilinear lookup), held to {ACCURACY_GOAL:.4g} (10 bits) where a layout can; space "
            f"{plan.scene.space}, basis {basis.content_hash}"
            + (f", scene basis {scene_basis.content_hash} ({SCENE_BASIS_FILE})" if scene_basis is not None else "")
            + "."
        ),
        "",
        (
            "| material | roughness | layout | max abs error of Fbar | full default build | "
            "error with Schlick, basis 2, 3, 4 terms, scene basis of 4… terms (all rows) |"
        ),
        "|---|---|---|---|---|---|",
        *[
            f"| {_cell(m.name)} | {m.roughness[0]:g}–{m.roughness[1]:g} | {plan.layouts[m.name]} | {plan.errors[m.name]:.2e} | "
            f"{plan.default_build_errors[m.name]:.2e} | "
            + ", ".join(
                f"{plan.full_errors[layout][m.name]:.1e}"
                for layout in ("schlick", "basis-2", "basis-3", "basis-4", *scene_layouts)
            )
            + " |"
            for m in plan.scene.materials
        ],
        "",
        'Paths (README\'s rule, "Which path for which material", as this plan applied it):',
        "",
        *[
            f"- {_cell(m.name)}: {path['choice']} ({path['why']})"
            for m in plan.scene.materials
            for path in [plan.path(m.name)]
        ],
        "",
        (
            f"Tables: {table_list}; {plan.rows} rows over roughness "
            f"{low:g}–{high:g} (the default build: {plan.scene.size} rows over 0–1), {plan.columns} columns."
        ),
        f"Left out: {', '.join(left_out) if left_out else 'no table'}"
        + (
            ""
            if "basis-4" in plan.tables
            or any(t.startswith("scene") for t in plan.tables)
            or not any(t.startswith("basis") for t in plan.tables)
            else f" (basis terms beyond {plan.tables[-1].split('-')[1]})"
        )
        + ".",
        (
            f"Shader include: {', '.join(name for name, _ in includes)}, generated from basis "
            f"{include_basis.content_hash} on these tables' grid: fresnelBasisLutUV addresses every table above (its "
            "rows span roughness "
            + (f"{low:g}-{high:g}" if high > low else f"{low:g} alone, one row")
            + "), with the per-pixel coefficients and direct light of that basis."
        ),
        (
            f"Bytes: {sum(exr_bytes.values()):,} of EXR written against {sum(full.values()):,} for the full default "
            f"build ({100.0 * (1.0 - sum(exr_bytes.values()) / max(1, sum(full.values()))):.1f} % saved)"
            + (f"; {sum(written.values()):,} in all of {', '.join(formats)}." if formats != ["exr"] else ".")
            if exr_bytes
            else f"Bytes: {sum(written.values()):,} written in {', '.join(formats)}."
        ),
    ]
    coefficients_path, report_path = out / "scene_coefficients.json", out / "scene_report.md"
    # the tables (in every format) and scene basis of a scene built here before are this build's set: those not
    # written again go, in the same transaction
    previous = _previous_files(coefficients_path)
    paths = write_tables(
        tables,
        out,
        formats,
        half,
        owned=sorted({Path(name).stem for name in previous if Path(name).suffix in FORMAT_SUFFIXES}),  # its tables
        owned_files=sorted(previous & ({SCENE_BASIS_FILE} | _INCLUDE_FILES)),
        texts=[
            *texts,
            (coefficients_path.name, json.dumps(document, indent=1) + "\n"),
            (report_path.name, "\n".join(report) + "\n"),
        ],
    )[: len(tables) * len(formats)]
    return {
        "tables": paths,
        "coefficients": coefficients_path,
        "report": report_path,
        "bytes": written,
        "scene_basis": [out / SCENE_BASIS_FILE] if scene_basis is not None else [],
        "shader_includes": [out / name for name, _ in includes],
        "full_bytes": full,
        "text": "\n".join(report),
    }


def _cell(text: str) -> str:
    """A name as one Markdown table cell: its pipes, backslashes and emphasis marks escaped."""
    return "".join("\\" + character if character in "\\|*_`[]<>#" else character for character in text)


def build_scene(
    file,
    out,
    formats=("exr",),
    half: bool = False,
    visibility: str | None = None,
    progress: Callable[[str], None] | None = None,
) -> dict:
    """``fresnel-lut scene``: read the scene file, plan it and write it (:func:`write_scene`); ``visibility``
    (given on the command line) must agree with the scene file's where both say one. ``progress`` gets a line
    before the plan and an indented one per trained scene basis."""
    formats = check_formats(formats)  # refused before the work
    scene = read_scene(file)
    if visibility is not None:
        check_choice("--visibility", visibility, list(VISIBILITIES))
        if scene.visibility_stated and scene.visibility != visibility:
            raise SceneError(
                f"scene file {file} says visibility = {scene.visibility!r}, the command line {visibility!r}; give one"
            )
        scene = dataclasses.replace(scene, visibility=visibility)
    if progress is not None:
        columns = f"{scene.size}" if scene.size_fixed else f"{scene.size} or more"
        progress(
            f"planning {len(scene.materials)} materials (tolerance {scene.tolerance:.4g}, {columns} columns, "
            f"{scene.visibility} G2) ..."
        )
    plan = plan_scene(scene, progress=None if progress is None else lambda text: progress(f"  {text}"))
    # the plan refuses before anything is written
    return write_scene(plan, out, formats=formats, half=half)
