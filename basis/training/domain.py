"""The training set of the eigen-basis: a seeded random sample of complex IORs and their curves.

Public objects: ``TrainingDomain``, ``Component``, ``DEFAULT_DOMAIN``, ``NOTEBOOK_DOMAIN``, ``REFINEMENT_DOMAINS``.

A domain is a mixture of components, each a box in (η, κ) or in Gulbrandsen's (r, g), drawn with a
given share of the curves. The sample is a pure function of (domain, count, seed), so a basis is
reproducible from the description stored in ``basis.json``.

References
----------
:cite:`Belcour2020` L. Belcour, M. Bati, P. Barla, "Bringing an Accurate Fresnel to Real-Time
    Rendering: a Preintegrable Decomposition", SIGGRAPH 2020 Talks, section "An Empirical Decomposition".
:cite:`Gulbrandsen2014` JCGT 3(4), eq. 7–9.
"""

from __future__ import annotations

import collections
import concurrent.futures
import dataclasses
import itertools
from collections.abc import Iterator

import numpy as np

from ..angles import cos_theta
from ..fresnel import fresnel_kernel
from ..gulbrandsen import gulbrandsen_to_nk
from ..parallel import worker_count
from ..validation import ParameterError, check_positive_int

__all__ = ["DEFAULT_DOMAIN", "NOTEBOOK_DOMAIN", "REFINEMENT_DOMAINS", "Component", "TrainingDomain"]


@dataclasses.dataclass(frozen=True)
class Component:
    """One box of the training mixture.

    ``space`` is ``"nk"`` (first = η, second = κ) or ``"gulbrandsen"`` (first = r, second = g).
    ``first_log`` draws the first parameter log-uniformly. ``share`` is the fraction of curves.
    """

    name: str
    space: str
    first: tuple[float, float]
    second: tuple[float, float]
    share: float
    first_log: bool = False

    def sample(self, rng: np.random.Generator, count: int) -> tuple[np.ndarray, np.ndarray]:
        """Draw ``count`` (η, κ) pairs."""
        low, high = self.first
        if self.first_log:
            first = np.exp(rng.uniform(np.log(low), np.log(high), count))
        else:
            first = rng.uniform(low, high, count)
        second = rng.uniform(self.second[0], self.second[1], count)
        if self.space == "gulbrandsen":
            return gulbrandsen_to_nk(first, second)
        return first, second


@dataclasses.dataclass(frozen=True)
class TrainingDomain:
    """A mixture of :class:`Component` boxes; its :meth:`describe` is stored with the basis."""

    components: tuple[Component, ...]

    def __post_init__(self):
        total = sum(component.share for component in self.components)
        if not self.components or abs(total - 1.0) > 1e-9:
            raise ParameterError(f"training component shares must sum to 1, got {total}")

    def sample_iors(self, count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
        """``count`` (η, κ) pairs, shuffled, deterministic for ``seed``."""
        count = check_positive_int("count", count, low=len(self.components))
        rng = np.random.default_rng(seed)
        counts = [int(round(component.share * count)) for component in self.components]
        counts[-1] = count - sum(counts[:-1])
        etas, kappas = zip(*(c.sample(rng, n) for c, n in zip(self.components, counts)))
        order = rng.permutation(count)
        return np.concatenate(etas)[order], np.concatenate(kappas)[order]

    def curves(
        self, theta: np.ndarray, count: int, seed: int, chunk: int = 2048, workers: int | None = None
    ) -> Iterator[np.ndarray]:
        """Yield the training curves F(θ) in order, in chunks of shape (≤ chunk, len(theta)).

        ``workers`` threads (default: the machine's cores) evaluate the next chunks while the caller
        consumes this one (numpy releases the GIL); at most ``workers + 1`` chunks exist at once, so
        memory stays bounded, and the order — hence every sum over the chunks — is deterministic.
        """
        eta, kappa = self.sample_iors(count, seed)
        mu = cos_theta(theta)
        workers = worker_count(workers)

        def evaluate(start: int) -> np.ndarray:
            stop = min(start + chunk, count)
            return fresnel_kernel(mu[None, :], eta[start:stop, None], kappa[start:stop, None])

        starts = iter(range(0, count, chunk))
        with concurrent.futures.ThreadPoolExecutor(max_workers=workers) as pool:
            pending = collections.deque(pool.submit(evaluate, start) for start in itertools.islice(starts, workers + 1))
            while pending:
                result = pending.popleft().result()
                for start in itertools.islice(starts, 1):
                    pending.append(pool.submit(evaluate, start))
                yield result

    def describe(self) -> list[dict]:
        """JSON-ready description of the mixture."""
        return [dataclasses.asdict(component) for component in self.components]

    @classmethod
    def from_description(cls, description: list[dict]) -> "TrainingDomain":
        """Inverse of :meth:`describe`."""
        try:
            components = tuple(
                Component(**{**item, "first": tuple(item["first"]), "second": tuple(item["second"])})
                for item in description
            )
        except (TypeError, KeyError) as error:
            raise ParameterError(f"malformed training-domain description: {error}") from None
        return cls(components)


#: Mostly dielectrics, a few Gulbrandsen g = 1 conductors (as the authors' notebook does) and 5 % metals
#: (η 0.1–4, κ 1–8). Measured (200k curves; ``fresnel-lut materials`` prints the sweep):
#:
#: * without the metal box, the four-point fit misses held-out dielectrics by 0.0062 and the measured
#:   metals of Hoffman's table by up to 0.19 ΔE2000, the ΔE-fitted coefficients by up to 0.135;
#: * with 5 % metals: dielectrics 0.0033, measured metals 0.11 (four-point) and 0.078 (ΔE fit, every metal
#:   under Hoffman's 0.08); synthetic held-out metals get slightly worse, 0.0101 → 0.0120;
#: * 2 % or 10 % metals, log-uniform η, or Gulbrandsen boxes with g < 1 (η up to 80) do worse: a broad
#:   conductor box lets high-F0 curves, whose spans are tiny, dominate the normalised SVD.
DEFAULT_DOMAIN = TrainingDomain(
    (
        Component("dielectrics", "nk", first=(1.01, 3.0), second=(0.0, 0.0), share=0.94),
        Component("gulbrandsen-g1", "gulbrandsen", first=(0.0, 0.999), second=(1.0, 1.0), share=0.01),
        Component("metals", "nk", first=(0.1, 4.0), second=(1.0, 8.0), share=0.05),
    )
)


#: The authors' public notebook: 99 % dielectrics η ∈ [1.01, 3] and 1 % Gulbrandsen g = 1 conductors (with
#: ``grid_kind="mu"``, uniform in cos θ): the comparison point of the report's basis-fidelity section.
NOTEBOOK_DOMAIN = TrainingDomain(
    (
        Component("dielectrics", "nk", first=(1.01, 3.0), second=(0.0, 0.0), share=0.99),
        Component("gulbrandsen-g1", "gulbrandsen", first=(0.0, 0.999), second=(1.0, 1.0), share=0.01),
    )
)


#: The groups a minimax refinement (:func:`basis.training.refine_basis`) of a generic basis weighs against each
#: other: the validation groups' boxes (drawn with their own seed) and, for the talk's Figure 2 material, the
#: "showcase" box around it (Gulbrandsen r 0.3–0.6 with g = 0 or 1: η up to 5.8 dielectrics and g = 1
#: conductors), never the material itself.
REFINEMENT_DOMAINS = {
    "dielectrics": TrainingDomain((Component("dielectrics", "nk", first=(1.2, 2.9), second=(0.0, 0.0), share=1.0),)),
    "metals": TrainingDomain(
        (Component("metals", "nk", first=(0.1, 4.0), second=(1.0, 8.0), share=1.0, first_log=True),)
    ),
    "showcase": TrainingDomain(
        (
            Component("showcase-g0", "gulbrandsen", first=(0.3, 0.6), second=(0.0, 0.0), share=0.5),
            Component("showcase-g1", "gulbrandsen", first=(0.3, 0.6), second=(1.0, 1.0), share=0.5),
        )
    ),
    "gulbrandsen": TrainingDomain(
        (Component("gulbrandsen", "gulbrandsen", first=(0.0, 0.9), second=(0.0, 1.0), share=1.0),)
    ),
}
