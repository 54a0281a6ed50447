"""The integration core: everything about integrating Fresnel channels against GGX: the distribution (``ggx``), the
deterministic quadrature (``quadrature``), the Monte-Carlo and Hammersley estimators (``estimators``), channel sets
(``channels``), the tables' grid, their building and the GPU's lookup (``lut``), linearly transformed cosines
(``ltc``) and multiple scattering. It reads and writes no files (that is :mod:`handoff`'s) and never imports the
hand-off or the application layer (:mod:`fresnel_lut`: the command, scenes, the renderer, the report)."""
