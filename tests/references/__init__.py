"""Deliberately independent re-typings of the physics (adaptive integrals, complex and decimal Fresnel):
the tests compare the product against these, never against itself."""
