"""Studies 2 and 3 of the report: Fresnel models' curve error against cost, and their preintegrated error.

Public objects: ``Representation``, ``REPRESENTATIONS``, ``representation``, ``curve_error_vs_cost``,
``preintegrated_error``, ``model_error_study``,
``plot_model_error``, ``model_error_markdown``, ``QUICK``.

The models are the ways a renderer represents a material (η, κ), :data:`REPRESENTATIONS`: the exact curve,
Schlick with F0 = F(0), and the eigen-basis with four-point, L2 least-squares and minimax coefficients; the materials are the held-out groups of
:func:`basis.training.holdout_materials`, none of them used in training.

* **Study 2, curve error vs cost** (:func:`curve_error_vs_cost`): max and RMS over θ of
  |F_model − F_exact| on a dense θ grid — uniform in θ plus a geometric sweep of μ towards grazing,
  where the stiff curves' Brewster dips are narrower than any uniform step; the RMS uses trapezoid
  weights in θ — worst and mean over each group's materials. Cost: nanoseconds per evaluation of F(μ)
  in vectorised numpy, one μ and one material's stored parameters per evaluation (best of ``repeats``
  runs over ``evaluations`` evaluations, ``time.perf_counter``); the per-material set-up (parameters);
  and the LUT channels a shader fetches for F̄.
* **Study 3, preintegrated error** (:func:`preintegrated_error`): max over the texel grid of
  :meth:`preintegrate.lut.LutGrid.centred` (μo, r; α = r²) of |F̄_model − F̄_exact|, per material, then
  worst and mean over the group and the number of materials above 1/255 (one 8-bit step).

Every model is a function of x = ω_o·h alone, so each texel is a linear functional of the curve
(DESIGN): F̄[f](μo, α) = ∫ f(x) K(x; μo, α) dx ≈ Σ_j W_tj f(θ_j). :func:`preintegrate.lut.lut_texel_weights` obtains W once on
a θ grid by integrating, with the one integrator :func:`preintegrate.quadrature.directional_albedo`, the
cardinal functions of a local cubic (four-point Lagrange) interpolation in θ; every model's table, for
every material at once, is then a matrix product. Two checks travel with the result: W against the LUT
channels the engine ships (basis and Schlick, :func:`preintegrate.lut.build_table`), and W against
direct integration of the exact curve for the worst materials of each group.

Run: ``python -m fresnel_lut.report.model_error [--quick] [--size N] [--png FILE] [--markdown FILE]``.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 2 (F̄), eq. 4 (F ≈ Σ c_k b_k), eq. 5 (F̄ = Σ c_k b̄_k).
:cite:`Schlick1994` Computer Graphics Forum 13(3), eq. 15. :cite:`Karis2013` (split sum F̄ = F0 R + G).
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from basis.angles import check_theta_grid, cos_theta, trapezoid_weights
from basis.coefficients import coefficients_from_nk
from basis.eigenbasis import Basis, resolve_basis
from basis.fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_conductor, fresnel_kernel
from basis.models.formulas import schlick_curve
from basis.storage import write_text
from basis.training import holdout_materials
from basis.validation import ParameterError, check_choice, check_positive_int, check_range
from preintegrate.channels import basis_channels, combine, schlick_channels
from preintegrate.ggx import roughness_to_alpha
from preintegrate.lut import LutGrid, build_table, lut_texel_weights
from preintegrate.quadrature import DEFAULT_ORDER, directional_albedo

from .figures import pyplot, save_figure

__all__ = [
    "QUICK",
    "REPRESENTATIONS",
    "Representation",
    "representation",
    "curve_error_vs_cost",
    "model_error_markdown",
    "model_error_study",
    "plot_model_error",
    "preintegrated_error",
]

#: Settings of ``quick=True`` (replacing the arguments): a few materials per group, a 32 × 32 table.
QUICK = {"materials_per_group": 12, "size": 32, "evaluations": 100_000, "repeats": 3, "theta_samples": 1025}

#: One 8-bit step: the report's target for F̄ of every metal with the basis.
EIGHT_BIT_STEP = 1.0 / 255.0


def _checked_nk(eta, kappa) -> tuple[np.ndarray, np.ndarray]:
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    return np.broadcast_arrays(eta, kappa)


def _exact_parameters(eta, kappa, basis: Basis) -> np.ndarray:
    return np.stack(_checked_nk(eta, kappa), axis=-1)


def _exact_curve(mu: np.ndarray, parameters: np.ndarray, basis: Basis) -> np.ndarray:
    return fresnel_kernel(mu, parameters[..., 0], parameters[..., 1])


def _schlick_parameters(eta, kappa, basis: Basis) -> np.ndarray:
    eta, kappa = _checked_nk(eta, kappa)
    return fresnel_kernel(np.ones_like(eta), eta, kappa)[..., None]


def _schlick_curve(mu: np.ndarray, parameters: np.ndarray, basis: Basis) -> np.ndarray:
    return schlick_curve(mu, parameters[..., 0])


def _basis_curve(mu: np.ndarray, parameters: np.ndarray, basis: Basis) -> np.ndarray:
    """Σ_k c_k b_k(arccos μ), the cubic spline of the basis in θ (what a 1-D texture holds)."""
    return np.einsum("...k,...k->...", parameters, basis.spline(np.arccos(mu)))


def _fitted(fit: str) -> Callable[[np.ndarray, np.ndarray, Basis], np.ndarray]:
    def parameters(eta, kappa, basis: Basis) -> np.ndarray:
        return coefficients_from_nk(eta, kappa, basis, fit=fit)

    return parameters


@dataclasses.dataclass(frozen=True)
class Representation:
    """How a renderer represents a material (η, κ): per-material parameters, the per-sample curve and its
    shader cost.

    Attributes
    ----------
    name : str
        Registry key.
    description : str
        The formula in words, for tables and legends.
    parameters : callable
        (eta, kappa, basis) → (..., P) what a renderer stores per material and colour channel.
    curve : callable
        (mu, parameters, basis) → (...) F(μ); unchecked, μ in [0, 1] broadcast against the materials.
    lut_channels : int, "basis" or None
        LUT channels a shader fetches for F̄: a count, "basis" for ``basis.n_terms``, ``None`` if the
        model has no shared split-sum LUT.
    """

    name: str
    description: str
    parameters: Callable[[np.ndarray, np.ndarray, Basis], np.ndarray]
    curve: Callable[[np.ndarray, np.ndarray, Basis], np.ndarray]
    lut_channels: int | str | None

    def shader_terms(self, basis: Basis | None = None) -> int | None:
        """Number of LUT channels (multiply-adds per colour channel) a shader needs for F̄."""
        if self.lut_channels == "basis":
            return resolve_basis(basis).n_terms
        return self.lut_channels

    def evaluate(self, mu, material, basis: Basis | None = None) -> np.ndarray:
        """F(μ) of ``material = (eta, kappa)``; μ broadcast against the material arrays.

        Parameters
        ----------
        mu : array_like
            Cosine of the angle of incidence, in [0, 1].
        material : tuple of array_like
            (η, κ), η in [1e-8, 1e6], κ in [0, 1e6], broadcast against each other.
        basis : Basis, optional
            Basis of the ``basis-*`` models; default the shipped one.

        Examples
        --------
        >>> round(float(REPRESENTATIONS["schlick"].evaluate(1.0, (1.5, 0.0))), 12)
        0.04
        """
        basis = resolve_basis(basis)
        if not isinstance(material, (tuple, list)) or len(material) != 2:
            raise ParameterError(f"material must be a pair (eta, kappa), got {type(material).__name__}")
        mu = check_range("mu", mu, 0.0, 1.0)
        return self.curve(mu, self.parameters(material[0], material[1], basis), basis)


#: Registry: name → representation; the report's rows are one lookup here.
REPRESENTATIONS: dict[str, Representation] = {
    "exact": Representation(
        "exact", "Fresnel equations of eta + i kappa (Hoffman 2020)", _exact_parameters, _exact_curve, None
    ),
    "schlick": Representation(
        "schlick", "Schlick 1994, F0 from the exact curve", _schlick_parameters, _schlick_curve, 2
    ),
    "basis-4point": Representation(
        "basis-4point",
        "eigen-basis, four-point coefficients (Belcour 2020)",
        _fitted("four-point"),
        _basis_curve,
        "basis",
    ),
    "basis-lsq": Representation(
        "basis-lsq",
        "eigen-basis, L2 least squares over theta, F0 and F90 exact",
        _fitted("least-squares"),
        _basis_curve,
        "basis",
    ),
    "basis-minimax": Representation(
        "basis-minimax",
        "eigen-basis, Lawson-reweighted least squares (max norm), F0 and F90 exact",
        _fitted("minimax"),
        _basis_curve,
        "basis",
    ),
}


def representation(name: str) -> Representation:
    """Look up a model by name; the error lists the valid names.

    Examples
    --------
    >>> representation("schlick").shader_terms()
    2
    """
    return REPRESENTATIONS[check_choice("representation", name, sorted(REPRESENTATIONS))]


# ---------------------------------------------------------------------------------------- inputs
def _groups(groups, quick: bool) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Validated (η, κ) groups; in quick mode each is thinned to ``QUICK["materials_per_group"]``."""
    groups = holdout_materials() if groups is None else groups
    if not isinstance(groups, dict) or not groups:
        raise ParameterError(f"groups must be a non-empty dict of name -> (eta, kappa), got {type(groups).__name__}")
    checked = {}
    for name, material in groups.items():
        if not isinstance(material, (tuple, list)) or len(material) != 2:
            raise ParameterError(f"groups[{name!r}] must be a pair (eta, kappa)")
        eta = check_range(f"groups[{name!r}] eta", material[0], *ETA_RANGE)
        kappa = check_range(f"groups[{name!r}] kappa", material[1], *KAPPA_RANGE)
        eta, kappa = (np.ravel(array) for array in np.broadcast_arrays(eta, kappa))
        if quick and eta.size > QUICK["materials_per_group"]:
            keep = np.unique(np.linspace(0, eta.size - 1, QUICK["materials_per_group"]).round().astype(int))
            eta, kappa = eta[keep], kappa[keep]
        checked[str(name)] = (eta, kappa)
    return checked


def _models(models) -> dict[str, Representation]:
    names = list(REPRESENTATIONS) if models is None else models
    if isinstance(names, str) or not isinstance(names, Sequence) or not names:
        raise ParameterError(f"models must be a non-empty sequence of names from {sorted(REPRESENTATIONS)}")
    return {name: representation(name) for name in names}


def _dense_theta(samples: int) -> np.ndarray:
    """``samples`` angles uniform in θ on [0, π/2] plus ``samples // 8`` at μ geometric from 1e-7 to 0.1."""
    samples = check_positive_int("theta_samples", samples, low=16, high=1 << 22)
    grazing = np.arccos(np.geomspace(1e-7, 0.1, samples // 8))
    return np.unique(np.concatenate([np.linspace(0.0, 0.5 * np.pi, samples), grazing]))


def _material(eta: np.ndarray, kappa: np.ndarray, index: int) -> dict:
    return {"index": index, "eta": float(eta[index]), "kappa": float(kappa[index])}


# ------------------------------------------------------------------------------------- study 2
def _best_seconds(function: Callable[[], object], repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return best


def curve_error_vs_cost(
    groups=None,
    models: Sequence[str] | None = None,
    basis: Basis | None = None,
    theta_samples: int = 4097,
    evaluations: int = 1_000_000,
    repeats: int = 5,
    quick: bool = False,
    seed: int = 5,
) -> dict:
    """Study 2: curve error over θ and evaluation cost of every model on every group.

    Parameters
    ----------
    groups : dict, optional
        name → (η, κ) arrays; default :func:`basis.training.holdout_materials`.
    models : sequence of str, optional
        Names from :data:`REPRESENTATIONS`; default all.
    basis : Basis, optional
        Basis of the ``basis-*`` models; default the shipped one.
    theta_samples : int
        Uniform θ samples of the dense grid (plus ``theta_samples // 8`` towards grazing), in [16, 2^22].
    evaluations : int
        Evaluations per timing run, in [1000, 10^8]; each has its own μ and material.
    repeats : int
        Timing runs; the best is kept. In [1, 100].
    quick : bool
        Use :data:`QUICK` instead of ``theta_samples``, ``evaluations``, ``repeats`` and thin the groups.
    seed : int
        Seed of the timing inputs (random μ and materials).

    Returns
    -------
    dict
        ``theta_samples`` (size of the dense grid), ``evaluations``, ``repeats``, ``seconds``, ``groups``
        (name → count) and ``models``: name → ``description``, ``shader_terms``, ``parameters`` (stored
        per material and colour channel), ``ns_per_evaluation``, ``ns_per_material_setup`` and
        ``groups``: name → ``max_worst``, ``max_mean``, ``rms_worst``, ``rms_mean``, ``worst_material``
        (η, κ, θ of the largest |ΔF|) and ``max_per_material`` (list).
    """
    started = time.perf_counter()
    if quick:
        theta_samples, evaluations, repeats = QUICK["theta_samples"], QUICK["evaluations"], QUICK["repeats"]
    groups = _groups(groups, quick)
    models = _models(models)
    basis = resolve_basis(basis)
    evaluations = check_positive_int("evaluations", evaluations, low=1000, high=10**8)
    repeats = check_positive_int("repeats", repeats, low=1, high=100)
    theta = _dense_theta(theta_samples)
    mu = cos_theta(theta)
    rms_weights = trapezoid_weights(theta) / (0.5 * np.pi)

    all_eta = np.concatenate([eta for eta, _ in groups.values()])
    all_kappa = np.concatenate([kappa for _, kappa in groups.values()])
    rng = np.random.default_rng(seed)
    timing_materials = rng.integers(0, all_eta.size, evaluations)
    timing_mu = rng.uniform(0.0, 1.0, evaluations)

    result_models = {}
    exact = REPRESENTATIONS["exact"]
    for name, model in models.items():
        entry = {"description": model.description, "shader_terms": model.shader_terms(basis), "groups": {}}
        for group, (eta, kappa) in groups.items():
            reference = exact.curve(mu, exact.parameters(eta, kappa, basis)[:, None, :], basis)
            parameters = model.parameters(eta, kappa, basis)
            difference = np.abs(model.curve(mu, parameters[:, None, :], basis) - reference)
            maximum = difference.max(axis=1)
            rms = np.sqrt(difference**2 @ rms_weights)
            worst = int(np.argmax(maximum))
            entry["groups"][group] = {
                "count": int(eta.size),
                "max_worst": float(maximum[worst]),
                "max_mean": float(maximum.mean()),
                "rms_worst": float(rms.max()),
                "rms_mean": float(rms.mean()),
                "worst_material": {**_material(eta, kappa, worst), "theta": float(theta[np.argmax(difference[worst])])},
                "max_per_material": maximum.tolist(),
            }
        # cost: set-up per material (parameters), then F(μ) with one μ and one material per evaluation
        setup = _best_seconds(lambda: model.parameters(all_eta, all_kappa, basis), repeats)
        stored = model.parameters(all_eta, all_kappa, basis)[timing_materials]
        model.curve(timing_mu[:1000], stored[:1000], basis)  # warm-up (spline set-up, caches)
        seconds = _best_seconds(lambda: model.curve(timing_mu, stored, basis), repeats)
        entry.update(
            parameters=int(stored.shape[-1]),
            ns_per_evaluation=1e9 * seconds / evaluations,
            ns_per_material_setup=1e9 * setup / all_eta.size,
        )
        result_models[name] = entry
    return {
        "theta_samples": int(theta.size),
        "evaluations": evaluations,
        "repeats": repeats,
        "groups": {name: int(eta.size) for name, (eta, _) in groups.items()},
        "models": result_models,
        "seconds": time.perf_counter() - started,
    }


# ------------------------------------------------------------------------------------- study 3
def preintegrated_error(
    groups=None,
    models: Sequence[str] | None = None,
    basis: Basis | None = None,
    size: int = 64,
    order=DEFAULT_ORDER,
    theta_grid=None,
    quick: bool = False,
    reference_materials: int = 3,
) -> dict:
    """Study 3: max over the texel grid of |F̄_model − F̄_exact| for every model, group and material.

    Parameters
    ----------
    groups, models, basis
        As in :func:`curve_error_vs_cost`; the ``exact`` model, the reference, is skipped.
    size : int
        Table width = height on the LUT texel grid (:meth:`preintegrate.lut.LutGrid.centred`), in [2, 1024].
    order : QuadratureOrder, optional
        Integrator node counts (default: the LUT build's).
    theta_grid : array_like, optional
        θ grid of the texel weights; default ``basis.theta``.
    quick : bool
        Thin the groups and use a ``QUICK["size"]`` table.
    reference_materials : int
        Per group, how many of the worst materials (over all models) are integrated directly to check
        the texel weights' F̄_exact, in [0, 32].

    Returns
    -------
    dict
        ``size``, ``theta_grid_size``, ``weights_seconds`` (time of :func:`preintegrate.lut.lut_texel_weights`),
        ``lut_check`` (max |W·f − LUT| over the basis and Schlick channels of :func:`build_table`,
        and its seconds), ``reference_check`` (group → max |W·F − direct| over its checked materials),
        ``groups`` (name → count), ``models``: name → group → ``max_worst``, ``max_mean``,
        ``above_8bit`` (materials with max > 1/255), ``worst_material`` (η, κ, μo, roughness of the
        largest |ΔF̄|) and ``max_per_material`` (list); and ``seconds``.
    """
    started = time.perf_counter()
    if quick:
        size = QUICK["size"]
    size = check_positive_int("size", size, low=2, high=1024)
    reference_materials = check_positive_int("reference_materials", reference_materials, low=0, high=32)
    groups = _groups(groups, quick)
    models = {name: model for name, model in _models(models).items() if name != "exact"}
    basis = resolve_basis(basis)
    theta_grid = basis.theta if theta_grid is None else check_theta_grid("theta_grid", theta_grid)
    mu_grid = cos_theta(theta_grid)
    grid = LutGrid.centred(size)
    mu_o, roughness = grid.mu_o, grid.roughness
    alpha = roughness_to_alpha(roughness)

    start = time.perf_counter()
    weights = lut_texel_weights(theta_grid, grid, order)
    weights_seconds = time.perf_counter() - start

    # W against the engine's channel tables: the same functionals through the LUT builder.
    start = time.perf_counter()
    channels = combine(basis_channels(basis), schlick_channels())
    table = build_table(channels, grid, order=order).reshape(size * size, -1)
    lut_check = {
        "channels": f"{channels.name} ({', '.join(channels.channel_names)})",
        "max_abs_difference": float(np.max(np.abs(weights @ channels.functions(mu_grid) - table))),
        "seconds": time.perf_counter() - start,
    }

    exact = REPRESENTATIONS["exact"]
    result_models: dict[str, dict] = {name: {} for name in models}
    reference_check = {}
    for group, (eta, kappa) in groups.items():
        exact_bar = exact.curve(mu_grid, exact.parameters(eta, kappa, basis)[:, None, :], basis) @ weights.T
        worst_indices = []
        for name, model in models.items():
            curve = model.curve(mu_grid, model.parameters(eta, kappa, basis)[:, None, :], basis)
            difference = np.abs(curve @ weights.T - exact_bar)  # (materials, texels)
            maximum = difference.max(axis=1)
            order_of_worst = np.argsort(maximum)[::-1]
            worst = int(order_of_worst[0])
            row, column = divmod(int(np.argmax(difference[worst])), size)
            result_models[name][group] = {
                "count": int(eta.size),
                "max_worst": float(maximum[worst]),
                "max_mean": float(maximum.mean()),
                "above_8bit": int(np.count_nonzero(maximum > EIGHT_BIT_STEP)),
                "worst_material": {
                    **_material(eta, kappa, worst),
                    "mu_o": float(mu_o[column]),
                    "roughness": float(roughness[row]),
                },
                "max_per_material": maximum.tolist(),
            }
            worst_indices += order_of_worst[:reference_materials].tolist()
        if worst_indices:
            chosen = np.unique(worst_indices)
            direct = directional_albedo(
                lambda x, chosen=chosen: fresnel_conductor(x[..., None], eta[chosen], kappa[chosen]),
                mu_o[None, :],
                alpha[:, None],
                order=order,
            ).reshape(size * size, -1)
            reference_check[group] = {
                "materials": int(chosen.size),
                "max_abs_difference": float(np.max(np.abs(exact_bar[chosen].T - direct))),
            }
    return {
        "size": size,
        "theta_grid_size": int(theta_grid.size),
        "weights_seconds": weights_seconds,
        "lut_check": lut_check,
        "reference_check": reference_check,
        "groups": {name: int(eta.size) for name, (eta, _) in groups.items()},
        "models": result_models,
        "seconds": time.perf_counter() - started,
    }


def model_error_study(quick: bool = False, size: int = 64, evaluations: int = 1_000_000, groups=None) -> dict:
    """Both studies on the same groups: ``{"curve": …, "preintegrated": …, "seconds": …}``."""
    started = time.perf_counter()
    curve = curve_error_vs_cost(groups, evaluations=evaluations, quick=quick)
    preintegrated = preintegrated_error(groups, size=size, quick=quick)
    return {"curve": curve, "preintegrated": preintegrated, "quick": quick, "seconds": time.perf_counter() - started}


# ------------------------------------------------------------------------------------- output
def _cell(entry: dict, key: str) -> str:
    return f"{entry[f'{key}_worst']:.2e} ({entry[f'{key}_mean']:.1e})"


def model_error_markdown(result: dict) -> str:
    """Markdown tables of :func:`model_error_study`'s result: curve error and cost, then preintegrated error."""
    curve, preintegrated = result["curve"], result["preintegrated"]
    groups = list(curve["groups"])
    heading = " | ".join(f"{group} ({curve['groups'][group]})" for group in groups)
    rule = "|---|" + "---:|" * len(groups)
    lines = [
        f"**Curve error** (study 2): max over θ of |F_model − F_exact|, worst (mean) over each group's materials; "
        f"dense grid of {curve['theta_samples']} angles. Cost: vectorised numpy, one μ and one material per "
        f"evaluation, best of {curve['repeats']} runs of {curve['evaluations']:,} evaluations.",
        "",
        f"| model | {heading} | ns / evaluation | set-up ns / material | stored parameters | LUT channels |",
        rule + "---:|---:|---:|---:|",
    ]
    for name, entry in curve["models"].items():
        cells = " | ".join(_cell(entry["groups"][group], "max") for group in groups)
        terms = "—" if entry["shader_terms"] is None else str(entry["shader_terms"])
        lines.append(
            f"| {name} | {cells} | {entry['ns_per_evaluation']:.1f} | {entry['ns_per_material_setup']:.0f} | "
            f"{entry['parameters']} | {terms} |"
        )
    lines += [
        "",
        "RMS over θ (trapezoid weights in θ) of |F_model − F_exact|, worst (mean) over materials:",
        "",
        f"| model | {heading} |",
        rule,
    ]
    for name, entry in curve["models"].items():
        lines.append(f"| {name} | " + " | ".join(_cell(entry["groups"][group], "rms") for group in groups) + " |")

    size = preintegrated["size"]
    lines += [
        "",
        f"**Preintegrated error** (study 3): max over the {size} × {size} LUT texel grid (μo, r; α = r²) of "
        f"|F̄_model − F̄_exact|, worst (mean) over materials, [materials above 1/255 / count]. Texel weights on "
        f"{preintegrated['theta_grid_size']} θ samples in {preintegrated['weights_seconds']:.1f} s.",
        "",
        f"| model | {heading} |",
        rule,
    ]
    for name, per_group in preintegrated["models"].items():
        cells = " | ".join(
            f"{_cell(per_group[group], 'max')} [{per_group[group]['above_8bit']}/{per_group[group]['count']}]"
            for group in groups
        )
        lines.append(f"| {name} | {cells} |")
    lines += [
        "",
        "Worst material per model and group (preintegrated):",
        "",
        "| model | group | η | κ | max \\|ΔF̄\\| | at μo | at r | same material: max \\|ΔF\\| over θ |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for name, per_group in preintegrated["models"].items():
        for group in groups:
            entry = per_group[group]
            material = entry["worst_material"]
            curve_entry = curve["models"].get(name, {}).get("groups", {}).get(group)
            curve_text = "" if curve_entry is None else f"{curve_entry['max_per_material'][material['index']]:.2e}"
            lines.append(
                f"| {name} | {group} | {material['eta']:.4g} | {material['kappa']:.4g} | {entry['max_worst']:.2e} | "
                f"{material['mu_o']:.3f} | {material['roughness']:.3f} | {curve_text} |"
            )
    checks = ", ".join(
        f"{group} {check['max_abs_difference']:.1e} ({check['materials']} materials)"
        for group, check in preintegrated["reference_check"].items()
    )
    lines += [
        "",
        f"Checks: texel weights vs the LUT channels {preintegrated['lut_check']['channels']} "
        f"max |Δ| = {preintegrated['lut_check']['max_abs_difference']:.1e}; F̄_exact by texel weights vs direct "
        f"integration of the worst materials: {checks}. Times: curve study {curve['seconds']:.1f} s, "
        f"preintegrated study {preintegrated['seconds']:.1f} s, total {result['seconds']:.1f} s.",
    ]
    return "\n".join(lines) + "\n"


def _strip(axes, per_group: dict, groups: list[str], names: list[str], colours: dict) -> None:
    """Per-material values as dots, the group's worst as a large diamond, models side by side per group."""
    width = 0.8 / len(names)
    rng = np.random.default_rng(0)
    for k, name in enumerate(names):
        for g, group in enumerate(groups):
            entry = per_group[name][group]
            values = np.asarray(entry["max_per_material"])
            values = values[values > 0.0]  # log axis
            centre = g - 0.4 + (k + 0.5) * width
            axes.scatter(
                centre + rng.uniform(-0.3, 0.3, values.size) * width,
                values,
                s=5,
                alpha=0.45,
                color=colours[name],
                linewidths=0,
            )
            if values.size:
                axes.scatter(
                    [centre],
                    [entry["max_worst"]],
                    s=45,
                    marker="D",
                    color=colours[name],
                    edgecolors="black",
                    linewidths=0.6,
                    zorder=3,
                    label=name if g == 0 else None,
                )
    for g in range(1, len(groups)):
        axes.axvline(g - 0.5, color="0.85", linewidth=0.8)
    axes.set_xticks(range(len(groups)))
    axes.set_xticklabels(
        [f"{group}\n({len(per_group[names[0]][group]['max_per_material'])} materials)" for group in groups]
    )
    axes.set_xlim(-0.5, len(groups) - 0.5)
    axes.set_yscale("log")
    axes.grid(True, axis="y", which="major", alpha=0.4)


def plot_model_error(result: dict, path=None) -> Path | bytes:
    """Write a PNG: curve error and preintegrated error per model and group, and cost against error.

    Written to a temporary sibling (its folder is created if missing) and renamed into place. Needs
    matplotlib (the ``plot`` extra).
    """
    plt = pyplot()
    curve, preintegrated = result["curve"], result["preintegrated"]
    groups = list(curve["groups"])
    names = [name for name in curve["models"] if name != "exact"]
    colours = {name: f"C{k}" for k, name in enumerate(curve["models"])}
    figure, (left, middle, right) = plt.subplots(
        1, 3, figsize=(18.0, 6.0), dpi=130, gridspec_kw={"width_ratios": [1.25, 1.25, 0.85]}
    )

    _strip(left, {name: curve["models"][name]["groups"] for name in names}, groups, names, colours)
    left.set_ylabel("max over θ of |F_model − F_exact|  (reflectance, unitless)")
    left.set_title("Study 2: curve error, per material (dots) and worst (◆)", fontsize=10)

    shown = [name for name in names if name in preintegrated["models"]]
    _strip(middle, preintegrated["models"], groups, shown, colours)
    middle.axhline(EIGHT_BIT_STEP, color="0.2", linestyle=":", linewidth=1.2, label="1/255 (one 8-bit step)")
    size = preintegrated["size"]
    middle.set_ylabel(f"max over {size}×{size} LUT texels (μo, r) of |F̄_model − F̄_exact|")
    middle.set_title("Study 3: GGX-preintegrated (split-sum) error, per material and worst", fontsize=10)
    bottom = min(left.get_ylim()[0], middle.get_ylim()[0])
    for axes in (left, middle):
        axes.set_ylim(bottom, 1.5)
        axes.legend(fontsize=8, loc="lower right", framealpha=0.95)

    ordinary = [group for group in ("dielectrics", "metals") if group in groups] or groups
    markers = {"exact": "o", "schlick": "s"}
    # what a shader pays for F̄: one LUT fetch and one multiply-add per stored channel and colour channel
    for offset, (name, per_group) in enumerate(preintegrated["models"].items()):
        terms = curve["models"][name]["shader_terms"]
        error = max(per_group[group]["max_worst"] for group in ordinary)
        right.scatter(
            [terms + 0.08 * (offset - 2)],
            [error],
            s=60,
            marker=markers.get(name, "D"),
            color=colours[name],
            edgecolors="black",
            linewidths=0.6,
            zorder=3,
            label=f"{name}: 1 fetch, {terms} multiply-adds per colour channel",
        )
    right.set_title(
        "Shader cost vs preintegrated error\n(exact: no shared LUT, the Fresnel equations per light sample)", fontsize=9
    )
    right.set_xticks([2, 4])
    right.set_xlim(1, 5)
    right.set_yscale("log")
    right.set_xlabel("LUT channels = multiply-adds per colour channel (1 fetch)")
    right.set_ylabel(f"worst max |ΔF̄| over the LUT, {' + '.join(ordinary)}")
    right.margins(y=0.4)
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=7.5, loc="center", framealpha=0.95)
    figure.suptitle(
        "Fresnel models on held-out materials (basis/training/holdout.py): curve error, preintegrated error, shader cost",
        fontsize=11,
    )
    figure.tight_layout()
    return save_figure(figure, path)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        description="Fresnel models: curve error vs cost, preintegrated error (report studies 2, 3)."
    )
    parser.add_argument("--quick", action="store_true", help="a few materials per group, 32 x 32 table")
    parser.add_argument("--size", type=int, default=64, help="table size of study 3 (default 64)")
    parser.add_argument("--png", type=Path, default=None, help="write the figure here")
    parser.add_argument("--markdown", type=Path, default=None, help="also write the tables here")
    arguments = parser.parse_args(argv)
    result = model_error_study(quick=arguments.quick, size=arguments.size)
    text = model_error_markdown(result)
    print(text)
    if arguments.markdown is not None:
        write_text(arguments.markdown, text)
    if arguments.png is not None:
        print(f"plot: {plot_model_error(result, arguments.png)}")


if __name__ == "__main__":
    main()
