"""Report section: basis fidelity — which basis holds which group, the frontier, and error against K.

Public objects: ``TARGETS``, ``FRONTIER``, ``BOUNDS``, ``QUICK``, ``notebook_basis``, ``refined_basis``,
``bound_basis``, ``group_errors``, ``terms_sweep``, ``fidelity_study``, ``fidelity_markdown``, ``plot_fidelity``,
``write_fidelity_report``.

Every basis is judged on :func:`basis.training.validation_groups` (fresh draws, never trained on): max |ΔF|
over θ (a 2049-point grid) and max |ΔF̄| over the (μo, r) texel centres of a 64 × 64 LUT (α = r²), with
four-point coefficients (the talk's scheme, what a live editor computes) and with minimax coefficients
(``coefficients_least_squares_from_table(fit="minimax")``, F0 and F90 exact). F̄ of the error curve
is the texel weights of :func:`preintegrate.quadrature.texel_weights` applied to it (DESIGN: each texel is a
linear functional of the curve). The bases: the authors' notebook recipe (:data:`basis.training.NOTEBOOK_DOMAIN`,
uniform in cos θ, searched fit angles), the shipped basis, both SVDs with each curve weighted by
(F90 − F0)² (the mean square error of F instead of F̂), and minimax refinements of the shipped (and once of the notebook) basis
(:func:`basis.training.refine_basis`) that weigh the groups differently (:data:`FRONTIER`): the frontier.
Then bounds (:data:`BOUNDS`): the same refinement trained on the validation curves themselves, with the
issue's targets (and other error levels) as tolerances. Such a basis has seen what it is judged on, so it is
no candidate; no four-term four-point basis, however trained, is likely to do better on this draw, and its
worst error / tolerance says how far out of reach a set of targets is (a local optimum of a non-convex
problem: the report runs the targets' bound from two starts). Then error against K = 2 … 8 for the generic build (:func:`basis.training.build_basis` with ``n_terms=K``)
per group, and for a scene basis of ``examples/showcase.toml`` (refined on the scene's F̄, as
``fresnel-lut scene`` does).

Run: ``fresnel-lut report --fidelity [--quick]`` (writes ``fidelity.md`` and ``basis_fidelity.png``).

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, Figure 2, eq. 4–6 and "Coefficients".
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from basis.angles import cos_theta
from basis.coefficients import coefficients_from_samples, coefficients_from_table, coefficients_least_squares_from_table
from basis.eigenbasis import Basis, default_basis
from basis.storage import write_together
from basis.training import (
    FIGURE_2,
    NOTEBOOK_DOMAIN,
    REFINEMENT_DOMAINS,
    build_basis,
    build_curves,
    refine_basis,
    validation_groups,
)
from basis.validation import ParameterError
from preintegrate.lut import LutGrid, lut_texel_weights
from preintegrate.quadrature import texel_weights

from .figures import pyplot, save_figure

__all__ = [
    "BOUNDS",
    "FRONTIER",
    "QUICK",
    "TARGETS",
    "bound_basis",
    "fidelity_markdown",
    "fidelity_study",
    "group_errors",
    "notebook_basis",
    "plot_fidelity",
    "refined_basis",
    "terms_sweep",
    "write_fidelity_report",
]

#: Issue 14's targets for the shipped default: group → (measure, bound); "curve" is max |ΔF| over θ,
#: "preintegrated" max |ΔF̄| over the LUT's (μo, r).
TARGETS = {
    "figure 2": ("preintegrated", 0.006),
    "measured metals": ("curve", 1.0 / 255.0),
    "dielectrics": ("curve", 0.004),
    "metals": ("curve", 0.010),
}

#: Start and tolerances of the refinement groups (:data:`basis.training.REFINEMENT_DOMAINS`) of each frontier point:
#: the worst error relative to its tolerance is what the refinement minimises, so each point trades the
#: Figure 2 neighbourhood ("showcase") against the dielectrics and metals differently.
_AT_TARGETS = {"dielectrics": 0.004, "metals": 0.010, "showcase": 0.006, "gulbrandsen": 0.24}
FRONTIER = {
    "refined: issue targets": ("shipped", _AT_TARGETS),
    "refined: metals first": (
        "shipped",
        {"dielectrics": 0.0035, "metals": 0.009, "showcase": 0.009, "gulbrandsen": 0.24},
    ),
    "refined: dielectrics first": (
        "shipped",
        {"dielectrics": 0.003, "metals": 0.008, "showcase": 0.015, "gulbrandsen": 0.24},
    ),
    # the same objective from another start: does the optimum depend on where it begins?
    "refined from the notebook: issue targets": ("notebook-style", _AT_TARGETS),
}

_TARGET_BOUNDS = {group: bound for group, (_measure, bound) in TARGETS.items()}

#: Tolerances of each bound (:func:`bound_basis`) and its start: the issue's targets (from both starts), the
#: better of the notebook-style and shipped bases' errors per group (the issue's "no group worse" condition),
#: the shipped basis' own errors (is the default on the frontier?) and the targets without the measured metals.
#: "better" and "shipped" are filled in from the study's own measurements.
BOUNDS = {
    "bound: issue targets": ("shipped", _TARGET_BOUNDS),
    "bound from the notebook: issue targets": ("notebook-style", _TARGET_BOUNDS),
    "bound: better of notebook-style and shipped": ("shipped", "better"),
    "bound: the shipped basis' own errors": ("shipped", "shipped"),
    "bound: issue targets without measured metals": (
        "shipped",
        {g: b for g, b in _TARGET_BOUNDS.items() if g != "measured metals"},
    ),
}

#: Settings of ``quick=True``: fewer curves, a smaller grid, the first frontier point and bound only, K = 4 and 6.
QUICK = {
    "count": 20_000,
    "size": 24,
    "theta": 513,
    "per_group": 60,
    "terms": (4, 6),
    "refinements": 1,
    "bounds": 1,
    "bound_iterations": 60,
}

_FULL = {
    "count": 200_000,
    "size": 64,
    "theta": 2049,
    "per_group": 300,
    "terms": (2, 3, 4, 5, 6, 7, 8),
    "refinements": len(FRONTIER),
    "bounds": len(BOUNDS),
    "bound_iterations": 800,
}

#: θ grid on which the refinements are trained (their bases live on it).
_REFINEMENT_GRID = np.linspace(0.0, 0.5 * np.pi, 257)

#: The seed of the refinement draws (neither the validation draws' nor the training sets').
_REFINEMENT_SEED = 1402

FITS = ("four-point", "minimax")


def notebook_basis(count: int = 200_000, weighting: str = "normalised") -> Basis:
    """The authors' notebook recipe: 99 % dielectrics, 1 % Gulbrandsen g = 1, uniform in cos θ, searched angles
    (``weighting="span"``: each curve weighted by (F90 − F0)² in the SVD, :func:`basis.training.build_curves`)."""
    return build_basis(count=count, domain=NOTEBOOK_DOMAIN, grid_kind="mu", fit_angles="auto", weighting=weighting)


def refined_basis(tolerances: dict[str, float], start: Basis | None = None, per_group: int = 300) -> Basis:
    """The minimax refinement of ``start`` (default: the shipped basis) over draws of
    :data:`basis.training.REFINEMENT_DOMAINS` with the given tolerances."""
    unknown = set(tolerances) - set(REFINEMENT_DOMAINS)
    if unknown:
        raise ParameterError(f"tolerances name unknown groups {sorted(unknown)}; known: {sorted(REFINEMENT_DOMAINS)}")
    groups = {
        name: (
            np.concatenate(list(REFINEMENT_DOMAINS[name].curves(_REFINEMENT_GRID, per_group, _REFINEMENT_SEED))),
            tolerance,
        )
        for name, tolerance in tolerances.items()
    }
    return refine_basis(_REFINEMENT_GRID, groups, start=default_basis() if start is None else start)


def bound_basis(tolerances: dict[str, float], start: Basis, size: int = 64, iterations: int = 800) -> Basis:
    """The four-point basis refined on the validation curves themselves (:func:`basis.training.validation_groups`)
    with ``tolerances`` (group → bound, each in its :data:`TARGETS` measure; F̄ over ``size`` × ``size`` texel
    centres): ``training["refinement"]["groups"][g]["max_abs_error"]`` / tolerance is how far from its
    target the best basis found for these very curves stays."""
    unknown = set(tolerances) - set(TARGETS)
    if unknown:
        raise ParameterError(f"tolerances name groups without a target {sorted(unknown)}; known: {sorted(TARGETS)}")
    weights = lut_texel_weights(_REFINEMENT_GRID, LutGrid.centred(size))
    groups = validation_groups()
    training = {
        name: (groups[name](cos_theta(_REFINEMENT_GRID)), bound)
        + ((weights,) if TARGETS[name][0] == "preintegrated" else ())
        for name, bound in tolerances.items()
    }
    return refine_basis(
        _REFINEMENT_GRID, training, start=start, dictionary_terms=12, powers=(16.0, 64.0, 256.0), iterations=iterations
    )


def _bound_tolerances(kind, errors: dict) -> dict[str, float]:
    """A bound's tolerances: given, or read from the four-point errors of the notebook-style and shipped bases."""
    if isinstance(kind, dict):
        return kind
    of = ("notebook-style", "shipped") if kind == "better" else ("shipped",)
    return {
        group: min(errors[name]["four-point"][group][measure] for name in of) for group, (measure, _) in TARGETS.items()
    }


def _worst_ratio(errors: dict, tolerances: dict[str, float]) -> float:
    """max over the groups of error / tolerance, each error in its :data:`TARGETS` measure."""
    return max(errors[group][TARGETS[group][0]] / bound for group, bound in tolerances.items())


def _coefficients(basis: Basis, group: Callable, fit: str) -> np.ndarray:
    if fit == "four-point":
        return coefficients_from_samples(group(cos_theta(basis.fit_angles)), basis)
    return coefficients_least_squares_from_table(basis.theta, group(cos_theta(basis.theta)), basis, fit="minimax")


def group_errors(
    basis: Basis, groups: dict[str, Callable], theta: np.ndarray, weights: np.ndarray, fits=FITS
) -> dict[str, dict[str, dict[str, float]]]:
    """fit → group → ``curve`` (max |ΔF| on ``theta``) and ``preintegrated`` (max |ΔF̄| over the texels of
    ``weights`` (T, len(theta)))."""
    exact = {name: group(cos_theta(theta)) for name, group in groups.items()}
    curves = basis.evaluate(theta)  # (M, K)
    result = {}
    for fit in fits:
        result[fit] = {}
        for name, group in groups.items():
            difference = _coefficients(basis, group, fit) @ curves.T - exact[name]
            result[fit][name] = {
                "curve": float(np.max(np.abs(difference))),
                "preintegrated": float(np.max(np.abs(difference @ weights.T))),
            }
    return result


def _figure_2_at_its_roughness(basis: Basis, theta: np.ndarray) -> float:
    """max over μo of |ΔF̄| at the talk's α = 0.08 (four-point), 128 texel centres."""
    group = validation_groups()["figure 2"]
    weights = texel_weights(theta, LutGrid.centred(128).mu_o, FIGURE_2["alpha"])
    difference = _coefficients(basis, group, "four-point") @ basis.evaluate(theta).T - group(cos_theta(theta))
    return float(np.max(np.abs(difference @ weights.T)))


def terms_sweep(terms, groups, theta, weights, count: int, progress=None, columns: int = 64) -> dict:
    """Error against K: the generic build (``n_terms=K``, the default domain, greedy fit angles) per group, and
    a scene basis of ``examples/showcase.toml`` trained as ``fresnel-lut scene`` trains it (max over its
    materials of max |ΔF̄| at ``columns`` view cosines and the training roughnesses of each range)."""
    from ..scene import read_scene
    from ..scene.layout import train_scene_basis, training_operators

    generic = {}
    for k in terms:
        basis = build_basis(count=count, n_terms=k)
        generic[k] = group_errors(basis, groups, theta, weights, fits=("four-point",))["four-point"]
        if progress is not None:
            progress(f"K = {k}: generic basis")
    scene = read_scene(Path(__file__).resolve().parents[2] / "examples" / "showcase.toml")
    shipped = default_basis()
    operators = training_operators(scene, shipped, LutGrid(columns, 1).mu_o)  # a scene table's columns
    scene_errors, plain_errors = {}, {}
    curves = np.concatenate([material.curve.T for material in scene.materials])
    for k in terms:
        trained = train_scene_basis(scene, shipped, operators, k)
        values = trained.evaluate(shipped.theta)
        worst = {}
        for material in scene.materials:
            coefficients = coefficients_from_table(shipped.theta, material.curve.T, trained)
            worst[material.name] = float(
                np.max(np.abs((coefficients @ values.T - material.curve.T) @ operators[material.name].T))
            )
        scene_errors[k] = worst
        # the reference: the plain SVD of the same curves with least-squares coefficients (c0, c1 exact;
        # least squares reads no fit angle, so the ones given only complete the Basis)
        plain = Basis(
            shipped.theta,
            build_curves(shipped.theta, [curves], k)[0],
            np.concatenate([[0.0, 0.5 * np.pi], np.linspace(1.45, 1.2, k - 2)]),
        )
        differences = {
            m.name: coefficients_least_squares_from_table(shipped.theta, m.curve.T, plain) @ plain.curves - m.curve.T
            for m in scene.materials
        }
        plain_errors[k] = {
            "preintegrated": max(float(np.max(np.abs(d @ operators[name].T))) for name, d in differences.items()),
            "curve": max(float(np.max(np.abs(d))) for d in differences.values()),
        }
        if progress is not None:
            progress(f"K = {k}: scene basis")
    return {
        "generic": generic,
        "scene": scene_errors,
        "scene_plain": plain_errors,
        "scene_file": "examples/showcase.toml",
    }


def fidelity_study(quick: bool = False, progress: Callable[[str], None] | None = None) -> dict:
    """The whole section: the bases' group errors, the frontier and the K sweep."""
    started = time.perf_counter()
    settings = QUICK if quick else _FULL
    say = progress or (lambda text: None)
    theta = np.linspace(0.0, 0.5 * np.pi, settings["theta"])
    weights = lut_texel_weights(theta, LutGrid.centred(settings["size"]))
    groups = validation_groups()
    bases = {
        "notebook-style": notebook_basis(settings["count"]),
        "shipped": default_basis(),
        # the first lever: the SVD of the error in F, each curve weighted by (F90 − F0)²
        "SVD weighted by span²: default domain": build_basis(count=settings["count"], weighting="span"),
        "SVD weighted by span²: notebook recipe": notebook_basis(settings["count"], weighting="span"),
    }
    say("built the notebook-style and span-weighted bases")
    for name, (start, tolerances) in list(FRONTIER.items())[: settings["refinements"]]:
        bases[name] = refined_basis(tolerances, start=bases[start], per_group=settings["per_group"])
        say(f"{name}")
    errors = {name: group_errors(basis, groups, theta, weights) for name, basis in bases.items()}
    bounds = {}
    for name, (start, kind) in list(BOUNDS.items())[: settings["bounds"]]:
        tolerances = _bound_tolerances(kind, errors)
        basis = bound_basis(tolerances, bases[start], settings["size"], settings["bound_iterations"])
        bases[name] = basis
        errors[name] = group_errors(basis, groups, theta, weights)
        trained = {
            group: {TARGETS[group][0]: entry["max_abs_error"]}
            for group, entry in basis.training["refinement"]["groups"].items()
        }
        # measured on the study's grid; "trained" is what the refinement saw on its coarser θ grid
        bounds[name] = {
            "tolerances": tolerances,
            "worst_ratio": _worst_ratio(errors[name]["four-point"], tolerances),
            "trained_ratio": _worst_ratio(trained, tolerances),
        }
        say(f"{name}: worst error / tolerance {bounds[name]['worst_ratio']:.3f}")
    figure_2 = {name: _figure_2_at_its_roughness(basis, theta) for name, basis in bases.items()}
    sweep = terms_sweep(settings["terms"], groups, theta, weights, settings["count"], say, settings["size"])
    return {
        "quick": quick,
        "settings": {key: list(value) if isinstance(value, tuple) else value for key, value in settings.items()},
        "groups": {name: int(group(np.array([1.0])).shape[0]) for name, group in groups.items()},
        "bases": {
            name: {"hash": basis.content_hash, "fit_angles": basis.fit_angles[2:].round(4).tolist()}
            for name, basis in bases.items()
        },
        "errors": errors,
        "bounds": bounds,
        "figure_2_at_alpha": figure_2,
        "terms": sweep,
        "seconds": time.perf_counter() - started,
    }


def _meets(entry: dict, group: str) -> str:
    measure, bound = TARGETS[group]
    return "yes" if entry[group][measure] <= bound else "no"


def fidelity_markdown(result: dict) -> str:
    """The section as Markdown: one table per fit, the targets, the frontier and the K sweep."""
    groups = list(result["groups"])
    lines = [
        "## Basis fidelity: which basis holds which group",
        "",
        (
            "Validation groups (fresh draws, never trained on; curves per group: "
            + ", ".join(f"{name} {count}" for name, count in result["groups"].items())
            + f"). max |ΔF| over {result['settings']['theta']} θ samples / max |ΔF̄| over the "
            f"{result['settings']['size']} × {result['settings']['size']} LUT texel centres. Made by `fresnel-lut report "
            f"--fidelity{' --quick' if result['quick'] else ''}` in {result['seconds']:.0f} s."
        ),
        "",
    ]
    for fit in FITS:
        lines += [
            f"**{fit} coefficients** (max |ΔF| / max |ΔF̄|):",
            "",
            "| basis | fit angles θ2, θ3 | " + " | ".join(groups) + " |",
            "|---|---|" + "---|" * len(groups),
        ]
        for name, entry in result["errors"].items():
            angles = ", ".join(f"{angle:.3f}" for angle in result["bases"][name]["fit_angles"])
            lines.append(
                f"| {name} | {angles} | "
                + " | ".join(
                    f"{entry[fit][group]['curve']:.4f} / {entry[fit][group]['preintegrated']:.4f}" for group in groups
                )
                + " |"
            )
        lines.append("")
    lines += [
        "**Targets** (four-point; "
        + ", ".join(f"{group} {measure} ≤ {bound:.4g}" for group, (measure, bound) in TARGETS.items())
        + "):",
        "",
        "| basis | " + " | ".join(TARGETS) + " | Figure 2 at α = 0.08 (max over μo of ΔF̄) |",
        "|---|" + "---|" * (len(TARGETS) + 1),
    ]
    for name, entry in result["errors"].items():
        lines.append(
            f"| {name} | "
            + " | ".join(_meets(entry["four-point"], group) for group in TARGETS)
            + f" | {result['figure_2_at_alpha'][name]:.4f} |"
        )
    if result["bounds"]:
        lines += [
            "",
            '**Bounds: four-point bases trained on the validation curves themselves** (rows "bound" above; '
            "no candidates, since they have seen what they are judged on). Each minimises the worst error / tolerance "
            "over these very curves, so a ratio above 1 means no four-term basis found meets those tolerances "
            "together, however it is trained; the same bound from two starts shows how local the optimum is:",
            "",
            "| bound | tolerances (" + ", ".join(TARGETS) + ") | worst error / tolerance | as trained (257 θ) |",
            "|---|---|---|---|",
        ]
        for name, bound in result["bounds"].items():
            tolerances = ", ".join(
                f"{bound['tolerances'][group]:.4f}" if group in bound["tolerances"] else "—" for group in TARGETS
            )
            lines.append(f"| {name} | {tolerances} | {bound['worst_ratio']:.3f} | {bound['trained_ratio']:.3f} |")
    sweep = result["terms"]
    terms = list(sweep["generic"])
    lines += [
        "",
        "**Error against the number of terms K** (four-point; max |ΔF̄|). Generic: the default domain's "
        "build with K terms and greedy fit angles. Scene: a basis refined on the F̄ of "
        f"`{sweep['scene_file']}` (six materials, each over its roughness range), worst material; beside it the "
        "issue's reference, the plain SVD of the same curves with least-squares coefficients (max |ΔF̄| / max |ΔF|):",
        "",
        "| K | " + " | ".join(groups) + " | scene (worst material) | scene, plain SVD + least squares |",
        "|---|" + "---|" * (len(groups) + 2),
    ]
    for k in terms:
        scene, plain = sweep["scene"][k], sweep["scene_plain"][k]
        worst = max(scene, key=scene.get)
        lines.append(
            f"| {k} | "
            + " | ".join(f"{sweep['generic'][k][group]['preintegrated']:.4f}" for group in groups)
            + f" | {scene[worst]:.2e} ({worst}) | {plain['preintegrated']:.2e} / {plain['curve']:.2e} |"
        )
    return "\n".join(lines) + "\n"


def plot_fidelity(result: dict, path=None) -> Path | bytes:
    """Left: the frontier, Figure 2 against the measured metals and the dielectrics (four-point), with the
    targets; right: error against K per group (generic) and for the scene basis."""
    plt = pyplot()
    figure, (left, right) = plt.subplots(1, 2, figsize=(12, 6.2))
    for name, entry in result["errors"].items():
        fit = entry["four-point"]
        left.scatter(
            fit["figure 2"]["preintegrated"],
            fit["measured metals"]["curve"],
            s=40,
            label=name,
            marker="x" if name in result["bounds"] else "o",
        )
        left.annotate(
            f"diel. {fit['dielectrics']['curve']:.4f}\nmetals {fit['metals']['curve']:.4f}",
            (fit["figure 2"]["preintegrated"], fit["measured metals"]["curve"]),
            fontsize=7,
            xytext=(4, 4),
            textcoords="offset points",
        )
    left.axvline(TARGETS["figure 2"][1], color="grey", linestyle=":")
    left.axhline(TARGETS["measured metals"][1], color="grey", linestyle=":")
    left.set_xlabel("Figure 2 material: max |ΔF̄| (four-point)")
    left.set_ylabel("measured metals: max |ΔF| (four-point)")
    meeting = [
        name
        for name, entry in result["errors"].items()
        if name not in result["bounds"] and all(_meets(entry["four-point"], group) == "yes" for group in TARGETS)
    ]
    left.set_title(
        f"four terms: {', '.join(meeting) if meeting else 'no basis'} meets the four targets\n"
        "(dotted: two of them; ×: bounds, trained on the validation curves)",
        fontsize=9,
    )
    left.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2)
    sweep = result["terms"]
    terms = list(sweep["generic"])
    for group in result["groups"]:
        right.semilogy(
            terms, [sweep["generic"][k][group]["preintegrated"] for k in terms], marker="o", label=f"generic: {group}"
        )
    right.semilogy(
        terms,
        [max(sweep["scene"][k].values()) for k in terms],
        marker="s",
        color="black",
        label="scene basis (showcase)",
    )
    right.axhline(1.0 / 1023.0, color="grey", linestyle=":", label="1/1023")
    right.set_xlabel("terms K")
    right.set_ylabel("max |ΔF̄| (four-point)")
    right.set_title("error against the number of terms")
    right.legend(fontsize=7)
    figure.tight_layout()
    return save_figure(figure, path)


def write_fidelity_report(folder, quick: bool = False, progress: Callable[[str], None] | None = None) -> dict:
    """``fresnel-lut report --fidelity``: :func:`fidelity_study` written to ``folder/fidelity.md`` and, with the plot
    extra, ``folder/basis_fidelity.png``; returns the study, the paths and one summary line per target."""
    result = fidelity_study(quick=quick, progress=progress)
    folder = Path(folder)
    text = "# Basis fidelity (issue 14)\n\n" + fidelity_markdown(result)
    writers, summary = [(folder / "fidelity.md", lambda temporary: temporary.write_text(text, encoding="utf-8"))], []
    try:
        png = plot_fidelity(result)
        writers.append((folder / "basis_fidelity.png", lambda temporary: temporary.write_bytes(png)))
    except ParameterError as error:  # matplotlib is the optional plot extra
        summary.append(f"no plot: {error}")
    paths = write_together(writers)  # the Markdown and its plot, or neither (a full disk, Ctrl-C)
    shipped = result["errors"]["shipped"]["four-point"]
    summary += [
        f"shipped basis, {group}: max {measure} error {shipped[group][measure]:.4f} (target {bound:.4f})"
        for group, (measure, bound) in TARGETS.items()
    ]
    return {"result": result, "paths": paths, "summary": summary}
