"""Deterministic split-sum quadrature of any functions of cos θ_d = ω_o·h against GGX.

Public objects: ``directional_albedo``, ``QuadratureOrder``, ``DEFAULT_ORDER``.

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

import dataclasses
from collections.abc import Callable

import numpy as np

from basis.validation import ParameterError, check_positive_int, check_range

__all__ = ["DEFAULT_ORDER", "QuadratureOrder", "directional_albedo"]


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
            f"piece A {self.theta_a}x{self.phi_a} (Gauss-Legendre in v = asinh(tan theta') x midpoint in phi), "
            f"piece B {self.theta_b}x{self.phi_b} (smoothstep Gauss-Legendre in v x Gauss-Legendre in phi)"
        )


DEFAULT_ORDER = QuadratureOrder()

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


def _texel_nodes(mu_o: np.ndarray, alpha: np.ndarray, order: QuadratureOrder):
    """Quadrature nodes for a flat batch of texels: x = ω_o·h, μ_i and weights, each (T, nodes)."""
    texels = mu_o.size
    theta_o = np.arccos(mu_o)
    sin_o = np.sqrt(np.maximum(1.0 - mu_o * mu_o, 0.0))
    # Piece A ends at θ_h = (π/2 − θo)/2, piece B at (π/2 + θo)/2; tan θ' = tan θ_h / α.
    with np.errstate(divide="ignore", over="ignore"):
        v_a = np.minimum(np.arcsinh(np.tan(0.5 * (0.5 * np.pi - theta_o)) / alpha), V_MAX)
        v_b = np.minimum(np.arcsinh(np.tan(0.5 * (0.5 * np.pi + theta_o)) / alpha), V_MAX)
    v_b = np.maximum(v_b, v_a)
    sin_sa, cos_sa, weight_sa = _stretched_segment(np.zeros(texels), v_a, order.theta_a, False)
    sin_sb, cos_sb, weight_sb = _stretched_segment(v_a, v_b, order.theta_b, True)

    def half_vector(sin_s, cos_s):
        norm = np.sqrt((alpha[:, None] * sin_s) ** 2 + cos_s**2)
        # measure factor 2 sin θ' √(α² sin²θ' + cos²θ') of the change of variables (module notes)
        return alpha[:, None] * sin_s / norm, cos_s / norm, 2.0 * sin_s * norm

    sin_a, mu_h_a, jacobian_a = half_vector(sin_sa, cos_sa)
    weight_a = weight_sa * jacobian_a * (np.pi / order.phi_a)
    sin_b, mu_h_b, jacobian_b = half_vector(sin_sb, cos_sb)
    # φ range of piece B: cos φ > c* = −μo cos 2θ_h / (sin θo sin 2θ_h).
    with np.errstate(divide="ignore", invalid="ignore"):
        c_star = -mu_o[:, None] * (mu_h_b * mu_h_b - sin_b * sin_b) / (sin_o[:, None] * 2.0 * sin_b * mu_h_b)
    phi_max = np.arccos(np.clip(np.nan_to_num(c_star, nan=1.0, posinf=1.0, neginf=-1.0), -1.0, 1.0))
    s_phi, w_phi = _gauss_legendre_unit(order.phi_b)
    weight_b = weight_sb * jacobian_b * phi_max

    cos_phi_a = np.cos((np.arange(order.phi_a) + 0.5) * np.pi / order.phi_a)
    cos_phi_b = np.cos(phi_max[:, :, None] * s_phi[None, None, :])

    def flat(values):
        return values.reshape(texels, -1)

    sin_h = np.concatenate([flat(np.repeat(sin_a[:, :, None], order.phi_a, 2)), flat(np.repeat(sin_b[:, :, None], order.phi_b, 2))], 1)
    mu_h = np.concatenate([flat(np.repeat(mu_h_a[:, :, None], order.phi_a, 2)), flat(np.repeat(mu_h_b[:, :, None], order.phi_b, 2))], 1)
    cos_phi = np.concatenate([flat(np.broadcast_to(cos_phi_a, sin_a.shape + (order.phi_a,))), flat(cos_phi_b)], 1)
    weight = np.concatenate([flat(np.repeat(weight_a[:, :, None], order.phi_a, 2)), flat(weight_b[:, :, None] * w_phi)], 1)
    x = sin_o[:, None] * sin_h * cos_phi + mu_o[:, None] * mu_h
    mu_i = 2.0 * x * mu_h - mu_o[:, None]
    return np.clip(x, 0.0, 1.0), mu_i, weight / np.pi


def _kernel(mu_o: np.ndarray, alpha: np.ndarray, x: np.ndarray, mu_i: np.ndarray) -> np.ndarray:
    """2 μ_i x / (μ_i Ro + μo Ri): the BRDF part of the integrand, 0 where μ_i ≤ 0."""
    def slope_root(mu):
        return np.sqrt(mu * mu + alpha[:, None] ** 2 * (1.0 - mu * mu))

    mu_i = np.maximum(mu_i, 0.0)
    denominator = mu_i * slope_root(mu_o[:, None]) + mu_o[:, None] * slope_root(mu_i)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(denominator > 0.0, 2.0 * mu_i * x / np.where(denominator > 0.0, denominator, 1.0), 0.0)


def directional_albedo(
    functions: Callable[[np.ndarray], np.ndarray],
    mu_o,
    alpha,
    order: QuadratureOrder = DEFAULT_ORDER,
    max_nodes: int = 4_000_000,
    progress: Callable[[int, int], None] | None = None,
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
    order : QuadratureOrder
        Node counts.
    max_nodes : int
        Bound on nodes evaluated at once (memory ≈ max_nodes × (8 + K) × 8 bytes).
    progress : callable, optional
        Called with (texels done, texels total).

    Returns
    -------
    numpy.ndarray
        Shape broadcast(mu_o, alpha).shape + (K,).
    """
    if not callable(functions):
        raise ParameterError(f"functions must be callable, got {type(functions).__name__}")
    mu_o = check_range("mu_o", mu_o, 0.0, 1.0)
    alpha = check_range("alpha", alpha, 0.0, 1.0)
    if not isinstance(order, QuadratureOrder):
        raise ParameterError(f"order must be a QuadratureOrder, got {type(order).__name__}")
    mu_o, alpha = np.broadcast_arrays(mu_o, alpha)
    shape = mu_o.shape
    mu_o, alpha = mu_o.ravel(), alpha.ravel()
    n_channels = np.shape(functions(np.array([0.5])))[-1]
    result = np.empty((mu_o.size, n_channels))
    mirror = alpha == 0.0
    if np.any(mirror):
        result[mirror] = functions(mu_o[mirror])
    rough = np.flatnonzero(~mirror)
    batch = max(1, max_nodes // order.nodes_per_texel)
    for start in range(0, rough.size, batch):
        index = rough[start : start + batch]
        x, mu_i, weight = _texel_nodes(mu_o[index], alpha[index], order)
        weighted = weight * _kernel(mu_o[index], alpha[index], x, mu_i)
        result[index] = np.einsum("tn,tnk->tk", weighted, functions(x))
        if progress is not None:
            progress(min(start + batch, rough.size), rough.size)
    return result.reshape(shape + (n_channels,))
