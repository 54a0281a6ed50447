"""The iterative SVD that extracts the Fresnel eigen-curves (Belcour et al. 2020, eq. 6).

Public objects: ``build_curves``, ``GramAccumulator``.

The training curves are normalised to F̂ = (F − F(0)) / (F(π/2) − F(0)), so each starts at 0 and
ends at 1. b0 = 1; b1 is the first right singular vector of the F̂ matrix scaled so b1(π/2) = 1.
The coefficient scheme gives every normalised curve the coefficient 1 on b1 (it interpolates both
ends), so the residual that the next elements must explain is R1 = F̂ − b1, which vanishes at both
ends. Each next b_k is the first singular vector of the residual after removing the orthogonal
projection on b2 … b_{k−1}; these therefore vanish at θ = 0 and π/2 too, which is what makes
c0 = F(0) and c1 = F(π/2) − F(0) exact.

With ``weighting="span"`` each normalised curve counts with weight (F(π/2) − F(0))², so the SVD minimises
the mean square error of F itself instead of F̂ (whose plain mean weighs a curve by 1/(F90 − F0)): the
lever issue 14 asks to measure.

Nothing N × M is ever held: one pass accumulates the weighted Gram matrix G = Σ ŷ ŷᵀ and the sum
s = Σ ŷ of the normalised curves (ŷ = F̂ √w with trapezoid weights w over θ), and every residual's
Gram matrix follows from G and s in closed form. Memory is O(M² + chunk × M).

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, "An Empirical Decomposition", eq. 4 and 6.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np

from ..angles import trapezoid_weights
from ..parallel import one_blas_thread
from ..validation import ParameterError, check_choice, check_positive_int

__all__ = ["GramAccumulator", "build_curves"]

#: Curves whose F(π/2) − F(0) is below this carry no shape information (e.g. η = 1) and are skipped.
MIN_SPAN = 1e-9

#: How a normalised curve counts in the Gram matrix: once ("normalised", the talk's), or by its span squared.
WEIGHTINGS = ("normalised", "span")


class GramAccumulator:
    """Streaming Σ v ŷ ŷᵀ and Σ v ŷ over chunks of curves (N, M): the one pass over the data; a curve's
    weight v is 1, or its span squared with ``weighting="span"``."""

    def __init__(self, theta: np.ndarray, weighting: str = "normalised"):
        self.weighting = check_choice("weighting", weighting, WEIGHTINGS)
        self.sqrt_weights = np.sqrt(trapezoid_weights(theta))
        size = theta.size
        self.gram = np.zeros((size, size))
        self.total = np.zeros(size)
        self.count = 0
        self.skipped = 0
        self.span_weight = 0.0

    @property
    def weight_sum(self) -> float:
        """Σ of the curves' weights in the Gram matrix: the kept curves' count, or Σ span²."""
        return float(self.count) if self.weighting == "normalised" else self.span_weight

    def add(self, curves: np.ndarray) -> None:
        """Normalise a chunk of curves F(θ) and fold it into the sums."""
        span = curves[:, -1:] - curves[:, :1]
        keep = span[:, 0] > MIN_SPAN
        self.skipped += int(np.count_nonzero(~keep))
        normalised = (curves[keep] - curves[keep, :1]) / span[keep]
        weighted = normalised * self.sqrt_weights
        if self.weighting == "span":
            scaled = weighted * span[keep] ** 2
            self.gram += scaled.T @ weighted
            self.total += scaled.sum(axis=0)
            self.span_weight += float(np.sum(span[keep] ** 2))
        else:
            self.gram += weighted.T @ weighted
            self.total += weighted.sum(axis=0)
        self.count += int(np.count_nonzero(keep))


def _leading_eigenvector(gram: np.ndarray) -> tuple[np.ndarray, float]:
    """Unit eigenvector of the largest eigenvalue of a symmetric matrix, and that eigenvalue."""
    values, vectors = np.linalg.eigh(0.5 * (gram + gram.T))
    return vectors[:, -1], float(values[-1])


def build_curves(
    theta: np.ndarray,
    chunks: Iterable[np.ndarray],
    n_terms: int = 4,
    progress: Callable[[int], None] | None = None,
    weighting: str = "normalised",
) -> tuple[np.ndarray, dict]:
    """Run the iterative SVD over streamed training curves.

    Parameters
    ----------
    theta : numpy.ndarray
        Increasing angles (M,) with theta[0] = 0 and theta[-1] = π/2.
    chunks : iterable of numpy.ndarray
        Training curves F(θ), each chunk (n, M).
    n_terms : int
        Number of basis elements K ≥ 2 (b0 = 1 included).
    progress : callable, optional
        Called with the number of curves processed so far.
    weighting : {"normalised", "span"}
        Each normalised curve counts once (the talk's SVD), or with weight (F(π/2) − F(0))²: the mean
        square error of F rather than of F̂.

    Returns
    -------
    curves : numpy.ndarray
        (K, M): b0 = 1; b1 with b1(π/2) = 1; b_k (k ≥ 2) scaled to max |b_k| = 1 with the sample of
        largest magnitude positive (the sign convention).
    stats : dict
        ``count``, ``skipped`` and ``residual_rms``: RMS over curves and θ of the normalised residual
        after 1 … K elements (a convergence measure of the decomposition).
    """
    n_terms = check_positive_int("n_terms", n_terms, low=2, high=16)
    if theta[0] != 0.0 or theta[-1] != 0.5 * np.pi:
        raise ParameterError("theta grid must start at 0 and end at pi/2")
    with one_blas_thread():  # the same bits whatever the machine's BLAS threads (basis.parallel)
        return _build_curves(theta, chunks, n_terms, progress, weighting)


def _build_curves(theta, chunks, n_terms: int, progress, weighting: str = "normalised") -> tuple[np.ndarray, dict]:
    accumulator = GramAccumulator(theta, weighting)
    for chunk in chunks:
        accumulator.add(chunk)
        if progress is not None:
            progress(accumulator.count + accumulator.skipped)
    if accumulator.count == 0:
        raise ParameterError("no training curve has F(pi/2) - F(0) > 0")
    gram, total, root_w = accumulator.gram, accumulator.total, accumulator.sqrt_weights
    norm = accumulator.weight_sum * float(theta[-1] - theta[0])

    def rms(residual_gram: np.ndarray) -> float:
        return float(np.sqrt(max(np.trace(residual_gram), 0.0) / norm))

    curves = [np.ones_like(theta)]
    residual_rms = [rms(gram)]
    first, _ = _leading_eigenvector(gram)
    b1 = first / root_w
    b1 /= b1[-1]
    b1[0], b1[-1] = 0.0, 1.0  # exact in theory (every F̂ row is 0 at θ = 0); remove rounding
    curves.append(b1)
    # Gram of the rows (F̂ − b1)√w: G − s b̂1ᵀ − b̂1 sᵀ + N b̂1 b̂1ᵀ with s = Σ F̂ √w.
    b1_weighted = b1 * root_w
    residual = gram - np.outer(total, b1_weighted) - np.outer(b1_weighted, total)
    residual += accumulator.weight_sum * np.outer(b1_weighted, b1_weighted)
    residual_rms.append(rms(residual))
    for _ in range(2, n_terms):
        vector, _ = _leading_eigenvector(residual)
        projector = np.eye(theta.size) - np.outer(vector, vector)
        residual = projector @ residual @ projector
        residual_rms.append(rms(residual))
        element = vector / root_w
        element = element / element[np.argmax(np.abs(element))]
        # Zero at both ends in theory (every residual row is); the closed-form Gram leaves ~1e-11,
        # which would make c0 = F(0) and c1 = F(π/2) − F(0) only approximately true.
        element[0] = element[-1] = 0.0
        curves.append(element)
    stats = {"count": accumulator.count, "skipped": accumulator.skipped, "residual_rms": residual_rms}
    return np.array(curves), stats
