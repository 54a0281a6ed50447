"""Issue 26 item 21: the tables' edges. Texel-centre tables never reach r = 1 or μo = 0, so a lookup there read the
texel half a step in (9.1e-3 off at μo = 0.002, r = 1); the default grid stands a texel on both ends of both axes
(columns uniform in √μo, rows in r) and every lookup in [0, 1]² interpolates.

Reference: the split-sum integral at the looked-up point itself (:func:`preintegrate.quadrature.directional_albedo`,
within 3e-8 of adaptive cubature: tests/fresnel_lut/test_cli.py), against the shipped 128 × 128 basis table read as a
GPU reads it (:func:`preintegrate.lut.lut_lookup`, the mirror of the include's coordinates, which tests/luts run on
llvmpipe, lavapipe and SwiftShader). ``python -m benchmarks.lut_edges`` measures the same with more points
(report/lut_edges.md).
"""

import numpy as np
import pytest

from handoff.exr import read_lut
from handoff.shipped import shipped_lut
from preintegrate.channels import basis_channels
from preintegrate.ggx import roughness_to_alpha
from preintegrate.lut import LutGrid, build_table, lut_lookup
from preintegrate.quadrature import directional_albedo

CHANNELS = basis_channels()
SHIPPED = read_lut(shipped_lut())[0]
ISSUE_POINTS = (np.array([0.5, 0.002, 0.002]), np.array([1.0, 0.5, 1.0]))


def _error(table_lookup, mu_o, roughness) -> float:
    exact = directional_albedo(CHANNELS.functions, mu_o, roughness_to_alpha(roughness))
    return float(np.max(np.abs(table_lookup(mu_o, roughness) - exact)))


def test_centre_tables_missed_the_edges():
    """The report's reproduction: the same 128 × 128 table at texel centres is 9.1e-3 off at the issue's points."""
    grid = LutGrid.centred(128)
    table = build_table(CHANNELS, grid)
    assert _error(lambda m, r: grid.lookup(table, m, r), *ISSUE_POINTS) > 8e-3


@pytest.mark.parametrize(
    "region, bound",
    [
        ("issue", 1.5e-4),  # measured 6.0e-5 (centres: 9.1e-3)
        ("r = 1", 1.5e-4),  # 5.5e-5 (2.1e-2)
        ("mu_o = 1", 1e-4),  # 3.2e-5 (3.8e-3)
        ("r = 0", 1e-3),  # 6.4e-4 (8.4e-2)
        ("mu_o = 0", 4e-3),  # 2.7e-3 (0.14): steep in r at the mirror's grazing corner
        ("anywhere", 2e-3),  # 1.4e-3 (5.0e-2)
    ],
)
def test_the_shipped_table_holds_its_edges(region, bound):
    """Lookups on each edge (64 seeded points), at the issue's points and anywhere in [0, 1]² (400 points) against the
    integral there, within the stated bounds (the default grid's worst cell is at grazing views of smooth surfaces,
    where the split sum is steepest; the interior with μo, r ≥ 0.1 is within 6.1e-4)."""
    rng = np.random.default_rng(21)
    free = rng.uniform(0.0, 1.0, 64)
    points = {
        "issue": ISSUE_POINTS,
        "r = 1": (free, np.ones(64)),
        "mu_o = 1": (np.ones(64), free),
        "r = 0": (free, np.zeros(64)),
        "mu_o = 0": (np.zeros(64), free),
        "anywhere": (rng.uniform(0.0, 1.0, 400), rng.uniform(0.0, 1.0, 400)),
    }[region]
    assert _error(lambda m, r: lut_lookup(SHIPPED, m, r), *points) <= bound


def test_the_ends_are_texels():
    """At the corners and along the edges a lookup returns the edge texel exactly (no clamping half a texel in)."""
    for (j, i), (mu_o, roughness) in {(0, 0): (0.0, 0.0), (127, 127): (1.0, 1.0), (0, 127): (1.0, 0.0)}.items():
        np.testing.assert_array_equal(lut_lookup(SHIPPED, mu_o, roughness), SHIPPED[j, i])
