"""The Fresnel eigen-basis as data: curves on a θ grid, fit angles, provenance; read, write, evaluate.

Public objects: ``Basis``, ``default_basis``, ``resolve_basis``, ``shipped_basis_path``, ``BasisFileError``,
``FORMAT``, ``TERMS_RANGE``.

``luts/basis.json`` holds the θ grid (radians), the K curves b_k(θ_j), the K fit angles of the
coefficient solver, the training-set description, build statistics and a SHA-256 content hash of the
numbers. Between grid samples b_k is a cubic spline in θ with zero slope at θ = 0 (every Fresnel curve
is a smooth function of cos θ, hence even in θ) and not-a-knot at π/2.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .angles import theta_spline
from .storage import read_json_document, shipped_path, write_json
from .validation import ParameterError, check_range

if TYPE_CHECKING:
    from scipy.interpolate import CubicSpline

__all__ = ["FORMAT", "TERMS_RANGE", "Basis", "BasisFileError", "default_basis", "resolve_basis", "shipped_basis_path"]

#: Identifies the file format; bumped when the layout changes.
FORMAT = "fresnel-basis/basis@1"


class BasisFileError(ParameterError):
    """A basis file is missing, truncated, corrupt, foreign or fails its hash."""


#: The supported numbers of basis terms, end to end: a basis file, ``fresnel-lut basis --terms``, the tables (terms
#: 0-3 and 4-7 in two RGBA textures), ``coeffs``' combination rule and the shaders' two-fetch path.
TERMS_RANGE = (2, 8)

#: Largest accepted magnitude of a basis curve (the build scales b_k, k ≥ 2, to max |b_k| = 1; b0 = 1, b1 ≤ 1).
MAX_CURVE = 1e3

#: Largest accepted condition number of the four-point system: beyond it the coefficients amplify
#: rounding in the target by more than 1e6 (the shipped basis has 4.8).
MAX_FIT_CONDITION = 1e6


def _check_structure(curves: np.ndarray, fit_angles: np.ndarray, spline: CubicSpline) -> None:
    """The properties the coefficient scheme relies on (c0 = F(0), c1 = F(π/2) − F(0), a solvable fit)."""
    if not np.allclose(curves[0], 1.0, rtol=0, atol=1e-12):
        raise BasisFileError("curves[0] (b0) must be 1 everywhere")
    if (
        np.any(np.abs(curves[1:, 0]) > 1e-12)
        or abs(curves[1, -1] - 1.0) > 1e-12
        or np.any(np.abs(curves[2:, -1]) > 1e-12)
    ):
        raise BasisFileError("b_k(0) must be 0 for k >= 1, b1(pi/2) = 1 and b_k(pi/2) = 0 for k >= 2")
    if abs(fit_angles[0]) > 1e-12 or abs(fit_angles[1] - 0.5 * np.pi) > 1e-12:
        raise BasisFileError(f"fit_angles must start with 0 and pi/2, got {fit_angles[:2].tolist()}")
    system = spline(fit_angles)
    condition = np.linalg.cond(system)
    if not np.isfinite(condition) or condition > MAX_FIT_CONDITION:
        raise BasisFileError(
            f"the four-point system at fit_angles {fit_angles.tolist()} is singular or ill-conditioned "
            f"(condition number {condition:.3g} > {MAX_FIT_CONDITION:g})"
        )


#: How far a stored hemispherical average may lie from the one recomputed from the curves (they are written
#: with 15 significant digits; engines read them from the file, so a stored value is checked, not trusted).
AVERAGE_TOLERANCE = 1e-12


def _check_derived(data: dict, basis: Basis) -> None:
    """The fields outside the content hash (``n_terms``, ``hemispherical_averages``) agree with the numbers."""
    if "n_terms" in data and (type(data["n_terms"]) is not int or data["n_terms"] != basis.n_terms):
        raise BasisFileError(f"n_terms {data['n_terms']!r} does not match the {basis.n_terms} curves")
    if "hemispherical_averages" in data:
        stored = data["hemispherical_averages"]
        try:
            stored = np.asarray(stored, dtype=np.float64)
        except (TypeError, ValueError):
            raise BasisFileError(
                f"hemispherical_averages must be {basis.n_terms} numbers, got {str(stored)[:60]!r}"
            ) from None
        if stored.shape != (basis.n_terms,) or not np.all(
            np.abs(stored - basis.hemispherical_averages) <= AVERAGE_TOLERANCE
        ):
            raise BasisFileError(
                f"hemispherical_averages {stored.tolist()} do not match the curves' own "
                f"{basis.hemispherical_averages.tolist()}: the file is corrupt or was edited"
            )


@dataclasses.dataclass(frozen=True, eq=False)
class Basis:
    """K Fresnel eigen-curves b_k(θ) sampled on ``theta`` (M,), with the coefficient fit angles.

    Attributes
    ----------
    theta : numpy.ndarray
        (M,) increasing, from 0 to π/2 (radians).
    curves : numpy.ndarray
        (K, M); curves[0] = 1.
    fit_angles : numpy.ndarray
        (K,) angles (radians) at which the four-point solver samples a target: 0, π/2, θ2, θ3.
    training : dict
        Description of the training set (domain, count, seed, grid kind) and build statistics.
    """

    theta: np.ndarray
    curves: np.ndarray
    fit_angles: np.ndarray
    training: dict = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        theta = np.asarray(self.theta, dtype=np.float64)
        curves = np.asarray(self.curves, dtype=np.float64)
        fit_angles = np.asarray(self.fit_angles, dtype=np.float64)
        if theta.ndim != 1 or theta.size < 16:
            raise BasisFileError(f"theta must be a 1-D grid of at least 16 angles, got shape {theta.shape}")
        if not (np.all(np.isfinite(theta)) and np.all(np.diff(theta) > 0)):
            raise BasisFileError("theta must be finite and strictly increasing")
        if abs(theta[0]) > 1e-12 or abs(theta[-1] - 0.5 * np.pi) > 1e-12:
            raise BasisFileError(f"theta must span [0, pi/2], got [{theta[0]}, {theta[-1]}]")
        low, high = TERMS_RANGE
        if curves.ndim != 2 or curves.shape[1] != theta.size or not low <= curves.shape[0] <= high:
            raise BasisFileError(
                f"curves must have shape (K, {theta.size}) with {low} <= K <= {high}, got {curves.shape}"
            )
        if not np.all(np.isfinite(curves)):
            raise BasisFileError("curves contain NaN or inf")
        if np.max(np.abs(curves)) > MAX_CURVE:  # b_k are scaled to max |b_k| = 1; beyond this the spline overflows
            raise BasisFileError(f"curves must stay within ±{MAX_CURVE:g}, got {np.max(np.abs(curves)):.3g}")
        if fit_angles.shape != (curves.shape[0],):
            raise BasisFileError(f"fit_angles must have shape ({curves.shape[0]},), got {fit_angles.shape}")
        check_range("fit_angles", fit_angles, 0.0, 0.5 * np.pi)
        spline = theta_spline(theta, curves.T, axis=0)
        _check_structure(curves, fit_angles, spline)
        self.__dict__["spline"] = spline  # the cached_property below, built once here
        object.__setattr__(self, "theta", theta)
        object.__setattr__(self, "curves", curves)
        object.__setattr__(self, "fit_angles", fit_angles)

    @property
    def n_terms(self) -> int:
        """K, the number of basis elements (texture channels)."""
        return self.curves.shape[0]

    @functools.cached_property
    def spline(self) -> CubicSpline:
        """Cubic spline in θ of all curves at once, zero slope at θ = 0."""
        return theta_spline(self.theta, self.curves.T, axis=0)

    @functools.cached_property
    def content_hash(self) -> str:
        """SHA-256 of the float64 bytes of theta, curves and fit angles (hex, first 16 digits)."""
        digest = hashlib.sha256()
        for array in (self.theta, self.curves, self.fit_angles):
            digest.update(np.ascontiguousarray(array, dtype="<f8").tobytes())
        return digest.hexdigest()[:16]

    @functools.cached_property
    def hemispherical_averages(self) -> np.ndarray:
        """avg(b_k) = 2 ∫₀¹ b_k(μ) μ dμ, (K,): the cosine-weighted average over the hemisphere. The average of a
        fitted curve is linear in its coefficients, F_avg = Σ c_k avg(b_k): what multiple-scattering
        compensation needs, exact for coloured edge tints (Kulla and Conty 2017; Fdez-Agüera 2019)."""
        nodes, weights = np.polynomial.legendre.leggauss(256)
        mu, weights = 0.5 * (nodes + 1.0), 0.5 * weights
        values = self.spline(np.arccos(mu))
        averages = 2.0 * (weights * mu) @ values
        averages.setflags(write=False)
        return averages

    def evaluate(self, theta) -> np.ndarray:
        """b_k(θ) for θ in [0, π/2]: shape (..., K)."""
        theta = check_range("theta", theta, 0.0, 0.5 * np.pi)
        return self.spline(theta)

    def evaluate_mu(self, mu) -> np.ndarray:
        """b_k(arccos μ) for μ in [0, 1]: shape (..., K)."""
        mu = check_range("mu", mu, 0.0, 1.0)
        return self.spline(np.arccos(mu))

    def _evaluate_mu_unchecked(self, mu: np.ndarray) -> np.ndarray:
        """:meth:`evaluate_mu` for the integrator's own nodes, already in [0, 1]."""
        return self.spline(np.arccos(np.clip(mu, 0.0, 1.0)))

    # ---------------------------------------------------------------- file I/O
    def to_dict(self) -> dict:
        """JSON-ready dictionary (floats written with full precision by ``json``)."""
        return {
            "format": FORMAT,
            "description": (
                "Fresnel eigen-basis after Belcour, Bati, Barla 2020: F(theta) ~ sum_k c_k b_k(theta). "
                "theta in radians; curves[k][j] = b_k(theta[j]); cubic spline in theta between samples "
                "(zero slope at 0); fit_angles: where the four-point solver samples a target, in order "
                "c0 <- F(0), c1 <- F(pi/2) - F(0), then c2, c3. hemispherical_averages[k] = 2 integral of "
                "b_k(mu) mu dmu over [0, 1] (derived; F_avg = sum_k c_k hemispherical_averages[k])."
            ),
            "content_hash": self.content_hash,
            "n_terms": self.n_terms,
            "theta": self.theta.tolist(),
            "fit_angles": self.fit_angles.tolist(),
            "curves": self.curves.tolist(),
            "hemispherical_averages": [float(f"{value:.15g}") for value in self.hemispherical_averages],
            "training": self.training,
        }

    def write(self, path) -> Path:
        """Write the basis as JSON atomically (temporary file in the same folder, then rename)."""
        return write_json(path, self.to_dict())

    @classmethod
    def from_dict(cls, data) -> "Basis":
        """Inverse of :meth:`to_dict`; checks the format tag and the content hash."""
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            found = data.get("format") if isinstance(data, dict) else type(data).__name__
            raise BasisFileError(f"not a fresnel-basis basis file (format {found!r}, expected {FORMAT!r})")
        training = data.get("training", {})
        if not isinstance(training, dict):
            raise BasisFileError(
                f"basis file's training field must be an object (the training set's description), got "
                f"{type(training).__name__}"
            )
        try:
            basis = cls(
                theta=np.asarray(data["theta"], dtype=np.float64),
                curves=np.asarray(data["curves"], dtype=np.float64),
                fit_angles=np.asarray(data["fit_angles"], dtype=np.float64),
                training=dict(training),
            )
        except KeyError as error:
            raise BasisFileError(f"basis file lacks the field {error}") from None
        except (TypeError, ValueError) as error:
            if isinstance(error, BasisFileError):
                raise
            raise BasisFileError(f"basis file has malformed numbers: {error}") from None
        if data.get("content_hash") != basis.content_hash:
            raise BasisFileError(
                f"basis file content hash {data.get('content_hash')!r} does not match its numbers "
                f"({basis.content_hash}): the file is corrupt or was edited"
            )
        _check_derived(data, basis)
        return basis

    @classmethod
    def read(cls, path) -> "Basis":
        """Read and verify a basis file written by :meth:`write`."""
        data = read_json_document(path, "basis file", error=BasisFileError)
        try:
            return cls.from_dict(data)
        except BasisFileError as error:
            raise BasisFileError(f"basis file {path}: {error}") from None


def shipped_basis_path() -> Path:
    """Path of the basis shipped with the package (``luts/basis.json``)."""
    return shipped_path("basis.json")


@functools.lru_cache(maxsize=1)
def default_basis() -> Basis:
    """The shipped basis, read once and cached."""
    return Basis.read(shipped_basis_path())


def resolve_basis(basis: Basis | None) -> Basis:
    """``basis``, or the shipped one when None; anything else is refused with one line."""
    if basis is None:
        return default_basis()
    if not isinstance(basis, Basis):
        raise ParameterError(f"basis must be a fresnel basis.Basis or None, got {type(basis).__name__}")
    return basis
