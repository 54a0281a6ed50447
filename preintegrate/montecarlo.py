"""Monte-Carlo reference of the split-sum directional albedo, by VNDF importance sampling.

Public objects: ``monte_carlo_albedo``.

Written independently of :mod:`preintegrate.quadrature` (it shares only the GGX formulas of
:mod:`preintegrate.ggx`): h is drawn from the visible-normal distribution D_ωo(h) (Heitz 2018), ω_i is
ω_o reflected about h, and each sample contributes f(ω_o·h) G2(ω_o, ω_i) / G1(ω_o) when ω_i is above
the horizon (Heitz 2018, eq. 19 with the pdf D_ωo(h) / (4 ω_o·h)). The estimator is unbiased; its
standard error is returned with the mean so tests can bound |Δ| by a multiple of σ.

References
----------
:cite:`Heitz2018` JCGT 7(4), 2018. :cite:`Heitz2014` JCGT 3(2), eq. 99.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from basis.validation import ParameterError, check_positive_int, check_range

from .ggx import g1, g2_height_correlated, sample_vndf

__all__ = ["monte_carlo_albedo"]


def monte_carlo_albedo(
    function: Callable[[np.ndarray], np.ndarray],
    mu_o: float,
    alpha: float,
    samples: int = 200_000,
    seed: int = 0,
    batch: int = 1_000_000,
) -> tuple[np.ndarray, np.ndarray]:
    """Estimate F̄[f](μo, α) = ∫ f(ω_o·h) ρ(ω_o, ω_i) μ_i dω_i for one texel.

    Parameters
    ----------
    function : callable
        f(x) for x = ω_o·h in [0, 1]; returns x.shape or x.shape + (K,).
    mu_o : float
        View cosine in (0, 1].
    alpha : float
        GGX width in (0, 1].
    samples : int
        Number of VNDF samples.
    seed : int
        Seed of the generator (results are reproducible).

    Returns
    -------
    (mean, standard_error) : tuple of numpy.ndarray
        Shape () or (K,).
    """
    mu_o = float(check_range("mu_o", mu_o, 0.0, 1.0, low_open=True))
    alpha = float(check_range("alpha", alpha, 0.0, 1.0, low_open=True))
    samples = check_positive_int("samples", samples, low=2)
    if not callable(function):
        raise ParameterError(f"function must be callable, got {type(function).__name__}")
    rng = np.random.default_rng(seed)
    omega_o = np.array([np.sqrt(max(1.0 - mu_o * mu_o, 0.0)), 0.0, mu_o])
    total = total_sq = 0.0
    for start in range(0, samples, batch):
        count = min(batch, samples - start)
        h = sample_vndf(omega_o, alpha, rng.random(count), rng.random(count))
        cos_d = np.clip(h @ omega_o, 0.0, 1.0)
        mu_i = 2.0 * cos_d * h[:, 2] - mu_o
        weight = g2_height_correlated(mu_o, mu_i, alpha) / g1(mu_o, alpha)
        values = np.asarray(function(cos_d), dtype=np.float64)
        contribution = values * (weight if values.ndim == 1 else weight[:, None])
        total = total + contribution.sum(axis=0)
        total_sq = total_sq + (contribution**2).sum(axis=0)
    mean = total / samples
    variance = np.maximum(total_sq / samples - mean**2, 0.0) * samples / (samples - 1)
    return np.asarray(mean), np.sqrt(variance / samples)
