"""Deterministic split-sum quadrature of any functions of cos θ_d = ω_o·h against GGX.

Public objects: ``directional_albedo``, ``texel_weights``, ``QuadratureOrder``, ``QuadratureSchedule``,
``DEFAULT_ORDER``, ``LagrangeCardinals``, ``lagrange_cardinals``.

Two methods side by side, as colour's ``sd_to_XYZ_integration`` beside its precomputed weighting factors:
:func:`directional_albedo` integrates *given functions*; :func:`texel_weights` integrates once the
cardinal functions of an interpolation on a θ grid, after which any curve *given by samples* on that grid
costs one matrix product.

For a set of functions f_k of x = ω_o·h,

    F̄_k(μo, α) = ∫ f_k(ω_o·h) ρ(ω_o, ω_i) μ_i dω_i,   ρ = D(h) G2(ω_o, ω_i) / (4 μo μi),

which is the talk's eq. 2 with the height-correlated G2. Changing variables to the half vector
(dω_i = 4 (ω_o·h) dω_h) and to GGX's inverse-CDF coordinates (u = sin²θ', tan θ_h = α tan θ',
D μ_h dω_h = du dφ / 2π) gives, with the integrand symmetric in φ,

    F̄_k = (1/π) ∫∫ f_k(x) · 2 μ_i x · 2 sin θ' √(α² sin²θ' + cos²θ') / (μ_i Ro + μo Ri) dθ' dφ,

with μ_i = 2 x μ_h − μo and R = √(μ² + α²(1 − μ²)). Every factor is smooth; the only obstacle to
spectral convergence is the cut μ_i > 0, where the reflected direction goes under the horizon. For
fixed θ_h the cut is cos φ > c*(θ_h) = −μo cos 2θ_h / (sin θo sin 2θ_h), so the domain splits
exactly at θ_h = (π/2 − θo)/2 (below: the whole circle is visible) and θ_h = (π/2 + θo)/2 (above:
nothing is):

* piece A, θ' ∈ [0, θ'_A], φ ∈ [0, π]: a smooth periodic integrand — Gauss–Legendre in
  v = asinh(tan θ') and the midpoint rule in φ (spectral for periodic functions);
* piece B, θ' ∈ [θ'_A, θ'_B], φ ∈ [0, arccos c*]: the inner integral has (v − v0)^{3/2} end-point
  behaviour, removed by the smoothstep map v = v_A + (v_B − v_A)(3s² − 2s³); then Gauss–Legendre in
  s and in φ / φ_max.

The variable v is θ' near the normal and log(2 tan θ') far from it: tan θ_h = α tan θ' squeezes all
θ_h ≫ α into a sliver of width ~α below θ' = π/2, which v opens up to width ~log(1/α).

No Monte Carlo, no noise; the error falls exponentially with the order (see the report).
α = 0 is the mirror limit F̄_k = f_k(μo).

References
----------
:cite:`Belcour2020` eq. 2. :cite:`Karis2013` B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH
2013 course notes (split sum). :cite:`Heitz2014` JCGT 3(2), eq. 72, 99. :cite:`Walter2007` eq. 35
(GGX sampling θ_h = atan(α √(u / (1 − u)))).
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
from collections.abc import Callable

import numpy as np

from basis.angles import check_theta_grid
from basis.parallel import one_blas_thread, worker_count
from basis.validation import ParameterError, check_choice, check_positive_int, check_range

from .ggx import VISIBILITIES, g1, g1_over_mu, g2_denominator

__all__ = [
    "DEFAULT_ORDER",
    "LagrangeCardinals",
    "QuadratureOrder",
    "QuadratureSchedule",
    "directional_albedo",
    "lagrange_cardinals",
    "texel_weights",
]


@dataclasses.dataclass(frozen=True)
class QuadratureOrder:
    """Node counts: v and φ in piece A (full circle), v and φ in piece B (cut by the horizon).

    v = asinh(tan θ') is θ' near the normal and log(2 tan θ') far from it (see the module notes).
    """

    theta_a: int = 32
    phi_a: int = 32
    theta_b: int = 32
    phi_b: int = 32

    def __post_init__(self):
        for field in dataclasses.fields(self):
            check_positive_int(f"order.{field.name}", getattr(self, field.name), low=1, high=4096)

    @classmethod
    def uniform(cls, order: int) -> "QuadratureOrder":
        """The same node count on every axis."""
        return cls(order, order, order, order)

    @property
    def nodes_per_texel(self) -> int:
        return self.theta_a * self.phi_a + self.theta_b * self.phi_b

    def describe(self) -> str:
        return (
            f"{self.nodes_per_texel} nodes per texel: piece A {self.theta_a}x{self.phi_a} (Gauss-Legendre in v = asinh(tan theta') x midpoint in phi), "
            f"piece B {self.theta_b}x{self.phi_b} (smoothstep Gauss-Legendre in v x Gauss-Legendre in phi)"
        )


@dataclasses.dataclass(frozen=True)
class QuadratureSchedule:
    """Node counts by texel, in three tiers.

    * ``extreme`` for μo < ``extreme_below`` (the first column of a 128-wide LUT, two of a 256-wide) or
      α < ``mirror_below``;
    * ``stiff`` for μo < ``grazing_below`` or α < ``smooth_below``;
    * ``regular`` elsewhere.

    Near grazing, and for nearly smooth surfaces, the pieces span a long range of v (≈ log(1/α) and
    more) and need more θ' nodes; elsewhere fewer nodes reach the same error. Measured against an
    independent quadrature over the incident direction at every texel of the 128 × 128 LUT grid
    (``tests.references.integration.reference_albedo_grid``, itself within 1.7e-8 of a uniform order 128 of
    this one), the default schedule stays within 4.7e-8 on the Schlick table's four channels, below float32's
    half step, with the nodes of a uniform order 28 on average. (The earlier schedule, regular 20 × 12 and
    stiff tiers up to α < 1e-4, missed by 1.4e-6 at μo = 1, α ≈ 0.02, where a narrow lobe seen head-on needs
    more θ' nodes: issue 39. A denser one, regular 28 × 16 and stiff to α < 0.2, reached 1.9e-8 at twice the
    time, beyond the report's 2 s for the table.)
    """

    regular: QuadratureOrder = QuadratureOrder(24, 12, 24, 16)
    stiff: QuadratureOrder = QuadratureOrder(40, 16, 40, 24)
    extreme: QuadratureOrder = QuadratureOrder(96, 24, 96, 32)
    grazing_below: float = 0.1
    smooth_below: float = 0.1
    extreme_below: float = 1e-2
    mirror_below: float = 1e-6

    @classmethod
    def uniform(cls, order: QuadratureOrder) -> "QuadratureSchedule":
        """The same order for every texel."""
        return cls(order, order, order)

    def scaled(self, factor: float) -> "QuadratureSchedule":
        """Every node count multiplied by ``factor`` (rounded, at least 2): a cheaper or dearer schedule."""

        def scale(order: QuadratureOrder) -> QuadratureOrder:
            return QuadratureOrder(
                *(max(2, int(round(getattr(order, field.name) * factor))) for field in dataclasses.fields(order))
            )

        return dataclasses.replace(
            self, regular=scale(self.regular), stiff=scale(self.stiff), extreme=scale(self.extreme)
        )

    def tiers(self, mu_o: np.ndarray, alpha: np.ndarray) -> list[tuple[np.ndarray, QuadratureOrder]]:
        """(mask, order) for each tier; the masks partition the texels."""
        extreme = (mu_o < self.extreme_below) | (alpha < self.mirror_below)
        stiff = ~extreme & ((mu_o < self.grazing_below) | (alpha < self.smooth_below))
        return [(~extreme & ~stiff, self.regular), (stiff, self.stiff), (extreme, self.extreme)]

    def describe(self) -> str:
        return (
            f"mu_o < {self.extreme_below:g} or alpha < {self.mirror_below:g}: {self.extreme.describe()}; "
            f"mu_o < {self.grazing_below:g} or alpha < {self.smooth_below:g}: {self.stiff.describe()}; "
            f"elsewhere: {self.regular.describe()}"
        )


DEFAULT_ORDER = QuadratureSchedule()

#: Smallest positive α integrated as given (α² stays a normal float64).
ALPHA_FLOOR = 1e-150

#: Upper bound of v = asinh(tan θ'): beyond it the measure sech²v is below 1e-30.
V_MAX = 35.0


def _gauss_legendre_unit(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on [0, 1]."""
    nodes, weights = np.polynomial.legendre.leggauss(count)
    return 0.5 * (nodes + 1.0), 0.5 * weights


def _stretched_segment(low: np.ndarray, high: np.ndarray, count: int, smoothstep: bool):
    """Gauss–Legendre nodes in v = asinh(tan θ') on [low, high] → (sin θ', cos θ', weight in dθ'), each (T, n).

    tan θ_h = α tan θ' packs the whole range θ_h ≫ α into a sliver of width ~α below θ' = π/2; in v
    that sliver has width ~log(1/α), while near the normal v ≈ θ', so Gauss–Legendre converges at every
    α. θ' = gd(v): sin θ' = tanh v, cos θ' = sech v, dθ' = sech v dv.
    """
    nodes, weights = _gauss_legendre_unit(count)
    if smoothstep:  # v = low + (high − low)(3s² − 2s³): removes (v − v0)^{3/2} end-point behaviour
        position, slope = nodes * nodes * (3.0 - 2.0 * nodes), 6.0 * nodes * (1.0 - nodes)
    else:
        position, slope = nodes, np.ones_like(nodes)
    width = (high - low)[:, None]
    v = low[:, None] + width * position[None, :]
    cos_s = 1.0 / np.cosh(v)
    return np.tanh(v), cos_s, cos_s * width * (slope * weights)[None, :]


def _texel_pieces(mu_o: np.ndarray, alpha: np.ndarray, order: QuadratureOrder):
    """Nodes of pieces A and B for a flat batch of T texels.

    Returns two tuples (x = ω_o·h, μ_i, weight), each array broadcastable to (T, n_θ, n_φ).
    """
    sin_o = np.sqrt(np.maximum(1.0 - mu_o * mu_o, 0.0))[:, None, None]
    cos_o = mu_o[:, None, None]
    alpha_column = alpha[:, None]
    # Piece A ends at θ_h = (π/2 − θo)/2 = arcsin(μo)/2 (no cancellation at grazing), piece B at its
    # complement π/2 − arcsin(μo)/2, so tan θ_h,B = 1 / tan θ_h,A; tan θ' = tan θ_h / α.
    tan_a = np.tan(0.5 * np.arcsin(mu_o))
    with np.errstate(divide="ignore", over="ignore"):
        v_a = np.minimum(np.arcsinh(tan_a / alpha), V_MAX)
        v_b = np.minimum(np.arcsinh(1.0 / (tan_a * alpha)), V_MAX)
    v_b = np.maximum(v_b, v_a)

    def half_vector(sin_s, cos_s, weight):
        """sin θ_h, cos θ_h and the weight times the measure 2 sin θ' √(α² sin²θ' + cos²θ') (module notes)."""
        norm = np.sqrt((alpha_column * sin_s) ** 2 + cos_s**2)
        return (
            (alpha_column * sin_s / norm)[:, :, None],
            (cos_s / norm)[:, :, None],
            (weight * 2.0 * sin_s * norm)[:, :, None],
        )

    def piece(sin_h, mu_h, cos_phi, weight):
        x = sin_o * sin_h * cos_phi + cos_o * mu_h
        return np.clip(x, 0.0, 1.0), 2.0 * x * mu_h - cos_o, weight / np.pi

    # Piece A: the whole circle is above the horizon; midpoint rule in φ ∈ [0, π].
    sin_h, mu_h, weight = half_vector(*_stretched_segment(np.zeros_like(mu_o), v_a, order.theta_a, False))
    cos_phi = np.cos((np.arange(order.phi_a) + 0.5) * np.pi / order.phi_a)[None, None, :]
    piece_a = piece(sin_h, mu_h, cos_phi, weight * (np.pi / order.phi_a))
    # Piece B: cos φ > c* = −μo cos 2θ_h / (sin θo sin 2θ_h); Gauss–Legendre in φ / φ_max.
    sin_h, mu_h, weight = half_vector(*_stretched_segment(v_a, v_b, order.theta_b, True))
    with np.errstate(divide="ignore", invalid="ignore"):
        c_star = -cos_o * (mu_h * mu_h - sin_h * sin_h) / (sin_o * 2.0 * sin_h * mu_h)
    phi_max = np.arccos(np.clip(np.nan_to_num(c_star, nan=1.0, posinf=1.0, neginf=-1.0), -1.0, 1.0))
    s_phi, w_phi = _gauss_legendre_unit(order.phi_b)
    piece_b = piece(sin_h, mu_h, np.cos(phi_max * s_phi), weight * phi_max * w_phi)
    return piece_a, piece_b


def _kernel(mu_o: np.ndarray, alpha: np.ndarray, x: np.ndarray, mu_i: np.ndarray, visibility: str) -> np.ndarray:
    """x G2 / μo: the BRDF part of the integrand, 0 where μ_i ≤ 0 (arrays (T, …)); height-correlated as
    2 μ_i x / (μ_i Ro + μo Ri), separable as x G1(μi) G1(μo)/μo: both finite at μo = 0."""
    alpha = alpha.reshape((-1,) + (1,) * (x.ndim - 1))
    mu_i = np.maximum(mu_i, 0.0)
    if visibility == "separable":
        return x * g1(mu_i, alpha) * g1_over_mu(mu_o.reshape(alpha.shape), alpha)
    if visibility != "height-correlated":
        raise ParameterError(f"visibility {visibility!r} has no kernel here; known: {sorted(VISIBILITIES)}")
    denominator = g2_denominator(mu_o.reshape(alpha.shape), mu_i, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(denominator > 0.0, 2.0 * mu_i * x / np.where(denominator > 0.0, denominator, 1.0), 0.0)


def _integrate_batch(
    functions, mu_o: np.ndarray, alpha: np.ndarray, order: QuadratureOrder, visibility: str
) -> np.ndarray:
    """(T, K) directional albedos of one batch of rough texels."""
    total = 0.0
    for x, mu_i, weight in _texel_pieces(mu_o, alpha, order):
        weighted = (weight * _kernel(mu_o, alpha, x, mu_i, visibility)).reshape(len(mu_o), 1, -1)
        if isinstance(functions, LagrangeCardinals):  # four non-zero values per node: accumulate only those
            total = total + functions.integrate(x, weighted.reshape(len(mu_o), -1))
            continue
        values = functions(x)
        total = total + np.matmul(weighted, values.reshape(len(mu_o), weighted.shape[2], -1))[:, 0, :]
    return total


def directional_albedo(
    functions: Callable[[np.ndarray], np.ndarray],
    mu_o,
    alpha,
    order: QuadratureOrder | QuadratureSchedule = DEFAULT_ORDER,
    max_nodes: int = 500_000,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
    visibility: str = "height-correlated",
) -> np.ndarray:
    """F̄_k(μo, α) for every function f_k of cos θ_d = ω_o·h.

    Parameters
    ----------
    functions : callable
        Maps an array x in [0, 1] of any shape to values of shape x.shape + (K,).
    mu_o : array_like
        Cosine of the view angle, in [0, 1].
    alpha : array_like
        GGX width, in [0, 1]; broadcast against ``mu_o``.
    order : QuadratureOrder or QuadratureSchedule
        Node counts: one order for every texel, or a schedule by view angle (the default).
    max_nodes : int
        Bound on nodes evaluated at once (memory ≈ max_nodes × (8 + K) × 8 bytes).
    progress : callable, optional
        Called with (texels done, texels total).
    workers : int, optional
        Threads integrating batches of texels in parallel (default: the machine's cores). Each texel
        is computed the same way whatever the count, so results do not depend on it.
    visibility : {"height-correlated", "separable"}
        The Smith masking-shadowing form of the BRDF (:data:`preintegrate.ggx.VISIBILITIES`): an engine's
        table must match its own BRDF (the two differ by up to 0.15 at r = 0.8 near grazing).

    Returns
    -------
    numpy.ndarray
        Shape broadcast(mu_o, alpha).shape + (K,).
    """
    if not callable(functions):
        raise ParameterError(f"functions must be callable, got {type(functions).__name__}")
    check_choice("visibility", visibility, sorted(VISIBILITIES))
    mu_o = check_range("mu_o", mu_o, 0.0, 1.0)
    alpha = check_range("alpha", alpha, 0.0, 1.0)
    if isinstance(order, QuadratureOrder):
        order = QuadratureSchedule.uniform(order)
    if not isinstance(order, QuadratureSchedule):
        raise ParameterError(f"order must be a QuadratureOrder or QuadratureSchedule, got {type(order).__name__}")
    mu_o, alpha = np.broadcast_arrays(mu_o, alpha)
    shape = mu_o.shape
    mu_o, alpha = mu_o.ravel(), alpha.ravel()
    # Below 1e-150, α² underflows; the result there equals that at 1e-150 to far below float64 precision
    # unless μo is as small, and both are then outside any physical meaning.
    alpha = np.where(alpha > 0.0, np.maximum(alpha, ALPHA_FLOOR), 0.0)
    n_channels = np.shape(functions(np.array([0.5])))[-1]
    result = np.empty((mu_o.size, n_channels))
    mirror = alpha == 0.0
    if np.any(mirror):
        result[mirror] = functions(mu_o[mirror])
    batches = []
    for group, group_order in order.tiers(mu_o, alpha):
        texels = np.flatnonzero(group & ~mirror)
        batch = max(1, max_nodes // group_order.nodes_per_texel)
        batches += [(texels[start : start + batch], group_order) for start in range(0, texels.size, batch)]
    rough_count = int(np.count_nonzero(~mirror))
    workers = worker_count(workers)
    with one_blas_thread(), concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
        futures = [
            pool.submit(_integrate_batch, functions, mu_o[index], alpha[index], batch_order, visibility)
            for index, batch_order in batches
        ]
        try:
            done = 0
            for (index, _), future in zip(batches, futures):
                result[index] = future.result()
                done += index.size
                if progress is not None:
                    progress(done, rough_count)
        except BaseException:  # Ctrl-C or a failure: the queued batches never start (each running one is < 0.3 s)
            for future in futures:
                future.cancel()
            raise
    return result.reshape(shape + (n_channels,))


class LagrangeCardinals:
    """x ↦ (L_j(arccos x))_j, x.shape + (M,): cardinal functions of the four-point Lagrange interpolation.

    Between θ_i and θ_{i+1} the interpolant is the cubic through θ_{i−1} … θ_{i+2} (the stencil is
    shifted inwards at both ends), so Σ_j f(θ_j) L_j(θ) reproduces cubics in θ exactly and at most four
    L_j are non-zero at any θ: :meth:`stencil` gives those four, and :meth:`integrate` sums weighted
    nodes into the M channels without forming the mostly-zero (nodes × M) array.
    """

    def __init__(self, theta_grid: np.ndarray):
        self.theta_grid = theta_grid
        self.size = theta_grid.size
        # 1 / Π_{j ≠ i} (θ_i − θ_j) of every stencil θ_s … θ_{s+3}: (M − 3, 4)
        nodes = theta_grid[np.arange(self.size - 3)[:, None] + np.arange(4)]
        differences = np.where(_OFF_DIAGONAL, nodes[:, :, None] - nodes[:, None, :], 1.0)
        self._inverse_denominators = 1.0 / np.prod(differences, axis=-1)

    def stencil(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(indices, values), each x.shape + (4,): the non-zero cardinals at x and where they stand."""
        theta = np.arccos(np.clip(x, 0.0, 1.0))
        start = np.clip(np.searchsorted(self.theta_grid, theta, side="right") - 2, 0, self.size - 4)
        indices = start[..., None] + np.arange(4)
        # L_i(θ) = Π_{j ≠ i} (θ − θ_j) / Π_{j ≠ i} (θ_i − θ_j) over the stencil
        d0, d1, d2, d3 = np.moveaxis(theta[..., None] - self.theta_grid[indices], -1, 0)
        low, high = d0 * d1, d2 * d3
        numerators = np.stack([d1 * high, d0 * high, low * d3, low * d2], axis=-1)
        return indices, numerators * self._inverse_denominators[start]

    def __call__(self, x: np.ndarray) -> np.ndarray:
        indices, values = self.stencil(x)
        dense = np.zeros(np.shape(x) + (self.size,))
        np.put_along_axis(dense, indices, values, axis=-1)
        return dense

    def integrate(self, x: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """(T, M): Σ_nodes weights[t, n] L_j(x[t, n]) for nodes x and weights of shape (T, N)."""
        count = len(weights)
        indices, values = self.stencil(x)
        flat = np.arange(count)[:, None, None] * self.size + indices.reshape(count, -1, 4)
        contributions = weights[:, :, None] * values.reshape(count, -1, 4)
        return np.bincount(flat.ravel(), contributions.ravel(), minlength=count * self.size).reshape(count, self.size)


_OFF_DIAGONAL = ~np.eye(4, dtype=bool)


def lagrange_cardinals(theta_grid) -> LagrangeCardinals:
    """The cardinal functions of the four-point Lagrange interpolation on ``theta_grid`` (M,), M ≥ 4."""
    return LagrangeCardinals(check_theta_grid("theta_grid", theta_grid))


def texel_weights(theta_grid, mu_o, alpha, order=DEFAULT_ORDER, visibility: str = "height-correlated") -> np.ndarray:
    """Quadrature weights W of each texel on a θ grid: F̄[f](μo, α) ≈ Σ_j W_j f(θ_j) for any curve f.

    Parameters
    ----------
    theta_grid : array_like
        (M,) strictly increasing angles covering [0, π/2] (radians), M ≥ 4, e.g. ``basis.theta``.
    mu_o : array_like
        Cosine of the view angle, in [0, 1].
    alpha : array_like
        GGX width, in [0, 1]; broadcast against ``mu_o``.
    order : QuadratureOrder or what :func:`directional_albedo` accepts
        Node counts of the integrator.
    visibility : str
        The BRDF's masking-shadowing form (:data:`preintegrate.ggx.VISIBILITIES`).

    Returns
    -------
    numpy.ndarray
        broadcast(mu_o, alpha).shape + (M,): W_j = F̄[L_j], the split-sum integral of the j-th cardinal
        function of the four-point Lagrange interpolation in θ on ``theta_grid``.

    Notes
    -----
    F̄[f](μo, α) = ∫ f(ω_o·h) ρ(ω_o, ω_i) μ_i dω_i (Belcour et al. 2020, eq. 2) is linear in f, so
    replacing f by its interpolant Σ_j f(θ_j) L_j gives F̄[f] ≈ Σ_j f(θ_j) F̄[L_j], exact for cubics
    in θ and with error O(h⁴ f⁗) otherwise. Only four cardinals are non-zero at a node, so each node adds
    four weighted values (:meth:`LagrangeCardinals.integrate`): the work is that of integrating four
    curves, after which any number of curves costs one matrix product.

    Examples
    --------
    >>> theta = np.linspace(0.0, 0.5 * np.pi, 64)
    >>> weights = texel_weights(theta, 0.5, 0.3)
    >>> weights.shape
    (64,)
    """
    return directional_albedo(lagrange_cardinals(theta_grid), mu_o, alpha, order=order, visibility=visibility)
