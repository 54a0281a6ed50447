"""Data shipped by fresnel-basis: ``basis.json`` (the eigen-basis) and the default EXR LUTs.

Regenerate with ``fresnel-lut basis`` and ``fresnel-lut build``; see README.md.
"""
