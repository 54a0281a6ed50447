"""Every table the include reads in one texture (issue 38 item 3: an engine's sampler budget is tight; Filament: "burning
2 samplers is most likely a no-go on mobile").

Public objects: ``ATLAS_WIDTH``, ``ATLAS_ROLES``, ``AtlasLayout``, ``pack_atlas``.

The tables (the basis table and its second half for K > 4, Schlick's, the LTC table, the coefficient and curve tables)
are packed on shelves of an RGBA texture :data:`ATLAS_WIDTH` texels wide, tallest first, each inside a one-texel guard
ring that repeats its edge texels: bilinear filtering at a table's outermost texel centres, where the include's
coordinates end, then reads only that table's values even when float32 rounding puts the coordinate a hair outside.
The include generated for the atlas (``fresnel_basis_atlas.*``) maps each table's own coordinates (u, v) into its
rectangle, u' = u · w/W + x0/W (and so for v): one multiply-add per read, none for the per-pixel tables, whose
axes' constants it composes with their rectangles.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from basis.validation import ParameterError

__all__ = ["ATLAS_ROLES", "ATLAS_WIDTH", "AtlasLayout", "pack_atlas"]

#: The atlas' width: WebGL 2's and OpenGL ES 3.0's guaranteed largest texture (the curve table and its guards fill it).
ATLAS_WIDTH = 2048
#: The tables an include reads, by role (the include's address functions are named after them).
ATLAS_ROLES = ("basis", "basis2", "schlick", "ltc", "coefficients", "curves")


@dataclasses.dataclass(frozen=True)
class AtlasLayout:
    """Where each table lies: ``rects`` role → (x0, y0, w, h) of its first texel and size, in an atlas ``width`` ×
    ``height``."""

    width: int
    height: int
    rects: dict[str, tuple[int, int, int, int]]

    def uv_map(self, role: str) -> tuple[float, float, float, float]:
        """(scale u, scale v, offset u, offset v) taking the table's own texture coordinates into the atlas."""
        x0, y0, w, h = self.rects[role]
        return w / self.width, h / self.height, x0 / self.width, y0 / self.height

    def describe(self) -> str:
        """``basis 1,1,128,128; …``: each role's first texel and size, for the atlas' header."""
        return "; ".join(f"{role} {','.join(map(str, rect))}" for role, rect in self.rects.items())


def pack_atlas(tables: dict[str, np.ndarray], width: int = ATLAS_WIDTH) -> tuple[np.ndarray, AtlasLayout]:
    """(atlas (H, W, 4) float64, layout) of ``tables`` role → (h, w, C ≤ 4) values: shelves tallest first, each table
    in a one-texel guard ring of its edge texels, channels beyond C zero, the rest of the atlas zero."""
    unknown = sorted(set(tables) - set(ATLAS_ROLES))
    if unknown:
        raise ParameterError(f"atlas roles are {list(ATLAS_ROLES)}, not {unknown}")
    order = sorted(tables, key=lambda role: (-tables[role].shape[0], ATLAS_ROLES.index(role)))
    placed, x, y, shelf_height = {}, 0, 0, 0
    for role in order:
        h, w = tables[role].shape[:2]
        if w + 2 > width or tables[role].shape[2] > 4:
            raise ParameterError(
                f"table {role!r} ({w} x {h} x {tables[role].shape[2]}) does not fit a {width}-wide RGBA atlas"
            )
        if x + w + 2 > width:
            y, x, shelf_height = y + shelf_height, 0, 0
        placed[role] = (x + 1, y + 1, w, h)
        x, shelf_height = x + w + 2, max(shelf_height, h + 2)
    height = y + shelf_height
    atlas = np.zeros((height, width, 4))
    for role, (x0, y0, w, h) in placed.items():
        values = np.asarray(tables[role], dtype=np.float64)
        padded = np.pad(values, ((1, 1), (1, 1), (0, 0)), mode="edge")
        atlas[y0 - 1 : y0 + h + 1, x0 - 1 : x0 + w + 1, : values.shape[2]] = padded
    return atlas, AtlasLayout(width, height, {role: placed[role] for role in ATLAS_ROLES if role in placed})
