"""The integration core: everything about integrating Fresnel channels against GGX: the distribution (``ggx``), the
deterministic quadrature (``quadrature``), the Monte-Carlo and Hammersley estimators (``estimators``), channel sets
(``channels``), LUT tables, their grid and lookup (``lut``), the build recipes and their writer (``tables``), EXR and
the other file formats (``exr``, ``formats``) and multiple scattering. It never imports the application layer
(:mod:`fresnel_lut`: the command, scenes, the renderer, the report)."""
